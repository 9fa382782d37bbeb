// Stage 3, the statement VM: runs compiled programs (values, expressions, control flow, calls,
// frames) and hands the rest to its parts, which the file list names in pipeline order:
//   arm_controller.*  speeds, durations, the hand, motion requests, halted-motion resume
//   scheduler.*       tasks, priorities, WAIT; between_steps.cpp: reactions and debugger stops
//   file_statements.* file I/O
//   cell_signals.*    signals and the reacting cell
// Holds the run-time state (call stack, the stopped execution); the memory (symbols, globals,
// programs) belongs to the interpreter.
#pragma once
#include "arm_controller.hpp"
#include "cell_signals.hpp"
#include "checker.hpp"
#include "code.hpp"
#include "errors.hpp"
#include "file_statements.hpp"
#include "frames.hpp"
#include "scheduler.hpp"
#include "settings.hpp"
#include "asimov/interpreter/interpreter.hpp"
#include "asimov/interpreter/values.hpp"

#include <array>
#include <deque>
#include <functional>
#include <iosfwd>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <utility>
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

// The compiled form of a real expression (Node::fast) run against `ctx`: false when it meets a
// value it does not handle (the generic path then evaluates; plain trees only read).
inline bool run_root(const RNode* r, const FastCtx& ctx, double& out) {
  try {
    out = r->fn(*r, ctx);
    return true;
  } catch (const Fallback&) {
    return false;
  }
}
inline bool run_fast(const Node& n, const FastCtx& ctx, double& out) {
  if (!n.fast) return false;
  try {
    out = n.fast->run(ctx);
    return true;
  } catch (const Fallback&) {
    return false;
  }
}

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
  // PROMPT's input (null: std::cin).
  void set_input(std::istream* in, bool interactive) { in_ = in, interactive_ = interactive; }

  // --- the parts (the monitor's speeds: arm(); the step hook: scheduler(); signals: cell()) ---
  ArmController& arm() { return arm_; }
  Scheduler& scheduler() { return sched_; }
  CellSignals& cell() { return cell_; }

  // --- what the parts use of the VM ---
  Value eval(const Node& n);
  void store(const Node& target, Value value);
  int signal_number(const Node& n, bool output);  // SIGNAL, SIG, REACT: checked range
  void call(const Instr& in);                     // pushes the frame of a CALL (or a reaction)
  RunStatus loop();                               // runs stack() until it is empty, or its task gives way
  RunStatus stop(Fault f);                        // keeps `f` for the report: RunStatus::error, or interrupted
  void warn_once(const std::string& keyword, const Instr& in);  // a §7 warning, once per execution
  FrameStack& stack() { return stack_; }          // the running task's
  FastCtx& fast_ctx() { return ctx_; }            // the globals and slots expressions see
  const std::vector<Variable*>& globals() const { return globals_; }  // by slot, set when a run starts
  const std::string& run_program() const { return run_program_; }     // the program this execution started with
  // Where the executing statement is (reports, step numbers): step_back() makes the statement
  // that waits run again; locate() moves the report to another statement (a motion's).
  const Program* current_program() const { return current_program_; }
  int current_line() const { return current_line_; }
  int step_of(int line) const { return current_program_ ? line - current_program_->line : 0; }
  void step_back() {
    if (!stack_.empty()) --stack_.back().pc;
  }
  void locate(const Program* program, int line) { current_program_ = program, current_line_ = line; }

 private:
  // The one protected boundary: runs `setup` then the loop and turns the status they return
  // (or a raised Fault) into the result.
  //
  // Status returns: the statements that can end a run return RunStatus::completed to go on, or
  // the status that ends it (collision: the report in the arm; error / interrupted: the
  // message in fault_, set by stop()).
  RunResult protected_run(const std::string& name, const std::function<RunStatus()>& setup);
  std::vector<std::shared_ptr<const Program>> pin_programs() const;  // Stopped::pinned of a new stop
  RunStatus execute(const Instr& in);  // the statements that can end a run, else statement()
  void statement(const Instr& in);
  void pop_frame();
  void prompt(const Instr& in);
  Value function(const Node& n);
  Variable& variable(const Node& n) {
    if (n.ref.scope == Scope::global) return *ctx_.globals[n.ref.slot];
    return *stack_.back().params[static_cast<std::size_t>(n.ref.slot)];
  }
  Index index(const Node& n);
  const Value& lookup(const Node& n);
  // The real fast path over Node::plain trees (no Value built): false, with nothing raised,
  // when a variable holds another kind; the generic path then evaluates (plain trees only read).
  bool try_real(const Node& n, double& out);
  double real(const Node& n, const char* what);
  void store_real(const Node& target, double x);
  bool store_in_place(const Node& target, double x);
  bool defined(const Node& n);

  // An execution stopped by an error or a collision, for PROCEED / RETRY.
  struct Stopped {
    std::vector<Frame> stack;
    RunStatus status = RunStatus::error;
    std::string program;                        // the program the run started with
    ArmSettings arm;
    std::optional<MotionRequest> motion;
    bool motion_halted = false;                 // Ctrl-C halted `motion`: its rest runs first
    std::vector<std::shared_ptr<const Program>> pinned;  // the frames' programs, even if reloaded
  };

  motion::Simulator& sim_;
  std::ostream& out_;
  Memory& memory_;
  const Limits& limits_;
  CellSignals cell_;
  ArmController arm_;
  Scheduler sched_;
  FileStatements files_;
  FrameStack stack_;
  const Program* current_program_ = nullptr;  // where the executing statement is
  int current_line_ = 0;
  std::string run_program_;                   // the program this execution started with
  std::istream* in_ = nullptr;                // PROMPT input (null: std::cin)
  bool interactive_ = false;                  // PROMPT asks again on bad input
  std::vector<Diagnostic> warnings_;          // this execution's §7 warnings
  std::optional<Stopped> stopped_;            // what PROCEED / RETRY continue
  // While a stopped execution runs again: its pins. A program it runs that memory_ no longer
  // holds (the monitor's temporary program of `DEBUG name(args)`, a reloaded one) stays pinned
  // when it stops again (pin_programs), however often it is stepped.
  std::vector<std::shared_ptr<const Program>> resumed_pins_;
  Fault fault_;                               // what ended the run (status error / interrupted)
  std::vector<Variable*> globals_;            // &memory_.globals[slot], set when a run starts
  FastCtx ctx_;                               // globals_ and the running frame's slots
};

}  // namespace asimov::interpreter
