// Continuous checking between two checked poses (docs/collision.md §12) [ours]: proves that no
// enabled pair comes into contact on the executed path between them, or finds the earliest
// contact to toc_tolerance_s, at any thickness.
//
// The proof: for a pair, mu(t1, t2) bounds how far any point of one body moves relative to the
// other along the path between t1 and t2 (robots/displacement_bound, sampler's
// pair_displacement), and mu is additive along the path. The surface distance d(t) is
// 1-Lipschitz in that motion, so for t in [a, b]: d(t) >= d(a) - mu(a, t) and
// d(t) >= d(b) - mu(t, b). If (d(a) - c) + (d(b) - c) > mu(a, b), one of the two stays above c
// at every t: the window is free. Otherwise it is split at its midpoint (a checked probe), left
// half first, so the first contact found is the earliest; a window of width <= toc_tolerance_s
// whose right end collides is the contact bracket. d(a), d(b) are Engine::distance values with a
// cut-off (a lower bound when beyond), so far pairs cost a step-2 bound.
#pragma once
#include "asimov/collision/engine.hpp"
#include "asimov/motion/sampler.hpp"
#include "asimov/motion/walk_observer.hpp"
#include "asimov/robots/configuration.hpp"

#include <cstdint>
#include <functional>
#include <memory>
#include <limits>
#include <optional>
#include <span>
#include <vector>

namespace asimov::motion {

// What the walker knows of the motion between two checked poses.
struct ContinuousPath {
  // Joints at time t on the executed path; `seed`: joints near t (an IK seed for lines).
  std::function<robots::JointVector(double t, const robots::JointVector& seed)> at;
  // Bound [mm] on the relative motion of pair `pair`'s bodies along the path from (t1, q1) to
  // (t2, q2) (index into Engine::enabled_pairs()).
  std::function<double(std::size_t pair, double t1, const robots::JointVector& q1, double t2,
                       const robots::JointVector& q2)>
      motion;
  // Optional: a bound [mm] on how much pair `pair`'s distance can differ between the poses
  // (t1, q1) and (t2, q2), whatever the path between them (joint moves: the motion bound of the
  // straight joint path; lines: the same, which is not their path's). Lets a distance measured
  // at an earlier checked pose bound the distance now by the net motion since, not the path
  // length (an arm going back and forth stays proven).
  std::function<double(std::size_t pair, double t1, const robots::JointVector& q1, double t2,
                       const robots::JointVector& q2)>
      jump;
  // Poses every moving engine body at joints q.
  std::function<void(const robots::JointVector& q, double t)> pose;  // at time t (parts move with it)
  // The pairs checked (pair indices refer to it); nullopt: Engine::enabled_pairs().
  std::optional<std::span<const collision::BodyPair>> pairs;
  // Optional: `at` and `motion` of pair `pair` as they are for the window being verified, kept
  // for later: the clearance report's minimum is refined at the end of the walk (lazy report) in
  // windows the walk has left (which stretch of a line, which part of a blended motion). Empty:
  // the current `at` and `motion` hold for any time of the walk.
  struct Frozen {
    std::function<robots::JointVector(double t, const robots::JointVector& seed)> at;
    std::function<double(double t1, const robots::JointVector& q1, double t2, const robots::JointVector& q2)> motion;
  };
  std::function<Frozen(std::size_t pair)> freeze;
};

// Distance queries one refinement of one pair may spend (a pair sliding at a constant distance
// would need one per 2e-3 mm of relative motion to prove its minimum to kMinimumToleranceMm);
// past it the report keeps the certified lower bound (ContinuousChecker::on_bound).
constexpr std::size_t kMinimumBudget = 4096;

struct ContinuousContact {
  bool found = false;
  // No probe collided, but a window of width <= toc_tolerance_s could not be proven free: the
  // pair came within the motion of that window (a conservative halt, docs/collision.md §12).
  bool graze = false;
  std::size_t pair = 0;  // index into Engine::enabled_pairs()
  double t_free = 0, t_hit = 0;
  robots::JointVector q_free, q_hit;
};

// Motion bounds of the executed paths. Joint moves are straight in joint space, so a pair's
// relative motion over q1 -> q2 is bounded by pair_displacement of q2 - q1 (each joint moves
// monotonically). Straight lines follow IK between validated samples: the bound sums
// pair_displacement over the samples strictly between sigma1 and sigma2 (the joints' total
// variation along the samples; each joint taken monotone between two neighbouring samples,
// which are <= 1 mm / 0.5 deg apart and refined to 0.9 step_mm, docs/collision.md §12).
double joint_motion(std::span<const robots::BodyReach> reach, const GapPair& pair, const robots::JointVector& q1,
                    const robots::JointVector& q2);
double line_motion(std::span<const robots::BodyReach> reach, const GapPair& pair, std::span<const LineSample> samples,
                   double sigma1, const robots::JointVector& q1, double sigma2, const robots::JointVector& q2);
// The joints' total variation along the samples from (sigma1, q1) to (sigma2, q2), per joint:
// pair_displacement is linear in |dq| per joint, so pair_displacement of it is line_motion for
// every pair at once (one pass over the samples per window, not one per pair).
robots::JointVector line_travel(std::span<const LineSample> samples, double sigma1, const robots::JointVector& q1,
                                double sigma2, const robots::JointVector& q2);

class ContinuousChecker {
 public:
  // tol: toc_tolerance_s; report_mm: distances below this are measured exactly at checked poses
  // (for the clearance report, on_measure), nearer than the pair's least one so far.
  ContinuousChecker(collision::Engine& engine, double clearance_mm, double tol_s, double report_mm);

