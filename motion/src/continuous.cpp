#include "continuous.hpp"

#include "asimov/motion/walk_observer.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace asimov::motion {
namespace {
constexpr double kGrazeS = 1e-6;  // [s] finest unprovable window before a graze halt (docs/collision.md §12)
}  // namespace

double joint_motion(std::span<const robots::BodyReach> reach, const GapPair& pair, const robots::JointVector& q1,
                    const robots::JointVector& q2) {
  return pair_displacement(reach, pair, q2 - q1);
}

double line_motion(std::span<const robots::BodyReach> reach, const GapPair& pair, std::span<const LineSample> samples,
                   double sigma1, const robots::JointVector& q1, double sigma2, const robots::JointVector& q2) {
  if (sigma2 < sigma1) return line_motion(reach, pair, samples, sigma2, q2, sigma1, q1);
  const auto first = std::upper_bound(samples.begin(), samples.end(), sigma1,
                                      [](double v, const LineSample& x) { return v < x.s; });
  double mu = 0;
  const robots::JointVector* prev = &q1;
  for (auto it = first; it != samples.end() && it->s < sigma2; ++it) {
    mu += pair_displacement(reach, pair, it->joints - *prev);
    prev = &it->joints;
  }
  return mu + pair_displacement(reach, pair, q2 - *prev);
}

ContinuousChecker::ContinuousChecker(collision::Engine& engine, double clearance_mm, double tol_s, double report_mm)
    : engine_(engine), clearance_(clearance_mm), tol_(tol_s), report_mm_(report_mm) {}

void ContinuousChecker::measure(std::size_t pair, Point& p, double upper, bool probe) {
  const collision::BodyPair bp = pairs_[pair];
  const std::uint64_t k0 = cpu_ticks();
  const collision::DistanceResult r = engine_.distance(bp.a, bp.b, {.upper_mm = upper});
  if (on_measure) on_measure(pair, r, p.t, probe, cpu_ticks() - k0);
  ++queries_;
  if (r.status != collision::DistanceStatus::beyond) least_[pair] = std::min(least_[pair], r.distance);
  p.hit = r.status == collision::DistanceStatus::contact ||
          (clearance_ > 0 && r.status == collision::DistanceStatus::exact && r.distance <= clearance_);
  p.d = p.hit ? 0.0 : r.distance;
  p.exact = r.status != collision::DistanceStatus::beyond;
}

// Earliest contact of the pair in (l.t, r.t]: l is free; r.hit says whether r collides. True
// with `out` filled when one is found. Windows are visited in time order.
bool ContinuousChecker::solve(std::size_t pair, const Point& l, const Point& r, const ContinuousPath& path,
                              ContinuousContact& out) {
  const double c = clearance_;
  const double mu = path.motion(pair, l.t, l.q, r.t, r.q);
  if (!r.hit && (l.d - c) + (r.d - c) > mu) {  // free: the two-sided bound
    if (!graze_) return false;
    out = *graze_;  // proven free after an unprovable window: the pair grazed there and left
    return true;
  }
  const double m_t = l.t + (r.t - l.t) / 2;
  // A colliding right end stops the split at toc_tolerance_s (the contact bracket). A free one
  // that cannot be proven free is split to kGrazeS at most (a coarse tolerance must not turn a
  // near miss into a contact before the real one) and then kept as a graze: the bounds cannot
  // prove the last stretch before a contact free, so what follows decides: a contact (the graze
  // was its approach) or a window proven free (a graze, a conservative halt).
  const double width = r.t - l.t;
  if ((r.hit ? width <= tol_ : width <= std::min(tol_, kGrazeS)) || !(m_t > l.t && m_t < r.t)) {
    const ContinuousContact here{.found = true, .graze = !r.hit, .pair = pair, .t_free = l.t, .t_hit = r.t, .q_free = l.q, .q_hit = r.q};
    if (!r.hit) {
      if (!graze_) graze_ = here;
      return false;
    }
    out = here;
    return true;
  }
  Point m;
  m.t = m_t;
  m.q = path.at(m_t, l.q);
  path.pose(m.q, m.t);
  posed_t_ = m_t;
  ++probes_;
  measure(pair, m, mu + 2 * c, true);
  if (solve(pair, l, m, path, out)) return true;
  return solve(pair, m, r, path, out);
}

