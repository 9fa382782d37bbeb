// Stage 3, the arm: speeds and durations, the hand, motion requests to the simulator, the
// checks of a finished motion and the resume of a halted one. The statement VM (evaluator.hpp)
// hands it the motion, hand and arm-setting statements and what their expressions evaluate to.
#pragma once
#include "cell_signals.hpp"
#include "code.hpp"
#include "errors.hpp"
#include "asimov/interpreter/interpreter.hpp"

#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

namespace asimov::interpreter {

class Evaluator;
struct Memory;

// A resolved motion, kept so that RETRY can restart it after a collision.
struct MotionRequest {
  std::optional<robots::JointVector> joints;  // joint target, or else `pose`
  motion::Location pose = motion::Location::Identity();
  bool straight = false;
  motion::SpeedSettings speed;
  const Program* program = nullptr;           // the motion instruction
  int line = 0;
};

// The program's speed and duration settings, as an execution leaves them (kept by a stop).
struct ArmSettings {
  double speed_always = 100;                  // SPEED ... ALWAYS; each execution starts at 100
  std::optional<double> speed_next;           // SPEED for the next motion only
  double duration_always = 0;                 // DURATION ... ALWAYS [s]; 0 = off
  std::optional<double> duration_next;        // DURATION for the next motion only
};

// A REACTI stopped the motion that the step in progress waited for (check_motion): the step
// runs again once the reaction is served (Evaluator::loop).
struct Braked {};

class ArmController {
 public:
  ArmController(motion::Simulator& sim, Memory& memory, CellSignals& cell, Evaluator& vm)
      : sim_(sim), memory_(memory), cell_(cell), vm_(vm) {}

  // --- an execution ---
  void begin_run();                           // SPEED 100 ALWAYS, no DURATION, no motion yet
  // A resumed execution: its settings and last motion as it stopped.
  void begin_resume(const ArmSettings& settings, std::optional<MotionRequest> motion);
  void begin_records();                       // this run's motion sites, times, halt: none yet
  void end_records(RunResult& r);             // ... into the result
  const ArmSettings& settings() const { return settings_; }
  const std::optional<MotionRequest>& last_motion() const { return last_motion_; }
  const std::optional<motion::InterruptReport>& halted() const { return halt_; }
  void set_halted(const motion::InterruptReport& at) { halt_ = at; }
  const motion::CollisionReport& contact() const { return contact_; }
  // Where the motion that is reported (contact, motion error, halt) was started.
  const Program* motion_program() const { return motion_program_; }
  int motion_line() const { return motion_line_; }

  // --- speeds (dialect §5) ---
  double monitor_speed() const { return speed_monitor_; }
  void set_monitor_speed(double percent) { speed_monitor_ = percent; }
  double speed_factor(int select) const;      // SPEED(select)
  double state(int select) const;             // STATE(select)

  // --- statements ---
  RunStatus motion(const Instr& in);          // MOVE, APPRO, DRIVE, ... (instructions.def)
  RunStatus hand(const Instr& in);            // OPEN, CLOSE, RELAX and their immediate forms
  void setting(const Instr& in);              // SPEED, DURATION, ACCEL, TOOL, BASE, RIGHTY ...
  RunStatus finish_motion();                  // BREAK: the pending motion carried out
  RunStatus start_motion(const MotionRequest& m);  // also RETRY's restart of a collided one
  RunStatus resume_halted_motion();           // PROCEED / RETRY after Ctrl-C halted a motion
  // A failed finish: collision, error, Ctrl-C; a REACTI's stop throws Braked.
  RunStatus check_motion(const motion::MotionResult& r);
  // Time passing at the statement of `line` (WAIT, hand times): a contact then is reported there.
  RunStatus check_dwell(const motion::MotionResult& r, int line);
  void braked();                              // a REACTI stopped the motion: the rest is dropped

  // --- what the other parts see of the arm ---
  // A motion under way: pending, or (with tasks) carried out ahead and not ended at the clock.
  bool moving() const;
  robots::JointVector planned_destination() const;  // #PDEST

 private:
  void record_timing(const motion::MotionTiming& t, const std::string& program);  // RunResult::motion_times

  motion::Simulator& sim_;
  Memory& memory_;                            // ACCEL, HAND.TIME
  CellSignals& cell_;                         // the hand grasps and releases parts
  Evaluator& vm_;                             // expressions, the stack top, stop(), the scheduler
  ArmSettings settings_;
  double speed_monitor_ = 100;
  const Program* motion_program_ = nullptr;   // where the last motion was started
  int motion_line_ = 0;
  std::optional<MotionRequest> last_motion_;  // the last motion started
  std::optional<motion::InterruptReport> halt_;  // this run's motion halted by Ctrl-C
  motion::CollisionReport contact_;           // what ended the run (status collision)
  std::vector<std::pair<const Program*, int>> motion_sites_;  // this execution's motions (RunResult::motions)
  std::vector<MotionTime> motion_times_;                      // RunResult::motion_times
  std::uint64_t motion_times_omitted_ = 0;
  double moving_until_ = 0;                   // the arm's last motion, carried out, ends here
  // The joints the motion before the pending one ends at (where the pending one starts from):
  // with tasks, what #PDEST is for a task running before the pending motion's start.
  robots::JointVector earlier_destination_;
  double earlier_until_ = 0;                  // the pending motion's start
};

}  // namespace asimov::interpreter
