#include "container_gap.hpp"

#include "asimov/collision/gap_bound.hpp"

#include <Eigen/LU>

#include <algorithm>
#include <array>
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

namespace {

// The point of the hull of the simplex p[0..k) (points of A - B, k <= 4, p[k - 1] the support
// point just added) nearest the origin, and the simplex reduced to the points that span it
// (GJK's sub-step). The nearest point lies inside one face holding the newest point, where its
// barycentric weights are all positive; those faces are tried (closed-form weights) and the
// nearest valid candidate kept. Each candidate is a convex combination of its points, so
// rounding can only give a point of the hull a little farther than the nearest, never one
// outside it. False when the origin is inside the tetrahedron (the hulls meet).
bool nearest_on_simplex(std::array<Vec3, 4>& p, int& k, Vec3& v) {
  double best = INFINITY;
  unsigned best_mask = 0;
  Vec3 best_v = Vec3::Zero();
  const int last = k - 1;
  const unsigned others = (1u << last) - 1;
  for (unsigned sub = 0; sub <= others; ++sub) {
    const unsigned mask = sub | (1u << last);
    std::array<int, 4> idx{};
    int m = 0;
    for (int i = 0; i < k; ++i)
      if (mask & (1u << i)) idx[static_cast<std::size_t>(m++)] = i;
    // Weights: min |q0 + sum mu_i e_i| with e_i = q_i - q0, G mu = -E^T q0 (G = E^T E).
    const Vec3& q0 = p[static_cast<std::size_t>(idx[0])];
    std::array<Vec3, 3> e;
    for (int i = 1; i < m; ++i)
      e[static_cast<std::size_t>(i - 1)] = p[static_cast<std::size_t>(idx[static_cast<std::size_t>(i)])] - q0;
    std::array<double, 4> w{1, 0, 0, 0};
    if (m == 2) {
      const double g = e[0].squaredNorm();
      if (!(g > 0)) continue;
      w[1] = -e[0].dot(q0) / g;
    } else if (m == 3) {
      const double g00 = e[0].squaredNorm(), g01 = e[0].dot(e[1]), g11 = e[1].squaredNorm();
      const double r0 = -e[0].dot(q0), r1 = -e[1].dot(q0);
      const double det = g00 * g11 - g01 * g01;
      if (!(det > 1e-14 * g00 * g11)) continue;  // flat: a segment covers it
      w[1] = (g11 * r0 - g01 * r1) / det;
      w[2] = (g00 * r1 - g01 * r0) / det;
    } else if (m == 4) {
      Mat3 g;
      Vec3 r;
      for (int i = 0; i < 3; ++i) {
        r[i] = -e[static_cast<std::size_t>(i)].dot(q0);
        for (int j = 0; j < 3; ++j) g(i, j) = e[static_cast<std::size_t>(i)].dot(e[static_cast<std::size_t>(j)]);
      }
      const double det = g.determinant();
      if (!(det > 1e-14 * g(0, 0) * g(1, 1) * g(2, 2))) continue;  // flat: a triangle covers it
      const Vec3 mu = g.inverse() * r;
      for (int i = 0; i < 3; ++i) w[static_cast<std::size_t>(i + 1)] = mu[i];
    }
    double sum = 0;
    bool inside = true;
    for (int i = 1; i < m; ++i) {
      sum += w[static_cast<std::size_t>(i)];
      inside = inside && w[static_cast<std::size_t>(i)] > 0;
    }
    w[0] = 1 - sum;
    if (!inside || !(w[0] > 0)) continue;
    if (m == 4) return false;  // the origin is inside the tetrahedron
    Vec3 x = Vec3::Zero();
    for (int i = 0; i < m; ++i) x += w[static_cast<std::size_t>(i)] * p[static_cast<std::size_t>(idx[static_cast<std::size_t>(i)])];
    if (const double xx = x.squaredNorm(); xx < best) best = xx, best_mask = mask, best_v = x;
  }
  if (best_mask == 0) return false;  // only with NaN coordinates (a single point is always valid)
  int n = 0;
  for (int i = 0; i < k; ++i)
    if (best_mask & (1u << i)) p[static_cast<std::size_t>(n++)] = p[static_cast<std::size_t>(i)];
  k = n;
  v = best_v;
  return true;
}

}  // namespace

double hull_gap(std::span<const Vec3> a, std::span<const Vec3> b, const Pose& a_from_b, double slack, double enough,
                int iterations, double stop, Vec3* guess) {
  if (a.empty() || b.empty()) return 0;
  const Mat3 r = a_from_b.linear();
  const Vec3 t = a_from_b.translation();
  // Each projection n.p carries a few ulps of |p| (|n| = 1 up to an ulp), B's also of the
  // mapping (within `slack`, the pair's margin, as for the containers). The magnitudes are
  // taken in the first pass over the vertices (a warm start is often the only one).
  double mag_a = 0, mag_b = 0, room = 0;
  // v: a point of the difference set A - B (its norm bounds the hull distance from above),
  // the nearest to the origin of the simplex w[0..k) of support points (GJK).
  Vec3 v = a[0] - (r * b[0] + t);
  std::array<Vec3, 4> w{v, Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
  int k = 1;
  double best = -INFINITY;
  Vec3 best_n = Vec3::Zero();
  // The warm start: a direction, not a point of A - B, so its pass only bounds and then starts
  // the iteration at its support point (a point of A - B).
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
    const Vec3 s = a[ia] - (r * b[ib] + t);
    if (warm) {
      warm = false;
      // The warm direction was (nearly) the best one: past `stop` the caller's question is
      // answered, and the last 1e-3 would gain little.
      // Far below `stop` it is a near pair the hulls will not prove apart (the caller measures
      // it): the warm bound is returned without the iterations.
      if (best >= enough || (stop > 0 && (best >= stop || best < 0.5 * stop))) break;
      v = s;
      w[0] = s;
      k = 1;
      continue;
    }
    // Done: the bound is enough, or near the hull distance (which is <= |v|), or cannot get
    // to `enough` any more.
    if (best >= enough || vn - bound <= 1e-3 * vn || vn < stop) break;
    // GJK's step: the support point joins the simplex, v becomes the point of the simplex's
    // hull nearest the origin.
    bool known = false;
    for (int i = 0; i < k; ++i) known = known || w[static_cast<std::size_t>(i)] == s;
    if (known) break;  // no progress (nearest_on_simplex leaves at most 3 points)
    w[static_cast<std::size_t>(k++)] = s;
    if (!nearest_on_simplex(w, k, v)) break;  // the origin is inside: the hulls meet
  }
  if (guess && best_n.squaredNorm() > 0) *guess = best_n;
  return best;
}

}  // namespace asimov::collision
