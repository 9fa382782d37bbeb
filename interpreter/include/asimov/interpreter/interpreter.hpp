// The public face of the VAL II interpreter: load .v2 sources, check them, run a program
// against a motion::Simulator. Errors never escape as exceptions from these calls.
#pragma once
#include "asimov/motion/cell_runtime.hpp"
#include "asimov/motion/simulator.hpp"
#include <atomic>
#include <iosfwd>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace asimov::interpreter {

struct Memory;  // evaluator.hpp: symbols, globals, programs

// One problem found in a source (load/check time) or raised while running.
struct Diagnostic {
  std::string message;      // "*Syntax error*", "*Undefined value*", ...
  std::string detail;       // short detail after the message, may be empty
  std::string file;         // source file as given
  int line = 0;             // 1-based file line, 0 if unknown
  int column = 0;           // 1-based column, 0 if unknown
  std::string program;      // program name when known
  int step = 0;             // step within the program (file line - .PROGRAM line)
  std::string source_line;  // the offending source line, for the report
  bool warning = false;
};

// Formats a diagnostic in the VAL style of dialect §10 (message, location, source, caret).
std::string format_diagnostic(const Diagnostic& d);

struct RunResult;
// "Program paused: name, step n" / "Program halted: name, step n" (no newline) for a run
// that ended in PAUSE or HALT; empty for any other status.
std::string format_pause(const RunResult& r);
// "motion halted at t = ... s, ... % of its path" and a "joints ..." line (newline-terminated)
// when Ctrl-C stopped the arm inside a motion; empty otherwise.
std::string format_interrupt(const RunResult& r);

// A motion instruction that a run started: the step that the simulator's collision, interrupt
// and replay reports carry, and where it is (the replay page names its frames with it).
struct MotionStep {
  int step = 0;             // file line - .PROGRAM line
  std::string program;
  int line = 0;             // file line
  std::string text;         // the source line, without leading blanks
};

// A task of a run that EXECUTEd others (dialect §7b), as the monitor's STATUS lists it.
struct TaskReport {
  int number = 0;
  std::string program;            // the program it was started with
  std::string state;              // "completed", "aborted", or where it was when the run ended
};

// The motion instruction that ran at `step`, when exactly one did (programs of a file may
// share a step number); null otherwise.
const MotionStep* motion_at_step(const std::vector<MotionStep>& motions, int step);

// "Closest approach: link5 / box 4.830 mm at t = 3.379356 s (crash, line 12)" and a newline:
// the nearest pair of the run's clearance report (docs/collision.md §12), the step's program
// line from `motions` where it is unique (else "step n"); empty when no pair came within
// report_within_mm.
std::string format_closest(const motion::Simulator& sim, const std::vector<MotionStep>& motions);

// A motion the run started, on the simulated clock (the report's per-motion durations): its
// start and planned duration; blended: it started while the previous motion was still
// decelerating (continuous path, docs/blending.md).
struct MotionTime {
  int step = 0;
  std::string program;
  double start_s = 0;
  double duration_s = 0;
  bool blended = false;
};
constexpr std::size_t kMaxMotionTimes = 10000;  // per run; later motions are counted, not listed

// How a run ended. error: a VAL error stopped it; interrupted: Ctrl-C (Limits::interrupt)
// stopped it between two steps or inside a motion (*Program interrupted*); paused: PAUSE
// (PROCEED continues with the next step); halted: HALT (cannot be resumed).
enum class RunStatus { completed, error, interrupted, collision, paused, halted };

// A REACTI that stopped the arm inside a motion (docs/val2-dialect.md §7c): the signal whose
// transition it saw (negative: the falling edge) and where the arm stopped.
struct ReactionStop {
  int signal = 0;
  int task = 0;
  motion::InterruptReport at;     // time, path fraction, joints, the motion's step
};

struct RunResult {
  RunStatus status = RunStatus::completed;
  std::string program;            // the program executing when the run ended
  int line = 0;                   // its file line (0 when completed normally)
  int step = 0;
  Diagnostic error;               // status error or interrupted (also filled for collision: "*Collision*")
  motion::CollisionReport collision;  // status == collision
  // Ctrl-C halted a motion (status interrupted): where the arm stopped.
  // PROCEED and RETRY first carry out the rest of that motion.
  std::optional<motion::InterruptReport> interrupt;
  std::vector<Diagnostic> warnings;   // V+ constructs ignored with a warning (dialect §7), once each
  std::vector<MotionStep> motions;    // the motion instructions started, once each, in first-run order
  std::vector<MotionTime> motion_times;   // every motion started, in order (at most kMaxMotionTimes)
  std::uint64_t motion_times_omitted = 0; // motions started beyond kMaxMotionTimes
  std::vector<TaskReport> tasks;      // every task when the run EXECUTEd others (dialect §7b); else empty
  std::vector<ReactionStop> reaction_stops;  // every motion a REACTI stopped, in order
};

