// Step 4 list: the unique face pairs (fa, fb) of a voxel-pair buffer, in increasing key
// order fa << 32 | fb, produced one at a time so the exact test can stop at the first hit.
// De-duplication uses a per-face stamp instead of sorting every raw pair: one face spans
// many voxels, and sorting the raw list was most of the query time.
#pragma once
#include "interference.hpp"
#include "voxel_grid.hpp"

#include <cstdint>
#include <vector>

namespace asimov::collision {

class FacePairs {
 public:
  // Sorts `pairs` by (vA, vB) in place. The grids must outlive the iteration.
  void start(const VoxelGrid& a, const VoxelGrid& b, std::vector<VoxelPair>& pairs);
  // The next unique pair in key order; false when there is none left.
  bool next(std::uint32_t& fa, std::uint32_t& fb);

 private:
  void fill_partners(std::uint32_t fa);
  const VoxelGrid* a_ = nullptr;
  const VoxelGrid* b_ = nullptr;
  const std::vector<VoxelPair>* pairs_ = nullptr;
  std::vector<std::uint32_t> faces_a_;  // candidate A faces, sorted, unique
  std::size_t next_a_ = 0;
  std::vector<std::uint32_t> partners_;  // B faces of the current A face, sorted, unique
  std::size_t next_b_ = 0;
  std::uint32_t current_a_ = 0;
  std::vector<std::uint32_t> mark_;  // per B face: stamp of the last A face that listed it
  std::uint32_t stamp_ = 0;
};

}  // namespace asimov::collision
