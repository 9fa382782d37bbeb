// The simulated arm in its cell (dialect §4-§5, docs/kinematics.md §5-§8, docs/collision-method.md §6.3).
//
// Frames: HERE = BASE . FK(q) . TOOL with the program's BASE and TOOL; the physical robot stays
// at cell.base ("BASE moves neither robot nor cell"), so collision bodies use cell.base . frames[k].
#include "asimov/motion/simulator.hpp"

#include "asimov/collision/container_gap.hpp"
#include "asimov/collision/engine.hpp"
#include "asimov/motion/profile.hpp"
#include "asimov/motion/sampler.hpp"
#include "asimov/motion/scene.hpp"
#include "asimov/robots/ik.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <optional>
#if defined(__x86_64__) || defined(__i386__)
#include <x86intrin.h>
#endif

namespace asimov::motion {
namespace {
using robots::JointVector;

constexpr int kMaxBisectionRounds = 4;  // contact-time bisections per contact (another pair met)

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// Adds the wall time of a scope to `acc`.
struct ScopeTimer {
  double& acc;
  Clock::time_point t0 = Clock::now();
  ~ScopeTimer() { acc += seconds_since(t0); }
};

// Per-query timer: reading the time-stamp counter costs a few ns, clock_gettime ~20 ns, which
// at two reads per checked pose (~1 us each) was 7 % of a run. Ticks become seconds with the
// steady_clock time of the whole motion (Impl::MotionClock); elsewhere steady_clock itself.
#if defined(__x86_64__) || defined(__i386__)
std::uint64_t ticks() { return __rdtsc(); }
#else
std::uint64_t ticks() { return static_cast<std::uint64_t>(Clock::now().time_since_epoch().count()); }
#endif

MotionResult error(const char* message, std::string detail = {}) {
  MotionResult r;
  r.status = MotionStatus::error;
  r.error.message = message;
  r.error.detail = std::move(detail);
  return r;
}

std::string fmt_limit(const robots::Robot& robot, int j, double v) {
  char buf[96];
  const double lo = robot.lower[j], hi = robot.upper[j];
  if (v > hi)
    std::snprintf(buf, sizeof buf, "J%d = %.3f > %.3f", j + 1, v, hi);
  else
    std::snprintf(buf, sizeof buf, "J%d = %.3f < %.3f", j + 1, v, lo);
  return buf;
}

std::string fmt_fraction(const char* what, double s) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "%s at %.1f %% of the path", what, 100 * s);
  return buf;
}
}  // namespace

struct Simulator::Impl {
  Cell cell;
  JointVector joints;
  Location base, tool, dest;
  robots::ConfigurationRequest request;
  double time = 0;
  std::uint64_t poses = 0;
  std::uint64_t bisection = 0;               // poses checked by contact-time bisection
  bool last_free = false;                    // the last visited pose was checked and found free
  std::vector<collision::BodyPair> hit_pairs;  // bisection: pairs colliding at the first hit
  bool tracing = false;
  std::vector<TraceSample> trace;
  double replay_grid = 0;                    // set_replay: > 0 records replay samples
  std::vector<ReplaySample> replay;
  collision::StepCounts counts;
  std::optional<collision::Engine> engine;
  bool engine_built = false;                 // build_engine() ran (engine empty: no enabled pair)
  std::vector<collision::BodyId> link_ids;  // per robot body (index into cell.robot.bodies)
  std::optional<collision::BodyId> tool_id;
  std::vector<robots::BodyReach> reach;      // robot bodies (index = body index), then the tool
  std::vector<BodyPair> moving_pairs;        // enabled pairs of two moving bodies (indices into reach)
  std::vector<collision::Pose> frames;
  bool start_checked = false;
  HandState hand = HandState::open;
  std::optional<HandState> hand_request;
  RunAccuracy accuracy;
  RunTiming timing;
  const std::atomic<bool>* interrupt = nullptr;  // Ctrl-C (set_interrupt), read before each checked pose
  std::function<void(double, const JointVector&)> pose_hook;
  // The rest of a motion halted by the interrupt (halted_motion / resume_motion).
  struct Rest {
    JointVector to;            // joint target
    bool straight = false;
    Location target;           // location target (dest of the motion)
    SpeedSettings speed;
    double elapsed_s = 0;      // time the motion ran before it halted
  } rest;
  std::optional<InterruptReport> halted;
  std::vector<collision::BodyId> unprepared;  // engine bodies whose voxel grid is not built yet
  std::uint64_t query_ticks = 0, grid_ticks = 0;  // this motion's engine queries (ticks())

