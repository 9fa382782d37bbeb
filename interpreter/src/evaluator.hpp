// Stage 3: runs compiled programs against the simulator. Holds the run-time state (call
// stack, speeds); the memory (symbols, globals, programs) belongs to the interpreter.
#pragma once
#include "checker.hpp"
#include "code.hpp"
#include "files.hpp"
#include "errors.hpp"
#include "asimov/interpreter/interpreter.hpp"
#include "asimov/interpreter/step_hook.hpp"
#include "reactions.hpp"
#include "settings.hpp"
#include "asimov/interpreter/values.hpp"
#include <array>
#include <deque>
#include <functional>
#include <iterator>
#include <string>
#include <set>
#include <utility>
#include <iosfwd>
#include <memory>
#include <optional>
#include <vector>

namespace asimov::interpreter {

// Everything LOAD puts in memory, indexed by the slots the checker resolved.
struct Memory {
  Symbols symbols;
  std::deque<Variable> globals;                            // by global slot
  std::vector<std::shared_ptr<const Program>> programs;    // by program slot; null if absent
  std::vector<std::string> load_order;                     // program names as first loaded
  std::set<int> signals;                                   // digital signals that are on
  std::array<std::pair<double, double>, 17> timers{};      // TIMER n: value set, clock then [s]
  Settings settings;                                       // PARAMETER, ENABLE / DISABLE
  int last_error = 0;                                      // ERROR(): code of the last run-time error
};

class Evaluator {
 public:
  Evaluator(motion::Simulator& sim, std::ostream& out, Memory& memory, const Limits& limits);
  // Runs the program in `slot` to its end. A stopped execution kept from earlier survives.
  // `resumable` false (a monitor DO): this run's own stop is not kept either.
  RunResult run(int slot, bool resumable = true);
  // The execution the last error or collision stopped (dialect §9 PROCEED / RETRY).
  bool can_resume() const;
  RunResult resume(bool retry);
  void abort();

  // Speeds for the monitor's SPEED and STATUS (dialect §5): the monitor speed, and the
  // ALWAYS and one-shot program speeds as the last execution left them.
  double monitor_speed() const { return speed_monitor_; }
  void set_monitor_speed(double percent) { speed_monitor_ = percent; }
  double program_speed() const { return speed_always_; }
  std::optional<double> next_speed() const { return speed_next_; }
  // Called before every instruction while set (step_hook.hpp; evaluator_step.cpp).
  void set_step_hook(StepHook hook) { step_hook_ = std::move(hook); }
  // PROMPT's input (null: std::cin).
  void set_input(std::istream* in, bool interactive) { in_ = in, interactive_ = interactive; }
  // The reacting cell's parts and devices, advanced to the arm's clock (evaluator_cell.cpp);
  // null for a cell without parts or devices.
  motion::CellRuntime* cell_runtime();
  // The same for reports, never raising (a logic loop leaves the state before it).
  const motion::CellRuntime* cell_state();
  // DO SIGNAL at the monitor: memory and devices; the message of a logic loop, if any.
  std::optional<std::string> monitor_signal(int k);

 private:
  struct Frame {
    const Program* program = nullptr;              // kept alive by memory_ or Stopped::pinned
    std::vector<Variable*> params;                 // by reference or into `owned`
    std::vector<Variable> owned;                   // by value, omitted, AUTO (reserved: stable)
    std::vector<double> temps;                     // FOR limits and steps
    int pc = 0;                                    // next instruction
    int restore_priority = -1;                     // a reaction's frame: the priority its RETURN restores
    bool trap = false;                             // the REACTE program's frame
  };

