#include "app/sigint.hpp"

#include <csignal>

namespace asimov::app {
namespace {

std::atomic<bool> g_sigint{false};
static_assert(std::atomic<bool>::is_always_lock_free, "set from a signal handler");

std::atomic<int> g_termination{0};  // SIGTERM or SIGHUP received, or 0

extern "C" void on_sigint(int) { g_sigint.store(true); }
extern "C" void on_termination(int signal) {
  g_termination.store(signal);
  g_sigint.store(true);
}

}  // namespace

std::atomic<bool>& sigint_flag() { return g_sigint; }

void install_sigint(bool once) {
  struct sigaction sa {};
  sa.sa_handler = on_sigint;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = once ? SA_RESETHAND : 0;
  sigaction(SIGINT, &sa, nullptr);
}

void install_termination() {
  g_termination.store(0);
  struct sigaction sa {};
  sa.sa_handler = on_termination;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGTERM, &sa, nullptr);
  sigaction(SIGHUP, &sa, nullptr);
}

void reraise_termination() {
  std::signal(SIGTERM, SIG_DFL);
  std::signal(SIGHUP, SIG_DFL);
  if (const int signal = g_termination.load()) std::raise(signal);
}

}  // namespace asimov::app