  // finish_motion's wall time: its queries' ticks, converted with the motion's steady_clock
  // time, go to collision (or preprocessing when they built a lazy grid); the rest, less what
  // bisection timed itself, is motion.
  struct MotionClock {
    Impl& s;
    Clock::time_point t0 = Clock::now();
    std::uint64_t k0 = ticks();
    double other0 = s.timing.collision_s + s.timing.preprocess_s;
    explicit MotionClock(Impl& impl) : s(impl) { s.query_ticks = s.grid_ticks = 0; }
    ~MotionClock() {
      const double wall = seconds_since(t0);
      const std::uint64_t k = ticks() - k0;
      const double per_tick = k > 0 ? wall / static_cast<double>(k) : 0.0;
      s.timing.collision_s += static_cast<double>(s.query_ticks) * per_tick;
      s.timing.preprocess_s += static_cast<double>(s.grid_ticks) * per_tick;
      s.timing.motion_s += wall - (s.timing.collision_s + s.timing.preprocess_s - other0);
    }
  };

  // Gap stepping (docs/collision-method.md §6.3): per engine body its step-2 container, where it sits and
  // its world box; per enabled pair (engine->enabled_pairs() order) its allowance.
  struct GapBody {
    collision::Container container;
    int reach = -1;          // index into `reach`; -1: never moves (object, base link)
    int frame = -1;          // index into `frames`; -1: fixed pose
    collision::Pose pose = collision::Pose::Identity();
    collision::PlacedContainer placed;  // at `pose`
  };
  std::vector<GapBody> gap_bodies;
  std::vector<GapPair> gap_pairs;
  std::vector<double> pair_mm, scratch;  // per pair bound of one grid interval; line scratch

  // The motion starts now: a pending OPEN/CLOSE/RELAX takes effect.
  void motion_started() {
    if (hand_request) hand = *hand_request, hand_request.reset();
  }

  // The pending motion.
  struct Pending {
    bool active = false;
    bool straight = false;
    JointVector from, to;
    int intervals = 1;
    LinePlan line;
    LinePath path;                               // straight: the tool-point line, and what maps
    Location base_inv, tool_inv;                 //   it to the flange, for poses between samples
    Location base, tool;                         // program BASE / TOOL (line deviation)
    robots::Configuration config;
    Profile profile;
    SpeedSettings speed;
    double t0 = 0;
    int step = 0;
  } pending;

  explicit Impl(Cell c) : cell(std::move(c)) {
    const ScopeTimer timer{timing.preprocess_s};
    const auto& robot = cell.robot;
    joints = start_joints(cell);
    base = cell.base;
    tool = cell.tool;
    frames.reserve(static_cast<std::size_t>(robot.joint_count()) + 1);
    for (const auto& b : robot.bodies) reach.push_back(robots::body_reach(robot, b.mesh, b.link));
    if (cell.tool_shape) reach.push_back(robots::body_reach(robot, *cell.tool_shape, robot.joint_count()));
    dest = here();
    if (cell.collision.enabled) build_engine();
  }

  Location here() const { return base * robots::flange_pose(cell.robot, joints) * tool; }
  Location here_at(const JointVector& q) const { return base * robots::flange_pose(cell.robot, q) * tool; }

  void build_engine() {
    engine_built = true;
    const auto& robot = cell.robot;
    collision::Engine e;
    // Bodies, groups and joined pairs: motion/scene.hpp (shared with `asimov pairs`).
    Scene scene = scene_bodies(cell);
    std::optional<collision::AutoPairs> generated;
    if (cell.collision.generated_pairs) {
      const collision::AutoPairsInput in = auto_pairs_input(cell, scene, cell.collision.pair_samples);
      try {
        generated = cell.collision.pairs_cache.empty() ? collision::generate_pairs(in)
                                                      : collision::generate_pairs_cached(in, cell.collision.pairs_cache);
      } catch (const std::exception&) {  // the cache could not be written: the matrix is still good
        generated = collision::generate_pairs(in);
      }
    }
    std::vector<collision::BodyId> statics, scene_ids;
    for (std::size_t i = 0; i < scene.bodies.size(); ++i) {  // robot bodies, "tool", objects
      SceneBody& b = scene.bodies[i];
      GapBody g;
      g.container = collision::make_container(b.mesh.vertices);
      if (i < robot.bodies.size() && robot.bodies[i].link > 0) {
        g.reach = static_cast<int>(i);
        g.frame = robot.bodies[i].link;
      } else if (i >= robot.bodies.size() && b.object < 0) {  // the tool, on the flange
        g.reach = static_cast<int>(robot.bodies.size());
        g.frame = robot.joint_count();
      } else {
        g.pose = i < robot.bodies.size() ? cell.base : cell.objects[static_cast<std::size_t>(b.object)].pose;
        g.placed = collision::place(g.container, g.pose);
      }
      gap_bodies.push_back(std::move(g));
      const auto id = e.add_body({.name = std::move(b.name), .mesh = std::move(b.mesh), .group = b.group,
                                  .is_static = b.is_static, .halvings = cell.collision.halvings});
      scene_ids.push_back(id);
      if (i < robot.bodies.size()) link_ids.push_back(id);
      else if (b.object < 0) tool_id = id;
      else statics.push_back(id);
    }
    if (generated) {
      collision::apply_pairs(*generated, e);  // body ids are the scene indices (a fresh engine)
    } else {
      for (const collision::BodyPair& p : scene.adjacent) e.set_pair_enabled(scene_ids[p.a], scene_ids[p.b], false);
      for (const collision::BodyPair& p : scene.ignored) e.set_pair_enabled(scene_ids[p.a], scene_ids[p.b], false);
    }
    if (!e.has_enabled_pairs()) return;  // never call the engine
    e.set_clearance(cell.collision.clearance_mm);
    for (std::size_t i = 0; i < cell.objects.size(); ++i) e.set_pose(statics[i], cell.objects[i].pose);
    for (std::size_t i = 0; i < robot.bodies.size(); ++i)
      if (robot.bodies[i].link == 0) e.set_pose(link_ids[i], cell.base);
    // Pairs of two moving bodies: their relative motion is bounded by the sum of both bounds.
    std::vector<collision::BodyId> ids = link_ids;
    if (tool_id) ids.push_back(*tool_id);
    for (std::size_t i = 0; i < ids.size(); ++i)
      for (std::size_t j = i + 1; j < ids.size(); ++j) {
        const bool moving_i = i >= robot.bodies.size() || robot.bodies[i].link > 0;
        const bool moving_j = j >= robot.bodies.size() || robot.bodies[j].link > 0;
        if (moving_i && moving_j && e.pair_enabled(ids[i], ids[j]))
          moving_pairs.emplace_back(static_cast<int>(i), static_cast<int>(j));
      }
    for (const collision::BodyPair& p : e.enabled_pairs()) {
      const GapBody &a = gap_bodies[p.a], &b = gap_bodies[p.b];
      gap_pairs.push_back({a.reach, b.reach, std::max(a.frame, 0), std::max(b.frame, 0), 0});
    }
    for (std::size_t i = 0; i < gap_bodies.size(); ++i) unprepared.push_back(static_cast<collision::BodyId>(i));
    engine.emplace(std::move(e));
  }

