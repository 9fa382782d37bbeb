// Stage 3, the signals and the reacting cell (cell_signals.hpp).
#include "cell_signals.hpp"

#include "errors.hpp"
#include "evaluator.hpp"

#include "asimov/robots/robot.hpp"

#include <fmt/format.h>

#include <cstdlib>

namespace asimov::interpreter {

motion::CellRuntime* CellSignals::runtime() {
  motion::CellRuntime* c = sim_.cell_runtime();
  if (!c) return nullptr;
  try {
    c->clock().advance_to(sim_.time_s());
  } catch (const motion::DeviceError& e) {
    raise_text("*Device logic loop*", e.what());
  }
  return c;
}

const motion::CellRuntime* CellSignals::state() {
  motion::CellRuntime* c = sim_.cell_runtime();
  if (!c) return nullptr;
  try {
    c->clock().advance_to(sim_.time_s());
  } catch (const motion::DeviceError&) {
    // the run already stopped on it (*Device logic loop*); the state is the one before
  }
  return c;
}

void CellSignals::set_signal(int k, int line) {
  if (k > 0) memory_.signals.insert(k);
  if (k < 0) memory_.signals.erase(-k);
  if (auto* c = runtime(); c && k != 0) {
    try {
      c->clock().set_signal(std::abs(k), k > 0, line);
    } catch (const motion::DeviceError& e) {
      raise_text("*Device logic loop*", e.what());
    }
  }
}

bool CellSignals::signal_on(int k) {
  waited_.insert(k);
  return signal_state(k);
}

bool CellSignals::signal_state(int k) {
  if (auto* c = runtime()) {
    // Inputs and device-set soft signals come from the devices; the program's own from memory.
    if (c->clock().signal(k)) return true;
    if (sim_.cell().workcell.drives(k)) return false;
  }
  return memory_.signals.count(k) > 0;
}

bool CellSignals::signal_at(int k, double t) {
  if (motion::CellRuntime* c = sim_.cell_runtime()) {
    c->clock().advance_to(t);  // a device logic loop: the walk reports it (*Device logic loop*)
    if (c->clock().signal(k)) return true;
    if (sim_.cell().workcell.drives(k)) return false;
  }
  return memory_.signals.count(k) > 0;
}

std::string CellSignals::undriven_signals() const {
  std::string list;
  for (int k : waited_)
    if (!sim_.cell().workcell.drives(k) && (motion::is_input_signal(k) || motion::is_soft_signal(k)))
      list += (list.empty() ? "" : ", ") + std::to_string(k);
  return list.empty() ? "" : fmt::format("; no device in the cell drives signal {}", list);
}

void CellSignals::hand_changed(motion::HandState h, int line) {
  auto* c = runtime();
  if (!c) return;
  const motion::Location flange = sim_.cell().base * robots::flange_pose(sim_.robot(), sim_.joints());
  if (h == motion::HandState::closed) {
    if (!c->close(flange, line) && c->close_on_air_error())
      raise_text("*Nothing in the gripper*", "CLOSE found no part in the grasp zone");
    return;
  }
  if (const auto why = c->open(flange, line)) raise_text("*No support below the part*", *why);
}

std::optional<std::string> CellSignals::monitor_signal(int k) {
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
