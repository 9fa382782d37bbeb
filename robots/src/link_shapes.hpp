// Box and cylinder pieces of the built-in arms' link bodies, placed in a link frame.
#pragma once
#include "asimov/robots/robot.hpp"

#include <Eigen/Geometry>
#include <numbers>

namespace asimov::robots::shapes {
constexpr int kSegments = 16;  // sides of a link cylinder (coarse bodies, as the PUMA's)

using collision::make_box;
using collision::make_cylinder;
using collision::Polyhedron;
using collision::transformed;

inline Pose translation(double x, double y, double z) {
  Pose p = Pose::Identity();
  p.translation() = Vec3(x, y, z);
  return p;
}

// Box with corners lo and hi (axis-aligned in the link frame).
inline Polyhedron box(const Vec3& lo, const Vec3& hi) {
  return transformed(make_box(hi - lo), translation(((lo + hi) / 2).x(), ((lo + hi) / 2).y(), ((lo + hi) / 2).z()));
}

// Cylinder of `radius` along local axis `axis` (0 = X, 1 = Y, 2 = Z) from `from` to `to` along
// that axis, its axis passing through (u, v) in the other two coordinates (in X, Y, Z order).
inline Polyhedron cylinder(int axis, double radius, double from, double to, double u = 0, double v = 0,
                           int segments = kSegments) {
  Polyhedron c = make_cylinder(radius, to - from, segments);
  Pose p = Pose::Identity();
  const double mid = (from + to) / 2;
  if (axis == 2) {
    p.translation() = Vec3(u, v, mid);
  } else if (axis == 1) {  // local Z -> +Y
    p.linear() = Eigen::AngleAxisd(-std::numbers::pi / 2, Vec3::UnitX()).toRotationMatrix();
    p.translation() = Vec3(u, mid, v);
  } else {  // local Z -> +X
    p.linear() = Eigen::AngleAxisd(std::numbers::pi / 2, Vec3::UnitY()).toRotationMatrix();
    p.translation() = Vec3(mid, u, v);
  }
  return transformed(c, p);
}

// Display ranges and maximum speeds of a built-in arm; accelerations 4x the speed per second
// (the ratio of docs/kinematics.md §3, a decision).
inline void set_ranges_and_speeds(Robot& r, const double* lo, const double* hi, const double* speed, int n) {
  r.lower.resize(n), r.upper.resize(n), r.max_velocity.resize(n), r.max_acceleration.resize(n);
  for (int i = 0; i < n; ++i) {
    r.lower[i] = lo[i], r.upper[i] = hi[i];
    r.max_velocity[i] = speed[i];
    r.max_acceleration[i] = 4 * speed[i];
  }
}

}  // namespace asimov::robots::shapes
