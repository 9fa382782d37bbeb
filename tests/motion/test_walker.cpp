// Planner, walker and recorders without the Simulator facade (motion/README.md): the same walk
// as the facade's, observers told in data-flow order, refusals before anything moves, the
// interrupt, and the trajectory's exact path at its ends.
#include "asimov/motion/cell_runtime.hpp"
#include "asimov/motion/planner.hpp"
#include "asimov/motion/scene.hpp"
#include "asimov/motion/simulator.hpp"
#include "asimov/motion/walker.hpp"
#include "asimov/robots/puma560.hpp"

#include "support/cell_bodies.hpp"
#include "support/joints.hpp"

#include <catch2/catch.hpp>
#include <algorithm>
#include <atomic>
#include <string>

using namespace asimov;
using namespace asimov::motion;
using asimov::test::jv;
using robots::JointVector;

namespace {

// A PUMA sweeping J1 towards a wall at y >= 200.
Cell wall_cell() {
  Cell cell;
  cell.robot = robots::puma560();
  cell.start_joints = jv({0, -90, 180, 0, 0, 0});
  cell.objects.push_back(test::box_object("wall", {1200, 50, 800}, {400, 225, 400}));
  return cell;
}

// Logs every callback as one letter: b(egin) s(tretch) p(ose) q(uery) i(k) c(ontact) e(nd).
struct Log final : WalkObserver {
  std::string events;
  std::uint64_t poses = 0, bisection = 0;
  void on_walk_begin(const Trajectory&) override { events += 'b'; }
  void on_stretch(const Trajectory&, const Stretch& s) override {
    CHECK(s.t_to >= s.t_from);
    events += 's';
  }
  void on_checked_pose(double, const JointVector&, bool) override {
    ++poses;
    events += 'p';
  }
  void on_query(const collision::QueryResult&, const QueryCost& c) override {
    bisection += c.kind == QueryKind::bisection_pose;
    events += 'q';
  }
  void on_distance(const collision::BodyPair&, const collision::DistanceResult&, const DistanceCost& c) override {
    bisection += c.probe;  // continuous checking's probes between checked poses
  }
  void on_ik(const PoseError&, std::uint64_t) override { events += 'i'; }
  void on_contact(const CollisionReport&, const JointVector&, double) override { events += 'c'; }
  void on_walk_end() override { events += 'e'; }
};

PlanStart start_of(const Cell& cell, const World& world, const WalkState& st) {
  return {cell.robot, world.reach(), world.moving_pairs(), step_mm(cell.collision), st.joints, cell.base, cell.tool,
          st.time_s};
}

}  // namespace

TEST_CASE("planner + walker: the facade's walk, bit for bit, observers in data-flow order", "[walker]") {
  const Cell cell = wall_cell();
  const JointVector target = jv({90, -90, 180, 0, 0, 0});

  Simulator sim(cell);
  REQUIRE(sim.start_joint_move(target, {}, 7).status == MotionStatus::ok);
  const MotionResult facade = sim.finish_motion();
  REQUIRE(facade.status == MotionStatus::collision);

  World world(cell);
  Walker walker(cell.robot, world, cell.collision);
  Log log;
  walker.add_observer(log);
  WalkState st{.joints = start_joints(cell)};
  const Plan plan = plan_joint_move(start_of(cell, world, st), target, {}, 7);
  REQUIRE(plan.result.status == MotionStatus::ok);
  CHECK(plan.trajectory.kind == PathKind::joint);
  CHECK(plan.trajectory.intervals >= 1);
  const MotionResult r = walker.walk(plan.trajectory, st);
  REQUIRE(r.status == MotionStatus::collision);
  CHECK(r.collision.body_b == facade.collision.body_b);
  CHECK(r.collision.body_a == facade.collision.body_a);
  CHECK(r.collision.time_s == facade.collision.time_s);
  CHECK(r.collision.time_free_s == facade.collision.time_free_s);
  CHECK(r.collision.point == facade.collision.point);
  CHECK(r.collision.joints == facade.collision.joints);
  CHECK(r.collision.step == 7);
  CHECK(st.joints == sim.joints());
  CHECK(st.time_s == sim.time_s());
  CHECK(log.poses == sim.recorders().counts.poses);
  CHECK(log.bisection == sim.recorders().counts.bisection);
  CHECK(log.bisection > 0);

  // b, the start pose (queried, then told), then per stretch: s q p; the contact; e.
  REQUIRE(log.events.size() > 6);
  CHECK(log.events.substr(0, 3) == "bqp");
  CHECK(log.events.substr(3, 3) == "sqp");
  CHECK(log.events.back() == 'e');
  CHECK(log.events[log.events.size() - 2] == 'c');
  CHECK(std::count(log.events.begin(), log.events.end(), 'c') == 1);
  CHECK(std::count(log.events.begin(), log.events.end(), 's') + 1 == static_cast<long>(log.poses));
}

