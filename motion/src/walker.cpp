// The walk over a trajectory's checked poses (docs/collision-method.md §6.3-§6.4).
#include "asimov/motion/walker.hpp"

#include "continuous.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

namespace asimov::motion {
namespace {
using robots::JointVector;

constexpr int kMaxBisectionRounds = 4;  // contact-time bisections per contact (another pair met)

double toc_tolerance(const CollisionSettings& s) { return s.toc_tolerance_s >= 0 ? s.toc_tolerance_s : 1e-6; }

// The clearance that halts: with on_clearance warn only touching does (the clearance report
// lists the pairs that came within clearance_mm).
double halting_clearance(const CollisionSettings& s) { return s.on_clearance == OnClearance::warn ? 0.0 : s.clearance_mm; }
}  // namespace

double step_mm(const CollisionSettings& s) { return std::max({s.clearance_mm, s.step_mm, kMinStepMm}); }

Walker::Walker(const robots::Robot& robot, World& world, const CollisionSettings& settings)
    : robot_(robot), world_(world), settings_(settings) {}
Walker::~Walker() = default;

void Walker::add_observer(WalkObserver& observer) { observers_.push_back(&observer); }

// One walk: the trajectory, the state it advances and the observers it tells.
struct Walker::Walk {
  Walker& w;
  const Trajectory& tr;
  WalkState& st;
  collision::Engine* engine;  // null: nothing to check (no engine, or collision disabled)
  double clearance;
  ContinuousChecker* checker;  // null: continuous checking off
  ContinuousPath path{};       // the trajectory as continuous checking sees it (continuous_path)
  std::uint64_t pairs_verified = ~std::uint64_t{0};  // World::pairs_revision() the checker's cache is of
  std::size_t line_i = 0, line_j = 0;  // lines: the checked samples of the current stretch
  bool in_overlap = false;             // walking the overlap with the previous motion (blended path)
  // Container gaps (QueryResult::gaps, per pair of pairs()) at the last checked pose found free
  // (`here`: gap stepping's allowances, continuous checking's lower bounds at a window's start)
  // and at the pose just visited (`next`: at the window's end), in w.gaps_here_ and
  // w.gaps_next_; each valid for the time of its pose and the World::pairs_revision() then.
  // Gap stepping's per-pair motion bound over the stretch starting at mu_t (w.window_mu_) is
  // continuous checking's window bound, not computed twice.
  struct Tag {
    bool ok = false;
    double t = 0;
    std::uint64_t rev = 0;
  };
  bool want_gaps = false;  // gap stepping or continuous checking: visit's query computes them
  Tag here{}, next{}, mu{};
  bool dwelling = false;               // time passing with the arm at rest (dwell)
  // While dwelling only the pairs with a belt-borne part can change distance: those are
  // checked (dwell_pairs; dwell_index: their indices in World::pairs()), the rest stay free.
  std::vector<collision::BodyPair> dwell_pairs{}, dwell_scratch{};
  std::vector<std::size_t> dwell_index{};
  std::span<const collision::BodyPair> checked_pairs() const {
    return dwelling ? std::span<const collision::BodyPair>(dwell_pairs) : w.world_.pairs();
  }
  std::size_t world_pair(std::size_t k) const { return dwelling ? dwell_index[k] : k; }

  template <class F>
  void tell(F&& f) {
    for (WalkObserver* o : w.observers_) f(*o);
  }

  // Fills `report` (bodies, point, faces, joints `q`) from a query that found a contact.
  bool record(const collision::QueryResult& r, QueryCost cost, const JointVector& q, CollisionReport& report) {
    tell([&](WalkObserver& o) { o.on_query(r, cost); });
    if (!r.collided) return false;
    report.body_a = w.world_.body_name(r.contact.body_a);
    report.body_b = w.world_.body_name(r.contact.body_b);
    report.id_a = r.contact.body_a;
    report.id_b = r.contact.body_b;
    report.point = r.contact.point;
    report.face_a = r.contact.face_a;
    report.face_b = r.contact.face_b;
    report.joints = q;
    return true;
  }

  // The world at q and time t, on `pairs` (nullopt: every pair tested now).
  const collision::QueryResult& query(const JointVector& q, double t,
                                      std::optional<std::span<const collision::BodyPair>> pairs = std::nullopt) {
    w.world_.pose(q, t);
    w.world_.query({.clearance_mm = clearance, .pairs = pairs}, w.result_);
    return w.result_;
  }

  // One checked pose at time t: checks it, tells the observers. True on contact (`report`).
  bool visit(const JointVector& q, double t, CollisionReport& report) {
    bool contact = false;
    if (engine) {
      w.world_.pose(q, t);
      const std::uint64_t k0 = cpu_ticks();
      // The gaps come with the contact test (one pass over the pairs; the next stretch's
      // allowances and the window's lower bounds at its end). A dwell tests its subset only.
      w.world_.query({.clearance_mm = clearance,
                      .pairs = dwelling ? std::optional(checked_pairs()) : std::nullopt,
                      .gaps = want_gaps && !dwelling},
                     w.result_, true);
      const QueryCost cost{QueryKind::checked_pose, cpu_ticks() - k0, w.world_.grids_built(w.result_)};
      if (want_gaps) {
        w.gaps_next_.assign(w.result_.gaps.begin(), w.result_.gaps.end());
        next = tag(t);
      }
      contact = record(w.result_, cost, q, report);
    }
    tell([&](WalkObserver& o) { o.on_checked_pose(t, q, contact); });
    if (!contact) {
      st.last_free = engine != nullptr;
      return false;
    }
    report.time_s = report.time_free_s = t;
    return true;
  }

