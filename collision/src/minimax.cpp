#include "minimax.hpp"

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
  const Vec3 centre = c.centre();
  double r2 = 0;
  for (const Vec3& v : vertices) r2 = std::max(r2, (v - centre).squaredNorm());
  // Rounded up past the rounding of the squared norms (a few ulps), with room.
  c.radius = std::sqrt(r2) * (1 + 64 * DBL_EPSILON);
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
  // Scalar, branch-free within the six face axes and within the nine edge axes (the early
  // exits per axis mispredicted on random poses and cost more than the arithmetic).
  double r[3][3], ar[3][3], ha[3], hb[3], cb[3], t[3];
  for (int i = 0; i < 3; ++i) {
    ha[i] = 0.5 * a.size[i];
    hb[i] = 0.5 * b.size[i];
  }
  double mag_a = 0, mag_b = 0, mag_h = 0;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      r[i][j] = a_from_b.linear()(i, j);  // B's axes in A's frame
      ar[i][j] = std::fabs(r[i][j]) + 256 * DBL_EPSILON;
    }
  }
  for (int i = 0; i < 3; ++i) {
    cb[i] = a_from_b.translation()[i];
    for (int j = 0; j < 3; ++j) cb[i] += r[i][j] * (b.origin[j] + hb[j]);
    const double ca = a.origin[i] + ha[i];
    t[i] = cb[i] - ca;
    mag_a = std::max(mag_a, std::fabs(ca));
    mag_b = std::max(mag_b, std::fabs(cb[i]));
    mag_h = std::max({mag_h, ha[i], hb[i]});
  }
  // Rounding slack: a few ulps of every magnitude in play (centres, half sizes), with room.
  const double slack = grow + 256 * DBL_EPSILON * (mag_a + mag_b + 2 * mag_h);
  bool apart = false;
  for (int i = 0; i < 3; ++i)  // A's axes
    apart |= std::fabs(t[i]) > ha[i] + ar[i][0] * hb[0] + ar[i][1] * hb[1] + ar[i][2] * hb[2] + slack;
  for (int j = 0; j < 3; ++j)  // B's axes
    apart |= std::fabs(r[0][j] * t[0] + r[1][j] * t[1] + r[2][j] * t[2]) >
             ar[0][j] * ha[0] + ar[1][j] * ha[1] + ar[2][j] * ha[2] + hb[j] + slack;
  if (apart) return true;
  for (int i = 0; i < 3; ++i) {  // A_i x B_j
    const int i1 = (i + 1) % 3, i2 = (i + 2) % 3;
    for (int j = 0; j < 3; ++j) {
      const int j1 = (j + 1) % 3, j2 = (j + 2) % 3;
      const double d = std::fabs(t[i2] * r[i1][j] - t[i1] * r[i2][j]);
      const double ra = ha[i1] * ar[i2][j] + ha[i2] * ar[i1][j];
      const double rb = hb[j1] * ar[i][j2] + hb[j2] * ar[i][j1];
      // The axis has length sin(angle) <= 1: compare unnormalised, slack scaled the same way
      // (for a near-zero axis both sides vanish and the test cannot separate).
      apart |= d > ra + rb + slack;
    }
  }
  return apart;
}

bool spheres_separated(const Vec3& centre_a, double radius_a, const Vec3& centre_b, double radius_b, double grow) {
  const double reach = radius_a + radius_b + grow;
  // The squared distance and the squared reach carry a few ulps each: 16 ulps of room.
  return (centre_a - centre_b).squaredNorm() > reach * reach * (1 + 16 * DBL_EPSILON);
}

double box_gap(const Box& a, const Box& b) {
  double gap = 0;
  for (int k = 0; k < 3; ++k) gap = std::max({gap, a.lo[k] - b.hi[k], b.lo[k] - a.hi[k]});
  return gap;
}


}  // namespace asimov::collision
