#include "app/sigint.hpp"

#include <csignal>

namespace asimov::app {
namespace {

std::atomic<bool> g_sigint{false};
static_assert(std::atomic<bool>::is_always_lock_free, "set from a signal handler");

extern "C" void on_sigint(int) { g_sigint.store(true); }

}  // namespace

std::atomic<bool>& sigint_flag() { return g_sigint; }

void install_sigint(bool once) {
  struct sigaction sa {};
  sa.sa_handler = on_sigint;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = once ? SA_RESETHAND : 0;
  sigaction(SIGINT, &sa, nullptr);
}

}  // namespace asimov::app
