// The reacting cell seen from the program (docs/cell-format.md "Parts and devices"): SIGNAL,
// SIG() and WAIT go through the devices' clock, the hand grasps and releases parts. Lazy: the
// devices are advanced to the arm's clock whenever the program looks at or changes them, which
// is exact because they are functions of time and of the signals the program set before.
#include "evaluator.hpp"

#include "errors.hpp"

#include "asimov/robots/robot.hpp"

#include <fmt/format.h>

namespace asimov::interpreter {

motion::CellRuntime* Evaluator::cell_runtime() {
  motion::CellRuntime* c = sim_.cell_runtime();
  if (!c) return nullptr;
  try {
    c->clock().advance_to(sim_.time_s());
  } catch (const motion::DeviceError& e) {
    raise_text("*Device logic loop*", e.what());
  }
  return c;
}

void Evaluator::set_signal(int k) {
  if (k > 0) memory_.signals.insert(k);
  if (k < 0) memory_.signals.erase(-k);
  if (auto* c = cell_runtime(); c && k != 0) {
    try {
      c->clock().set_signal(std::abs(k), k > 0, current_line_);
    } catch (const motion::DeviceError& e) {
      raise_text("*Device logic loop*", e.what());
    }
  }
}

bool Evaluator::signal_on(int k) {
  waited_.insert(k);
  return signal_state(k);
}

bool Evaluator::signal_state(int k) {
  if (auto* c = cell_runtime()) {
    // Inputs and device-set soft signals come from the devices; the program's own from memory.
    if (c->clock().signal(k)) return true;
    if (sim_.cell().workcell.drives(k)) return false;
  }
  return memory_.signals.count(k) > 0;
}

std::string Evaluator::undriven_signals() const {
  std::string list;
  for (int k : waited_)
    if (!sim_.cell().workcell.drives(k) && (motion::is_input_signal(k) || motion::is_soft_signal(k)))
      list += (list.empty() ? "" : ", ") + std::to_string(k);
  return list.empty() ? "" : fmt::format("; no device in the cell drives signal {}", list);
}

void Evaluator::hand_changed(motion::HandState h, int line) {
  auto* c = cell_runtime();
  if (!c) return;
  const motion::Location flange = sim_.cell().base * robots::flange_pose(sim_.robot(), sim_.joints());
  if (h == motion::HandState::closed) {
    if (!c->close(flange, line) && c->close_on_air_error())
      raise_text("*Nothing in the gripper*", "CLOSE found no part in the grasp zone");
    return;
  }
  if (const auto why = c->open(flange, line)) raise_text("*No support below the part*", *why);
}

std::optional<std::string> Evaluator::monitor_signal(int k) {
  if (k > 0) memory_.signals.insert(k);
  if (k < 0) memory_.signals.erase(-k);
  motion::CellRuntime* c = sim_.cell_runtime();
  if (!c || k == 0) return std::nullopt;
  try {
    c->clock().advance_to(sim_.time_s());
    c->clock().set_signal(std::abs(k), k > 0, 0);
  } catch (const motion::DeviceError& e) {
    return std::string(e.what());
  }
  return std::nullopt;
}

}  // namespace asimov::interpreter

namespace asimov::interpreter {

const motion::CellRuntime* Evaluator::cell_state() {
  motion::CellRuntime* c = sim_.cell_runtime();
  if (!c) return nullptr;
  try {
    c->clock().advance_to(sim_.time_s());
  } catch (const motion::DeviceError&) {
    // the run already stopped on it (*Device logic loop*); the state is the one before
  }
  return c;
}

}  // namespace asimov::interpreter
