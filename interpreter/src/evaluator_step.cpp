// The step hook (step_hook.hpp): the debugger's view of a run between two instructions.
#include "evaluator.hpp"

namespace asimov::interpreter {

RunStatus Evaluator::at_step(const Instr& in, Frame& f) {
  const Program& p = *f.program;
  const StepEvent e{p.name, in.line - p.line, in.line, static_cast<std::size_t>(f.pc),
                    static_cast<int>(stack_.size()), task_number(), running_ == nullptr};
  if (step_hook_(e) != StepAction::pause || running_) return RunStatus::completed;
  // The motions already started end first, so that a paused run shows the arm where its steps
  // so far put it. The pc is past `in` meanwhile, as when a statement waits for a motion: a
  // contact or Ctrl-C then leaves the stop located and resumable as for that statement (the
  // instruction runs again); a clean end puts it back, so PROCEED runs `in` next.
  ++f.pc;
  if (const RunStatus s = finish_motion(); s != RunStatus::completed) return s;
  --f.pc;
  current_program_ = &p;
  current_line_ = in.line;
  return RunStatus::paused;
}

}  // namespace asimov::interpreter
