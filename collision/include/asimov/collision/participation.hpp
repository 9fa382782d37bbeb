// Step 1: the participation matrix. One flag per body pair says whether it is ever tested;
// the enabled pairs are also kept as a sorted list (i < j), which is what step 2 walks.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

namespace asimov::collision {

struct BodyPair {
  std::uint32_t a = 0, b = 0;  // a < b
  friend bool operator==(const BodyPair&, const BodyPair&) = default;
  friend auto operator<=>(const BodyPair&, const BodyPair&) = default;
};

class Participation {
 public:
  // Grows the matrix to n bodies; new pairs start disabled, existing flags are kept.
  void resize(std::size_t n);
  std::size_t size() const { return n_; }
  void set(std::uint32_t a, std::uint32_t b, bool enabled);  // a != b, either order
  bool enabled(std::uint32_t a, std::uint32_t b) const;
  const std::vector<BodyPair>& pairs() const;  // sorted, a < b

 private:
  std::size_t bit(std::uint32_t a, std::uint32_t b) const { return std::size_t{a} * stride_ + b; }
  void sort() const;
  std::size_t n_ = 0;
  std::size_t stride_ = 0;           // capacity: rows and columns allocated
  std::vector<std::uint64_t> bits_;  // row-major stride x stride, both halves kept in sync
  mutable std::vector<BodyPair> pairs_;
  mutable bool sorted_ = true;       // pairs_ is sorted (set() appends; pairs() sorts)
};

}  // namespace asimov::collision
