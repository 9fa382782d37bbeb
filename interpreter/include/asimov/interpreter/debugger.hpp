// The program debugger (docs/monitor.md "The program debugger"): breakpoints by program and
// step, and runs driven one step at a time (into CALLs or over them) through the interpreter's
// step hook. The monitor's DEBUG, SSTEP, XSTEP, BPT, NOBPT and PROCEED use it; so can the studio.
#pragma once
#include "asimov/interpreter/interpreter.hpp"
#include <functional>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace asimov::interpreter {

struct Breakpoint {
  std::string program;  // normalized name
  int step = 0;
  auto operator<=>(const Breakpoint&) const = default;
};

// How far a driven run goes: to a breakpoint or its end (run), one step not stopping inside the
// programs it CALLs (over: SSTEP), one step stopping at the first step of a CALLed program
// (into: XSTEP; a run started this way stops before its first step: DEBUG).
enum class DebugMode { run, over, into };
enum class DebugStop { none, step, breakpoint };

// A step where a driven run stopped: the next one to run.
struct StepPlace {
  std::string program;
  int step = 0;
  int line = 0;          // file line
  std::string file;
  std::string text;      // the source line, without leading blanks
  int depth = 0;         // call depth (1: the program the run started with)
};

class Debugger {
 public:
  explicit Debugger(Interpreter& interp) : interp_(interp) {}

  // BPT: false when it was already set. NOBPT: false when it was not.
  bool set_breakpoint(const Breakpoint& b) { return breakpoints_.insert(b).second; }
  bool clear_breakpoint(const Breakpoint& b) { return breakpoints_.erase(b) > 0; }
  void clear_breakpoints(const std::string& program);  // every one in `program`
  void clear_breakpoints() { breakpoints_.clear(); }
  const std::set<Breakpoint>& breakpoints() const { return breakpoints_; }
  // The monitor's helper programs (exec.tmp): never stopped in, their steps not counted.
  void hide(std::string program) { hidden_.insert(std::move(program)); }

  // Runs `call` (a run or a resumption of the interpreter) with the hook set for `mode`.
  // `resuming`: the first instruction met is the step being resumed; SSTEP and XSTEP run it, and
  // so does PROCEED from a stop of the debugger (its breakpoint does not stop it again).
  // Without breakpoints, mode run sets no hook at all.
  RunResult drive(DebugMode mode, bool resuming, const std::function<RunResult()>& call);
  // Why the last driven run paused (none: it ended otherwise, or PAUSE paused it).
  DebugStop last_stop() const { return stop_; }
  const StepPlace& place() const { return place_; }

 private:
  StepAction on_step(const StepEvent& e);
  Interpreter& interp_;
  std::set<Breakpoint> breakpoints_;
  std::set<std::string> hidden_;
  // The driven run's state.
  DebugMode mode_ = DebugMode::run;
  bool skip_first_ = false;           // the step being resumed runs
  int origin_depth_ = 0;              // over: the depth of the step it began at
  const std::string* prev_program_ = nullptr;  // the last instruction seen, to find a step's start
  int prev_line_ = 0;
  std::size_t prev_instruction_ = 0;
  int prev_depth_ = 0;
  DebugStop stop_ = DebugStop::none;
  bool held_ = false;                 // the last driven run ended in a stop of the debugger's
  StepPlace place_;
};

// The step at `line` of `file` among the programs in memory (a step holding an instruction),
// for a breakpoint set on a file line (the studio's gutter); none when no program has one there.
std::optional<Breakpoint> step_at_line(Interpreter& interp, const std::string& file, int line);

// "transfer, step 2:  MOVES src": the step a driven run stopped at, as the monitor shows it.
std::string format_step(const StepPlace& p);

}  // namespace asimov::interpreter