  void set_clearance(double clearance_mm) { clearance_ = clearance_mm; }
  // Lazy clearance report (docs/collision.md §12): at checked poses a pair is measured only as
  // exactly as the proof needs; a pose where its bound leaves it possibly nearer than the report
  // threshold and its least so far is kept, and flush() measures the kept poses nearest bound
  // first, skipping those that can no longer be the least (all of them for a pair that ends in
  // contact). Only where posing at an earlier time moves nothing but the arm (no parts).
  void set_lazy_report(bool on) { lazy_ = on; }
  // Measures the kept poses at or before until_s (drops the later ones: after a contact) and
  // leaves the engine posed wherever path.pose put it last: the caller poses it again.
  // Returns whether it posed anything.
  bool flush(const ContinuousPath& path, double until_s = std::numeric_limits<double>::infinity());
  void set_report_mm(double report_mm) { report_mm_ = report_mm; }
  // Told of every distance measured: the pair (engine ids), the time, whether at a probe (a pose
  // between checked poses, or one refining the report's minimum) and the cpu_ticks() it took.
  std::function<void(const collision::BodyPair& pair, const collision::DistanceResult&, double t, bool probe,
                     std::uint64_t ticks)>
      on_measure;
  // Told when a refinement of the report's minimum ran out of kMinimumBudget: the pair's distance
  // over the windows refined is at least lower_mm (the least found may be above it by more than
  // kMinimumToleranceMm).
  std::function<void(const collision::BodyPair& pair, double lower_mm)> on_bound;
  // Forget the cached distances (the bodies were posed elsewhere than the last checked pose, or
  // the pairs changed). The poses and windows kept for the report name their pairs by bodies and
  // stay (flush() measures them).
  void reset() {
    cache_t_ = -1;
    anchors_.clear();
  }
  // Whether the distance being told (on_measure) refines the report's minimum.
  bool refining() const { return refining_; }
  // Drops what the report kept (a new walk: the poses kept belong to the last one's path).
  void discard() {
    kept_.clear();
    windows_.clear();
  }

  // What the walker already knows of a window, per pair (each span empty, or one per pair).
  struct WindowBounds {
    std::span<const double> lower_a, lower_b;  // lower bounds on the distance at a and at b (container gaps)
    std::span<const double> mu;                // ContinuousPath::motion over [t_a, t_b] (gap stepping's sums)
  };
  // The window from the checked pose (t_a, q_a), found free against every pair, to the checked
  // pose (t_b, q_b), which the engine is posed at now (checked or not). Returns the earliest
  // contact in (t_a, t_b], if any; every pair is then free on [t_a, t_free]. Leaves the engine
  // posed at q_b. A pair that what is known proves free on the window, and that the clearance
  // report need not see at b, costs no distance query (the far field).
  ContinuousContact verify(double t_a, const robots::JointVector& q_a, double t_b, const robots::JointVector& q_b,
                           const ContinuousPath& path, const WindowBounds& known = {});

  std::uint64_t probes() const { return probes_; }            // poses posed and measured between checked poses
  std::uint64_t distance_queries() const { return queries_; } // Engine::distance calls