  // Before each stretch of a motion: the broad phase's near lists, recomputed when an arm body
  // has less room than a stretch of step_mm (World::broad_refresh); gap stepping then keeps each
  // body's motion over the stretch within its room (docs/collision.md §14).
  void broad() {
    if (engine && w.world_.broad_phase())
      w.world_.broad_refresh(report_distance_mm(w.settings_), step_mm(w.settings_));
  }

  Tag tag(double t) const { return {true, t, w.world_.pairs_revision()}; }
  bool valid(const Tag& g, double t, const std::vector<double>& v) const {
    return g.ok && g.t == t && g.rev == w.world_.pairs_revision() && v.size() == w.world_.pairs().size();
  }
  // The gaps at the current engine poses (the last checked pose, of time t): visit's when the
  // pairs have not changed since (a grasp, a release, a part excused no more), else queried now.
  void gaps_here(double t) {
    if (valid(here, t, w.gaps_here_)) return;
    w.world_.query({.clearance_mm = clearance, .contact = false, .gaps = true}, w.result_);
    w.gaps_here_.assign(w.result_.gaps.begin(), w.result_.gaps.end());
    here = tag(t);
  }
  // The stretch to the pose just visited is done: its gaps are the next stretch's start.
  void advance_gaps() {
    if (next.ok) std::swap(w.gaps_here_, w.gaps_next_);
    here = next;
    next.ok = false;
  }

  // Allowance of every enabled pair at the current engine poses (the last checked pose, time t).
  void update_gaps(double t) {
    gaps_here(t);
    const double c = w.settings_.clearance_mm, step = step_mm(w.settings_);
    const std::span<GapPair> gaps = w.world_.gap_pairs();
    for (std::size_t i = 0; i < gaps.size(); ++i) gaps[i].allow_mm = gap_allowance(w.gaps_here_[i], c, step);
  }

  // Contact time (docs/collision-method.md §6.4). `report` holds the contact at the checked
  // pose of report.time_s; the pose `q_free` at `t_free` was checked free against every pair.
  // Bisects in time on the exact path `at(t, q_ref)` (joints at time t; q_ref: the nearest
  // free joints, an IK seed) with only the pairs that collide at the colliding pose, until
  // t_hit - t_free <= toc_tolerance_s, then checks the halting pose against every pair: should
  // another pair meet there (a contact between the samples that the sampled poses missed),
  // that contact is bisected from the start again. Leaves the report at t_hit, time_free_s =
  // t_free and `q_free` at the halting pose; returns false when the halting pose could not be
  // verified free (then it is the original free pose).
  template <class PathAt>
  bool bisect_contact(double t_free, JointVector& q_free, PathAt&& at, CollisionReport& report) {
    const double t_start = t_free;
    const JointVector q_start = q_free;
    const double tol = toc_tolerance(w.settings_);
    std::vector<collision::BodyPair>& hit_pairs = w.hit_pairs_;
    for (int round = 0; round < kMaxBisectionRounds; ++round) {
      w.world_.pose(report.joints, report.time_s);
      hit_pairs.clear();
      CollisionReport probe;
      w.probe_pairs_.assign(w.world_.pairs().begin(), w.world_.pairs().end());
      w.probe_pairs_.insert(w.probe_pairs_.end(), w.world_.touching().begin(), w.world_.touching().end());
      for (const collision::BodyPair& pair : w.probe_pairs_) {
        w.world_.query({.clearance_mm = clearance, .pairs = std::span(&pair, 1)}, w.result_);
        if (record(w.result_, {QueryKind::probe}, report.joints, probe)) hit_pairs.push_back(pair);
      }
      if (hit_pairs.empty()) break;  // cannot happen (the full query found one)
      double t_hit = report.time_s;
      while (t_hit - t_free > tol) {
        const double t = t_free + (t_hit - t_free) / 2;
        if (!(t > t_free && t < t_hit)) break;  // the bracket is one ulp wide
        const JointVector q = at(t, q_free);
        if (record(query(q, t, hit_pairs), {QueryKind::bisection_pose}, q, report)) {
          t_hit = t;
        } else {
          t_free = t;
          q_free = q;
        }
      }
      report.time_s = t_hit;
      report.time_free_s = t_free;
      if (t_free == t_start) return true;  // q_start: checked against every pair already
      CollisionReport other;
      if (!record(query(q_free, t_free), {QueryKind::bisection_pose}, q_free, other)) return true;
      other.time_s = t_free;  // an earlier contact of another pair: bisect it from the start
      report = std::move(other);
      t_free = t_start;
      q_free = q_start;
    }
    report.time_free_s = t_start;
    q_free = q_start;
    return false;
  }

