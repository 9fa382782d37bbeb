// The Simulator facade: the arm's state and hand, and the wiring of planner, walker and
// recorders (dialect §4-§5; motion/README.md).
//
// Frames: HERE = BASE . FK(q) . TOOL with the program's BASE and TOOL; the physical robot stays
// at cell.base ("BASE moves neither robot nor cell"), so collision bodies use cell.base . frames[k].
#include "asimov/motion/simulator.hpp"

#include "asimov/motion/planner.hpp"
#include "asimov/motion/scene.hpp"
#include "asimov/motion/walker.hpp"
#include "asimov/motion/world.hpp"

#include <algorithm>
#include <limits>

namespace asimov::motion {
namespace {
MotionResult error(const char* message) {
  MotionResult r;
  r.status = MotionStatus::error;
  r.error.message = message;
  return r;
}

// set_pose_hook: called at each checked pose found free.
struct PoseHook final : WalkObserver {
  std::function<void(double, const robots::JointVector&)> f;
  void on_checked_pose(double t, const robots::JointVector& q, bool contact) override {
    if (!contact && f) f(t, q);
  }
};
}  // namespace

struct Simulator::Impl {
  Cell cell;
  ArmSettings settings;
  Location dest;
  WalkState state;
  Hand hand;
  Recorders rec{cell.robot, settings.base, settings.tool};  // before world: it times the preprocessing
  World world;
  std::optional<CellRuntime> runtime;  // parts and devices; absent for a static cell
  PoseHook hook;
  Walker walker{cell.robot, world, cell.collision};
  std::optional<Trajectory> pending;
  // The rest of a motion halted by the interrupt (halted_motion / resume_motion).
  struct Rest {
    robots::JointVector to;    // joint target
    bool straight = false;
    Location target;           // location target (dest of the motion)
    SpeedSettings speed;
    double elapsed_s = 0;      // time the motion ran before it halted
  } rest;
  std::optional<InterruptReport> halted;

  explicit Impl(Cell c) : cell(std::move(c)), world(timed_world(cell, rec.timing.timing)) {
    const ScopeTimer timer{rec.timing.timing.preprocess_s};
    state.joints = start_joints(cell);
    settings.base = cell.base;
    settings.tool = cell.tool;
    dest = here();
    rec.clearance.within_mm = std::max(cell.collision.report_within_mm, cell.collision.clearance_mm);
    rec.clearance.clearance_mm = cell.collision.clearance_mm;
    if (!cell.workcell.empty()) {
      runtime.emplace(cell);
      world.attach(*runtime);
      rec.replay.runtime = &*runtime;
    }
    rec.trace.world = &world;
    for (WalkObserver* o : std::initializer_list<WalkObserver*>{&rec.timing, &rec.counts, &rec.trace, &rec.replay,
                                                              &rec.accuracy, &rec.clearance, &hook})
      walker.add_observer(*o);
  }
  static World timed_world(const Cell& cell, RunTiming& t) {
    const ScopeTimer timer{t.preprocess_s};
    return World(cell);
  }

  Location here() const { return settings.base * robots::flange_pose(cell.robot, state.joints) * settings.tool; }

  PlanStart plan_start() const { return plan_from(state.joints, state.time_s); }
  PlanStart plan_from(const robots::JointVector& joints, double time_s) const {
    return {cell.robot, world.reach(), world.moving_pairs(), step_mm(cell.collision), joints, settings.base, settings.tool, time_s};
  }

  // Carries the pending motion out up to `until_s` (all of it by default); an interrupted
  // motion keeps its rest (halted_motion). The pending motion is consumed either way.
  MotionResult walk_pending(double until_s = std::numeric_limits<double>::infinity()) {
    const Trajectory tr = std::move(*pending);
    pending.reset();
    MotionResult r;
    try {
      r = walker.walk(tr, state, until_s);
    } catch (const DeviceError& e) {  // the devices' clock advanced with the walk
      r.status = MotionStatus::error;
      r.error = {.message = "*Device logic loop*", .detail = e.what(), .file = {}, .line = 0};
    }
    if (runtime && runtime->carried())  // the part in the gripper is where the flange took it
      runtime->clock().move_carried(*runtime->carried(), runtime->carried_pose(cell.base * robots::flange_pose(cell.robot, state.joints)));
    if (r.status == MotionStatus::interrupted) {
      rest = Rest{tr.to, tr.kind == PathKind::line, dest, tr.speed, r.interrupt.time_s - tr.t0};
      halted = r.interrupt;
    }
    return r;
  }