  // Gap stepping in use for the motion being carried out (needs the engine: gaps are its containers).
  bool gap_stepping() const {
    return engine && cell.collision.enabled && cell.collision.stepping == Stepping::gap;
  }

  // Allowance of every enabled pair at the pose whose link frames are in `frames`.
  void update_gaps() {
    for (GapBody& g : gap_bodies)
      if (g.frame >= 0) {
        g.pose = cell.base * frames[static_cast<std::size_t>(g.frame)];
        g.placed = collision::place(g.container, g.pose);
      }
    const auto pairs = engine->enabled_pairs();
    const double c = cell.collision.clearance_mm, st = step_mm();
    for (std::size_t i = 0; i < pairs.size(); ++i) {
      const GapBody &a = gap_bodies[pairs[i].a], &b = gap_bodies[pairs[i].b];
      const double margin = collision::relative_margin(a.container, a.pose, b.container, b.pose);
      gap_pairs[i].allow_mm = gap_allowance(collision::container_gap(a.placed, b.placed, margin), c, st);
    }
  }

  // Wall time of one engine query: preprocessing when it built a lazy voxel grid, else collision.
  // Grids are built only for pairs that pass step 2, so most queries need no look at the bodies.
  void charge_query(std::uint64_t dt, const collision::QueryResult& r) {
    if (r.counts.pairs_after_minimax > 0 && !unprepared.empty()) {
      const std::size_t before = unprepared.size();
      std::erase_if(unprepared, [this](collision::BodyId id) { return engine->body_preprocessed(id); });
      if (unprepared.size() != before) {
        grid_ticks += dt;
        return;
      }
    }
    query_ticks += dt;
  }

  // Poses the moving bodies at `q` in the engine.
  void pose_bodies(const JointVector& q) {
    robots::link_frames(cell.robot, q, frames);
    const auto& bodies = cell.robot.bodies;
    for (std::size_t i = 0; i < bodies.size(); ++i)
      if (bodies[i].link > 0) engine->set_pose(link_ids[i], cell.base * frames[static_cast<std::size_t>(bodies[i].link)]);
    if (tool_id) engine->set_pose(*tool_id, cell.base * frames.back());
  }

  // Adds a query's counts; on contact fills `report` (bodies, point, faces, joints `q`).
  bool record(const collision::QueryResult& r, const JointVector& q, CollisionReport& report) {
    counts.pairs_enabled += r.counts.pairs_enabled;
    counts.pairs_after_minimax += r.counts.pairs_after_minimax;
    counts.pairs_after_voxels += r.counts.pairs_after_voxels;
    counts.voxel_pairs += r.counts.voxel_pairs;
    counts.face_pairs += r.counts.face_pairs;
    if (!r.collided) return false;
    report.body_a = engine->body_name(r.contact.body_a);
    report.body_b = engine->body_name(r.contact.body_b);
    report.point = r.contact.point;
    report.face_a = r.contact.face_a;
    report.face_b = r.contact.face_b;
    report.joints = q;
    return true;
  }

  // Checks the arm at `q`; fills `report` on contact.
  bool collides(const JointVector& q, CollisionReport& report) {
    if (!engine || !cell.collision.enabled) return false;
    pose_bodies(q);
    const std::uint64_t k0 = ticks();
    const collision::QueryResult r = engine->check();
    charge_query(ticks() - k0, r);
    return record(r, q, report);
  }

