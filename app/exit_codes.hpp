// Exit codes of the asimov executable (documented in README.md).
#pragma once

namespace asimov::app {

enum ExitCode : int {
  kExitCompleted = 0,     // program finished (or `check` found no problem)
  kExitUsage = 1,         // usage, file or cell error: nothing ran
  kExitProgramError = 2,  // syntax, runtime, out of reach, joint limit
  kExitCollision = 3,     // halted by collision
  kExitTestFailed = 4,    // `asimov test`: at least one case failed
  kExitInterrupted = 130, // `asimov run` stopped by Ctrl-C (128 + SIGINT, as shells report it)
};

}  // namespace asimov::app
