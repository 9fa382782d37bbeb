#include "container_gap.hpp"

#include "asimov/collision/gap_bound.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>

namespace asimov::collision {


PlacedContainer place(const Container& c, const Pose& pose) {
  return {minimax_box(c, pose), pose * c.centre(), c.radius};
}


double container_gap(const Container& a, const Pose& pose_a, const Container& b, const Pose& pose_b) {
  return container_gap(place(a, pose_a), place(b, pose_b), relative_margin(a, pose_a, b, pose_b));
}

// As container_gap, without its clamp at 0 (a bound may be negative: the pair may touch).
double gap_bound(const Engine::PlacedBounds& a, const Engine::PlacedBounds& b) {
  const double spheres = (a.centre - b.centre).norm() - a.radius - b.radius;
  return std::max(box_distance(Box{a.lo, a.hi}, Box{b.lo, b.hi}), spheres) - relative_margin(a.magnitude, b.magnitude);
}

double gap_bound(const Engine::PlacedBounds& a, const Vec3& lo, const Vec3& hi, double share) {
  return box_distance(Box{a.lo, a.hi}, Box{lo, hi}) - relative_margin(a.magnitude, share);
}

}  // namespace asimov::collision

namespace asimov::collision {

double hull_gap(std::span<const Vec3> a, std::span<const Vec3> b, const Pose& a_from_b, double slack, double enough,
                int iterations, double stop, Vec3* guess) {
  if (a.empty() || b.empty()) return 0;
  const Mat3 r = a_from_b.linear();
  const Vec3 t = a_from_b.translation();
  // Each projection n.p carries a few ulps of |p| (|n| = 1 up to an ulp), B's also of the
  // mapping (within `slack`, the pair's margin, as for the containers). The magnitudes are
  // taken in the first pass over the vertices (a warm start is often the only one).
  double mag_a = 0, mag_b = 0, room = 0;
  // v: a point of the difference set A - B (its norm bounds the hull distance from above).
  Vec3 v = a[0] - (r * b[0] + t);
  double best = -INFINITY;
  Vec3 best_n = Vec3::Zero();
  // The warm start: a direction, not a point of A - B, so its pass only bounds and then starts
  // Gilbert's iteration at its support point (a point of A - B).
  const double gn = guess ? guess->norm() : 0.0;
  bool warm = gn > 0 && std::isfinite(gn);
  for (int it = 0; it < iterations; ++it) {
    const double vn = warm ? INFINITY : v.norm();
    if (!(vn > 0)) break;
    const Vec3 n = warm ? Vec3(*guess / gn) : Vec3(v / vn);
    // The support point of A - B in direction -n: A's vertex least along n, B's farthest.
    const Vec3 nb = r.transpose() * n;  // n in B's frame
    std::size_t ia = 0, ib = 0;
    double min_a = INFINITY, max_b = -INFINITY;
    if (it == 0) {
      for (std::size_t i = 0; i < a.size(); ++i) {
        mag_a = std::max(mag_a, a[i].cwiseAbs().maxCoeff());
        if (const double p = n.dot(a[i]); p < min_a) min_a = p, ia = i;
      }
      for (std::size_t i = 0; i < b.size(); ++i) {
        mag_b = std::max(mag_b, b[i].cwiseAbs().maxCoeff());
        if (const double p = nb.dot(b[i]); p > max_b) max_b = p, ib = i;
      }
      room = slack + 16 * DBL_EPSILON * (mag_a + mag_b + t.cwiseAbs().maxCoeff());
    } else {
      for (std::size_t i = 0; i < a.size(); ++i)
        if (const double p = n.dot(a[i]); p < min_a) min_a = p, ia = i;
      for (std::size_t i = 0; i < b.size(); ++i)
        if (const double p = nb.dot(b[i]); p > max_b) max_b = p, ib = i;
    }
    const double bound = min_a - (max_b + n.dot(t)) - room;
    if (bound > best) best = bound, best_n = n;
    if (warm) {
      warm = false;
      // The warm direction was (nearly) the best one: past `stop` the caller's question is
      // answered, and Gilbert's slow approach to the last 1e-3 would gain little.
      // Far below `stop` it is a near pair the hulls will not prove apart (the caller measures
      // it): the warm bound is returned without the iterations.
      if (best >= enough || (stop > 0 && (best >= stop || best < 0.5 * stop))) break;
      v = a[ia] - (r * b[ib] + t);
      continue;
    }
    // Done: the bound is enough, or near the hull distance (which is <= |v|), or cannot get
    // to `enough` any more.
    if (best >= enough || vn - bound <= 1e-3 * vn || vn < stop) break;
    // Gilbert's step: the point of the segment [v, w] nearest the origin.
    const Vec3 w = a[ia] - (r * b[ib] + t);
    const Vec3 d = w - v;
    const double dd = d.squaredNorm();
    if (!(dd > 0)) break;
    const double s = std::clamp(-v.dot(d) / dd, 0.0, 1.0);
    if (s == 0) break;  // no progress: v is the nearest point the iteration finds
    v += s * d;
  }
  if (guess && best_n.squaredNorm() > 0) *guess = best_n;
  return best;
}

}  // namespace asimov::collision