  // Contact time (docs/collision-method.md §6.4). `report` holds the contact at the checked pose of
  // report.time_s; the pose `q_free` at `t_free` was checked free against every pair. Bisects in
  // time on the exact path `at(t, q_ref)` (joints at time t; q_ref: the nearest free joints, an
  // IK seed) with only the pairs that collide at the colliding pose, until t_hit - t_free <=
  // toc_tolerance_s, then checks the halting pose against every pair: should another pair meet
  // there (a contact between the samples that the sampled poses missed), that contact is
  // bisected from the start again. Leaves the report at t_hit, time_free_s = t_free and `q_free`
  // at the halting pose; returns false when the halting pose could not be verified free (then
  // it is the original free pose).
  template <class PathAt>
  bool bisect_contact(double t_free, JointVector& q_free, PathAt&& at, CollisionReport& report) {
    const double t_start = t_free;
    const JointVector q_start = q_free;
    const double tol = cell.collision.toc_tolerance_s >= 0 ? cell.collision.toc_tolerance_s : 1e-6;
    for (int round = 0; round < kMaxBisectionRounds; ++round) {
      pose_bodies(report.joints);
      hit_pairs.clear();
      CollisionReport probe;
      for (const collision::BodyPair& pair : engine->enabled_pairs())
        if (record(engine->check_pairs(std::span(&pair, 1)), report.joints, probe)) hit_pairs.push_back(pair);
      if (hit_pairs.empty()) break;  // cannot happen (check() found one)
      double t_hit = report.time_s;
      while (t_hit - t_free > tol) {
        const double t = t_free + (t_hit - t_free) / 2;
        if (!(t > t_free && t < t_hit)) break;  // the bracket is one ulp wide
        const JointVector q = at(t, q_free);
        pose_bodies(q);
        ++bisection;
        if (record(engine->check_pairs(hit_pairs), q, report)) {
          t_hit = t;
        } else {
          t_free = t;
          q_free = q;
        }
      }
      report.time_s = t_hit;
      report.time_free_s = t_free;
      if (t_free == t_start) return true;  // q_start: checked against every pair already
      pose_bodies(q_free);
      ++bisection;
      CollisionReport other;
      if (!record(engine->check(), q_free, other)) return true;
      other.time_s = t_free;  // an earlier contact of another pair: bisect it from the start
      report = std::move(other);
      t_free = t_start;
      q_free = q_start;
    }
    report.time_free_s = t_start;
    q_free = q_start;
    return false;
  }

  // Halts the pending motion on the contact found at the checked pose of `report.time_s`;
  // `t_prev` is the time of the pose before (the current joints), `was_free` whether it was
  // checked and free (then the contact time is bisected). The arm stays at the last free pose,
  // the clock at the contact time.
  template <class PathAt>
  MotionResult halt(CollisionReport report, double t_prev, bool was_free, PathAt&& at, int step) {
    const ScopeTimer timer{timing.collision_s};
    report.time_free_s = t_prev;
    last_free = was_free && bisect_contact(t_prev, joints, at, report);
    time = report.time_s;
    if (replay_grid > 0) replay_halt(report.time_free_s);
    return collision_result(std::move(report), step);
  }

  // One checked pose at time t: counts it, traces it, checks it.
  bool visit(const JointVector& q, double t, CollisionReport& report) {
    ++poses;
    if (tracing) trace.push_back({t, q, here_at(q)});
    if (replay_grid > 0) replay_push(t, q, true);
    if (!collides(q, report)) {
      last_free = engine && cell.collision.enabled;
      if (pose_hook) pose_hook(t, q);
      return false;
    }
    report.time_s = report.time_free_s = t;
    return true;
  }