  // The call stack. Popped frames stay allocated and are reused by the next CALL, with their
  // vectors' capacity and their (emptied) variables: no construction, move or allocation per
  // CALL. back() is valid until the next next().
  class FrameStack {
   public:
    bool empty() const { return size_ == 0; }
    std::size_t size() const { return size_; }
    Frame& back() { return frames_[size_ - 1]; }
    // The frame above the top, cleared (its owned variables are emptied as they are taken),
    // filled by the caller, then pushed by commit().
    Frame& next() {
      if (size_ == frames_.size()) frames_.emplace_back();
      Frame& f = frames_[size_];
      f.program = nullptr;
      f.params.clear();
      f.temps.clear();
      f.pc = 0;
      f.restore_priority = -1;
      f.trap = false;
      return f;
    }
    void commit() { ++size_; }
    void pop() { --size_; }
    void clear() { size_ = 0; }
    std::vector<Frame> take() {  // the frames, for a stopped execution
      std::vector<Frame> out(std::make_move_iterator(frames_.begin()),
                             std::make_move_iterator(frames_.begin() + static_cast<std::ptrdiff_t>(size_)));
      frames_.clear();
      size_ = 0;
      return out;
    }
    void assign(std::vector<Frame> frames) {
      frames_ = std::move(frames);
      size_ = frames_.size();
    }

   private:
    std::vector<Frame> frames_;
    std::size_t size_ = 0;
  };

  // A resolved motion, kept so that RETRY can restart it after a collision.
  struct MotionRequest {
    std::optional<robots::JointVector> joints;  // joint target, or else `pose`
    motion::Location pose = motion::Location::Identity();
    bool straight = false;
    motion::SpeedSettings speed;
    const Program* program = nullptr;           // the motion instruction
    int line = 0;
  };
  // An execution stopped by an error or a collision, for PROCEED / RETRY.
  struct Stopped {
    std::vector<Frame> stack;
    RunStatus status = RunStatus::error;
    std::string program;                        // the program the run started with
    double speed_always = 100;
    std::optional<double> speed_next;
    std::optional<MotionRequest> motion;
    double duration_always = 0;
    std::optional<double> duration_next;
    bool motion_halted = false;                 // Ctrl-C halted `motion`: its rest runs first
    std::vector<std::shared_ptr<const Program>> pinned;  // the frames' programs, even if reloaded
  };

  // A task of dialect §7b: its own call stack and LOCAL variables, and when it may run again.
  struct Task {
    int number = 0;
    FrameStack stack;                 // while it does not run (the running task's is stack_)
    std::string program;              // the program it was started with
    double wake_s = 0;                // it may run again from this simulated time on
    double wait_since = -1;           // WAIT with a condition: when the wait began; < 0: none
    bool done = false;
    bool aborted = false;             // ended by ABORT / KILL
    const Program* at_program = nullptr;  // where it stopped or gave way
    int at_line = 0;
    std::vector<Variable*> globals;   // globals_ with this task's LOCAL slots redirected
    std::deque<Variable> locals;      // its LOCAL variables (every task but the first)
    Reactions reactions;              // its REACT / REACTI / REACTE, its priority (dialect §7c)
  };

