#include "asimov/collision/participation.hpp"

#include <algorithm>
#include <cassert>
#include <utility>

namespace asimov::collision {

void Participation::set(std::uint32_t a, std::uint32_t b, bool on) {
  assert(a != b && a < n_ && b < n_);
  if (a > b) std::swap(a, b);
  if (on ? !enabled_.insert(key(a, b)).second : enabled_.erase(key(a, b)) == 0) return;  // unchanged
  // pairs_ is brought up to date when next read: a sorted insert or erase per pair was
  // quadratic in the pairs of a cell with 10^5 objects.
  const BodyPair p{a, b};
  if (!on) tidy_ = false;  // still listed
  else if (tidy_ && !pairs_.empty() && !(pairs_.back() < p)) tidy_ = false;
  if (on) pairs_.push_back(p);
  if (pairs_.size() > 2 * enabled_.size() + 64) (void)pairs();  // toggled often, never read
}

const std::vector<BodyPair>& Participation::pairs() const {
  if (tidy_) return pairs_;
  // Sorted, each once, only the enabled (a pair disabled and enabled again is listed twice).
  std::sort(pairs_.begin(), pairs_.end());
  pairs_.erase(std::unique(pairs_.begin(), pairs_.end()), pairs_.end());
  std::erase_if(pairs_, [this](const BodyPair& p) { return !enabled_.contains(key(p.a, p.b)); });
  tidy_ = true;
  return pairs_;
}

bool Participation::enabled(std::uint32_t a, std::uint32_t b) const {
  if (a >= n_ || b >= n_ || a == b) return false;
  if (a > b) std::swap(a, b);
  return enabled_.contains(key(a, b));
}

}  // namespace asimov::collision
