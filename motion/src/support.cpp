// Resting geometry without physics (docs/cell-format.md "Resting contact"): vertical gaps from a
// part down to the bodies below it.
#include "asimov/motion/support.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace asimov::motion {
namespace {
using collision::Vec3;

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

// Least vertical gap (>= -eps) from points down (points_above) or up to the faces.
void vertex_face(const std::vector<Vec3>& pts, const Posed& faces, bool points_above, double eps, double& best) {
  for (const auto& p : pts) {
    if (p.x() < faces.lo.x() || p.x() > faces.hi.x() || p.y() < faces.lo.y() || p.y() > faces.hi.y()) continue;
    for (const auto& t : *faces.tris) {
      const auto z = z_at(faces.v[t[0]], faces.v[t[1]], faces.v[t[2]], p.x(), p.y());
      if (!z) continue;
      const double d = points_above ? p.z() - *z : *z - p.z();
      if (d >= -eps) best = std::min(best, std::max(0.0, d));
    }
  }
}

void edge_edge(const Posed& part, const Posed& support, double eps, double& best) {
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
      if (d >= -eps) best = std::min(best, std::max(0.0, d));
    });
  });
}

std::optional<double> gap(const Posed& p, const Support& s, double tolerance_mm) {
  const Posed q = posed(*s.mesh, s.pose);
  // Only supports under the part's footprint.
  if (q.hi.x() < p.lo.x() || q.lo.x() > p.hi.x() || q.hi.y() < p.lo.y() || q.lo.y() > p.hi.y()) return std::nullopt;
  // A support reaches lower than the part: one whose lowest point is not below the part's (a
  // part resting on this one, a part beside it on the same table) does not carry it.
  if (q.lo.z() >= p.lo.z()) return std::nullopt;
  // Rounding of the posed coordinates: a part set down exactly on a support is within it.
  const double eps = tolerance_mm + 1e-9 + 1e-14 * std::max(p.hi.cwiseAbs().maxCoeff(), p.lo.cwiseAbs().maxCoeff());
  double best = std::numeric_limits<double>::infinity();
  vertex_face(p.v, q, true, eps, best);
  vertex_face(q.v, p, false, eps, best);
  edge_edge(p, q, eps, best);
  if (!std::isfinite(best)) return std::nullopt;
  return best;
}
}  // namespace

double resting_tolerance(const collision::Polyhedron& mesh) {
  if (mesh.vertices.empty()) return 0;
  Vec3 lo = mesh.vertices.front(), hi = lo;
  for (const auto& v : mesh.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
  return kRestingRelative * (hi - lo).norm();
}

std::optional<double> gap_below(const collision::Polyhedron& part, const Location& pose, const Support& support,
                                double tolerance_mm) {
  return gap(posed(part, pose), support, tolerance_mm);
}

std::optional<double> drop_distance(const collision::Polyhedron& part, const Location& pose,
                                    std::span<const Support> supports, double tolerance_mm) {
  const Posed p = posed(part, pose);
  std::optional<double> best;
  for (const auto& s : supports)
    if (const auto g = gap(p, s, tolerance_mm); g && (!best || *g < *best)) best = g;
  return best;
}

std::vector<std::size_t> resting_on(const collision::Polyhedron& part, const Location& pose,
                                    std::span<const Support> supports, double tolerance_mm) {
  const Posed p = posed(part, pose);
  std::vector<std::size_t> out;
  for (std::size_t k = 0; k < supports.size(); ++k)
    if (const auto g = gap(p, supports[k], tolerance_mm); g && *g <= tolerance_mm) out.push_back(k);
  return out;
}

}  // namespace asimov::motion
