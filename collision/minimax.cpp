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

Box basic_axes_box(const Vec3& origin, const Mat3& r, const Vec3& size, double grow) {
  Box b{origin - Vec3::Constant(grow), origin + Vec3::Constant(grow)};
  for (int k = 0; k < 3; ++k) {
    const Vec3 v = r.col(k) * size[k];
    b.lo += v.cwiseMin(0.0);
    b.hi += v.cwiseMax(0.0);
  }
  return b;
}

Box minimax_box(const Container& c, const Pose& pose) {
  return basic_axes_box(pose * c.origin, pose.linear(), c.size);
}

Box grown(const Box& b, double margin) {
  return {(b.lo.array() - margin).matrix(), (b.hi.array() + margin).matrix()};
}

bool separated(const Box& a, const Box& b, double margin) {
  for (int k = 0; k < 3; ++k)
    if (a.lo[k] > b.hi[k] + margin || b.lo[k] > a.hi[k] + margin) return true;
  return false;
}

Pose relative_pose(const Pose& pose_a, const Pose& pose_b) {
  // Written out: Eigen's inverse-then-product went through a 4x4 temporary (a fifth of a
  // step-3 query's fixed cost in the FCL benchmark).
  const Mat3& ra = pose_a.linear();
  const Mat3& rb = pose_b.linear();
  const Vec3 d = pose_b.translation() - pose_a.translation();
  Pose p;
  p.makeAffine();
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) p.linear()(i, j) = ra(0, i) * rb(0, j) + ra(1, i) * rb(1, j) + ra(2, i) * rb(2, j);
    p.translation()[i] = ra(0, i) * d[0] + ra(1, i) * d[1] + ra(2, i) * d[2];
  }
  return p;
}

bool containers_separated(const Container& a, const Container& b, const Pose& a_from_b, double grow) {
  const Vec3 ha = 0.5 * a.size, hb = 0.5 * b.size;
  const Mat3& r = a_from_b.linear();  // B's axes in A's frame
  const Vec3 ca = a.origin + ha, cb = r * (b.origin + hb) + a_from_b.translation();
  const Vec3 t = cb - ca;
  Mat3 ar = r.cwiseAbs();
  // Rounding slack: a few ulps of every magnitude in play (centres, half sizes), with room.
  const double mag = ca.cwiseAbs().maxCoeff() + cb.cwiseAbs().maxCoeff() + ha.maxCoeff() + hb.maxCoeff();
  const double slack = grow + 256 * DBL_EPSILON * mag;
  ar.array() += 256 * DBL_EPSILON;
  for (int i = 0; i < 3; ++i)  // A's axes
    if (std::fabs(t[i]) > ha[i] + ar.row(i).dot(hb) + slack) return true;
  for (int j = 0; j < 3; ++j)  // B's axes
    if (std::fabs(r.col(j).dot(t)) > ar.col(j).dot(ha) + hb[j] + slack) return true;
  for (int i = 0; i < 3; ++i)  // A_i x B_j
    for (int j = 0; j < 3; ++j) {
      const int i1 = (i + 1) % 3, i2 = (i + 2) % 3, j1 = (j + 1) % 3, j2 = (j + 2) % 3;
      const double d = std::fabs(t[i2] * r(i1, j) - t[i1] * r(i2, j));
      const double ra_ = ha[i1] * ar(i2, j) + ha[i2] * ar(i1, j);
      const double rb_ = hb[j1] * ar(i, j2) + hb[j2] * ar(i, j1);
      // The axis has length sin(angle) <= 1: compare unnormalised, slack scaled the same way
      // (for a near-zero axis both sides vanish and the test cannot separate).
      if (d > ra_ + rb_ + slack) return true;
    }
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
