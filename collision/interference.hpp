// Step 3 per pose: interference sub-matrices of two voxel grids and the voxel-pair buffer.
#pragma once
#include "collision/voxel_grid.hpp"

#include <cstdint>
#include <vector>

namespace asimov::collision {

struct VoxelPair {
  std::uint32_t a = 0, b = 0;  // voxel indices in grid A and grid B
};

struct SubMatrices {
  CellRange a, b;  // voxels of A overlapping B's container, and of B overlapping A's
};

// Each container's minimax box in the other's frame, grown by `grow`, clipped to the grid.
SubMatrices interference_sub_matrices(const VoxelGrid& ga, const Pose& pose_a, const VoxelGrid& gb,
                                      const Pose& pose_b, double grow);

// Fills `out` (cleared first) with every pair (vA, vB) of non-empty voxels such that vB's box
// mapped into A's frame and grown by `grow` overlaps vA, both within their sub-matrices.
void collect_voxel_pairs(const VoxelGrid& ga, const Pose& pose_a, const VoxelGrid& gb, const Pose& pose_b,
                         double grow, std::vector<VoxelPair>& out);

}  // namespace asimov::collision