  // Replay recording (set_replay). Only called when replay_grid > 0.
  void replay_push(double t, const JointVector& q, bool checked) {
    if (!replay.empty() && t <= replay.back().time_s) {
      if (t < replay.back().time_s) return;
      checked = checked || replay.back().checked;  // same instant (a zero-length motion)
      replay.pop_back();
    }
    replay.push_back({t, q, pending.step, checked});
  }
  // The grid instants strictly between two checked poses, joints from `path(t)`.
  template <class PathAt>
  void replay_between(double t_a, double t_b, PathAt&& path) {
    for (double k = std::floor(t_a / replay_grid) + 1; k * replay_grid < t_b; ++k) replay_push(k * replay_grid, path(k * replay_grid), false);
  }
  // After a contact: the arm stands at `joints` (the halting pose) from time_free_s on.
  void replay_halt(double t_free) {
    while (!replay.empty() && replay.back().time_s > t_free) replay.pop_back();
    replay_push(t_free, joints, false);
  }
  // A straight line's joints at time tm between its samples a and b: the line's pose at sigma(tm),
  // IK in the motion's configuration seeded with `seed`, as plan_line solves its samples; where
  // that fails or jumps, the joints interpolated between a and b (ik_used false).
  struct LinePoint {
    JointVector joints;
    Location flange;  // the line's flange pose at sigma(tm)
    bool ik_used = false;
  };
  LinePoint line_joints(const Pending& p, const LineSample& a, const LineSample& b, double tm,
                        const JointVector& seed) const {
    const double sigma = std::clamp(p.profile.sigma(tm - p.t0), a.s, b.s);
    const JointVector lin = interpolate_joints(a.joints, b.joints, b.s > a.s ? (sigma - a.s) / (b.s - a.s) : 1.0);
    const Location flange = p.base_inv * line_pose(p.path, sigma) * p.tool_inv;
    const robots::IkResult ik = robots::solve_ik(cell.robot, flange, seed, p.config, false);
    const bool ik_used = ik.status == robots::IkStatus::ok && (ik.joints - lin).cwiseAbs().maxCoeff() <= kMaxJointJumpDeg;
    return {ik_used ? ik.joints : lin, flange, ik_used};
  }
  // The same for the replay between checked samples i and j (gap stepping checks few of the
  // plan's samples: bracket tm by the nearest ones), seeded with the last replay joints.
  JointVector replay_line(const Pending& p, std::size_t i, std::size_t j, double tm) const {
    const auto& samples = p.line.samples;
    const double sigma = std::clamp(p.profile.sigma(tm - p.t0), samples[i].s, samples[j].s);
    const auto next = std::upper_bound(samples.begin() + static_cast<std::ptrdiff_t>(i) + 1,
                                       samples.begin() + static_cast<std::ptrdiff_t>(j), sigma,
                                       [](double v, const LineSample& x) { return v < x.s; });
    return line_joints(p, *(next - 1), *next, tm, replay.empty() ? (next - 1)->joints : replay.back().joints).joints;
  }

  MotionResult collision_result(CollisionReport report, int step) {
    MotionResult r;
    r.status = MotionStatus::collision;
    report.step = step;
    ++accuracy.contacts;
    accuracy.contact_bracket_s = std::max(accuracy.contact_bracket_s, report.time_s - report.time_free_s);
    r.collision = std::move(report);
    return r;
  }

  // Ctrl-C: one relaxed load per checked pose, no syscall.
  bool interrupt_requested() const { return interrupt && interrupt->load(std::memory_order_relaxed); }

  // Stops the pending motion at the current joints (the last checked pose, of time t_halt, at
  // path parameter `fraction`) and keeps its rest for resume_motion.
  MotionResult interrupt_halt(const Pending& p, double t_halt, double fraction) {
    time = t_halt;
    rest = Rest{p.to, p.straight, dest, p.speed, t_halt - p.t0};
    halted = InterruptReport{t_halt, fraction, joints, p.step};
    MotionResult r;
    r.status = MotionStatus::interrupted;
    r.interrupt = *halted;
    return r;
  }

  // Step rule (docs/collision-method.md §6.3): pairs may move max(c, step_mm) relative to each other.
  double step_mm() const { return std::max({cell.collision.clearance_mm, cell.collision.step_mm, kMinStepMm}); }

  double speed_factor(const SpeedSettings& s) const { return s.monitor / 100 * s.program / 100; }

  MotionResult plan_joint(const JointVector& target, const SpeedSettings& speed, int step) {
    const auto& robot = cell.robot;
    const double f = speed_factor(speed);
    std::array<ProfileAxis, robots::kMaxJoints> axes{};
    for (int i = 0; i < robot.joint_count(); ++i)
      axes[static_cast<std::size_t>(i)] = {std::abs(target[i] - joints[i]), robot.max_velocity[i] * f,
                                           robot.max_acceleration[i]};
    pending = Pending{};
    pending.active = true;
    pending.from = joints;
    pending.to = target;
    pending.intervals = joint_move_intervals(reach, joints, target, step_mm(), moving_pairs);
    pending.profile = plan_profile(std::span(axes.data(), static_cast<std::size_t>(robot.joint_count())), speed.duration_s);
    pending.speed = speed;
    pending.t0 = time;
    halted.reset();  // a new motion drops the rest of an interrupted one
    pending.step = step;
    dest = here_at(target);
    motion_started();
    return {};
  }
};

Simulator::Simulator(Cell cell) : impl_(std::make_unique<Impl>(std::move(cell))) {}
Simulator::~Simulator() = default;
Simulator::Simulator(Simulator&&) noexcept = default;