  // Continuous checking sees the trajectory through two facts only: its joints at time t and a
  // bound on each pair's relative motion over [t1, t2] (docs/collision.md §12), so any path
  // that can state both (blended segments too) is checked the same way.
  // Where the walk is: its `at` and `motion` differ between the blended overlap, the segment's
  // stretches (a line's between its checked samples) and a dwell (ContinuousPath::freeze).
  struct Place {
    bool overlap = false, dwell = false;
    std::size_t line_i = 0, line_j = 0;
  };
  Place place() const { return {in_overlap, dwelling, line_i, line_j}; }
  JointVector joints_at(double t, const JointVector& seed) { return joints_at(t, seed, place()); }
  JointVector joints_at(double t, const JointVector& seed, const Place& at) {
    if (at.dwell) return tr.to;
    if (at.overlap) return blended_joints_at(tr, t);
    if (tr.kind != PathKind::line) return joint_path_at(tr, t);
    const LinePoint lp = line_path_between(w.robot_, tr, at.line_i, at.line_j, t, &seed);
    if (lp.ik_used) {
      const PoseError e = pose_error(robots::flange_pose(w.robot_, lp.joints), lp.flange);
      tell([&](WalkObserver& o) { o.on_ik(e, 1); });
    }
    return lp.joints;
  }
  // The joints' travel over [t1, t2] (per joint, the sum of |dq| along the path): the same for
  // every pair of a window, and each pair's bound is linear in it (pair_displacement), so it is
  // computed once per window, not once per pair (a cell of 50 parts has ~400 pairs).
  struct TravelMemo {
    bool ok = false;
    bool overlap = false;
    double t1 = 0, t2 = 0;
    JointVector q1, q2, travel;
  };
  mutable TravelMemo travel_memo{};
  const JointVector& window_travel(double t1, const JointVector& q1, double t2, const JointVector& q2,
                                   bool overlap) const {
    TravelMemo& m = travel_memo;
    if (m.ok && m.overlap == overlap && m.t1 == t1 && m.t2 == t2 && m.q1 == q1 && m.q2 == q2) return m.travel;
    // The overlap: each joint travels at most what both motions' joints travel (docs/blending.md).
    if (overlap) m.travel = blended_travel(tr, t1, t2);
    else if (tr.kind != PathKind::line) m.travel = (q2 - q1).cwiseAbs();
    else m.travel = line_travel(tr.line.samples, tr.profile.sigma(t1 - tr.t0), q1, tr.profile.sigma(t2 - tr.t0), q2);
    m.ok = true;
    m.overlap = overlap;
    m.t1 = t1;
    m.t2 = t2;
    m.q1 = q1;
    m.q2 = q2;
    return m.travel;
  }
  double motion_bound(std::size_t pair, double t1, const JointVector& q1, double t2, const JointVector& q2) const {
    return motion_bound(w.world_.gap_pairs()[world_pair(pair)], t1, q1, t2, q2, in_overlap);
  }
  double motion_bound(const GapPair& p, double t1, const JointVector& q1, double t2, const JointVector& q2,
                      bool overlap) const {
    // Parts on a running conveyor (0 * inf would be NaN on a 1e308 s motion: no belt, no term).
    const double belt = p.speed_mm_s > 0 ? p.speed_mm_s * std::abs(t2 - t1) : 0.0;
    return pair_displacement(w.world_.reach(), p, window_travel(t1, q1, t2, q2, overlap)) + belt;
  }
  void continuous_path() {
    path.at = [this](double t, const JointVector& seed) { return joints_at(t, seed); };
    path.motion = [this](std::size_t pair, double t1, const JointVector& q1, double t2, const JointVector& q2) {
      return motion_bound(pair, t1, q1, t2, q2);
    };
    path.jump = [this](std::size_t pair, double t1, const JointVector& q1, double t2, const JointVector& q2) {
      const GapPair& p = w.world_.gap_pairs()[pair];
      const double belt = p.speed_mm_s > 0 ? p.speed_mm_s * std::abs(t2 - t1) : 0.0;
      return joint_motion(w.world_.reach(), p, q1, q2) + belt;
    };
    path.pose = [this](const JointVector& q, double t) { w.world_.pose(q, t); };
    // The path as it is now, for the clearance report's refinement at the walk's end (the pair's
    // bound by value: the pairs may change by then).
    path.freeze = [this](std::size_t pair) {
      const Place at = place();
      const GapPair p = w.world_.gap_pairs()[world_pair(pair)];
      return ContinuousPath::Frozen{
          [this, at](double t, const JointVector& seed) { return joints_at(t, seed, at); },
          [this, at, p](double t1, const JointVector& q1, double t2, const JointVector& q2) {
            return motion_bound(p, t1, q1, t2, q2, at.overlap);
          }};
    };
    checker->on_measure = [this](const collision::BodyPair& bp, const collision::DistanceResult& r, double t, bool probe,
                                 std::uint64_t ticks) {
      tell([&](WalkObserver& o) { o.on_distance(bp, r, {t, probe, tr.step, ticks, checker->refining()}); });
    };
    checker->on_bound = [this](const collision::BodyPair& bp, double lower_mm) {
      tell([&](WalkObserver& o) { o.on_distance_bound(bp, lower_mm); });
    };
  }