struct Limits {
  std::uint64_t max_statements = 100'000'000;  // executed statements per run
  int max_call_depth = 1000;                   // nested CALLs before *Too many nested calls*
  // Set (Ctrl-C): the run stops before the next step, and a motion being carried out stops at
  // its next checked pose (the simulator reads the flag while a run goes on).
  const std::atomic<bool>* interrupt = nullptr;
  double tick_s = 0.016;          // WAIT: the clock advances by ticks [s]
  double max_wait_s = 3600;       // WAIT: simulated seconds before *Wait limit exceeded*
  // Files (dialect §7a): every path FOPENR ... names is resolved beneath this folder (the
  // program file's folder, or `asimov run --files DIR`), never outside it (docs/limits.md).
  std::string files_root = ".";
  std::size_t max_record_bytes = 64 * 1024;     // one record READ or WRITE
  std::uint64_t max_file_bytes = 256ull << 20;  // every byte a run writes to files
};

class Interpreter {
 public:
  Interpreter(motion::Simulator& sim, std::ostream& out);
  ~Interpreter();

  // Parses and checks `text` as file `file_name`. All problems are returned together. As V+
  // loads (dialect §8), a program with an error is loaded marked not executable and the rest
  // of the file loads; an error outside every program (stray text, a data section) or past a
  // file-wide limit loads nothing.
  std::vector<Diagnostic> load_source(const std::string& text, const std::string& file_name);
  // Reads the file then load_source; a missing file is a "*File not found*" diagnostic.
  std::vector<Diagnostic> load_file(const std::string& path);

  std::vector<std::string> program_names() const;  // in load order
  bool has_program(const std::string& name) const;
  // The first program that `name` or a program it reaches by CALL or EXECUTE (as written) that
  // LOAD marked not executable; nullopt when all of them can run (those not loaded aside).
  std::optional<std::string> not_executable_from(const std::string& name) const;

  // Runs `name` from its start; waits for the last motion to end.
  RunResult run(const std::string& name);

  Limits& limits();

  // Where PROMPT reads its replies (default std::cin). `interactive` (a terminal): bad input
  // asks again; otherwise bad input or the end of input is an *Illegal value*.
  void set_input(std::istream& in, bool interactive);

  // The execution that the last error or collision stopped (dialect §9). PROCEED skips the
  // failing step (after a collision: drops the interrupted motion and re-runs the step that
  // found the contact); RETRY re-runs the failing step (after a collision: first restarts the
  // interrupted motion from the halted pose). After Ctrl-C both run the step not yet run; when
  // Ctrl-C halted a motion, both first carry out its rest towards its target (at the monitor
  // speed then in effect). run() keeps a stopped execution (so DO can fix a value before
  // RETRY); abort() drops it. Without one: "*No program to resume*".
  bool can_resume() const;
  RunResult proceed();
  RunResult retry();
  void abort();

  // For the monitor (monitor.cpp): what LOAD put in memory, read and changed in place.
  Memory& memory();
  // The cell's parts and devices at the simulator's time (events, part poses); null for a cell
  // without parts or devices.
  const motion::CellRuntime* cell_state();
  // The monitor's DO SIGNAL k (negative: off), inputs included: the signal memory and the
  // cell's devices (outputs run conveyors, feeders and logic rules; an input a sensor or rule
  // drives is theirs again at their next change). Returns the message of a logic loop.
  std::optional<std::string> set_signal(int k);
  // Runs `name` for a monitor DO: a stop there is not resumable, and the execution stopped
  // before (if any) stays resumable.
  RunResult run_detached(const std::string& name);
  // Speeds (dialect §5): the monitor speed, and the program speeds (ALWAYS, and the one-shot
  // SPEED still pending) as the last execution left them.
  double monitor_speed() const;
  void set_monitor_speed(double percent);
  double program_speed() const;
  std::optional<double> next_program_speed() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace asimov::interpreter
