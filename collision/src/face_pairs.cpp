#include "face_pairs.hpp"

#include <algorithm>

namespace asimov::collision {

void FacePairs::start(const VoxelGrid& a, const VoxelGrid& b, std::vector<VoxelPair>& pairs) {
  a_ = &a;
  b_ = &b;
  pairs_ = &pairs;
  std::sort(pairs.begin(), pairs.end(), [](const VoxelPair& x, const VoxelPair& y) {
    return x.a != y.a ? x.a < y.a : x.b < y.b;
  });
  faces_a_.clear();
  for (std::size_t i = 0; i < pairs.size(); ++i)
    if (i == 0 || pairs[i].a != pairs[i - 1].a) {
      const auto f = a.faces_in(pairs[i].a);
      faces_a_.insert(faces_a_.end(), f.begin(), f.end());
    }
  std::sort(faces_a_.begin(), faces_a_.end());
  faces_a_.erase(std::unique(faces_a_.begin(), faces_a_.end()), faces_a_.end());
  if (mark_.size() < b.face_count) mark_.resize(b.face_count, 0);
  next_a_ = 0;
  partners_.clear();
  next_b_ = 0;
}

void FacePairs::fill_partners(std::uint32_t fa) {
  if (++stamp_ == 0) {  // wrapped: forget every old stamp
    std::fill(mark_.begin(), mark_.end(), 0);
    stamp_ = 1;
  }
  partners_.clear();
  next_b_ = 0;
  const auto by_a = [](const VoxelPair& p, std::uint32_t v) { return p.a < v; };
  for (const std::uint32_t va : a_->voxels_of(fa)) {
    for (auto it = std::lower_bound(pairs_->begin(), pairs_->end(), va, by_a); it != pairs_->end() && it->a == va; ++it)
      for (const std::uint32_t fb : b_->faces_in(it->b))
        if (mark_[fb] != stamp_) {
          mark_[fb] = stamp_;
          partners_.push_back(fb);
        }
  }
  std::sort(partners_.begin(), partners_.end());
}

bool FacePairs::next(std::uint32_t& fa, std::uint32_t& fb) {
  while (next_b_ == partners_.size()) {
    if (next_a_ == faces_a_.size()) return false;
    current_a_ = faces_a_[next_a_++];
    fill_partners(current_a_);
  }
  fa = current_a_;
  fb = partners_[next_b_++];
  return true;
}

}  // namespace asimov::collision