const Cell& Simulator::cell() const { return impl_->cell; }
const robots::Robot& Simulator::robot() const { return impl_->cell.robot; }
const robots::JointVector& Simulator::joints() const { return impl_->joints; }
Location Simulator::here() const { return impl_->here(); }
Location Simulator::dest() const { return impl_->dest; }
Location Simulator::base() const { return impl_->base; }
Location Simulator::tool() const { return impl_->tool; }
void Simulator::set_base(const Location& base) { impl_->base = base; }
void Simulator::set_tool(const Location& tool) { impl_->tool = tool; }
robots::Configuration Simulator::configuration() const { return robots::configuration_of(impl_->cell.robot, impl_->joints); }
robots::ConfigurationRequest& Simulator::request() { return impl_->request; }
double Simulator::time_s() const { return impl_->time; }
std::uint64_t Simulator::bisection_checks() const { return impl_->bisection; }
std::uint64_t Simulator::poses_checked() const { return impl_->poses; }
bool Simulator::motion_pending() const { return impl_->pending.active; }
void Simulator::set_trace(bool on) { impl_->tracing = on; }
const std::vector<TraceSample>& Simulator::trace() const { return impl_->trace; }
void Simulator::set_replay(double grid_s) { impl_->replay_grid = grid_s > 0 ? grid_s : 0; }
const std::vector<ReplaySample>& Simulator::replay() const { return impl_->replay; }
const collision::StepCounts& Simulator::collision_counts() const { return impl_->counts; }
bool Simulator::collision_engine_used() const { return impl_->engine.has_value(); }
const RunAccuracy& Simulator::accuracy() const { return impl_->accuracy; }
const RunTiming& Simulator::timing() const { return impl_->timing; }
void Simulator::add_parse_time(double seconds) { impl_->timing.parse_s += seconds; }
void Simulator::add_preprocess_time(double seconds) { impl_->timing.preprocess_s += seconds; }

MotionResult Simulator::start_joint_move(const robots::JointVector& target, SpeedSettings speed, int step) {
  if (impl_->pending.active)
    if (MotionResult r = finish_motion(); r.status != MotionStatus::ok) return r;
  const ScopeTimer timer{impl_->timing.motion_s};
  const auto& robot = impl_->cell.robot;
  if (!(impl_->speed_factor(speed) > 0)) return error("*Illegal value*", "speed must be > 0");
  if (target.size() != robot.joint_count()) return error("*Illegal value*", "wrong number of joints");
  if (const int j = robots::first_limit_violation(robot, target); j >= 0)
    return error("*Joint limit exceeded*", fmt_limit(robot, j, target[j]));
  return impl_->plan_joint(target, speed, step);
}

MotionResult Simulator::start_move(const Location& target, bool straight, SpeedSettings speed, int step) {
  if (impl_->pending.active)
    if (MotionResult r = finish_motion(); r.status != MotionStatus::ok) return r;
  Impl& s = *impl_;
  const ScopeTimer timer{s.timing.motion_s};
  const auto& robot = s.cell.robot;
  if (!(s.speed_factor(speed) > 0)) return error("*Illegal value*", "speed must be > 0");
  const Location flange = s.base.inverse() * target * s.tool.inverse();
  const robots::Configuration current = robots::configuration_of(robot, s.joints);
  if (!straight) {
    const robots::Configuration want = robots::requested_configuration(current, s.request);
    const robots::IkResult ik = robots::solve_ik(robot, flange, s.joints, want, s.request.single);
    if (ik.status == robots::IkStatus::out_of_reach) return error("*Location out of reach*");
    if (ik.status == robots::IkStatus::joint_limit)
      return error("*Joint limit exceeded*", fmt_limit(robot, ik.joint, ik.value));
    s.accuracy.ik_residual.merge(pose_error(robots::flange_pose(robot, ik.joints), flange));
    ++s.accuracy.ik_solves;
    s.request.righty = s.request.above = s.request.noflip = -1;  // consumed by this motion
    MotionResult r = s.plan_joint(ik.joints, speed, step);
    s.dest = target;
    return r;
  }
  LineRequest req;
  req.path = make_line(s.here(), target);
  req.base = s.base;
  req.tool = s.tool;
  req.start = s.joints;
  req.config = current;
  req.step_mm = s.step_mm();
  req.pairs = s.moving_pairs;
  LinePlan plan;
  const LineStatus planned = plan_line(robot, s.reach, req, plan);
  s.accuracy.ik_residual.merge(plan.ik_residual);
  s.accuracy.ik_solves += plan.ik_solves;
  switch (planned) {
    case LineStatus::ok: break;
    case LineStatus::out_of_reach: return error("*Location out of reach*", fmt_fraction("no solution", plan.fail_fraction));
    case LineStatus::joint_limit:
      return error("*Joint limit exceeded*",
                   fmt_limit(robot, plan.joint, plan.value) + ", " + fmt_fraction("", plan.fail_fraction).substr(1));
    case LineStatus::singularity: {
      const char* what = plan.singularity == SingularityKind::shoulder ? "shoulder"
                         : plan.singularity == SingularityKind::elbow  ? "elbow"
                         : plan.singularity == SingularityKind::joint_jump ? "joint jump"
                                                                           : "unresolved step";
      return error("*Singularity on straight-line path*", fmt_fraction(what, plan.fail_fraction));
    }
  }
  const double f = s.speed_factor(speed);
  const double fr = (speed.rotation < 0 ? speed.program : speed.rotation) / 100 * speed.monitor / 100;
  // Axes: tool translation and rotation, and every joint with "distance" max |dq_j / dsigma|
  // along the solved samples, so that its speed S_j * sigma'(t) stays within V_j; then the
  // profile is stretched until every joint's acceleration d2q/dsigma2 * sigma'^2 + dq/dsigma *
  // sigma'' (curvature + profile) stays within A_j (fit_path_acceleration).
  std::array<ProfileAxis, 2 + robots::kMaxJoints> axes{};
  axes[0] = {req.path.length, robot.max_tool_speed * f, robot.max_tool_accel};
  axes[1] = {req.path.angle_deg(), robot.max_tool_rot_speed * fr, robot.max_tool_rot_accel};
  const int n = robot.joint_count();
  for (int j = 0; j < n; ++j) {
    double slope = 0;
    for (std::size_t i = 1; i < plan.samples.size(); ++i) {
      const double ds = plan.samples[i].s - plan.samples[i - 1].s;
      if (ds > 0) slope = std::max(slope, std::abs(plan.samples[i].joints[j] - plan.samples[i - 1].joints[j]) / ds);
    }
    axes[static_cast<std::size_t>(2 + j)] = {slope, robot.max_velocity[j] * f, robot.max_acceleration[j]};
  }
  std::vector<double> path_s(plan.samples.size()), path_q(plan.samples.size() * static_cast<std::size_t>(n));
  for (std::size_t i = 0; i < plan.samples.size(); ++i) {
    path_s[i] = plan.samples[i].s;
    for (int j = 0; j < n; ++j) path_q[i * static_cast<std::size_t>(n) + static_cast<std::size_t>(j)] = plan.samples[i].joints[j];
  }
  const Profile profile = fit_path_acceleration(plan_profile(std::span(axes.data(), static_cast<std::size_t>(2 + n)), speed.duration_s),
                                                {path_s, path_q, n}, std::span(robot.max_acceleration.data(), static_cast<std::size_t>(n)));
  s.pending = Impl::Pending{};
  s.pending.active = true;
  s.pending.straight = true;
  s.pending.from = s.joints;
  s.pending.to = plan.samples.back().joints;
  s.pending.line = std::move(plan);
  s.pending.path = req.path;
  s.pending.base_inv = s.base.inverse();
  s.pending.tool_inv = s.tool.inverse();
  s.pending.base = s.base;
  s.pending.tool = s.tool;
  s.pending.config = current;
  s.pending.profile = profile;
  s.pending.speed = speed;
  s.pending.t0 = s.time;
  s.halted.reset();  // a new motion drops the rest of an interrupted one
  s.pending.step = step;
  s.dest = target;
  s.motion_started();
  return {};
}

