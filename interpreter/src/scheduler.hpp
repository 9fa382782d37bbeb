// Stage 3, the task scheduler (dialect §7b, §7c): the tasks EXECUTE starts, each with its call
// stack, LOCAL variables, reactions and priority; WAIT; and the point between two statements
// where a reaction (REACT / REACTI) or a debugger stop (the step hook) takes over. The
// statement VM (evaluator.hpp) runs the stack of the task the scheduler picks.
#pragma once
#include "cell_signals.hpp"
#include "code.hpp"
#include "errors.hpp"
#include "frames.hpp"
#include "limits.hpp"
#include "reactions.hpp"
#include "asimov/interpreter/interpreter.hpp"
#include "asimov/interpreter/step_hook.hpp"

#include <cstdint>
#include <deque>
#include <memory>
#include <string>
#include <vector>

namespace asimov::interpreter {

class Evaluator;
class ArmController;
struct Memory;

// A task of dialect §7b: its own call stack and LOCAL variables, and when it may run again.
struct Task {
  int number = 0;
  FrameStack stack;                 // while it does not run (the running task's is the VM's)
  std::string program;              // the program it was started with
  double wake_s = 0;                // it may run again from this simulated time on
  double wait_since = -1;           // WAIT with a condition: when the wait began; < 0: none
  bool done = false;
  bool aborted = false;             // ended by ABORT / KILL
  const Program* at_program = nullptr;  // where it stopped or gave way
  int at_line = 0;
  std::vector<Variable*> globals;   // the VM's globals with this task's LOCAL slots redirected
  std::deque<Variable> locals;      // its LOCAL variables (every task but the first)
  Reactions reactions;              // its REACT / REACTI / REACTE, its priority (dialect §7c)
};

// The statements an execution has run, and the count at which its task gives way (its time
// slice) or, at Limits::max_statements, the run stops.
struct StepBudget {
  std::uint64_t done = 0;
  std::uint64_t until = 0;
};

class Scheduler {
 public:
  Scheduler(Evaluator& vm, ArmController& arm, CellSignals& cell, motion::Simulator& sim, Memory& memory,
            const Limits& limits)
      : vm_(vm), arm_(arm), cell_(cell), sim_(sim), memory_(memory), limits_(limits) {}

  // --- an execution ---
  void begin_execution();             // a new run: no reactions, no priority, no trap, no WAIT loop
  void begin_run();                   // a run or resumption: no task but 0, the robot attached to it
  // The tasks' reports and the REACTI stops into the result; `program` / `line`: where the
  // running task is.
  void end_run(RunResult& r, const Program* program, int line);
  void drop_tasks();                  // the tasks of a run end with it (a stop resumes task 0 only)
  RunStatus run_tasks();              // runs the VM's stack, and every task EXECUTE starts, to their end
  StepBudget& budget() { return budget_; }

  // --- tasks (dialect §7b) ---
  bool has_tasks() const { return !tasks_.empty(); }
  bool tasks_running() const { return running_ != nullptr; }  // EXECUTE made task 0 a Task
  double now() const { return now_; }  // the scheduler's simulated clock (tasks only)
  double clock() const { return running_ ? now_ : sim_.time_s(); }  // the simulated clock (TIMER)
  int task_number() const { return running_ ? running_->number : 0; }
  bool robot_task() const { return task_number() == robot_task_; }
  void require_robot() const;         // only the robot task moves the arm, sets TOOL and BASE
  double task_state(int number) const;  // TASK(1, n): 4 while task n executes, else 0
  bool executing(const std::string& program, const std::string& run_program) const;  // STATUS()
  void execute_task(const Instr& in);  // EXECUTE
  void task_instruction(const Instr& in);  // ABORT, KILL, CYCLE.END, RELEASE
  void robot_attach(bool attach);     // robot ATTACH () / DETACH ()
  RunStatus wait(const Instr& in);    // WAIT, WAIT.EVENT
  // After a statement of the running task: true when it gave way (the robot task's statement
  // carried the arm ahead in time, a WAIT, ...).
  bool gives_way();
  void slice_used() {                 // the running task's time slice is used up
    --budget_.done;
    block_until(now_ + kSliceS);
  }

  // --- between statements: reactions (dialect §7c) and the debugger (between_steps.cpp) ---
  Reactions& reactions() { return running_ ? running_->reactions : reactions0_; }
  void reaction_instruction(const Instr& in);  // REACT, REACTI, REACTE, IGNORE, LOCK
  // Sees the running task's signals, stops the arm for a REACTI, and calls the reaction due,
  // if any (`pushed`: a frame was pushed).
  RunStatus react(bool& pushed);
  bool brake_now(double t);             // the simulator's stop condition: a REACTI transition by t
  void braked(const motion::InterruptReport& at);  // a REACTI stopped the motion there
  bool trap_error(const Fault& f);      // REACTE: the trap program called instead of stopping
  void set_step_hook(StepHook hook) { step_hook_ = std::move(hook); }
  bool hooked() const { return static_cast<bool>(step_hook_); }
  // The step hook before `in` (frame `f`, pc at `in`): RunStatus::paused when it asks for a
  // pause (the motions started before it carried out first), else completed (between_steps.cpp).
  RunStatus at_step(const Instr& in, Frame& f);

 private:
  Task* next_task() const;
  RunStatus advance_clock(double t);
  void switch_to(Task* t);
  void block_until(double t);         // the running task gives way until `t`
  RunStatus task_wait(const Instr& in);
  void push_reaction_frame(int program, int priority, bool trap);
  Reactions* robot_reactions();

  Evaluator& vm_;
  ArmController& arm_;
  CellSignals& cell_;
  motion::Simulator& sim_;
  Memory& memory_;
  const Limits& limits_;
  std::vector<std::unique_ptr<Task>> tasks_;  // by number; empty: task 0 alone (no EXECUTE yet)
  Task* running_ = nullptr;                   // the task in the VM's stack (null: task 0 alone)
  bool yield_ = false;                        // the running task gave way (WAIT, motion, RELEASE ...)
  double now_ = 0;                            // the scheduler's simulated clock (tasks only)
  double bare_wait_start_ = 0, bare_wait_end_ = -1;  // a run of bare WAITs: its start, the last one's end
  int robot_task_ = 0;                        // the task that moves the arm; -1: DETACHed
  StepBudget budget_;
  StepHook step_hook_;                        // the debugger's (unset: not called)
  Reactions reactions0_;                      // task 0's until EXECUTE makes it a Task
  int brake_signal_ = 0;                      // a REACTI seen between steps: stop the pending motion
  std::vector<ReactionStop> reaction_stops_;  // RunResult::reaction_stops
};

}  // namespace asimov::interpreter
