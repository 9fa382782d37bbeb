#include "collision/minimax.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>

namespace asimov::collision {

Container make_container(const std::vector<Vec3>& vertices) {
  Container c;
  if (vertices.empty()) return c;
  Vec3 lo = vertices.front(), hi = vertices.front();
  for (const Vec3& v : vertices) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  // Pad sides shorter than 1e-6 of the diagonal (a flat plate still gets a grid), and grow
  // each rounded size until origin + size really reaches the largest coordinate.
  const double diag = (hi - lo).norm();
  const double min_side = diag > 0 ? 1e-6 * diag : 1e-6 * std::max(1.0, lo.cwiseAbs().maxCoeff());
  for (int k = 0; k < 3; ++k) {
    if (hi[k] - lo[k] < min_side) {
      const double mid = 0.5 * (lo[k] + hi[k]);
      lo[k] = std::min(lo[k], mid - min_side);
      hi[k] = std::max(hi[k], mid + min_side);
    }
    c.origin[k] = lo[k];
    double s = hi[k] - lo[k];
    while (lo[k] + s < hi[k]) s = std::nextafter(s, INFINITY);
    c.size[k] = s;
  }
  c.scale = std::max(lo.cwiseAbs().maxCoeff(), (lo + c.size).cwiseAbs().maxCoeff());
  return c;
}

Box minimax_box(const Container& c, const Pose& pose) {
  const Mat3 r = pose.linear();
  const Vec3 o = pose * c.origin;
  Box b{o, o};
  for (int k = 0; k < 3; ++k) {
    const Vec3 v = r.col(k) * c.size[k];
    b.lo += v.cwiseMin(0.0);
    b.hi += v.cwiseMax(0.0);
  }
  return b;
}

Box grown(const Box& b, double margin) {
  return {(b.lo.array() - margin).matrix(), (b.hi.array() + margin).matrix()};
}

bool separated(const Box& a, const Box& b, double margin) {
  for (int k = 0; k < 3; ++k)
    if (a.lo[k] > b.hi[k] + margin || b.lo[k] > a.hi[k] + margin) return true;
  return false;
}

double box_gap(const Box& a, const Box& b) {
  double gap = 0;
  for (int k = 0; k < 3; ++k) gap = std::max({gap, a.lo[k] - b.hi[k], b.lo[k] - a.hi[k]});
  return gap;
}

double relative_margin(const Container& a, const Pose& pose_a, const Container& b, const Pose& pose_b) {
  // Each mapped coordinate carries a few ulps of (|t| + sqrt(3) * scale); a pair mapping
  // world -> local -> other local compounds a handful of those. 64 ulps covers it with room.
  const double magnitude = pose_a.translation().cwiseAbs().maxCoeff() + pose_b.translation().cwiseAbs().maxCoeff() +
                           2 * (a.scale + b.scale);
  return 64 * DBL_EPSILON * magnitude;
}

}  // namespace asimov::collision
