#include "asimov/collision/polyhedron.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace asimov::collision {

Polyhedron make_box(const Vec3& size) {
  const Vec3 h = size / 2;
  Polyhedron p;
  for (int i = 0; i < 8; ++i)
    p.vertices.emplace_back((i & 1) ? h.x() : -h.x(), (i & 2) ? h.y() : -h.y(), (i & 4) ? h.z() : -h.z());
  // Two triangles per face, outward normals.
  p.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                 {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  return p;
}

Polyhedron make_cylinder(double radius, double height, int segments) {
  segments = std::max(segments, 3);  // fewer sides would not enclose a volume
  Polyhedron p;
  const double h = height / 2;
  for (int i = 0; i < segments; ++i) {
    const double a = 2 * std::numbers::pi * i / segments;
    p.vertices.emplace_back(radius * std::cos(a), radius * std::sin(a), -h);
    p.vertices.emplace_back(radius * std::cos(a), radius * std::sin(a), h);
  }
  const auto bottom_centre = static_cast<std::uint32_t>(p.vertices.size());
  p.vertices.emplace_back(0, 0, -h);
  p.vertices.emplace_back(0, 0, h);
  const std::uint32_t top_centre = bottom_centre + 1;
  for (int i = 0; i < segments; ++i) {
    const auto b0 = static_cast<std::uint32_t>(2 * i), t0 = b0 + 1;
    const auto b1 = static_cast<std::uint32_t>(2 * ((i + 1) % segments)), t1 = b1 + 1;
    p.triangles.push_back({b0, b1, t1});
    p.triangles.push_back({b0, t1, t0});
    p.triangles.push_back({bottom_centre, b1, b0});
    p.triangles.push_back({top_centre, t0, t1});
  }
  return p;
}

Polyhedron transformed(const Polyhedron& mesh, const Pose& pose) {
  Polyhedron p;
  p.triangles = mesh.triangles;
  transform_vertices(mesh.vertices, pose, p.vertices);
  return p;
}

Polyhedron merged(const Polyhedron& a, const Polyhedron& b) {
  Polyhedron p = a;
  const auto shift = static_cast<std::uint32_t>(a.vertices.size());
  p.vertices.insert(p.vertices.end(), b.vertices.begin(), b.vertices.end());
  for (const auto& t : b.triangles) p.triangles.push_back({t[0] + shift, t[1] + shift, t[2] + shift});
  return p;
}

void transform_vertices(const std::vector<Vec3>& vertices, const Pose& pose, std::vector<Vec3>& out) {
  out.resize(vertices.size());
  for (std::size_t i = 0; i < vertices.size(); ++i) out[i] = transform_vertex(pose, vertices[i]);
}

Vec3 transform_vertex(const Pose& pose, const Vec3& v) {
  const Mat3 r = pose.linear();
  const Vec3& t = pose.translation();
  // Written out so the rounding is fixed: ((r0 x + r1 y) + r2 z) + t, no contraction.
  return Vec3(((r(0, 0) * v.x() + r(0, 1) * v.y()) + r(0, 2) * v.z()) + t.x(),
              ((r(1, 0) * v.x() + r(1, 1) * v.y()) + r(1, 2) * v.z()) + t.y(),
              ((r(2, 0) * v.x() + r(2, 1) * v.y()) + r(2, 2) * v.z()) + t.z());
}

}  // namespace asimov::collision
