// The asynchronous reactions of one task (docs/val2-dialect.md §7c, V+ Language User's Guide
// "Asynchronous Processing" and "Error Trapping"): the signals REACT and REACTI watch, the
// transitions seen and not yet served, the program priority that LOCK sets and a reaction
// raises, and the REACTE error trap. Plain data and its rules; the evaluator reads the signals
// and calls the reaction programs (between_steps.cpp).
#pragma once
#include <functional>
#include <optional>
#include <vector>

namespace asimov::interpreter {

struct Reaction {
  int signal = 0;          // the signal watched (> 0)
  bool falling = false;    // REACT -n: the on -> off transition; else off -> on
  int program = -1;        // program slot called; -1: none (REACTI without a program)
  int priority = 1;        // 1 ... 127
  bool stops_arm = false;  // REACTI: the arm stops when the transition is seen
  bool was_on = false;     // the signal as last seen
  bool triggered = false;  // the transition was seen: runs once the program priority is lower
};

class Reactions {
 public:
  static constexpr int kMaxPriority = 127;  // REACT and LOCK (V+: 0 ... 127)
  static constexpr int kTrapPriority = 254;  // while the REACTE program runs

  // REACT / REACTI: watches `r.signal` from its state now (r.was_on); replaces a reaction on
  // the same signal, triggered or not.
  void arm(const Reaction& r);
  // IGNORE n: the reaction on signal |n| ends, also when triggered and waiting. False: none.
  bool ignore(int signal);
  bool empty() const { return table_.empty(); }
  const std::vector<Reaction>& table() const { return table_; }

  // Looks at every watched signal (`on(n)`: its state now): a transition to the state a
  // reaction waits for triggers it (once: it is no longer watched). The signal of a REACTI
  // this look triggered (negative: falling; the caller stops the arm), else 0.
  int see(const std::function<bool(int)>& on);
  // The triggered reaction to run now, taken out of the table: the one of highest priority
  // above the program priority (the first armed at equal priorities). None: nothing is due.
  std::optional<Reaction> take_due();

  // The program priority (PRIORITY(); LOCK sets it, a reaction raises it while it runs).
  int priority() const { return priority_; }
  void set_priority(int p) { priority_ = p; }

  // Whether a triggered reaction would run now (its priority above the program priority).
  bool due() const;

  // REACTE: the program slot called when an error would stop this task; -1: none.
  int trap = -1;
  bool trapping = false;  // the trap program runs (an error in it is not trapped again)

 private:
  std::vector<Reaction> table_;
  int priority_ = 0;
};

}  // namespace asimov::interpreter