TEST_CASE("planner: refusals carry the VAL error and no trajectory; nothing moves", "[walker]") {
  const Cell cell = wall_cell();
  World world(cell);
  const WalkState st{.joints = start_joints(cell)};
  Plan p = plan_joint_move(start_of(cell, world, st), jv({0, -90, 300, 0, 0, 0}), {}, 1);
  CHECK(p.result.status == MotionStatus::error);
  CHECK(p.result.error.message == "*Joint limit exceeded*");
  CHECK(p.result.error.detail.starts_with("J3 = 300.000 >"));
  p = plan_joint_move(start_of(cell, world, st), jv({0, -90, 180, 0, 0}), {}, 1);
  CHECK(p.result.error.message == "*Illegal value*");
  p = plan_joint_move(start_of(cell, world, st), jv({10, -90, 180, 0, 0, 0}), {.monitor = 0}, 1);
  CHECK(p.result.error.detail == "speed must be > 0");
  robots::ConfigurationRequest request;
  Location far = Location::Identity();
  far.translation() = collision::Vec3(5000, 0, 0);
  p = plan_move(start_of(cell, world, st), request, far, false, {}, 1);
  CHECK(p.result.error.message == "*Location out of reach*");
  CHECK(inrange(start_of(cell, world, st), request, far) == 1);
  p = plan_move(start_of(cell, world, st), request, far, true, {}, 1);  // stretches out: refused on the way
  CHECK(p.result.status == MotionStatus::error);
  CHECK(p.trajectory.line.samples.empty());
  CHECK(p.result.error.detail.ends_with("% of the path"));
}

TEST_CASE("walker: an interrupt before the first step halts at the start pose, clock unchanged", "[walker]") {
  Cell cell = wall_cell();
  cell.objects.clear();  // nothing to hit
  cell.start_joints = jv({0, -90, 90, 0, 0, 0});
  World world(cell);
  Walker walker(cell.robot, world, cell.collision);
  Log log;
  walker.add_observer(log);
  std::atomic<bool> stop{true};
  walker.set_interrupt(&stop);
  WalkState st{.joints = start_joints(cell), .time_s = 2.5};
  const Plan plan = plan_joint_move(start_of(cell, world, st), jv({40, -90, 90, 0, 0, 0}), {}, 3);
  REQUIRE(plan.result.status == MotionStatus::ok);
  const MotionResult r = walker.walk(plan.trajectory, st);
  REQUIRE(r.status == MotionStatus::interrupted);
  CHECK(r.interrupt.time_s == 2.5);
  CHECK(r.interrupt.path_fraction == 0);
  CHECK(r.interrupt.step == 3);
  CHECK(st.joints == jv({0, -90, 90, 0, 0, 0}));
  CHECK(log.poses == 1);  // the start pose of the first walk, checked before the flag is read
  stop = false;
  const Plan rest = plan_joint_move(start_of(cell, world, st), jv({40, -90, 90, 0, 0, 0}), {}, 3);
  CHECK(walker.walk(rest.trajectory, st).status == MotionStatus::ok);
  CHECK(st.joints == jv({40, -90, 90, 0, 0, 0}));
  CHECK(st.time_s == rest.trajectory.end_time());
  CHECK(st.time_s > 2.5);
}

