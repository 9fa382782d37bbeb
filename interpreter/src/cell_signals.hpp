// Stage 3, the signals and the reacting cell as the program sees them (docs/cell-format.md
// "Parts and devices"): SIGNAL, SIG() and WAIT go through the devices' clock, the hand grasps
// and releases parts. Lazy: the devices are advanced to the arm's clock whenever the program
// looks at or changes them, which is exact because they are functions of time and of the
// signals the program set before.
#pragma once
#include "asimov/interpreter/interpreter.hpp"

#include <optional>
#include <set>
#include <string>

namespace asimov::interpreter {

struct Memory;

class CellSignals {
 public:
  CellSignals(motion::Simulator& sim, Memory& memory) : sim_(sim), memory_(memory) {}
  // The cell's parts and devices, advanced to the arm's clock (a logic loop raises); null for a
  // cell without parts or devices.
  motion::CellRuntime* runtime();
  // The same for reports, never raising (a logic loop leaves the state before it).
  const motion::CellRuntime* state();
  // DO SIGNAL at the monitor: memory and devices; the message of a logic loop, if any.
  std::optional<std::string> monitor_signal(int k);

  void set_signal(int k, int line);             // SIGNAL k (negative: off) at the statement of `line`
  bool signal_on(int k);                        // SIG(k), remembered for WAIT's message
  bool signal_state(int k);                     // the same, not remembered (reactions)
  bool signal_at(int k, double t);              // signal k at time t of a motion being carried out
  void begin_wait() { waited_.clear(); }        // a WAIT condition starts: no signal read yet
  std::string undriven_signals() const;         // WAIT: the waited inputs no device drives
  void hand_changed(motion::HandState h, int line);  // grasp / release at the flange now

 private:
  motion::Simulator& sim_;
  Memory& memory_;
  std::set<int> waited_;                        // signals SIG() read during the current WAIT
};

}  // namespace asimov::interpreter
