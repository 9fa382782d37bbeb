#include "asimov/collision/participation.hpp"

#include <algorithm>
#include <cassert>
#include <utility>

namespace asimov::collision {

void Participation::resize(std::size_t n) {
  if (n <= n_) return;
  if (n <= stride_) {  // room left: the new rows and columns are already zero
    n_ = n;
    return;
  }
  // Capacity doubles, so adding bodies one by one costs O(n^2) bits in all, not O(n^3).
  Participation grown;
  grown.n_ = n;
  grown.stride_ = std::max(n, 2 * stride_);
  grown.bits_.assign((grown.stride_ * grown.stride_ + 63) / 64, 0);
  for (const BodyPair& p : pairs_) {
    for (const std::size_t k : {grown.bit(p.a, p.b), grown.bit(p.b, p.a)})
      grown.bits_[k / 64] |= std::uint64_t{1} << (k % 64);
  }
  grown.pairs_ = std::move(pairs_);
  grown.sorted_ = sorted_;
  *this = std::move(grown);
}

void Participation::set(std::uint32_t a, std::uint32_t b, bool on) {
  assert(a != b && a < n_ && b < n_);
  if (a > b) std::swap(a, b);
  if (enabled(a, b) == on) return;
  for (const std::size_t k : {bit(a, b), bit(b, a)}) bits_[k / 64] ^= std::uint64_t{1} << (k % 64);
  const BodyPair p{a, b};
  if (on) {
    // Appended and sorted when next read: a sorted insert per pair was quadratic in the pairs
    // of a cell with 10^5 objects.
    if (!pairs_.empty() && p < pairs_.back()) sorted_ = false;
    pairs_.push_back(p);
    return;
  }
  sort();
  pairs_.erase(std::lower_bound(pairs_.begin(), pairs_.end(), p));
}

const std::vector<BodyPair>& Participation::pairs() const {
  sort();
  return pairs_;
}

void Participation::sort() const {
  if (sorted_) return;
  std::sort(pairs_.begin(), pairs_.end());
  sorted_ = true;
}

bool Participation::enabled(std::uint32_t a, std::uint32_t b) const {
  if (a >= n_ || b >= n_ || a == b) return false;
  const std::size_t k = bit(a, b);
  return (bits_[k / 64] >> (k % 64)) & 1;
}

}  // namespace asimov::collision