  // Continuous path (docs/blending.md): `plan_at(start)` plans the next motion b from the
  // pending motion a's target as if a had been reached at its end; b then starts
  // tau = min(a's deceleration time, b's acceleration time) before a's end, so the two
  // overlap on [a.end - tau, a.end]. a is carried out up to b's start; b (with a as its
  // `previous`) becomes the pending motion. A refused plan leaves a pending, untouched.
  template <class PlanAt>
  MotionResult blend(PlanAt&& plan_at) {
    const double a_end = pending->end_time();
    Plan plan;
    {
      const ScopeTimer timer{rec.timing.timing.motion_s};
      plan = plan_at(plan_from(pending->to, a_end));
    }
    if (plan.result.status != MotionStatus::ok) return accept(std::move(plan));
    Trajectory& b = plan.trajectory;
    const double tau = std::min(pending->profile.yd, b.profile.y);
    if (tau > 0) b.t0 = a_end - tau;
    auto a = std::make_shared<Trajectory>(*pending);
    if (MotionResult r = walk_pending(b.t0); r.status != MotionStatus::ok) return r;
    if (tau > 0) {
      a->previous.reset();  // walked past its own overlap: at most two motions overlap
      b.previous = std::move(a);
    }
    return accept(std::move(plan));
  }

  // A planned motion becomes the pending one; a pending OPEN/CLOSE/RELAX takes effect.
  MotionResult accept(Plan plan) {
    rec.accuracy.on_ik(plan.ik_residual, plan.ik_solves);
    if (plan.result.status != MotionStatus::ok) return plan.result;
    dest = plan.trajectory.target;
    pending = std::move(plan.trajectory);
    halted.reset();  // a new motion drops the rest of an interrupted one
    if (hand.pending) set_hand(*hand.pending), hand.pending.reset();
    return {};
  }

