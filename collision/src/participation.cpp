#include "asimov/collision/participation.hpp"

#include <algorithm>
#include <cassert>
#include <utility>

namespace asimov::collision {
namespace {
std::size_t slot_of(std::uint64_t k, std::size_t mask) {
  return static_cast<std::size_t>((k * 0x9E3779B97F4A7C15ull) >> 32) & mask;
}
}  // namespace

bool Participation::contains(std::uint64_t k) const {
  if (slots_.empty()) return false;
  const std::size_t mask = slots_.size() - 1;
  for (std::size_t i = slot_of(k, mask);; i = (i + 1) & mask) {
    if (slots_[i] == k) return true;
    if (slots_[i] == 0) return false;
  }
}

void Participation::rehash(std::size_t slots) {
  std::vector<std::uint64_t> old = std::move(slots_);
  slots_.assign(slots, 0);
  filled_ = live_;
  const std::size_t mask = slots - 1;
  for (const std::uint64_t k : old)
    if (k != 0 && k != kErased) {
      std::size_t i = slot_of(k, mask);
      while (slots_[i] != 0) i = (i + 1) & mask;
      slots_[i] = k;
    }
}

bool Participation::insert(std::uint64_t k) {
  if (contains(k)) return false;
  if (2 * (filled_ + 1) > slots_.size()) rehash(std::max<std::size_t>(64, live_ >= slots_.size() / 4 ? 2 * slots_.size() : slots_.size()));
  const std::size_t mask = slots_.size() - 1;
  std::size_t i = slot_of(k, mask);
  while (slots_[i] != 0 && slots_[i] != kErased) i = (i + 1) & mask;
  if (slots_[i] == 0) ++filled_;
  slots_[i] = k;
  ++live_;
  return true;
}

bool Participation::erase(std::uint64_t k) {
  if (slots_.empty()) return false;
  const std::size_t mask = slots_.size() - 1;
  for (std::size_t i = slot_of(k, mask);; i = (i + 1) & mask) {
    if (slots_[i] == k) {
      slots_[i] = kErased;
      --live_;
      return true;
    }
    if (slots_[i] == 0) return false;
  }
}

void Participation::set(std::uint32_t a, std::uint32_t b, bool on) {
  assert(a != b && a < n_ && b < n_);
  if (a > b) std::swap(a, b);
  if (on ? !insert(key(a, b)) : !erase(key(a, b))) return;  // unchanged
  // pairs_ is brought up to date when next read: a sorted insert or erase per pair was
  // quadratic in the pairs of a cell with 10^5 objects.
  const BodyPair p{a, b};
  if (!on) tidy_ = false;  // still listed
  else if (tidy_ && !pairs_.empty() && !(pairs_.back() < p)) tidy_ = false;
  if (on) pairs_.push_back(p);
  if (pairs_.size() > 2 * live_ + 64) (void)pairs();  // toggled often, never read
}

const std::vector<BodyPair>& Participation::pairs() const {
  if (tidy_) return pairs_;
  // Sorted, each once, only the enabled (a pair disabled and enabled again is listed twice).
  std::sort(pairs_.begin(), pairs_.end());
  pairs_.erase(std::unique(pairs_.begin(), pairs_.end()), pairs_.end());
  std::erase_if(pairs_, [this](const BodyPair& p) { return !contains(key(p.a, p.b)); });
  tidy_ = true;
  return pairs_;
}

bool Participation::enabled(std::uint32_t a, std::uint32_t b) const {
  if (a >= n_ || b >= n_ || a == b) return false;
  if (a > b) std::swap(a, b);
  return contains(key(a, b));
}

}  // namespace asimov::collision