  // The one protected boundary: runs `setup` then the loop and turns the status they return
  // (or a raised Fault) into the result.
  //
  // Status returns: the statements that can end a run return RunStatus::completed to go on, or
  // the status that ends it (collision: the report in contact_; error / interrupted: the
  // message in fault_, set by stop()).
  RunResult protected_run(const std::string& name, const std::function<RunStatus()>& setup);
  std::vector<std::shared_ptr<const Program>> pin_programs() const;  // Stopped::pinned of a new stop
  RunStatus start_motion(const MotionRequest& m);
  void record_timing(const motion::MotionTiming& t, const std::string& program);  // RunResult::motion_times
  RunStatus execute(const Instr& in);  // the statements that can end a run, else statement()
  void statement(const Instr& in);
  RunStatus loop();  // runs stack_ until it is empty, or until its task gives way
  // The step hook before `in` (frame `f`, pc at `in`): RunStatus::paused when it asks for a
  // pause (the motions started before it carried out first), else completed (evaluator_step.cpp).
  RunStatus at_step(const Instr& in, Frame& f);
  // --- tasks (dialect §7b) ---
  RunStatus run_tasks();              // runs stack_, and every task EXECUTE starts, to their end
  Task* next_task() const;
  RunStatus advance_clock(double t);
  void switch_to(Task* t);
  void block_until(double t);         // the running task gives way until `t`
  RunStatus task_wait(const Instr& in);
  void execute_task(const Instr& in);
  void task_instruction(const Instr& in);
  void robot_attach(bool attach);
  // --- reactions (evaluator_reactions.cpp, dialect §7c) ---
  Reactions& reactions() { return running_ ? running_->reactions : reactions0_; }
  void reaction_instruction(const Instr& in);  // REACT, REACTI, REACTE, IGNORE, LOCK
  // Between steps: sees the running task's signals, stops the arm for a REACTI, and calls the
  // reaction due, if any (`pushed`: a frame was pushed).
  RunStatus react(bool& pushed);
  Reactions* robot_reactions();
  bool brake_now(double t);             // the simulator's stop condition: a REACTI transition by t
  bool signal_at(int k, double t);      // signal k at time t of a motion being carried out
  void braked(const motion::InterruptReport& at);  // a REACTI stopped the motion there
  bool trap_error();                    // REACTE: the trap program called instead of stopping
  void push_reaction_frame(int program, int priority, bool trap);
  void require_robot() const;         // only the robot task moves the arm, sets TOOL and BASE
  int task_number() const { return running_ ? running_->number : 0; }
  bool robot_task() const { return task_number() == robot_task_; }
  void call(const Instr& in);
  void pop_frame();
  RunStatus motion(const Instr& in);
  RunStatus hand(const Instr& in);
  void type(const Instr& in);
  std::vector<Value> eval_all(const std::vector<Node>& nodes);
  RunStatus finish_motion();
  RunStatus check_motion(const motion::MotionResult& r);  // a failed finish: collision, error, Ctrl-C
  // Time passing at the statement of `line` (WAIT, hand times): a contact then is reported there.
  RunStatus check_dwell(const motion::MotionResult& r, int line);
  int step_of(int line) const { return current_program_ ? line - current_program_->line : 0; }
  RunStatus resume_halted_motion();  // PROCEED / RETRY after Ctrl-C halted a motion
  RunStatus stop(Fault f);  // keeps `f` for the report: RunStatus::error, or interrupted
  RunStatus wait(const Instr& in);
  void prompt(const Instr& in);
  void settings(const Instr& in);
  void warn_once(const std::string& keyword, const Instr& in);
  void io(const Instr& in);  // dialect §7a
  int unit_number(const Instr& in);

  motion::Location as_transformation(const Value& v);
  Value eval(const Node& n);
  Value function(const Node& n);
  double state(int select) const;  // STATE(select)
  // A motion under way: pending, or (with tasks) carried out ahead and not ended at the clock.
  bool moving() const { return sim_.motion_pending() || (running_ && now_ < moving_until_); }
  double clock() const { return running_ ? now_ : sim_.time_s(); }  // the simulated clock (TIMER)
  robots::JointVector planned_destination() const;  // #PDEST
  double speed_factor(int select) const;              // SPEED(select)
  int signal_number(const Node& n, bool output);
  Variable& variable(const Node& n) {
    if (n.ref.scope == Scope::global) return *ctx_.globals[n.ref.slot];
    return *stack_.back().params[static_cast<std::size_t>(n.ref.slot)];
  }
  Index index(const Node& n);
  Value read(const Node& n);
  const Value& lookup(const Node& n);
  void store(const Node& target, Value value);
  // The real fast path over Node::plain trees (no Value built): false, with nothing raised,
  // when a variable holds another kind; the generic path then evaluates (plain trees only read).
  bool try_real(const Node& n, double& out);
  // The compiled form (Node::fast) when there is one and it handles the values met.
  bool run_root(const RNode* r, double& out) {
    try {
      out = r->fn(*r, ctx_);
      return true;
    } catch (const Fallback&) {
      return false;
    }
  }
  bool run_fast(const Node& n, double& out) {
    if (!n.fast) return false;
    try {
      out = n.fast->run(ctx_);
      return true;
    } catch (const Fallback&) {
      return false;
    }
  }
  double real(const Node& n, const char* what);
  // The reacting cell (evaluator_cell.cpp).
  void set_signal(int k);                       // SIGNAL k (negative: off)
  bool signal_on(int k);                        // SIG(k), remembered for WAIT's message
  bool signal_state(int k);                     // the same, not remembered (reactions)
  void hand_changed(motion::HandState h, int line);  // grasp / release at the flange now
  std::string undriven_signals() const;         // WAIT: the waited inputs no device drives
  void store_real(const Node& target, double x);
  bool store_in_place(const Node& target, double x);
  bool defined(const Node& n);

