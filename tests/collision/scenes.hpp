// Shared meshes and random poses for the collision tests (fixed seeds everywhere).
#pragma once
#include "asimov/collision/polyhedron.hpp"

#include <cmath>
#include <random>

namespace asimov::collision::test {

// A closed prism over the L-shaped polygon (non-convex), z in [0, h].
inline Polyhedron make_l_prism(double a, double t, double h) {
  const double xy[6][2] = {{0, 0}, {a, 0}, {a, t}, {t, t}, {t, a}, {0, a}};
  Polyhedron p;
  for (double z : {0.0, h})
    for (const auto& q : xy) p.vertices.emplace_back(q[0], q[1], z);
  // Caps: a fan from the reflex vertex 3, which sees the whole polygon.
  for (std::uint32_t i : {4u, 5u, 0u, 1u}) {
    const std::uint32_t j = (i + 1) % 6;
    p.triangles.push_back({3 + 6, i + 6, j + 6});  // top, counter-clockwise from +z
    p.triangles.push_back({3, j, i});              // bottom, reversed
  }
  for (std::uint32_t i = 0; i < 6; ++i) {
    const std::uint32_t j = (i + 1) % 6;
    p.triangles.push_back({i, j, j + 6});
    p.triangles.push_back({i, j + 6, i + 6});
  }
  return p;
}

// Non-convex, two shells: an L prism with a cylinder standing in its notch.
inline Polyhedron make_merged_part() {
  Pose at = Pose::Identity();
  at.translation() = Vec3(-20, -20, -10);
  Pose post = Pose::Identity();
  post.translation() = Vec3(8, 8, 12);
  return merged(transformed(make_l_prism(40, 10, 20), at), transformed(make_cylinder(6, 24, 8), post));
}

inline Pose random_pose(std::mt19937_64& rng, double reach) {
  std::normal_distribution<double> n(0, 1);
  std::uniform_real_distribution<double> u(-reach, reach);
  Eigen::Quaterniond q(n(rng), n(rng), n(rng), n(rng));
  q.normalize();
  Pose p = Pose::Identity();
  p.linear() = q.toRotationMatrix();
  p.translation() = Vec3(u(rng), u(rng), u(rng));
  return p;
}

}  // namespace asimov::collision::test
