// The between-steps hook of a run (the program debugger's: docs/monitor.md "The program
// debugger"). When set, the evaluator calls it before every instruction it is about to
// execute; the hook may ask the run to pause there. A paused run ends with RunStatus::paused
// and is resumable exactly where it stopped (Interpreter::proceed runs that instruction next),
// the arm at the end of the motions started before it.
#pragma once
#include <cstddef>
#include <functional>
#include <string>

namespace asimov::interpreter {

struct StepEvent {
  const std::string& program;  // the program of the instruction
  int step = 0;                // its step (file line - .PROGRAM line)
  int line = 0;                // its file line
  std::size_t instruction = 0; // its index in the compiled program: a step may have several
  int depth = 0;               // call depth: 1 for the program the run started with
  int task = 0;                // the task running it (dialect §7b)
  bool pausable = true;        // false while the run has several tasks: a pause is not honoured
};

enum class StepAction { go, pause };

// Unset: the run does not call anything (one test of a pointer per instruction).
// A pause is honoured only while the run has one task (a run that EXECUTEd others cannot be
// resumed, dialect §7b; StepEvent::pausable); the hook is still called for every task's
// instructions.
using StepHook = std::function<StepAction(const StepEvent&)>;

}  // namespace asimov::interpreter
