// The clearance report's minimum [ours] (docs/collision.md §12): per pair, the least distance
// along the motion to within kMinimumToleranceMm, with its time and witness points.
//
// Continuous checking proves a window [a, b] free from two lower bounds and the motion bound mu
// (d is 1-Lipschitz in the relative motion: d(t) >= d(a) - mu(a, t), d(t) >= d(b) - mu(t, b)).
// The same two bounds bound the window's minimum: since mu(a, t) + mu(t, b) = mu(a, b), the
// larger of the two is at least (d(a) + d(b) - mu(a, b)) / 2 at every t. A window whose bound
// is below the pair's least distance found so far less the tolerance may hold a nearer pose: it
// is split at its midpoint (a pose measured exactly below the least, otherwise bounded), nearest
// bound first (branch and bound, as Piyavskii's search for a Lipschitz minimum), until every
// window left is bounded by the least less the tolerance. The least found is then a distance the
// run met (its pose measured), within the tolerance of the true minimum, and the distances go to
// the report through on_measure like every other.
#include "continuous.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>

namespace asimov::motion {
namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
// The window's lower bound on its minimum (rounding: a relative 1e-9 and 1e-9 mm, as continuous
// checking's `less`).
double window_bound(double da, double db, double mu) { return 0.5 * (da + db - mu * (1 + 1e-9)) - 1e-9; }
}  // namespace

double ContinuousChecker::least_of(const collision::BodyPair& pair) const {
  for (std::size_t i = 0; i < least_pairs_.size() && i < least_.size(); ++i)
    if (least_pairs_[i] == pair) return least_[i];
  return kInf;
}

void ContinuousChecker::measure_bodies(const collision::BodyPair& pair, Point& p, double upper, bool probe,
                                       double& least, double exact_below) {
  const std::uint64_t k0 = cpu_ticks();
  const collision::DistanceResult r = engine_.distance(pair.a, pair.b, {.upper_mm = upper, .exact_below_mm = exact_below});
  if (on_measure) on_measure(pair, r, p.t, probe, cpu_ticks() - k0);
  ++queries_;
  p.hit = r.status == collision::DistanceStatus::contact;
  p.exact = r.status != collision::DistanceStatus::beyond;
  p.d = p.hit ? 0.0 : r.distance;
  if (!p.exact || !(r.distance < least)) return;
  least = r.distance;
  for (std::size_t i = 0; i < least_pairs_.size() && i < least_.size(); ++i)
    if (least_pairs_[i] == pair) least_[i] = std::min(least_[i], r.distance);
}

void ContinuousChecker::keep_window(std::size_t pair, const Point& a, const Point& b, double mu,
                                    const ContinuousPath& path) {
  const double least = std::min(report_mm_, least_[pair]);
  if (!(window_bound(a.d, b.d, mu) < least - kMinimumToleranceMm) || !(b.t > a.t)) return;
  Window w{.pair = pairs_[pair], .least = least, .ta = a.t, .da = a.d, .tb = b.t, .db = b.d, .mu = mu,
           .ea = a.exact || a.hit, .eb = b.exact || b.hit, .qa = a.q, .qb = b.q, .path = nullptr, .index = pair};
  if (path.freeze) w.path = std::make_shared<ContinuousPath::Frozen>(path.freeze(pair));
  windows_.push_back(std::move(w));
}