  // The stretch from the last checked pose (t_a, st.joints), free against every pair, to the
  // pose just checked at t_b (the engine is posed there): true with `report` when continuous
  // checking finds a contact in it; then the arm is at the last pose proven free, the clock at
  // the contact.
  bool continuous_contact(double t_a, double t_b, const JointVector& q_b, CollisionReport& report) {
    // The pairs tested now (they change as parts appear, leave, are grasped or released).
    if (w.world_.pairs_revision() != pairs_verified) checker->reset(), pairs_verified = w.world_.pairs_revision();
    path.pairs = checked_pairs();
    ContinuousChecker::WindowBounds known;  // per pair of World::pairs(): not for a dwell's subset
    if (!dwelling && valid(here, t_a, w.gaps_here_)) known.lower_a = w.gaps_here_;
    if (!dwelling && valid(next, t_b, w.gaps_next_)) known.lower_b = w.gaps_next_;
    if (!dwelling && valid(mu, t_a, w.window_mu_)) {
      const std::span<const GapPair> gaps = w.world_.gap_pairs();
      for (std::size_t i = 0; i < gaps.size(); ++i)  // parts on a running conveyor (as motion_bound)
        if (gaps[i].speed_mm_s > 0) w.window_mu_[i] += gaps[i].speed_mm_s * std::abs(t_b - t_a);
      known.mu = w.window_mu_;
    }
    mu.ok = false;
    ContinuousContact c = checker->verify(t_a, st.joints, t_b, q_b, path, known);
    // A part coming to rest on an object or another part (docs/collision.md §15): that pair joins
    // the resting contacts and the stretch is proven again without it.
    while (c.found) {
      const collision::BodyPair p = checked_pairs()[c.pair];
      if (!w.world_.resting_pair(p)) break;
      CollisionReport probe;
      if (record(query(c.q_hit, c.t_hit, std::span(&p, 1)), {QueryKind::probe}, c.q_hit, probe)) break;
      w.world_.rest(p, c.t_hit);
      if (dwelling) moving_pairs();
      checker->reset();
      pairs_verified = w.world_.pairs_revision();
      path.pairs = checked_pairs();
      c = checker->verify(t_a, st.joints, t_b, q_b, path, {});
      if (!c.found) {
        w.world_.pose(q_b, t_b);
        w.world_.confirm_resting();
      }
    }
    if (!c.found) return false;
    checker->reset();
    const collision::BodyPair pair = checked_pairs()[c.pair];
    CollisionReport r;
    if (!record(query(c.q_hit, c.t_hit, std::span(&pair, 1)), {QueryKind::probe}, c.q_hit, r)) {
      // A graze (no probe in contact, docs/collision.md §12): the pair, the point halfway
      // between its witnesses.
      const collision::DistanceResult d = engine->distance(pair.a, pair.b);
      r.body_a = w.world_.body_name(pair.a);
      r.body_b = w.world_.body_name(pair.b);
      r.id_a = pair.a;
      r.id_b = pair.b;
      r.point = 0.5 * (d.point_a + d.point_b);
      r.face_a = d.face_a;
      r.face_b = d.face_b;
      r.joints = c.q_hit;
    }
    r.time_s = c.t_hit;
    r.time_free_s = c.t_free;
    st.joints = c.q_free;
    st.last_free = true;
    st.time_s = c.t_hit;
    report = std::move(r);
    return true;
  }

  MotionResult collision_result(CollisionReport report, double search_s) {
    report.step = tr.step;
    w.world_.rewind_to(st.time_s);  // the devices at the contact instant, not the checked pose after
    tell([&](WalkObserver& o) { o.on_contact(report, st.joints, search_s); });
    MotionResult r;
    r.status = MotionStatus::collision;
    r.collision = std::move(report);
    return r;
  }

