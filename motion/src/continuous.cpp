#include "continuous.hpp"

#include "asimov/motion/walk_observer.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <limits>

namespace asimov::motion {
namespace {
// A pair measured at a checked pose gets a cut-off this fraction of the clearance report's
// threshold above what the window needs: the answer "beyond" (a lower bound) then proves the
// following windows too while the arm moves less than that from there (Anchor). Measured on
// bench_continuous: queries with a higher cut-off cost more than the ones they save.
constexpr double budget_ = 0.5;
// A lower bound at the far end of a motion bound mu from a lower bound d (with room for the
// rounding of both).
double less(double d, double mu) { return d - mu * (1 + 1e-9) - 1e-9; }
constexpr double kGrazeS = 1e-6;  // [s] finest unprovable window before a graze halt (docs/collision.md §12)
}  // namespace

double joint_motion(std::span<const robots::BodyReach> reach, const GapPair& pair, const robots::JointVector& q1,
                    const robots::JointVector& q2) {
  return pair_displacement(reach, pair, q2 - q1);
}

robots::JointVector line_travel(std::span<const LineSample> samples, double sigma1, const robots::JointVector& q1,
                                double sigma2, const robots::JointVector& q2) {
  if (sigma2 < sigma1) return line_travel(samples, sigma2, q2, sigma1, q1);
  const auto first = std::upper_bound(samples.begin(), samples.end(), sigma1,
                                      [](double v, const LineSample& x) { return v < x.s; });
  robots::JointVector travel = robots::JointVector::Zero(q1.size());
  const robots::JointVector* prev = &q1;
  for (auto it = first; it != samples.end() && it->s < sigma2; ++it) {
    travel += (it->joints - *prev).cwiseAbs();
    prev = &it->joints;
  }
  return travel + (q2 - *prev).cwiseAbs();
}

double line_motion(std::span<const robots::BodyReach> reach, const GapPair& pair, std::span<const LineSample> samples,
                   double sigma1, const robots::JointVector& q1, double sigma2, const robots::JointVector& q2) {
  return pair_displacement(reach, pair, line_travel(samples, sigma1, q1, sigma2, q2));
}

ContinuousChecker::ContinuousChecker(collision::Engine& engine, double clearance_mm, double tol_s, double report_mm)
    : engine_(engine), clearance_(clearance_mm), tol_(tol_s), report_mm_(report_mm) {}

void ContinuousChecker::measure(std::size_t pair, Point& p, double upper, bool probe, double exact_below) {
  const collision::BodyPair bp = pairs_[pair];
  const std::uint64_t k0 = cpu_ticks();
  if (guesses_.size() < pairs_.size()) guesses_.resize(pairs_.size());
  Guess& g = guesses_[pair];
  const collision::DistanceResult r =
      engine_.distance(bp.a, bp.b,
                       {.upper_mm = upper, .guess = g.pair == bp ? g.dir : collision::Vec3::Zero(), .exact_below_mm = exact_below});
  g = {bp, r.guess};
  if (on_measure) on_measure(bp, r, p.t, probe, cpu_ticks() - k0);
  ++queries_;
  if (r.status != collision::DistanceStatus::beyond) least_[pair] = std::min(least_[pair], r.distance);
  p.hit = r.status == collision::DistanceStatus::contact ||
          (clearance_ > 0 && r.status == collision::DistanceStatus::exact && r.distance <= clearance_);
  p.d = p.hit ? 0.0 : r.distance;
  p.exact = r.status != collision::DistanceStatus::beyond;
}

// A pose between checked poses. Lazy: bisection needs only a bound (a positive one from the
// hulls proves the pose free), and the report keeps the pose if it may be nearer than the least.
void ContinuousChecker::measure_probe(std::size_t pair, Point& p, double upper) {
  if (!lazy_) return measure(pair, p, upper, true);
  measure(pair, p, upper, true, std::max(clearance_ * (1 + 1e-9), DBL_MIN));
  keep(pair, p, p.q);
}

// Lazy: a pose measured only as a bound that may still be nearer than the pair's least and the
// report threshold is kept for flush().
void ContinuousChecker::keep(std::size_t pair, const Point& p, const robots::JointVector& q) {
  if (lazy_ && !p.hit && !p.exact && p.d < std::min(report_mm_, least_[pair])) kept_.push_back({pairs_[pair], p.t, p.d, q});
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
      // Ends known only by bounds (lazy probes: the hulls' bound, loose a hair from a face): their
      // exact distances may prove the window after all, before it is taken for a graze.
      if (!l.exact || !r.exact) {
        Point le = l, re = r;
        for (Point* e : {&le, &re}) {
          if (e->exact) continue;
          path.pose(e->q, e->t);
          posed_t_ = e->t;
          measure(pair, *e, mu + 2 * c, true);
          if (e->hit) return solve(pair, l, *e, path, out);  // (cannot happen at l: it is free)
        }
        if ((le.d - c) + (re.d - c) > mu) return false;
      }
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
  measure_probe(pair, m, mu + 2 * c);
  if (solve(pair, l, m, path, out)) return true;
  return solve(pair, m, r, path, out);
}

ContinuousContact ContinuousChecker::verify(double t_a, const robots::JointVector& q_a, double t_b,
                                            const robots::JointVector& q_b, const ContinuousPath& path,
                                            const WindowBounds& known) {
  posed_t_ = t_b;
  pairs_ = path.pairs ? *path.pairs : engine_.enabled_pairs();
  const std::size_t n = pairs_.size();
  if (!std::equal(pairs_.begin(), pairs_.end(), least_pairs_.begin(), least_pairs_.end())) {
    least_.assign(n, std::numeric_limits<double>::infinity());  // another list: its indices name other pairs
    least_pairs_.assign(pairs_.begin(), pairs_.end());
  }
  if (anchors_.size() != n) anchors_.assign(n, {});
  const double c = clearance_;
  const bool cached = cache_t_ == t_a && cache_d_.size() == n;
  const bool have_a = known.lower_a.size() == n, have_b = known.lower_b.size() == n, have_mu = known.mu.size() == n;
  // Per pair what is known at a: the distance cached from the last window (exact, or a lower
  // bound) and the container gap there; the larger is the lower bound.
  const auto at_a = [&](std::size_t i) {
    const double d = cached ? cache_d_[i] : 0.0;
    return have_a && known.lower_a[i] > d ? known.lower_a[i] : d;
  };
  least_before_.assign(least_.begin(), least_.end());
  mu_.resize(n);
  end_d_.resize(n);  // every entry is written below (as end_flags_)
  end_flags_.resize(n);
  // At b (the engine is posed there) a lower bound on each pair's distance comes for free: its
  // container gap there, what is known at a less the window's motion, and the distance at the
  // pair's anchor (the last checked pose it was measured at) less the net motion since (d is
  // 1-Lipschitz in the motion). A pair whose bounds satisfy the two-sided inequality, and whose
  // bound at b is no nearer than the clearance report asks, needs no distance query: gap
  // stepping chose b so that this holds for every pair not near its allowance's floor. Every
  // other pair is measured at b with the cut-off the two-sided bound needs given what is known
  // at a and the one the clearance report needs (only distances below the pair's least one so
  // far), raised by a budget so that the answer "beyond" stays a proof while the arm moves
  // less than that budget from here (its anchor). The values are the next window's start.
  for (std::size_t i = 0; i < n; ++i) {
    const double m = have_mu ? known.mu[i] : path.motion(i, t_a, q_a, t_b, q_b);
    mu_[i] = m;
    const double la = at_a(i);
    const double report = std::min(report_mm_, least_[i]);
    double lb = std::max(have_b ? known.lower_b[i] : 0.0, less(la, m));
    const auto proven = [&] { return lb >= report && (la - c) + (lb - c) > m * (1 + 1e-9) + 1e-9; };
    Anchor& an = anchors_[i];
    if (!proven() && an.set) lb = std::max(lb, less(an.d, path.jump(i, an.t, an.q, t_b, q_b)));
    if (proven()) {
      end_d_[i] = lb;
      end_flags_[i] = kFree;
      continue;
    }
    Point e;
    e.t = t_b;
    // Exact below what the window and the report need (lazy: the window only); up to the
    // budget's cut-off a bound from the hulls is enough (the anchor's room).
    const double proof = std::max((m + 2 * c - la) * (1 + 1e-9) + 1e-9, c);
    const double need = lazy_ ? proof : std::max(proof, report);
    measure(i, e, std::max(proof, report * (1 + budget_)), false, need);
    if (!e.hit && !e.exact) e.d = std::max(e.d, lb);  // "beyond": the better of the two bounds
    keep(i, e, q_b);  // (e.q unset: the checked pose's joints are q_b)
    end_d_[i] = e.d;
    end_flags_[i] = (e.hit ? kHit : 0) | (e.exact ? kExact : 0) |
                    (!e.hit && (la - c) + (e.d - c) > m ? kFree : 0);
    if (path.jump && !e.hit) an = {true, t_b, e.d, q_b};
  }
  ContinuousContact best;
  for (std::size_t i = 0; i < n; ++i) {
    if (end_flags_[i] & kFree) continue;  // free from both ends' bounds on [t_a, t_b]
    Point l, r;
    l.t = t_a;
    l.q = q_a;
    r.t = t_b;
    r.q = q_b;
    r.d = end_d_[i];
    r.hit = (end_flags_[i] & kHit) != 0;
    r.exact = (end_flags_[i] & kExact) != 0;
    double m = mu_[i];
    if (best.found && best.t_hit < r.t) {  // the earliest contact so far bounds the window of the other pairs
      r.t = best.t_hit;
      r.q = best.q_hit;
      path.pose(r.q, r.t);
      posed_t_ = r.t;
      m = path.motion(i, t_a, q_a, r.t, r.q);
      measure_probe(i, r, m + 2 * c);
    }
    l.d = at_a(i);
    l.exact = cached && (cache_flags_[i] & kExact) && l.d == cache_d_[i];
    if (!r.hit && (l.d - c) + (r.d - c) > m) continue;  // free from both ends' bounds
    if (!l.exact) {  // the last checked pose's cut-off was too low: measure there
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
  // The report's minimum: every pair's window to b (to the contact, if any) whose bounds leave
  // room below its least (lazy: kept for flush(); eager: refined now). After a contact the
  // distances measured past it (at b) never happened: the leasts before the window are kept.
  const double until = best.found ? best.t_hit : t_b;
  if (best.found) least_.swap(least_before_);
  for (std::size_t i = 0; i < n; ++i) {
    if (best.found && i == best.pair) continue;  // its least is the contact
    Point a, b;
    a.t = t_a;
    a.q = q_a;
    a.d = at_a(i);
    a.exact = cached && (cache_flags_[i] & kExact) && a.d == cache_d_[i];
    b.t = t_b;
    b.q = q_b;
    b.d = (end_flags_[i] & kHit) ? 0.0 : end_d_[i];
    b.exact = (end_flags_[i] & kExact) != 0;
    double m = mu_[i];
    if (until < t_b) {  // clipped at the contact: d there from both ends' bounds
      const robots::JointVector q_u = best.q_hit;
      const double m_a = path.motion(i, t_a, q_a, until, q_u);
      b.d = std::max(less(a.d, m_a), less(b.d, path.motion(i, until, q_u, t_b, q_b)));
      b.t = until;
      b.q = q_u;
      b.exact = false;
      m = m_a;
    }
    keep_window(i, a, b, m, path);
  }
  if (!lazy_ && !windows_.empty() && refine(path, until)) posed_t_ = -1;
  // The distances at b are the next window's start (unless a contact ends the motion here); a
  // pair in contact has d 0 there (measure).
  cache_t_ = t_b;
  cache_d_.swap(end_d_);
  cache_flags_.swap(end_flags_);
  if (best.found && flush(path, best.t_hit)) posed_t_ = -1;  // the report's poses before the contact
  if (posed_t_ != t_b) {
    path.pose(q_b, t_b);
    posed_t_ = t_b;
  }
  return best;
}

bool ContinuousChecker::flush(const ContinuousPath& path, double until_s) {
  if (!path.pose) {
    kept_.clear();
    windows_.clear();
    return false;
  }
  // Nearest bound first: the first measured sets the pair's least, and every pose whose bound
  // is not below it cannot be nearer (a pair that ended in contact has least 0: none is).
  std::stable_sort(kept_.begin(), kept_.end(), [](const Kept& x, const Kept& y) { return x.bound < y.bound; });
  bool posed = false;
  for (Kept& k : kept_) {
    if (k.t > until_s) continue;
    double least = least_of(k.pair);
    const double report = std::min(report_mm_, least);
    if (!(k.bound < report)) continue;
    path.pose(k.q, k.t);
    posed = true;
    Point p;
    p.t = k.t;
    p.q = k.q;
    measure_bodies(k.pair, p, report, false, least);
    if (p.exact) flushed_.push_back({k.pair, k.t, p.hit ? 0.0 : p.d});
  }
  kept_.clear();
  // Then the windows between, with the leasts the kept poses gave (and their distances: a
  // window's end measured just now is not measured again).
  const bool refined = refine(path, until_s);
  flushed_.clear();
  return refined || posed;
}

}  // namespace asimov::motion