void Simulator::set_interrupt(const std::atomic<bool>* flag) { impl_->interrupt = flag; }
const std::optional<InterruptReport>& Simulator::halted_motion() const { return impl_->halted; }
void Simulator::drop_halted_motion() { impl_->halted.reset(); }
void Simulator::set_pose_hook(std::function<void(double, const robots::JointVector&)> hook) {
  impl_->pose_hook = std::move(hook);
}

MotionResult Simulator::resume_motion(std::optional<double> monitor_speed) {
  Impl& s = *impl_;
  if (!s.halted) return error("*No motion to resume*");
  const Impl::Rest rest = s.rest;
  const int step = s.halted->step;
  SpeedSettings speed = rest.speed;
  if (monitor_speed) speed.monitor = *monitor_speed;
  if (speed.duration_s > 0) speed.duration_s = std::max(0.0, speed.duration_s - rest.elapsed_s);
  // The joints where it stopped lie on the planned path, so a new joint move to the same joint
  // target (or a line from here to the same location) is the rest of the same path.
  MotionResult r = rest.straight ? start_move(rest.target, true, speed, step) : start_joint_move(rest.to, speed, step);
  if (r.status == MotionStatus::ok) s.dest = rest.target;
  return r;
}

void Simulator::request_hand(HandState state) { impl_->hand_request = state; }

MotionResult Simulator::hand_immediate(HandState state, double hand_time_s) {
  if (MotionResult r = finish_motion(); r.status != MotionStatus::ok) return r;
  impl_->hand = state;
  impl_->hand_request.reset();
  if (hand_time_s > 0) impl_->time += hand_time_s;
  return {};
}

MotionResult Simulator::wait(double seconds) {
  if (MotionResult r = finish_motion(); r.status != MotionStatus::ok) return r;
  if (seconds > 0) impl_->time += seconds;
  return {};
}

void Simulator::set_collision_enabled(bool on) {
  impl_->cell.collision.enabled = on;
  const ScopeTimer timer{impl_->timing.preprocess_s};
  if (on && !impl_->engine_built) impl_->build_engine();
}

bool Simulator::collision_enabled() const { return impl_->cell.collision.enabled; }

void Simulator::set_clearance(double clearance_mm) {
  impl_->cell.collision.clearance_mm = clearance_mm;
  if (impl_->engine) impl_->engine->set_clearance(clearance_mm);
}

double Simulator::clearance_mm() const { return impl_->cell.collision.clearance_mm; }

HandState Simulator::hand() const { return impl_->hand; }
bool Simulator::hand_pending() const { return impl_->hand_request.has_value(); }

