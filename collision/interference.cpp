#include "collision/interference.hpp"

namespace asimov::collision {

SubMatrices interference_sub_matrices(const VoxelGrid& ga, const Pose& pose_a, const VoxelGrid& gb,
                                      const Pose& pose_b, double grow) {
  const Pose a_from_b = pose_a.inverse(Eigen::Isometry) * pose_b;
  const Pose b_from_a = pose_b.inverse(Eigen::Isometry) * pose_a;
  return {cell_range(ga, grown(minimax_box(gb.container, a_from_b), grow)),
          cell_range(gb, grown(minimax_box(ga.container, b_from_a), grow))};
}

void collect_voxel_pairs(const VoxelGrid& ga, const Pose& pose_a, const VoxelGrid& gb, const Pose& pose_b,
                         double grow, std::vector<VoxelPair>& out) {
  out.clear();
  const SubMatrices sub = interference_sub_matrices(ga, pose_a, gb, pose_b, grow);
  if (sub.a.empty() || sub.b.empty()) return;
  const Pose a_from_b = pose_a.inverse(Eigen::Isometry) * pose_b;
  const Mat3 r = a_from_b.linear();
  // B's voxel edges in A's frame are the same for every voxel: the minimax offsets of one
  // voxel are computed once, and each voxel's corner is base + i dx + j dy + k dz.
  const Vec3 dx = r.col(0) * gb.cell.x(), dy = r.col(1) * gb.cell.y(), dz = r.col(2) * gb.cell.z();
  const Vec3 lo_off = dx.cwiseMin(0.0) + dy.cwiseMin(0.0) + dz.cwiseMin(0.0) - Vec3::Constant(grow);
  const Vec3 hi_off = dx.cwiseMax(0.0) + dy.cwiseMax(0.0) + dz.cwiseMax(0.0) + Vec3::Constant(grow);
  const Vec3 base = a_from_b * gb.container.origin;
  for (int k = sub.b.lo[2]; k <= sub.b.hi[2]; ++k)
    for (int j = sub.b.lo[1]; j <= sub.b.hi[1]; ++j)
      for (int i = sub.b.lo[0]; i <= sub.b.hi[0]; ++i) {
        const std::size_t vb = gb.index(i, j, k);
        if (gb.voxel_empty(vb)) continue;
        const Vec3 corner = base + static_cast<double>(i) * dx + static_cast<double>(j) * dy + static_cast<double>(k) * dz;
        const CellRange ra = intersect(cell_range(ga, Box{corner + lo_off, corner + hi_off}), sub.a);
        for (int kk = ra.lo[2]; kk <= ra.hi[2]; ++kk)
          for (int jj = ra.lo[1]; jj <= ra.hi[1]; ++jj)
            for (int ii = ra.lo[0]; ii <= ra.hi[0]; ++ii) {
              const std::size_t va = ga.index(ii, jj, kk);
              if (!ga.voxel_empty(va)) out.push_back({static_cast<std::uint32_t>(va), static_cast<std::uint32_t>(vb)});
            }
      }
}

}  // namespace asimov::collision