TEST_CASE("trajectory: the exact path starts and ends at the planned joints", "[walker]") {
  const Cell cell = wall_cell();
  World world(cell);
  const WalkState st{.joints = start_joints(cell), .time_s = 1};
  const Plan p = plan_joint_move(start_of(cell, world, st), jv({20, -80, 170, 10, 5, 0}), {}, 1);
  REQUIRE(p.result.status == MotionStatus::ok);
  const Trajectory& tr = p.trajectory;
  CHECK(tr.t0 == 1);
  CHECK(joint_path_at(tr, tr.t0) == tr.from);
  CHECK((joint_path_at(tr, tr.end_time()) - tr.to).cwiseAbs().maxCoeff() < 1e-12);
  CHECK(tr.target.isApprox(Location(robots::flange_pose(cell.robot, tr.to))));  // BASE, TOOL identity
}

// World's broad phase (docs/collision.md §14): a pair leaves pairs() only when its bodies' exact
// distance at the current poses exceeds keep plus the arm body's room, whatever the order of
// pairs() against the engine's own pair list; with the broad phase off every pair stays.
TEST_CASE("the broad phase leaves out only the pairs farther than keep plus room", "[walker]") {
  Cell cell = wall_cell();
  cell.objects.clear();
  // Resting parts near and far from the arm at its start joints, and an object between.
  for (int i = 0; i < 12; ++i)
    cell.workcell.parts.push_back({"p" + std::to_string(i), "", collision::make_box({40, 40, 40}),
                                   trans(-900 + 150 * i, 300, 200, 0, 0, 0)});
  cell.objects.push_back(test::box_object("post", {40, 40, 400}, {500, 0, 0}));
  // One part on the flange itself: its pairs with the wrist touch, so they always stay.
  const Location flange = robots::flange_pose(cell.robot, start_joints(cell));
  cell.workcell.parts.push_back({"on_flange", "", collision::make_box({40, 40, 40}), flange});
  Cell off = cell;
  off.collision.broad_phase = false;
  CellRuntime runtime(cell), runtime_off(off);
  World world(cell), reference(off);
  world.attach(runtime);
  reference.attach(runtime_off);
  world.build_engine(cell);
  reference.build_engine(off);
  REQUIRE(world.engine());
  REQUIRE(world.broad_phase());
  REQUIRE(!reference.broad_phase());
  world.pose(start_joints(cell), 0);
  reference.pose(start_joints(cell), 0);
  const std::vector<collision::BodyPair> all(reference.pairs().begin(), reference.pairs().end());
  for (const double room : {1.0, 150.0}) {
    CAPTURE(room);
    constexpr double kKeep = 10;
    world.broad_refresh(kKeep, room);
    const std::vector<collision::BodyPair> kept(world.pairs().begin(), world.pairs().end());
    CHECK(std::is_sorted(kept.begin(), kept.end()) == std::is_sorted(all.begin(), all.end()));
    std::size_t left_out = 0;
    for (const collision::BodyPair& p : all) {
      if (std::find(kept.begin(), kept.end(), p) != kept.end()) continue;
      ++left_out;
      const double d = world.engine()->distance(p.a, p.b, {.upper_mm = kKeep + room + 1}).distance;
      CHECK(d > kKeep + room);
    }
    for (const collision::BodyPair& p : kept) CHECK(std::find(all.begin(), all.end(), p) != all.end());
    CHECK(left_out > 0);
    CHECK(kept.size() + left_out == all.size());
    for (const double r : world.room()) CHECK(r >= room);
  }
}