ContinuousContact ContinuousChecker::verify(double t_a, const robots::JointVector& q_a, double t_b,
                                            const robots::JointVector& q_b, const ContinuousPath& path) {
  posed_t_ = t_b;
  pairs_ = path.pairs ? *path.pairs : engine_.enabled_pairs();
  const auto pairs = pairs_;
  const std::size_t n = pairs.size();
  least_.resize(n, std::numeric_limits<double>::infinity());
  const double c = clearance_;
  const bool cached = cache_t_ == t_a && cache_d_.size() == n;
  std::vector<double> mu(n);
  std::vector<Point> end(n);
  // At b (the engine is posed there): every pair, with the cut-off the two-sided bound needs
  // given the distance cached at a (gap stepping chose b so that most pairs need next to
  // nothing: their step-2 bound decides), and the one the clearance report needs (only
  // distances below the pair's least one so far). The values are the next window's start.
  for (std::size_t i = 0; i < n; ++i) {
    mu[i] = path.motion(i, t_a, q_a, t_b, q_b);
    end[i].t = t_b;
    end[i].q = q_b;
    const double need = mu[i] + 2 * c - (cached ? cache_d_[i] : 0.0);
    const double report = std::min(report_mm_, least_[i]);
    measure(i, end[i], std::max({need * (1 + 1e-9) + 1e-9, report, c}), false);
  }
  ContinuousContact best;
  Point start;
  start.t = t_a;
  start.q = q_a;
  for (std::size_t i = 0; i < n; ++i) {
    Point l = start, r = end[i];
    if (best.found) {  // the earliest contact so far bounds the window of the other pairs
      if (best.t_hit < r.t) {
        r.t = best.t_hit;
        r.q = best.q_hit;
        path.pose(r.q, r.t);
        posed_t_ = r.t;
        measure(i, r, path.motion(i, t_a, q_a, r.t, r.q) + 2 * c, true);
      }
    }
    const double m = path.motion(i, l.t, l.q, r.t, r.q);
    if (cached) {
      l.d = cache_d_[i];
      l.exact = cache_exact_[i] != 0;
    }
    if (!r.hit && cached && (l.d - c) + (r.d - c) > m) continue;  // free from both ends' bounds
    if (!cached || !l.exact) {  // the last checked pose's cut-off was too low: measure there
      path.pose(q_a, t_a);
      posed_t_ = t_a;
      measure(i, l, m + 2 * c, false);
      l.hit = false;  // a was checked free (only a rounding at the clearance could say otherwise)
    }
    ContinuousContact found;
    graze_.reset();
    if (!solve(i, l, r, path, found)) {
      if (!graze_) continue;
      found = *graze_;  // unprovable up to b (checked free): a graze
    }
    if (!best.found || found.t_hit < best.t_hit) {
      const double t_free = best.found ? std::min(best.t_free, found.t_free) : found.t_free;
      const robots::JointVector q_free = best.found && best.t_free < found.t_free ? best.q_free : found.q_free;
      best = found;
      best.t_free = t_free;
      best.q_free = q_free;
    } else if (found.t_free < best.t_free) {
      best.t_free = found.t_free;
      best.q_free = found.q_free;
    }
  }
  // The distances at b are the next window's start (unless a contact ends the motion here).
  cache_t_ = t_b;
  cache_d_.resize(n);
  cache_exact_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    cache_d_[i] = end[i].hit ? 0.0 : end[i].d;
    cache_exact_[i] = end[i].exact;
  }
  if (posed_t_ != t_b) {
    path.pose(q_b, t_b);
    posed_t_ = t_b;
  }
  return best;
}

}  // namespace asimov::motion
