// Independent geometry for test oracles (deliberately not the engine's code).
#pragma once
#include "asimov/collision/polyhedron.hpp"
#include <algorithm>
#include <limits>

namespace asimov::test {

using collision::Vec3;

// An axis-aligned box from its corner coordinates (outward triangles).
inline collision::Polyhedron box_between(const Vec3& lo, const Vec3& hi) {
  collision::Polyhedron b = collision::make_box(hi - lo);
  for (auto& v : b.vertices)
    v = Vec3(v.x() < 0 ? lo.x() : hi.x(), v.y() < 0 ? lo.y() : hi.y(), v.z() < 0 ? lo.z() : hi.z());
  return b;
}

// Distance from p to triangle abc (Ericson, Real-Time Collision Detection, 5.1.5).
inline double point_triangle_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return (p - a).norm();
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return (p - b).norm();
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return (p - (a + ab * (d1 / (d1 - d3)))).norm();
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return (p - c).norm();
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return (p - (a + ac * (d2 / (d2 - d6)))).norm();
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
    return (p - (b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6))))).norm();
  const double denom = 1 / (va + vb + vc);
  return (p - (a + ab * (vb * denom) + ac * (vc * denom))).norm();
}

// Distance from world point p to the surface of `mesh` placed by `pose`.
inline double point_surface_distance(const Vec3& p, const collision::Polyhedron& mesh,
                                     const collision::Pose& pose) {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& t : mesh.triangles)
    best = std::min(best, point_triangle_distance(p, pose * mesh.vertices[t[0]], pose * mesh.vertices[t[1]],
                                                  pose * mesh.vertices[t[2]]));
  return best;
}

}  // namespace asimov::test
