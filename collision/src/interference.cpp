#include "interference.hpp"

#include "minimax.hpp"

namespace asimov::collision {

SubMatrices interference_sub_matrices(const VoxelGrid& ga, const Pose& pose_a, const VoxelGrid& gb,
                                      const Pose& pose_b, double grow) {
  const Pose a_from_b = pose_a.inverse(Eigen::Isometry) * pose_b;
  const Pose b_from_a = pose_b.inverse(Eigen::Isometry) * pose_a;
  return {cell_range(ga, grown(minimax_box(gb.container, a_from_b), grow)),
          cell_range(gb, grown(minimax_box(ga.container, b_from_a), grow))};
}

VoxelMapping map_voxels(const VoxelGrid& ga, const Pose& pose_a, const VoxelGrid& gb, const Pose& pose_b,
                        double grow) {
  VoxelMapping m;
  m.sub = interference_sub_matrices(ga, pose_a, gb, pose_b, grow);
  if (m.empty()) return m;
  const Pose a_from_b = pose_a.inverse(Eigen::Isometry) * pose_b;
  const Mat3 r = a_from_b.linear();
  m.dx = r.col(0) * gb.cell.x();
  m.dy = r.col(1) * gb.cell.y();
  m.dz = r.col(2) * gb.cell.z();
  m.lo_off = m.dx.cwiseMin(0.0) + m.dy.cwiseMin(0.0) + m.dz.cwiseMin(0.0) - Vec3::Constant(grow);
  m.hi_off = m.dx.cwiseMax(0.0) + m.dy.cwiseMax(0.0) + m.dz.cwiseMax(0.0) + Vec3::Constant(grow);
  m.base = a_from_b * gb.container.origin;
  m.grow = grow;
  return m;
}

CellRange VoxelMapping::a_cells(const VoxelGrid& ga, int i, int j, int k) const {
  const Vec3 corner = base + static_cast<double>(i) * dx + static_cast<double>(j) * dy + static_cast<double>(k) * dz;
  return intersect(cell_range(ga, Box{corner + lo_off, corner + hi_off}), sub.a);
}

void collect_voxel_pairs(const VoxelGrid& ga, const Pose& pose_a, const VoxelGrid& gb, const Pose& pose_b,
                         double grow, std::vector<VoxelPair>& out) {
  out.clear();
  const VoxelMapping m = map_voxels(ga, pose_a, gb, pose_b, grow);
  if (m.empty()) return;
  for (int k = m.sub.b.lo[2]; k <= m.sub.b.hi[2]; ++k)
    for (int j = m.sub.b.lo[1]; j <= m.sub.b.hi[1]; ++j)
      for (int i = m.sub.b.lo[0]; i <= m.sub.b.hi[0]; ++i) {
        const std::size_t vb = gb.index(i, j, k);
        if (gb.voxel_empty(vb)) continue;
        const CellRange ra = m.a_cells(ga, i, j, k);
        for (int kk = ra.lo[2]; kk <= ra.hi[2]; ++kk)
          for (int jj = ra.lo[1]; jj <= ra.hi[1]; ++jj)
            for (int ii = ra.lo[0]; ii <= ra.hi[0]; ++ii) {
              const std::size_t va = ga.index(ii, jj, kk);
              if (!ga.voxel_empty(va)) out.push_back({static_cast<std::uint32_t>(va), static_cast<std::uint32_t>(vb)});
            }
      }
}

}  // namespace asimov::collision
