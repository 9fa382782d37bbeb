#include "asimov/motion/parts.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace asimov::motion {
namespace {
using collision::Vec3;
// Contact tolerance of the drop [mm]: a part resting within it counts as touching.
constexpr double kEps = 1e-9;

struct Posed {
  std::vector<Vec3> v;
  const std::vector<collision::Triangle>* tris;
  Vec3 lo, hi;
};

Posed posed(const collision::Polyhedron& m, const Location& pose) {
  Posed p{{}, &m.triangles, Vec3::Constant(std::numeric_limits<double>::infinity()),
          Vec3::Constant(-std::numeric_limits<double>::infinity())};
  p.v.reserve(m.vertices.size());
  for (const auto& x : m.vertices) {
    p.v.push_back(pose * x);
    p.lo = p.lo.cwiseMin(p.v.back()), p.hi = p.hi.cwiseMax(p.v.back());
  }
  return p;
}

// z of triangle (a, b, c) above/below the vertical line through (x, y); nullopt when the line
// misses it (closed triangle) or the triangle is vertical.
std::optional<double> z_at(const Vec3& a, const Vec3& b, const Vec3& c, double x, double y) {
  const double d = (b.x() - a.x()) * (c.y() - a.y()) - (c.x() - a.x()) * (b.y() - a.y());
  if (std::abs(d) < 1e-12) return std::nullopt;
  const double l1 = ((b.x() - x) * (c.y() - y) - (c.x() - x) * (b.y() - y)) / d;
  const double l2 = ((c.x() - x) * (a.y() - y) - (a.x() - x) * (c.y() - y)) / d;
  const double l3 = 1 - l1 - l2;
  constexpr double tol = -1e-12;
  if (l1 < tol || l2 < tol || l3 < tol) return std::nullopt;
  return l1 * a.z() + l2 * b.z() + l3 * c.z();
}

// Least non-negative vertical gap from points of `upper` down to faces of `lower`.
void vertex_face(const std::vector<Vec3>& pts, const Posed& faces, bool points_above, double& best) {
  for (const auto& p : pts) {
    if (p.x() < faces.lo.x() || p.x() > faces.hi.x() || p.y() < faces.lo.y() || p.y() > faces.hi.y()) continue;
    for (const auto& t : *faces.tris) {
      const auto z = z_at(faces.v[t[0]], faces.v[t[1]], faces.v[t[2]], p.x(), p.y());
      if (!z) continue;
      const double d = points_above ? p.z() - *z : *z - p.z();
      if (d >= -kEps) best = std::min(best, std::max(0.0, d));
    }
  }
}

void edge_edge(const Posed& part, const Posed& support, double& best) {
  const auto edges = [](const Posed& p, auto&& f) {
    for (const auto& t : *p.tris)
      for (int k = 0; k < 3; ++k) f(p.v[t[k]], p.v[t[(k + 1) % 3]]);
  };
  edges(part, [&](const Vec3& p1, const Vec3& p2) {
    edges(support, [&](const Vec3& s1, const Vec3& s2) {
      const double rx = p2.x() - p1.x(), ry = p2.y() - p1.y(), sx = s2.x() - s1.x(), sy = s2.y() - s1.y();
      const double den = rx * sy - ry * sx;
      if (std::abs(den) < 1e-12) return;
      const double qx = s1.x() - p1.x(), qy = s1.y() - p1.y();
      const double u = (qx * sy - qy * sx) / den, v = (qx * ry - qy * rx) / den;
      if (u < 0 || u > 1 || v < 0 || v > 1) return;
      const double d = (p1.z() + u * (p2.z() - p1.z())) - (s1.z() + v * (s2.z() - s1.z()));
      if (d >= -kEps) best = std::min(best, std::max(0.0, d));
    });
  });
}
}  // namespace

std::optional<std::size_t> grasp_candidate(const DeviceClock& clock, const Region& zone_world) {
  std::optional<std::size_t> best;
  double best_d = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < clock.parts().size(); ++i) {
    const Holder h = clock.parts()[i].holder;
    if (h != Holder::world && h != Holder::conveyor) continue;
    const Vec3 o = clock.part_pose(i).translation();
    if (!zone_world.contains(o)) continue;
    const double d = (o - zone_world.pose.translation()).norm();
    if (d < best_d) best = i, best_d = d;
  }
  return best;
}

std::optional<double> drop_distance(const collision::Polyhedron& part, const Location& pose,
                                    std::span<const Support> supports) {
  const Posed p = posed(part, pose);
  double best = std::numeric_limits<double>::infinity();
  for (const auto& s : supports) {
    const Posed q = posed(*s.mesh, s.pose);
    // Only supports under the part's footprint and not wholly above its lowest point.
    if (q.hi.x() < p.lo.x() || q.lo.x() > p.hi.x() || q.hi.y() < p.lo.y() || q.lo.y() > p.hi.y()) continue;
    if (q.lo.z() > p.hi.z()) continue;
    vertex_face(p.v, q, true, best);
    vertex_face(q.v, p, false, best);
    edge_edge(p, q, best);
  }
  if (!std::isfinite(best)) return std::nullopt;
  return best;
}

}  // namespace asimov::motion