  motion::Simulator& sim_;
  std::ostream& out_;
  Memory& memory_;
  const Limits& limits_;
  FrameStack stack_;
  const Program* current_program_ = nullptr;  // where the executing statement is
  int current_line_ = 0;
  std::string run_program_;                   // the program this execution started with
  const Program* motion_program_ = nullptr;   // where the last motion was started
  int motion_line_ = 0;
  double speed_always_ = 100;                 // SPEED ... ALWAYS
  std::optional<double> speed_next_;          // SPEED for the next motion only
  double speed_monitor_ = 100;
  double duration_always_ = 0;                // DURATION ... ALWAYS [s]; 0 = off
  std::optional<double> duration_next_;       // DURATION for the next motion only
  std::istream* in_ = nullptr;                // PROMPT input (null: std::cin)
  bool interactive_ = false;                  // PROMPT asks again on bad input
  std::vector<Diagnostic> warnings_;          // this execution's §7 warnings
  std::vector<std::pair<const Program*, int>> motion_sites_;  // this execution's motions (RunResult::motions)
  std::vector<MotionTime> motion_times_;                      // RunResult::motion_times
  std::uint64_t motion_times_omitted_ = 0;
  std::optional<MotionRequest> last_motion_;  // the last motion started
  std::optional<Stopped> stopped_;            // what PROCEED / RETRY continue
  // While a stopped execution runs again: its pins. A program it runs that memory_ no longer
  // holds (the monitor's temporary program of `DEBUG name(args)`, a reloaded one) stays pinned
  // when it stops again (pin_programs), however often it is stepped.
  std::vector<std::shared_ptr<const Program>> resumed_pins_;
  std::optional<motion::InterruptReport> halt_;  // this run's motion halted by Ctrl-C
  Fault fault_;                               // what ended the run (status error / interrupted)
  motion::CollisionReport contact_;           // what ended the run (status collision)
  std::vector<Variable*> globals_;            // &memory_.globals[slot], set when a run starts
  FastCtx ctx_;                               // globals_ and the running frame's slots
  FileUnits files_;                           // logical units; all closed at the end of a run
  std::vector<std::unique_ptr<Task>> tasks_;  // by number; empty: task 0 alone (no EXECUTE yet)
  Task* running_ = nullptr;                   // the task in stack_ (null: task 0 alone)
  bool yield_ = false;                        // the running task gave way (WAIT, motion, RELEASE ...)
  double now_ = 0;                            // the scheduler's simulated clock (tasks only)
  double moving_until_ = 0;                   // the arm's last motion, carried out, ends here
  double bare_wait_start_ = 0, bare_wait_end_ = -1;  // a run of bare WAITs: its start, the last one's end
  // The joints the motion before the pending one ends at (where the pending one starts from):
  // with tasks, what #PDEST is for a task running before the pending motion's start.
  robots::JointVector earlier_destination_;
  double earlier_until_ = 0;                  // the pending motion's start
  int robot_task_ = 0;                        // the task that moves the arm; -1: DETACHed
  std::uint64_t statements_ = 0;              // executed in this execution
  std::uint64_t budget_ = 0;                  // at this count the task yields, or the run stops
  std::set<int> waited_;                      // signals SIG() read during the current WAIT
  StepHook step_hook_;                        // the debugger's (unset: not called)
  Reactions reactions0_;                      // task 0's until EXECUTE makes it a Task
  int brake_signal_ = 0;                      // a REACTI seen between steps: stop the pending motion
  std::vector<ReactionStop> reaction_stops_;  // RunResult::reaction_stops
};

// A REACTI stopped the motion that the step in progress waited for (check_motion): the step
// runs again once the reaction is served (loop()).
struct Braked {};

}  // namespace asimov::interpreter
