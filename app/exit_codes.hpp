// Exit codes of the asimov executable (documented in README.md).
#pragma once

namespace asimov::app {

enum ExitCode : int {
  kExitCompleted = 0,     // program finished (or `check` found no problem)
  kExitUsage = 1,         // usage, file or cell error: nothing ran
  kExitProgramError = 2,  // syntax, runtime, out of reach, joint limit
  kExitCollision = 3,     // halted by collision
  kExitTestFailed = 4,    // `asimov test`: at least one case failed
  kExitOutputLost = 5,    // the run ended well (0) but an output file could not be written; a run
                          // that failed keeps its own code (a collision is 3 with a lost report)
  kExitInterrupted = 130, // `asimov run` stopped by Ctrl-C (128 + SIGINT, as shells report it)
};

}  // namespace asimov::app
