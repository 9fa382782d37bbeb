// Step 3 per pose: interference sub-matrices of two voxel grids and the voxel-pair buffer.
#pragma once
#include "voxel_grid.hpp"

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

// B's voxels mapped into A's frame for one pose: the edge terms are the same for every voxel,
// so the minimax offsets of one voxel are computed once and each corner is
// base + i dx + j dy + k dz (docs/collision-method.md §3, per pose 4).
struct VoxelMapping {
  SubMatrices sub;
  Vec3 dx = Vec3::Zero(), dy = Vec3::Zero(), dz = Vec3::Zero();  // B's voxel edges in A's frame
  Vec3 lo_off = Vec3::Zero(), hi_off = Vec3::Zero();             // minimax offsets, grown
  Vec3 base = Vec3::Zero();                                      // B's container origin in A's frame
  bool empty() const { return sub.a.empty() || sub.b.empty(); }
  // A voxels (within A's sub-matrix) that B's voxel (i, j, k), mapped and grown, overlaps.
  CellRange a_cells(const VoxelGrid& ga, int i, int j, int k) const;
  double grow = 0;
};
VoxelMapping map_voxels(const VoxelGrid& ga, const Pose& pose_a, const VoxelGrid& gb, const Pose& pose_b,
                        double grow);

// Fills `out` (cleared first) with every pair (vA, vB) of non-empty voxels such that vB's box
// mapped into A's frame and grown by `grow` overlaps vA, both within their sub-matrices.
void collect_voxel_pairs(const VoxelGrid& ga, const Pose& pose_a, const VoxelGrid& gb, const Pose& pose_b,
                         double grow, std::vector<VoxelPair>& out);

}  // namespace asimov::collision