bool ContinuousChecker::refine(const ContinuousPath& path, double until_s) {
  if (windows_.empty()) return false;
  std::vector<Window> windows;
  windows.swap(windows_);
  std::stable_sort(windows.begin(), windows.end(), [](const Window& x, const Window& y) {
    return x.pair.a != y.pair.a ? x.pair.a < y.pair.a : x.pair.b < y.pair.b;
  });
  struct Piece {  // a part of a kept window
    double bound;
    double ta, da, tb, db, mu;
    bool ea, eb;  // da, db exact (else lower bounds: measured first when they keep the piece open)
    robots::JointVector qa, qb;
    const Window* from;
    bool operator>(const Piece& o) const { return bound > o.bound; }
  };
  bool posed = false;
  refining_ = true;
  struct Done {
    bool& flag;
    ~Done() { flag = false; }
  } done{refining_};
  for (std::size_t first = 0; first < windows.size();) {
    std::size_t last = first;
    while (last < windows.size() && windows[last].pair == windows[first].pair) ++last;
    const collision::BodyPair pair = windows[first].pair;
    double least = least_of(pair);
    for (std::size_t k = first; k < last; ++k) least = std::min(least, windows[k].least);
    std::priority_queue<Piece, std::vector<Piece>, std::greater<>> heap;
    for (std::size_t k = first; k < last; ++k) {
      const Window& w = windows[k];
      if (!(w.ta < until_s)) continue;  // after the contact: never reached
      Piece p{window_bound(w.da, w.db, w.mu), w.ta, w.da, w.tb, w.db, w.mu, w.ea, w.eb, w.qa, w.qb, &w};
      heap.push(std::move(p));
    }
    std::size_t spent = 0;
    while (!heap.empty()) {
      const double threshold = std::min(report_mm_, least) - kMinimumToleranceMm;
      if (!(heap.top().bound < threshold)) break;  // every piece left is proven
      Piece p = heap.top();
      heap.pop();
      const double tm = p.ta + (p.tb - p.ta) / 2;
      if (spent == kMinimumBudget || !(tm > p.ta && tm < p.tb)) {
        // Out of budget (or a window one ulp wide): what is proven is the bound.
        if (on_bound) on_bound(pair, p.bound);
        break;
      }
      ++spent;
      const Window& w = *p.from;
      const double need = std::min(report_mm_, least);
      // An end known only by a bound below the least (the checked pose measured as far as its
      // proof needed): measured first, since no split improves it.
      const auto known = [&](double t, double& d, bool& exact) {  // measured by flush()
        for (const Flushed& f : flushed_)
          if (f.pair == pair && f.t == t) {
            d = std::max(d, f.d);
            exact = true;
            return true;
          }
        return false;
      };
      if ((!p.ea && p.da < need && known(p.ta, p.da, p.ea)) || (!p.eb && p.db < need && known(p.tb, p.db, p.eb))) {
        p.bound = window_bound(p.da, p.db, p.mu);
        heap.push(std::move(p));
        continue;
      }
      const auto measure_end = [&](double t, const auto& q, double& d, bool& exact) {
        Point e;
        e.t = t;
        e.q = q;
        path.pose(e.q, e.t);
        posed = true;
        measure_bodies(pair, e, need + 0.5 * p.mu, false, least, need);
        d = std::max(d, e.d);
        exact = true;
        p.bound = window_bound(p.da, p.db, p.mu);
        heap.push(std::move(p));
      };
      if (!p.ea && p.da < need) {
        measure_end(p.ta, p.qa, p.da, p.ea);
        continue;
      }
      if (!p.eb && p.db < need) {
        measure_end(p.tb, p.qb, p.db, p.eb);
        continue;
      }
      Point m;
      m.t = tm;
      m.q = w.path ? w.path->at(tm, p.qa) : path.at(tm, p.qa);
      path.pose(m.q, m.t);
      posed = true;
      ++probes_;
      // Exact below the least (only a nearer distance counts); above it, a bound up to what the
      // halves need: a half is proven when its two ends' bounds exceed the least by mu / 2.
      measure_bodies(pair, m, need + 0.5 * p.mu, true, least, need);
      if (m.hit) continue;  // (cannot happen: the window was proven free; keep it sound)
      const auto motion = [&](double t1, const robots::JointVector& q1, double t2, const robots::JointVector& q2) {
        return w.path ? w.path->motion(t1, q1, t2, q2) : path.motion(w.index, t1, q1, t2, q2);
      };
      const double mu_l = motion(p.ta, p.qa, tm, m.q), mu_r = motion(tm, m.q, p.tb, p.qb);
      heap.push(Piece{window_bound(p.da, m.d, mu_l), p.ta, p.da, tm, m.d, mu_l, p.ea, true, p.qa, m.q, &w});
      heap.push(Piece{window_bound(m.d, p.db, mu_r), tm, m.d, p.tb, p.db, mu_r, true, p.eb, m.q, p.qb, &w});
    }
    first = last;
  }
  return posed;
}

}  // namespace asimov::motion