  // RELAX leaves the fingers where they are (no force either way) [decision].
  void set_hand(HandState s) {
    hand.state = s;
    if (s != HandState::relaxed) world.set_hand(s == HandState::closed);
  }
};

Simulator::Simulator(Cell cell) : impl_(std::make_unique<Impl>(std::move(cell))) {}
Simulator::~Simulator() = default;
Simulator::Simulator(Simulator&&) noexcept = default;

const Cell& Simulator::cell() const { return impl_->cell; }
const robots::Robot& Simulator::robot() const { return impl_->cell.robot; }
const robots::JointVector& Simulator::joints() const { return impl_->state.joints; }
Location Simulator::here() const { return impl_->here(); }
Location Simulator::dest() const { return impl_->dest; }
robots::Configuration Simulator::configuration() const { return robots::configuration_of(impl_->cell.robot, impl_->state.joints); }
ArmSettings& Simulator::settings() { return impl_->settings; }
const ArmSettings& Simulator::settings() const { return impl_->settings; }
double Simulator::time_s() const { return impl_->state.time_s; }
bool Simulator::motion_pending() const { return impl_->pending.has_value(); }
void Simulator::add_observer(WalkObserver& observer) { impl_->walker.add_observer(observer); }
Recorders& Simulator::recorders() { return impl_->rec; }
const Recorders& Simulator::recorders() const { return impl_->rec; }
bool Simulator::collision_engine_used() const { return impl_->world.engine() != nullptr; }
std::string Simulator::body_name(std::uint32_t id) const {
  const collision::Engine* e = impl_->world.engine();
  return e ? e->body_name(id) : std::string();
}
int Simulator::motion_step() const { return impl_->pending ? impl_->pending->step : 0; }

MotionResult Simulator::start_joint_move(const robots::JointVector& target, SpeedSettings speed, int step) {
  if (impl_->pending && impl_->settings.continuous_path)
    return impl_->blend([&](const PlanStart& st) { return plan_joint_move(st, target, speed, step); });
  if (impl_->pending)
    if (MotionResult r = finish_motion(); r.status != MotionStatus::ok) return r;
  const ScopeTimer timer{impl_->rec.timing.timing.motion_s};
  return impl_->accept(plan_joint_move(impl_->plan_start(), target, speed, step));
}

MotionResult Simulator::start_move(const Location& target, bool straight, SpeedSettings speed, int step) {
  if (impl_->pending && impl_->settings.continuous_path)
    return impl_->blend(
        [&](const PlanStart& st) { return plan_move(st, impl_->settings.request, target, straight, speed, step); });
  if (impl_->pending)
    if (MotionResult r = finish_motion(); r.status != MotionStatus::ok) return r;
  const ScopeTimer timer{impl_->rec.timing.timing.motion_s};
  return impl_->accept(plan_move(impl_->plan_start(), impl_->settings.request, target, straight, speed, step));
}

MotionResult Simulator::finish_motion() { return impl_->pending ? impl_->walk_pending() : MotionResult{}; }

const robots::JointVector& Simulator::planned_joints() const {
  return impl_->pending ? impl_->pending->to : impl_->state.joints;
}
Location Simulator::planned_here() const {
  return impl_->settings.base * robots::flange_pose(impl_->cell.robot, planned_joints()) * impl_->settings.tool;
}
std::optional<MotionTiming> Simulator::pending_timing() const {
  const auto& p = impl_->pending;
  if (!p) return std::nullopt;
  return MotionTiming{p->step, p->t0, p->profile.duration, p->previous != nullptr};
}

void Simulator::set_interrupt(const std::atomic<bool>* flag) { impl_->walker.set_interrupt(flag); }
void Simulator::set_stop_condition(std::function<bool(double, const robots::JointVector&)> condition) {
  impl_->walker.set_stop_condition(std::move(condition));
}
const std::optional<InterruptReport>& Simulator::halted_motion() const { return impl_->halted; }
void Simulator::drop_halted_motion() { impl_->halted.reset(); }
void Simulator::set_pose_hook(std::function<void(double, const robots::JointVector&)> hook) {
  impl_->hook.f = std::move(hook);
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

void Simulator::request_hand(HandState state) { impl_->hand.pending = state; }
CellRuntime* Simulator::cell_runtime() { return impl_->runtime ? &*impl_->runtime : nullptr; }
const CellRuntime* Simulator::cell_runtime() const { return impl_->runtime ? &*impl_->runtime : nullptr; }

MotionResult Simulator::hand_immediate(HandState state, double hand_time_s, int step) {
  if (MotionResult r = finish_motion(); r.status != MotionStatus::ok) return r;
  impl_->hand.pending.reset();
  impl_->set_hand(state);
  return dwell(hand_time_s, step);
}

MotionResult Simulator::wait(double seconds, int step) {
  if (MotionResult r = finish_motion(); r.status != MotionStatus::ok) return r;
  return dwell(seconds, step);
}

// The clock advances with the arm at rest; parts on a running conveyor are walked (Walker::dwell).
MotionResult Simulator::dwell(double seconds, int step) {
  if (!(seconds > 0)) return {};
  Impl& s = *impl_;
  MotionResult r;
  try {
    r = s.walker.dwell(s.state, s.state.time_s + seconds, step);
  } catch (const DeviceError& e) {  // the devices' clock advanced with the walk
    r.status = MotionStatus::error;
    r.error = {.message = "*Device logic loop*", .detail = e.what(), .file = {}, .line = 0};
  }
  return r;
}

void Simulator::set_collision_enabled(bool on) {
  impl_->cell.collision.enabled = on;
  const ScopeTimer timer{impl_->rec.timing.timing.preprocess_s};
  if (on) impl_->world.build_engine(impl_->cell);
}

// The one copy of the clearance: every query carries it (the engine keeps none).
void Simulator::set_clearance(double clearance_mm) {
  impl_->cell.collision.clearance_mm = clearance_mm;
  ClearanceRecorder& r = impl_->rec.clearance;
  r.within_mm = std::max(r.within_mm, clearance_mm);  // on_clearance warn lists the pairs within it
  r.clearance_mm = clearance_mm;
}

Hand Simulator::hand() const { return impl_->hand; }

int Simulator::inrange(const Location& target) const { return motion::inrange(impl_->plan_start(), impl_->settings.request, target); }

}  // namespace asimov::motion
