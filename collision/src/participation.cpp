#include "asimov/collision/participation.hpp"

#include <algorithm>
#include <cassert>
#include <utility>

namespace asimov::collision {

void Participation::resize(std::size_t n) {
  if (n <= n_) return;
  Participation grown;
  grown.n_ = n;
  grown.bits_.assign((n * n + 63) / 64, 0);
  for (const BodyPair& p : pairs_) {
    for (const std::size_t k : {grown.bit(p.a, p.b), grown.bit(p.b, p.a)})
      grown.bits_[k / 64] |= std::uint64_t{1} << (k % 64);
  }
  grown.pairs_ = std::move(pairs_);
  *this = std::move(grown);
}

void Participation::set(std::uint32_t a, std::uint32_t b, bool on) {
  assert(a != b && a < n_ && b < n_);
  if (a > b) std::swap(a, b);
  if (enabled(a, b) == on) return;
  for (const std::size_t k : {bit(a, b), bit(b, a)}) bits_[k / 64] ^= std::uint64_t{1} << (k % 64);
  const BodyPair p{a, b};
  const auto it = std::lower_bound(pairs_.begin(), pairs_.end(), p);
  if (on)
    pairs_.insert(it, p);
  else
    pairs_.erase(it);
}

bool Participation::enabled(std::uint32_t a, std::uint32_t b) const {
  if (a >= n_ || b >= n_ || a == b) return false;
  const std::size_t k = bit(a, b);
  return (bits_[k / 64] >> (k % 64)) & 1;
}

}  // namespace asimov::collision
