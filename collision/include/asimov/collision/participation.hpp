// Step 1: the participation matrix. One flag per body pair says whether it is ever tested;
// the enabled pairs are also kept as a sorted list (i < j), which is what step 2 walks.
#pragma once
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace asimov::collision {

struct BodyPair {
  std::uint32_t a = 0, b = 0;  // a < b
  friend bool operator==(const BodyPair&, const BodyPair&) = default;
  friend auto operator<=>(const BodyPair&, const BodyPair&) = default;
};

// Sparse: a cell of 10^5 static objects has ~10^6 enabled pairs (objects x moving bodies) out
// of 5 * 10^9, so a bit per pair (1.25 GB) would cost more than the bodies (docs/limits.md).
class Participation {
 public:
  // Grows the matrix to n bodies; new pairs start disabled, existing flags are kept.
  void resize(std::size_t n) { n_ = std::max(n_, n); }
  std::size_t size() const { return n_; }
  void set(std::uint32_t a, std::uint32_t b, bool enabled);  // a != b, either order
  bool enabled(std::uint32_t a, std::uint32_t b) const;
  const std::vector<BodyPair>& pairs() const;  // sorted, a < b

 private:
  static std::uint64_t key(std::uint32_t a, std::uint32_t b) { return std::uint64_t{a} << 32 | b; }  // a < b
  std::size_t n_ = 0;
  // key(a, b) of each enabled pair, open addressing (linear probing, a power of two of slots,
  // at most half filled): enabled() runs for every pair of every query given a pair list, and
  // std::unordered_set's division and node per key cost more than the sphere test after it.
  // 0 is an empty slot (key(0, 0) is no pair), kErased one whose pair was disabled.
  static constexpr std::uint64_t kErased = ~std::uint64_t{0};
  bool contains(std::uint64_t k) const;
  bool insert(std::uint64_t k);  // false: already there
  bool erase(std::uint64_t k);   // false: not there
  void rehash(std::size_t slots);
  std::vector<std::uint64_t> slots_;
  std::size_t live_ = 0, filled_ = 0;  // enabled keys; slots not empty (live and erased)
  mutable std::vector<BodyPair> pairs_;
  mutable bool tidy_ = true;  // pairs_ is sorted and lists the enabled pairs once (else pairs() tidies it)
};

}  // namespace asimov::collision
