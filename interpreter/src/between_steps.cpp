// Stage 3, between two statements (scheduler.hpp): asynchronous reactions and error traps
// (docs/val2-dialect.md §7c; V+ Language User's Guide, "Asynchronous Processing", "Error
// Trapping": REACT, REACTI, REACTE, IGNORE, LOCK) and the debugger's step hook (step_hook.hpp).
// The table of reactions and its rules are reactions.cpp's.
#include "scheduler.hpp"

#include "arm_controller.hpp"
#include "evaluator.hpp"
#include "operators.hpp"

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

void Scheduler::reaction_instruction(const Instr& in) {
  Reactions& table = reactions();
  auto program_exists = [&](int slot) {
    if (slot >= 0 && !memory_.programs[static_cast<std::size_t>(slot)])
      raise(Message::undefined_name, memory_.symbols.programs[static_cast<std::size_t>(slot)]);
  };
  switch (in.code) {
    case Code::react: {  // REACT / REACTI signal, program, priority
      const char* what = in.word == ast::Kw::reacti ? "REACTI" : "REACT";
      const int s = vm_.signal_number(in.args[0], false);
      if (std::abs(s) <= 512)  // outputs are set by the program itself; V+ watches inputs and soft signals
        raise(Message::illegal_value, fmt::format("{} watches inputs and soft signals, not output {}", what, s));
      program_exists(in.program);
      Reaction r;
      r.signal = std::abs(s);
      r.falling = s < 0;
      r.program = in.program;
      r.priority = in.args[1].kind == NodeKind::absent
          ? 1 : priority_value(to_real(vm_.eval(in.args[1]), "priority"), 1, Reactions::kMaxPriority, what);
      r.stops_arm = in.word == ast::Kw::reacti;
      r.was_on = cell_.signal_state(r.signal);  // a transition from now on triggers it
      table.arm(r);
      return;
    }
    case Code::reacte:  // REACTE [program]: the error trap, or none
      program_exists(in.program);
      table.trap = in.program;
      return;
    case Code::ignore:
      table.ignore(std::abs(vm_.signal_number(in.args[0], false)));
      return;
    case Code::lock:
      table.set_priority(priority_value(to_real(vm_.eval(in.args[0]), "LOCK priority"), 0, Reactions::kMaxPriority, "LOCK"));
      return;
    default: return;
  }
}

// Called as a subroutine without arguments, at `priority`; its RETURN restores the priority now.
void Scheduler::push_reaction_frame(int program, int priority, bool trap) {
  Reactions& table = reactions();
  Instr call_in;
  call_in.code = Code::call;
  call_in.program = program;
  vm_.call(call_in);
  Frame& f = vm_.stack().back();
  f.restore_priority = table.priority();
  f.trap = trap;
  table.set_priority(priority);
  if (trap) table.trapping = true;
}

// Between steps of the running task: its watched signals are looked at; a REACTI transition
// stops the motion under way (the robot task's), then the reaction due, if any, is called.
RunStatus Scheduler::react(bool& pushed) {
  Reactions& table = reactions();
  const int stop = table.see([this](int k) { return cell_.signal_state(k); });
  if (stop != 0 && robot_task() && sim_.motion_pending()) {
    brake_signal_ = stop;  // the stop condition answers true at the motion's next checked pose
    try {
      if (const RunStatus s = arm_.finish_motion(); s != RunStatus::completed) return s;
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
Reactions* Scheduler::robot_reactions() {
  if (tasks_.empty()) return robot_task_ == 0 ? &reactions0_ : nullptr;
  for (const auto& t : tasks_)
    if (t->number == robot_task_ && !t->done) return &t->reactions;
  return nullptr;
}

// The simulator's stop condition, asked at each checked pose of a motion (time t): true when a
// REACTI of the robot task sees its transition by then (the devices' signals at t), or one
// was seen between steps.
bool Scheduler::brake_now(double t) {
  if (brake_signal_ != 0) return true;
  Reactions* table = robot_reactions();
  if (!table || table->empty()) return false;
  brake_signal_ = table->see([&](int k) { return cell_.signal_at(k, t); });
  return brake_signal_ != 0;
}

// A REACTI stopped the motion at `at`: the rest is dropped (V+ does not resume it; the next
// motion starts from here), the stop goes in the report.
void Scheduler::braked(const motion::InterruptReport& at) {
  reaction_stops_.push_back({brake_signal_, robot_task_, at});
  brake_signal_ = 0;
  arm_.braked();
}

// REACTE: an error that would stop the running task calls its trap program instead (at
// priority 254, no other reaction interrupts it); the trap's RETURN goes on after the step
// that failed. An error inside the trap program stops the task as without a trap.
bool Scheduler::trap_error(const Fault& f) {
  Reactions& table = reactions();
  if (table.trap < 0 || table.trapping || !memory_.programs[static_cast<std::size_t>(table.trap)]) return false;
  memory_.last_error = error_code(f.message);  // ERROR() and $ERROR() in the trap program
  push_reaction_frame(table.trap, Reactions::kTrapPriority, true);
  return true;
}

// The debugger's view of a run between two instructions.
RunStatus Scheduler::at_step(const Instr& in, Frame& f) {
  const Program& p = *f.program;
  const StepEvent e{p.name, in.line - p.line, in.line, static_cast<std::size_t>(f.pc),
                    static_cast<int>(vm_.stack().size()), task_number(), running_ == nullptr};
  if (step_hook_(e) != StepAction::pause || running_) return RunStatus::completed;
  // The motions already started end first, so that a paused run shows the arm where its steps
  // so far put it. The pc is past `in` meanwhile, as when a statement waits for a motion: a
  // contact or Ctrl-C then leaves the stop located and resumable as for that statement (the
  // instruction runs again); a clean end puts it back, so PROCEED runs `in` next.
  ++f.pc;
  if (const RunStatus s = arm_.finish_motion(); s != RunStatus::completed) return s;
  --f.pc;
  vm_.locate(&p, in.line);
  return RunStatus::paused;
}

}  // namespace asimov::interpreter