int Simulator::inrange(const Location& target) const {
  const Impl& s = *impl_;
  const auto& robot = s.cell.robot;
  const Location flange = s.base.inverse() * target * s.tool.inverse();
  const robots::Configuration want = robots::requested_configuration(robots::configuration_of(robot, s.joints), s.request);
  const robots::IkResult ik = robots::solve_ik(robot, flange, s.joints, want, s.request.single);
  return ik.status == robots::IkStatus::ok ? 0 : ik.status == robots::IkStatus::out_of_reach ? 1 : 2;
}

MotionResult Simulator::finish_motion() {
  Impl& s = *impl_;
  if (!s.pending.active) return {};
  const Impl::MotionClock clock{s};
  Impl::Pending& p = s.pending;
  p.active = false;
  ++s.accuracy.motions;
  CollisionReport report;
  if (!s.start_checked) {  // the start pose of the first motion
    s.start_checked = true;
    if (s.visit(s.joints, s.time, report)) return s.collision_result(std::move(report), p.step);
  }
  const bool gap = s.gap_stepping();
  if (gap) robots::link_frames(s.cell.robot, s.joints, s.frames);  // gaps at the start pose
  RunAccuracy& acc = s.accuracy;
  JointVector q(s.joints.size());
  double t_prev = s.time;  // time of the current joints
  if (p.straight) {
    const auto& samples = p.line.samples;
    for (std::size_t i = 0; i + 1 < samples.size();) {
      if (s.interrupt_requested()) return s.interrupt_halt(p, t_prev, samples[i].s);
      // Next checked sample j: the next one, or with gap stepping the farthest the gaps allow.
      std::size_t j = i + 1;
      double bound = samples[j].bound_mm;
      if (gap) {
        s.update_gaps();
        j = gap_next_sample(s.reach, samples, i, s.gap_pairs, s.scratch, bound);
      }
      acc.step_displacement_mm = std::max(acc.step_displacement_mm, bound);
      const LineSample &a = samples[i], &b = samples[j];
      const JointVector mid = interpolate_joints(a.joints, b.joints, 0.5);
      acc.line_deviation.merge(pose_error(p.base * robots::flange_pose(s.cell.robot, mid) * p.tool,
                                          line_pose(p.path, (a.s + b.s) / 2)));
      ++acc.line_intervals;
      const double t = p.t0 + p.profile.time_at(b.s);
      const bool was_free = s.last_free;
      if (s.replay_grid > 0) s.replay_between(t_prev, t, [&s, &p, i, j](double tm) { return s.replay_line(p, i, j, tm); });
      if (s.visit(b.joints, t, report)) {
        // Between samples: the line's pose at sigma(t), IK in the motion's configuration seeded
        // with the nearest free joints, as plan_line solves its samples; where that fails or
        // jumps, the joints interpolated between the two samples.
        const auto at = [&s, &p, &a, &b](double tm, const JointVector& ref) {
          const Impl::LinePoint lp = s.line_joints(p, a, b, tm, ref);
          if (lp.ik_used) {
            s.accuracy.ik_residual.merge(pose_error(robots::flange_pose(s.cell.robot, lp.joints), lp.flange));
            ++s.accuracy.ik_solves;
          }
          return lp.joints;
        };
        return s.halt(std::move(report), t_prev, was_free, at, p.step);
      }
      s.joints = b.joints;
      t_prev = t;
      i = j;
    }
  } else {
    const auto at = [&p](double tm, const JointVector&) {
      return interpolate_joints(p.from, p.to, p.profile.sigma(tm - p.t0));
    };
    // Bound per grid interval of each body: the bound is linear in the joint step.
    const JointVector step = (p.to - p.from) / p.intervals;
    double body_max = 0;
    for (const robots::BodyReach& r : s.reach) body_max = std::max(body_max, robots::max_displacement(r, step));
    if (gap) {
      s.pair_mm.resize(s.gap_pairs.size());
      for (std::size_t k = 0; k < s.gap_pairs.size(); ++k) s.pair_mm[k] = pair_displacement(s.reach, s.gap_pairs[k], step);
    }
    for (int i = 0; i < p.intervals;) {
      if (s.interrupt_requested()) return s.interrupt_halt(p, t_prev, static_cast<double>(i) / p.intervals);
      int k = 1;
      if (gap) {
        s.update_gaps();
        k = gap_intervals(s.pair_mm, s.gap_pairs, p.intervals - i);
      }
      i += k;
      acc.step_displacement_mm = std::max(acc.step_displacement_mm, k * body_max);
      const double sigma = static_cast<double>(i) / p.intervals;
      q = i == p.intervals ? p.to : interpolate_joints(p.from, p.to, sigma);
      const double t = p.t0 + p.profile.time_at(sigma);
      const bool was_free = s.last_free;
      if (s.replay_grid > 0) s.replay_between(t_prev, t, [&at, &q](double tm) { return at(tm, q); });
      if (s.visit(q, t, report)) return s.halt(std::move(report), t_prev, was_free, at, p.step);
      s.joints = q;
      t_prev = t;
    }
  }
  s.joints = p.to;
  s.time = p.t0 + p.profile.duration;
  return {};
}

}  // namespace asimov::motion
