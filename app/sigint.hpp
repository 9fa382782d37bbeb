// Ctrl-C for the commands that run programs. SIGINT only sets a flag; the interpreter polls it
// between steps and the simulator before each checked pose of a motion (Limits::interrupt), so
// a program stops with *Program interrupted* and the arm stops where it is.
#pragma once
#include <atomic>

namespace asimov::app {

// Set by the handler; the commands clear it before each run.
std::atomic<bool>& sigint_flag();

// Installs the handler, without SA_RESTART (a blocking read returns EINTR). `once`: the first
// Ctrl-C sets the flag and restores the default action, so a second one ends the process (a
// batch run that does not reach its next check can still be killed).
void install_sigint(bool once);

// SIGTERM and SIGHUP handled as Ctrl-C (the flag above) by a command that must clean up before
// it ends (`asimov test`'s scratch folder); the command then calls reraise_termination(), which
// restores the default actions and, if one came, ends the process by that signal, as the sender
// expects.
void install_termination();
void reraise_termination();

}  // namespace asimov::app