  // Halts on the contact found at the checked pose of `report.time_s`; `t_prev` is the time of
  // the pose before (the current joints), `was_free` whether it was checked and free (then the
  // contact time is bisected). The arm stays at the last free pose, the clock at the contact.
  template <class PathAt>
  MotionResult halt(CollisionReport report, double t_prev, bool was_free, PathAt&& at) {
    const auto t0 = std::chrono::steady_clock::now();
    report.time_free_s = t_prev;
    st.last_free = was_free && bisect_contact(t_prev, st.joints, at, report);
    st.time_s = report.time_s;
    return collision_result(std::move(report), std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }

  // Ctrl-C's flag, then the stop condition (a REACTI) at the current joints, of time t_prev.
  bool interrupt_requested(double t_prev) {
    if (w.interrupt_ && w.interrupt_->load(std::memory_order_relaxed)) return true;
    by_condition = w.stop_condition_ && w.stop_condition_(t_prev, st.joints);
    return by_condition;
  }
  bool by_condition = false;  // the last interrupt_requested() was the stop condition's

  // The checked pose q at t, reached from the current joints at t_prev: true (with `stopped`)
  // when a contact at it or on the stretch before it stops the walk; otherwise the arm is there.
  template <class PathAt>
  bool stopped_at(const JointVector& q, double t_prev, double t, CollisionReport& report, PathAt&& at,
                  MotionResult& stopped) {
    const bool was_free = st.last_free;
    const bool hit = visit(q, t, report);
    if (checker && was_free && continuous_contact(t_prev, t, q, report)) {
      stopped = collision_result(std::move(report), 0);
      return true;
    }
    if (hit) {
      stopped = halt(std::move(report), t_prev, was_free, at);
      return true;
    }
    st.joints = q;
    advance_gaps();
    if (engine) w.world_.free_pose_seen();
    return false;
  }

  // Stops at the current joints (the last checked pose, of time t_halt, at path parameter
  // `fraction`).
  MotionResult interrupt_halt(double t_halt, double fraction) {
    st.time_s = t_halt;
    MotionResult r;
    r.status = MotionStatus::interrupted;
    r.interrupt = InterruptReport{t_halt, fraction, st.joints, tr.step, by_condition, false};
    return r;
  }

  void stretch(const Stretch& s) {
    tell([&](WalkObserver& o) { o.on_stretch(tr, s); });
  }

  // The latest end in (t_prev, t] for a stretch of an arm motion while parts ride on running
  // conveyors: never past the devices' next change (the part speeds are constant up to it, as
  // the motion bounds of gap stepping and continuous checking assume), nor past the broad
  // phase's room for the belt-borne parts (World::belt_time), and, with continuous checking
  // off, the belt's share within the step rule: fixed stepping moves each belt-borne part at
  // most step_mm, gap stepping keeps each of its pairs within its gap allowance (the arm's
  // share over the stretch, segment_travel, plus the belt's), halving the stretch until it fits.
  // Without parts on a running belt: t.
  template <class Travel>
  double part_cap(double t_prev, double t, bool gap, Travel&& travel) {
    if (!engine || !w.world_.has_parts()) return t;
    const double floor = std::nextafter(t_prev, INFINITY);  // progress, whatever the bounds
    t = std::min(t, std::max(floor, w.world_.next_part_change()));
    t = std::min(t, std::max(floor, t_prev + w.world_.belt_time()));
    if (checker) return t;  // continuous checking proves the windows with the belts' motion
    double speed = 0;
    for (const GapPair& p : w.world_.gap_pairs()) speed = std::max(speed, p.speed_mm_s);
    if (!(speed > 0)) return t;
    if (!gap) return std::min(t, std::max(floor, t_prev + step_mm(w.settings_) / speed));
    for (int halvings = 0; halvings < 60 && t > floor; ++halvings) {
      const JointVector arm = travel(t_prev, t);
      bool fits = true;
      for (const GapPair& p : w.world_.gap_pairs())
        if (p.speed_mm_s > 0 && pair_displacement(w.world_.reach(), p, arm) + p.speed_mm_s * (t - t_prev) > p.allow_mm) {
          fits = false;
          break;
        }
      if (fits) return t;
      t = std::max(floor, t_prev + (t - t_prev) / 2);
    }
    return t;
  }

  // The segment's own grid from the current time (tr.t0, or the end of the overlap with the
  // previous motion) to `stop` (tr.end_time(), or earlier when the next motion blends in at
  // `stop`): checked poses on the grid between, then the pose at `stop` itself.
  MotionResult line(bool gap, double stop) {
    const auto& samples = tr.line.samples;
    const bool to_end = stop >= tr.end_time();
    const double sigma_stop = to_end ? 1.0 : tr.profile.sigma(stop - tr.t0);
    double t_prev = st.time_s;  // time and path parameter of the current joints
    double sigma_prev = tr.profile.sigma(t_prev - tr.t0);
    std::size_t i = sample_before(samples, sigma_prev);
    // The last sample to visit: the end, or the first at or after sigma_stop (visited as the
    // pose at `stop`).
    std::size_t last = samples.size() - 1;
    if (!to_end)
      while (last > i + 1 && samples[last - 1].s >= sigma_stop) --last;
    CollisionReport report;
    while (i < last) {
      if (interrupt_requested(t_prev)) return interrupt_halt(t_prev, sigma_prev);
      // Next checked sample j: the next one, or with gap stepping the farthest the gaps allow.
      std::size_t j = i + 1;
      double bound = samples[j].bound_mm;
      broad();
      if (gap) {
        update_gaps(t_prev);
        j = std::min(gap_next_sample(w.world_.reach(), samples, i, w.world_.gap_pairs(), w.gap_scratch_, bound,
                                     w.world_.room()),
                     last);
        // Its per-pair sums to the sample it chose (>= j: a bound for the stretch): the
        // stretch's motion bounds, line_motion's.
        if (checker) {
          const std::size_t n = w.world_.reach().size();
          w.window_mu_.assign(w.gap_scratch_.sums.begin() + n, w.gap_scratch_.sums.begin() + n + w.world_.gap_pairs().size());
          mu = tag(t_prev);
        }
      } else if (checker) {
        gaps_here(t_prev);
      }
      const LineSample &a = samples[i], &b = samples[j];
      const bool at_stop = j == last && !to_end;
      double t = at_stop ? stop : tr.t0 + tr.profile.time_at(b.s);
      JointVector q = at_stop ? segment_joints_at(tr, stop) : b.joints;
      double sigma = at_stop ? sigma_stop : b.s;
      // Parts on a belt may end the stretch before sample j (part_cap): a pose on the line's
      // joint path between the samples, and sample i stays the next stretch's start.
      const double t_cap = part_cap(t_prev, t, gap, [this](double x, double y) { return segment_travel(tr, x, y); });
      const bool capped = t_cap < t;
      if (capped) {
        t = t_cap;
        q = segment_joints_at(tr, t);
        sigma = tr.profile.sigma(t - tr.t0);
      }
      stretch({t_prev, t, sigma_prev, sigma, i, j, bound});
      const bool was_free = st.last_free;
      const bool hit = visit(q, t, report);
      line_i = i;
      line_j = j;
      // The distances are measured in the engine's time (timing: on_distance).
      if (checker && was_free && continuous_contact(t_prev, t, q, report))
        return collision_result(std::move(report), 0);
      if (hit) {
        // Between samples: the line's pose at sigma(t) by IK seeded with the nearest free
        // joints, as plan_line solves its samples (line_path_at).
        const auto at = [this, &a, &b](double tm, const JointVector& ref) {
          const LinePoint lp = line_path_at(w.robot_, tr, a, b, tm, ref);
          if (lp.ik_used) {
            const PoseError e = pose_error(robots::flange_pose(w.robot_, lp.joints), lp.flange);
            tell([&](WalkObserver& o) { o.on_ik(e, 1); });
          }
          return lp.joints;
        };
        return halt(std::move(report), t_prev, was_free, at);
      }
      st.joints = q;
      advance_gaps();
      if (engine) w.world_.free_pose_seen();  // after the stretch's continuous check: excused there
      t_prev = t;
      sigma_prev = sigma;
      if (!capped) i = j;
    }
    return {};
  }

  MotionResult joint(bool gap, double stop) {
    const auto at = [this](double tm, const JointVector&) { return joint_path_at(tr, tm); };
    // Bound per grid interval of each body: the bound is linear in the joint step.
    const JointVector step = (tr.to - tr.from) / tr.intervals;
    double body_max = 0;
    for (const robots::BodyReach& r : w.world_.reach()) body_max = std::max(body_max, robots::max_displacement(r, step));
    // Per pair of the world: what one grid interval can change its distance by (again when
    // the pairs change: parts appear, leave, are grasped or released).
    std::uint64_t pairs_seen = ~std::uint64_t{0};
    const auto pair_bounds = [&] {
      if (w.world_.pairs_revision() == pairs_seen) return;
      pairs_seen = w.world_.pairs_revision();
      const std::span<const GapPair> gaps = w.world_.gap_pairs();
      w.pair_mm_.resize(gaps.size());
      for (std::size_t k = 0; k < gaps.size(); ++k) w.pair_mm_[k] = pair_displacement(w.world_.reach(), gaps[k], step);
    };
    const int n = tr.intervals;
    const bool to_end = stop >= tr.end_time();
    const double sigma_stop = to_end ? 1.0 : tr.profile.sigma(stop - tr.t0);
    double t_prev = st.time_s;
    double sigma_from = tr.profile.sigma(t_prev - tr.t0);
    // Grid points: from the one at or before the current sigma to the one at or after sigma_stop.
    int i = std::clamp(static_cast<int>(std::floor(sigma_from * n)), 0, n);
    const int last = to_end ? n : std::clamp(static_cast<int>(std::ceil(sigma_stop * n)), i + 1, n);
    JointVector q(st.joints.size());
    CollisionReport report;
    while (i < last) {
      if (interrupt_requested(t_prev)) return interrupt_halt(t_prev, sigma_from);
      int k = 1;
      broad();
      if (gap) {
        pair_bounds();
        update_gaps(t_prev);
        k = gap_intervals(w.pair_mm_, w.world_.gap_pairs(), last - i);
        // Each arm body within its broad-phase room (at least one interval: broad() left it room
        // for one interval of step_mm).
        const std::span<const double> room = w.world_.room();
        for (std::size_t b = 0; b < room.size(); ++b)
          if (const double per = robots::max_displacement(w.world_.reach()[b], step); per > 0 && room[b] < k * per)
            k = std::max(1, static_cast<int>(std::min<double>(k, std::floor(room[b] / per))));
        // k intervals of pair_mm_ each (the first may start past a grid point, the last end
        // before one): the stretch's motion bounds, joint_motion's.
        if (checker) {
          w.window_mu_.resize(w.pair_mm_.size());
          for (std::size_t p = 0; p < w.pair_mm_.size(); ++p) w.window_mu_[p] = k * w.pair_mm_[p];
          mu = tag(t_prev);
        }
      } else if (checker) {
        gaps_here(t_prev);
      }
      const bool at_last = i + k == last;
      double sigma = at_last ? sigma_stop : static_cast<double>(i + k) / n;
      q = at_last && to_end ? tr.to : interpolate_joints(tr.from, tr.to, sigma);
      double t = at_last ? stop : tr.t0 + tr.profile.time_at(sigma);
      // Parts on a belt may end the stretch before grid point i + k (part_cap): a pose between
      // grid points, from which the next stretch's k intervals are counted from i again.
      if (const double t_cap = part_cap(t_prev, t, gap, [this](double x, double y) { return segment_travel(tr, x, y); });
          t_cap < t) {
        t = t_cap;
        sigma = tr.profile.sigma(t - tr.t0);
        q = interpolate_joints(tr.from, tr.to, sigma);
      } else {
        i += k;
      }
      stretch({t_prev, t, sigma_from, sigma, 0, 0, k * body_max});
      if (MotionResult r; stopped_at(q, t_prev, t, report, at, r)) return r;
      t_prev = t;
      sigma_from = sigma;
    }
    return {};
  }

  // The overlap with the previous motion up to `stop` (<= tr.blend_end()): the superposed path
  // (blended_joints_at), stepped in time so that the bound over each interval from the joint
  // travel of both segments (blended_travel) keeps the step rule (every body and moving pair
  // within step_mm; with gap stepping every pair within its gap allowance at the last checked
  // pose): the interval is halved until it fits, and doubled again after each checked pose.
  MotionResult overlap(bool gap, double stop) {
    const auto at = [this](double tm, const JointVector&) { return blended_joints_at(tr, tm); };
    const double limit = step_mm(w.settings_);
    const auto fits = [&](const JointVector& travel, double& body) {
      const double d = max_body_displacement(w.world_.reach(), travel, w.world_.moving_pairs(), &body);
      if (!gap) return d <= limit;
      for (const GapPair& p : w.world_.gap_pairs())
        if (pair_displacement(w.world_.reach(), p, travel) > p.allow_mm) return false;
      const std::span<const double> room = w.world_.room();  // the broad phase's (docs/collision.md §14)
      for (std::size_t b = 0; b < room.size(); ++b)
        if (robots::max_displacement(w.world_.reach()[b], travel) > room[b]) return false;
      return true;
    };
    double t_prev = st.time_s, dt = stop - t_prev;
    CollisionReport report;
    while (t_prev < stop) {
      if (interrupt_requested(t_prev)) return interrupt_halt(t_prev, tr.profile.sigma(t_prev - tr.t0));
      broad();
      if (gap) update_gaps(t_prev);
      else if (checker) gaps_here(t_prev);
      double t = std::min(stop, t_prev + dt), body = 0;
      for (int halvings = 0; !fits(blended_travel(tr, t_prev, t), body) && halvings < 60; ++halvings) {
        dt /= 2;
        t = t_prev + dt;
      }
      if (!(t > t_prev)) t = std::min(stop, std::nextafter(t_prev, stop));
      t = part_cap(t_prev, t, gap, [this](double x, double y) { return blended_travel(tr, x, y); });
      const JointVector q = at(t, st.joints);
      stretch({t_prev, t, tr.profile.sigma(t_prev - tr.t0), tr.profile.sigma(t - tr.t0), 0, 0, body, true});
      if (MotionResult r; stopped_at(q, t_prev, t, report, at, r)) return r;
      t_prev = t;
      dt *= 2;
    }
    st.time_s = stop;  // the segment's own walk goes on from here
    return {};
  }

  // Time passing with the arm at rest up to `stop` (tr: the arm's joints, from = to): only
  // parts carried by a running conveyor move. The speeds are constant between two device
  // changes (DeviceClock::next_change), so each such stretch is walked with checked poses no
  // farther apart than the step rule allows the fastest pair (its belt speed times the
  // interval within step_mm; with gap stepping within each moving pair's gap allowance), and
  // continuous checking proves the stretches between them. A stretch where nothing moves is
  // skipped to the next change without a query.
  // The pairs of a belt-borne part now (the checker's cache is of the list: reset on a change).
  void moving_pairs() {
    const std::span<const collision::BodyPair> all = w.world_.pairs();
    const std::span<const GapPair> gaps = w.world_.gap_pairs();
    dwell_scratch.clear();
    std::vector<std::size_t> index;
    for (std::size_t k = 0; k < gaps.size() && k < all.size(); ++k)
      if (gaps[k].speed_mm_s > 0) dwell_scratch.push_back(all[k]), index.push_back(k);
    const bool same = index == dwell_index;  // same indices, same revision: the same pairs
    dwell_pairs.swap(dwell_scratch);
    dwell_index = std::move(index);
    if (!same && checker) checker->reset();
  }

  MotionResult dwell(bool gap, double stop) {
    const auto at = [this](double, const JointVector&) { return tr.to; };
    const double limit = step_mm(w.settings_);
    double t_prev = st.time_s;
    w.world_.pose(tr.to, t_prev);  // the parts' state now (the program may have changed signals)
    CollisionReport report;
    while (t_prev < stop) {
      // Ctrl-C (or SIGTERM) during a wait with parts moving: the clock stops where it is. No
      // motion was halted: the interpreter does not keep it as a motion to resume.
      if (w.interrupt_ && w.interrupt_->load(std::memory_order_relaxed)) {  // Ctrl-C's flag only
        st.time_s = t_prev;
        MotionResult r;
        r.status = MotionStatus::interrupted;
        r.interrupt = InterruptReport{t_prev, 1, tr.to, tr.step, false, true};
        return r;
      }
      const double change = std::min(stop, w.world_.next_part_change());
      double speed = 0;
      broad();  // the belt-borne parts' near lists (their room: below)
      for (const GapPair& p : w.world_.gap_pairs()) speed = std::max(speed, p.speed_mm_s);
      moving_pairs();
      if (!(speed > 0)) {  // nothing moves until the next change
        if (change < stop) w.world_.pose(tr.to, change);
        t_prev = change;
        continue;
      }
      if (!st.start_checked) {  // the run's first pose (no motion before): the stretches start free
        st.start_checked = true;
        if (visit(tr.to, t_prev, report)) return collision_result(std::move(report), 0);
      }
      double dt = limit / speed;
      if (gap) {  // each moving pair within its allowance (at least the step)
        dt = std::numeric_limits<double>::infinity();
        // The gaps of the moving pairs only (the others cannot change distance while the arm
        // rests); every pair's when the engine skipped one of them (then the orders differ).
        w.world_.query({.clearance_mm = clearance, .pairs = std::optional(checked_pairs()), .contact = false, .gaps = true},
                       w.result_);
        const std::span<const GapPair> gaps = w.world_.gap_pairs();
        if (w.result_.gaps.size() == dwell_pairs.size()) {
          const double c = w.settings_.clearance_mm, step = step_mm(w.settings_);
          for (std::size_t k = 0; k < dwell_pairs.size(); ++k) {
            const GapPair& p = gaps[dwell_index[k]];
            dt = std::min(dt, gap_allowance(w.result_.gaps[k], c, step) / p.speed_mm_s);
          }
        } else {
          update_gaps(t_prev);
          for (const GapPair& p : gaps)
            if (p.speed_mm_s > 0) dt = std::min(dt, p.allow_mm / p.speed_mm_s);
        }
        dt = std::min(dt, w.world_.belt_time());  // the pairs the broad phase left out stay beyond keep
      }
      double t = std::min(change, t_prev + dt);
      if (!(t > t_prev)) t = std::min(stop, std::nextafter(t_prev, stop));
      stretch({t_prev, t, 1, 1, 0, 0, speed * (t - t_prev)});
      const bool was_free = st.last_free;
      const bool hit = visit(tr.to, t, report);
      if (checker && was_free && continuous_contact(t_prev, t, tr.to, report)) return collision_result(std::move(report), 0);
      if (hit) return halt(std::move(report), t_prev, was_free, at);
      w.world_.free_pose_seen();
      t_prev = t;
    }
    st.time_s = stop;
    return {};
  }

  MotionResult run(double until_s) {
    CollisionReport report;
    if (!st.start_checked) {  // the start pose of the first motion
      st.start_checked = true;
      if (visit(st.joints, st.time_s, report)) return collision_result(std::move(report), 0);
    }
    // Gap stepping needs the engine: the gaps are its containers' (at the current pose).
    const bool gap = engine && w.settings_.stepping == Stepping::gap;
    if (engine) w.world_.pose(st.joints, st.time_s);  // parts grasped or released since: their pairs
    if (checker) continuous_path();
    want_gaps = gap || checker != nullptr;
    const double stop = std::min(until_s, tr.end_time());
    if (st.time_s < tr.blend_end()) {  // continuous path: the overlap with the previous motion first
      in_overlap = true;
      MotionResult r = overlap(gap, std::min(stop, tr.blend_end()));
      in_overlap = false;
      if (r.status != MotionStatus::ok) return r;
    }
    if (st.time_s < stop || stop >= tr.end_time()) {
      if (engine) w.world_.pose(st.joints, st.time_s);  // the gaps are of the current pose
      MotionResult r = tr.kind == PathKind::line ? line(gap, stop) : joint(gap, stop);
      if (r.status != MotionStatus::ok) return r;
    }
    if (stop >= tr.end_time()) {
      st.joints = tr.to;
      st.time_s = tr.end_time();
    } else {
      st.time_s = stop;
    }
    return {};
  }
};

ContinuousChecker* Walker::checker(collision::Engine* engine) {
  if (!engine || !settings_.continuous) return nullptr;
  if (!continuous_) continuous_ = std::make_unique<ContinuousChecker>(*engine, 0, toc_tolerance(settings_), 0);
  continuous_->set_clearance(halting_clearance(settings_));
  continuous_->set_report_mm(report_distance_mm(settings_));
  // Posing at an earlier time moves only the arm when no part can move by itself.
  continuous_->set_lazy_report(!world_.has_parts());
  continuous_->reset();  // between walks the hand, the parts or the settings may have changed
  continuous_->discard();
  return continuous_.get();
}

MotionResult Walker::dwell(WalkState& state, double until_s, int step) {
  collision::Engine* engine = settings_.enabled ? world_.engine() : nullptr;
  if (!(until_s > state.time_s)) return {};
  if (!engine || !world_.has_parts()) {  // nothing can move without the arm: the clock only
    state.time_s = until_s;
    return {};
  }
  Trajectory tr;  // the arm at rest: a null joint move at its joints
  tr.from = tr.to = state.joints;
  tr.t0 = state.time_s;
  tr.step = step;
  Walk walk{.w = *this, .tr = tr, .st = state, .engine = engine, .clearance = halting_clearance(settings_), .checker = checker(engine)};
  walk.dwelling = true;
  if (walk.checker) walk.continuous_path();
  walk.tell([&](WalkObserver& o) { o.on_walk_begin(tr); });
  MotionResult r = walk.dwell(settings_.stepping == Stepping::gap, until_s);
  walk.tell([](WalkObserver& o) { o.on_walk_end(); });
  return r;
}

MotionResult Walker::walk(const Trajectory& tr, WalkState& state, double until_s) {
  collision::Engine* engine = settings_.enabled ? world_.engine() : nullptr;
  Walk walk{.w = *this, .tr = tr, .st = state, .engine = engine, .clearance = halting_clearance(settings_), .checker = checker(engine)};
  walk.tell([&](WalkObserver& o) { o.on_walk_begin(tr); });
  MotionResult r = walk.run(until_s);
  if (walk.checker) {  // the clearance report's kept poses, before the recorders close the walk
    const JointVector q = world_.posed_joints();
    const double t = world_.posed_time();
    if (walk.checker->flush(walk.path)) world_.pose(q, t);
  }
  walk.tell([](WalkObserver& o) { o.on_walk_end(); });
  return r;
}

}  // namespace asimov::motion