 private:
  struct Point {
    double t = 0;
    robots::JointVector q;
    double d = 0;      // lower bound on the pair's distance [mm] (exact when below the cut-off)
    bool hit = false;  // the pair is in contact (distance 0, or <= c with a clearance)
    bool exact = false;  // d is the distance (not a lower bound from the cut-off)
  };
  // Exact below exact_below (default: below upper), else a lower bound (Point::exact false).
  void measure(std::size_t pair, Point& p, double upper, bool probe,
               double exact_below = std::numeric_limits<double>::infinity());
  // The same for a pair named by its bodies (kept poses and windows: the index may be stale);
  // `least`: the pair's least so far, lowered by an exact distance below it.
  void measure_bodies(const collision::BodyPair& pair, Point& p, double upper, bool probe, double& least,
                      double exact_below = std::numeric_limits<double>::infinity());
  // The report's minimum: a window [a, b] of a pair whose lower bound (d(a) + d(b) - mu) / 2 may
  // be below the pair's least less kMinimumToleranceMm is kept (lazy: until flush(); eager: the
  // window is refined at once), and refine() splits the kept windows of each pair nearest bound
  // first until none may hold a distance below its least less the tolerance.
  void keep_window(std::size_t pair, const Point& a, const Point& b, double mu, const ContinuousPath& path);
  bool refine(const ContinuousPath& path, double until_s);
  void measure_probe(std::size_t pair, Point& p, double upper);
  void keep(std::size_t pair, const Point& p, const robots::JointVector& q);
  bool solve(std::size_t pair, const Point& l, const Point& r, const ContinuousPath& path, ContinuousContact& out);

  collision::Engine& engine_;
  double clearance_;
  double tol_;
  double report_mm_;
  double posed_t_ = -1;         // time the engine's bodies are posed at (probes)
  std::span<const collision::BodyPair> pairs_;  // of the current verify (ContinuousPath::pairs)
  double cache_t_ = -1;         // time of the cached distances (the last checked pose)
  std::vector<double> cache_d_; // per pair: lower bound at cache_t_
  std::vector<char> cache_flags_;  // per pair: its end_flags_ at cache_t_ (kExact: cache_d_ is the distance)
  std::vector<double> least_;   // per pair: least exact distance met (the report needs only nearer ones)
  std::vector<collision::BodyPair> least_pairs_;  // the pairs least_ is of (a new list starts it again)
  std::vector<double> least_before_;  // least_ at the start of the window being verified
  struct Anchor {  // the last checked pose a pair was measured at
    bool set = false;
    double t = 0, d = 0;  // d: its distance there (exact or a lower bound)
    robots::JointVector q;
  };
  std::vector<Anchor> anchors_;  // per pair (ContinuousPath::jump)
  struct Guess {  // the pair's last hull-bound direction (DistanceRequest::guess)
    collision::BodyPair pair;  // {0, 0}: none (a pair has a < b)
    collision::Vec3 dir = collision::Vec3::Zero();
  };
  std::vector<Guess> guesses_;  // per pair index; used only while it names the same pair
  // verify, per pair: its motion bound over the window; its distance (or lower bound) at b and
  // what it is (kHit, kExact) and whether the window is proven free (kFree).
  static constexpr char kHit = 1, kExact = 2, kFree = 4;
  std::vector<double> mu_, end_d_;
  std::vector<char> end_flags_;
  std::optional<ContinuousContact> graze_;  // solve: the first unprovable window of the pair
  struct Kept {  // a checked pose the clearance report may still need (lazy_)
    collision::BodyPair pair;
    double t, bound;  // bound: a lower bound on the pair's distance there
    robots::JointVector q;
  };
  std::vector<Kept> kept_;
  struct Window {  // a window the report's minimum may still need (keep_window)
    collision::BodyPair pair;
    double least;  // the pair's least when kept (the report threshold if none)
    double ta, da, tb, db, mu;  // ends: times, lower bounds (exact where measured); mu over [ta, tb]
    bool ea, eb;                // whether da, db are exact distances
    robots::JointVector qa, qb;
    std::shared_ptr<ContinuousPath::Frozen> path;  // null: the path's own at / motion (index `index`)
    std::size_t index;
  };
  std::vector<Window> windows_;
  struct Flushed {  // a kept pose flush() measured exactly: refine() takes its distance as known
    collision::BodyPair pair;
    double t, d;
  };
  std::vector<Flushed> flushed_;
  // The least distance of a pair named by its bodies: least_ where the current pairs name it.
  double least_of(const collision::BodyPair& pair) const;
  bool lazy_ = false;
  bool refining_ = false;
  std::uint64_t probes_ = 0, queries_ = 0;
};

}  // namespace asimov::motion
