// Asynchronous reactions and error traps (docs/val2-dialect.md §7c; V+ Language User's Guide,
// "Asynchronous Processing", "Error Trapping"): REACT, REACTI, REACTE, IGNORE, LOCK and what
// the evaluator does between steps. The table and its rules are reactions.cpp's.
#include "evaluator.hpp"

#include "errors.hpp"

#include <fmt/format.h>

#include <cmath>
#include <cstdlib>

namespace asimov::interpreter {

namespace {

// A priority argument: a whole number in [lo, hi].
int priority_value(double x, int lo, int hi, const char* what) {
  if (!(x >= lo && x <= hi) || x != std::floor(x))
    raise(Message::illegal_value, fmt::format("{} priority {} (allowed: {} to {})", what, format_number(x), lo, hi));
  return static_cast<int>(x);
}

}  // namespace

void Evaluator::reaction_instruction(const Instr& in) {
  Reactions& table = reactions();
  auto program_exists = [&](int slot) {
    if (slot >= 0 && !memory_.programs[static_cast<std::size_t>(slot)])
      raise(Message::undefined_name, memory_.symbols.programs[static_cast<std::size_t>(slot)]);
  };
  switch (in.code) {
    case Code::react: {  // REACT / REACTI signal, program, priority
      const char* what = in.word == ast::Kw::reacti ? "REACTI" : "REACT";
      const int s = signal_number(in.args[0], false);
      if (std::abs(s) <= 512)  // outputs are set by the program itself; V+ watches inputs and soft signals
        raise(Message::illegal_value, fmt::format("{} watches inputs and soft signals, not output {}", what, s));
      program_exists(in.program);
      Reaction r;
      r.signal = std::abs(s);
      r.falling = s < 0;
      r.program = in.program;
      r.priority = in.args[1].kind == NodeKind::absent
          ? 1 : priority_value(to_real(eval(in.args[1]), "priority"), 1, Reactions::kMaxPriority, what);
      r.stops_arm = in.word == ast::Kw::reacti;
      r.was_on = signal_state(r.signal);  // a transition from now on triggers it
      table.arm(r);
      return;
    }
    case Code::reacte:  // REACTE [program]: the error trap, or none
      program_exists(in.program);
      table.trap = in.program;
      return;
    case Code::ignore:
      table.ignore(std::abs(signal_number(in.args[0], false)));
      return;
    case Code::lock:
      table.set_priority(priority_value(to_real(eval(in.args[0]), "LOCK priority"), 0, Reactions::kMaxPriority, "LOCK"));
      return;
    default: return;
  }
}

// Called as a subroutine without arguments, at `priority`; its RETURN restores the priority now.
void Evaluator::push_reaction_frame(int program, int priority, bool trap) {
  Reactions& table = reactions();
  Instr call_in;
  call_in.code = Code::call;
  call_in.program = program;
  call(call_in);
  Frame& f = stack_.back();
  f.restore_priority = table.priority();
  f.trap = trap;
  table.set_priority(priority);
  if (trap) table.trapping = true;
}

// Between steps of the running task: its watched signals are looked at; a REACTI transition
// stops the motion under way (the robot task's), then the reaction due, if any, is called.
RunStatus Evaluator::react(bool& pushed) {
  Reactions& table = reactions();
  const int stop = table.see([this](int k) { return signal_state(k); });
  if (stop != 0 && robot_task() && sim_.motion_pending()) {
    brake_signal_ = stop;  // the stop condition answers true at the motion's next checked pose
    try {
      if (const RunStatus s = finish_motion(); s != RunStatus::completed) return s;
    } catch (const Braked&) {  // the step about to run is the next one: nothing runs again
    }
    brake_signal_ = 0;
  }
  const std::optional<Reaction> due = table.take_due();
  if (!due) return RunStatus::completed;
  push_reaction_frame(due->program, due->priority, false);
  pushed = true;
  return RunStatus::completed;
}

// The reactions of the task that moves the arm (null: none, or it has none).
Reactions* Evaluator::robot_reactions() {
  if (tasks_.empty()) return robot_task_ == 0 ? &reactions0_ : nullptr;
  for (const auto& t : tasks_)
    if (t->number == robot_task_ && !t->done) return &t->reactions;
  return nullptr;
}

// The simulator's stop condition, asked at each checked pose of a motion (time t): true when a
// REACTI of the robot task sees its transition by then (the devices' signals at t), or one
// was seen between steps.
bool Evaluator::brake_now(double t) {
  if (brake_signal_ != 0) return true;
  Reactions* table = robot_reactions();
  if (!table || table->empty()) return false;
  brake_signal_ = table->see([&](int k) { return signal_at(k, t); });
  return brake_signal_ != 0;
}

bool Evaluator::signal_at(int k, double t) {
  if (motion::CellRuntime* c = sim_.cell_runtime()) {
    c->clock().advance_to(t);  // a device logic loop: the walk reports it (*Device logic loop*)
    if (c->clock().signal(k)) return true;
    if (sim_.cell().workcell.drives(k)) return false;
  }
  return memory_.signals.count(k) > 0;
}

// A REACTI stopped the motion at `at`: the rest is dropped (V+ does not resume it; the next
// motion starts from here), the stop goes in the report.
void Evaluator::braked(const motion::InterruptReport& at) {
  sim_.drop_halted_motion();
  reaction_stops_.push_back({brake_signal_, robot_task_, at});
  brake_signal_ = 0;
  moving_until_ = sim_.time_s();
}

// REACTE: an error that would stop the running task calls its trap program instead (at
// priority 254, no other reaction interrupts it); the trap's RETURN goes on after the step
// that failed. An error inside the trap program stops the task as without a trap.
bool Evaluator::trap_error() {
  Reactions& table = reactions();
  if (table.trap < 0 || table.trapping || !memory_.programs[static_cast<std::size_t>(table.trap)]) return false;
  memory_.last_error = error_code(fault_.message);  // ERROR() and $ERROR() in the trap program
  push_reaction_frame(table.trap, Reactions::kTrapPriority, true);
  return true;
}

}  // namespace asimov::interpreter
