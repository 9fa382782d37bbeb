#include "reactions.hpp"

#include <algorithm>

namespace asimov::interpreter {

void Reactions::arm(const Reaction& r) {
  ignore(r.signal);
  table_.push_back(r);
}

bool Reactions::ignore(int signal) {
  const auto it = std::remove_if(table_.begin(), table_.end(), [&](const Reaction& r) { return r.signal == signal; });
  const bool found = it != table_.end();
  table_.erase(it, table_.end());
  return found;
}

int Reactions::see(const std::function<bool(int)>& on) {
  int stop = 0;
  for (Reaction& r : table_) {
    if (r.triggered) continue;
    const bool now = on(r.signal);
    if (now != r.was_on && now != r.falling) {  // off -> on (rising) or on -> off (falling)
      r.triggered = true;
      if (r.stops_arm && stop == 0) stop = r.falling ? -r.signal : r.signal;
    }
    r.was_on = now;
  }
  return stop;
}

bool Reactions::due() const {
  for (const Reaction& r : table_)
    if (r.triggered && (r.program < 0 || r.priority > priority_)) return true;
  return false;
}

std::optional<Reaction> Reactions::take_due() {
  // A REACTI without a program has done all it does (the arm stopped) once triggered.
  std::erase_if(table_, [](const Reaction& r) { return r.triggered && r.program < 0; });
  auto best = table_.end();
  for (auto it = table_.begin(); it != table_.end(); ++it)
    if (it->triggered && it->priority > priority_ && (best == table_.end() || it->priority > best->priority)) best = it;
  if (best == table_.end()) return std::nullopt;
  Reaction r = *best;
  table_.erase(best);
  return r;
}

}  // namespace asimov::interpreter
