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
#include <numbers>
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
    bisection += c.probe && !c.minimum;  // continuous checking's probes (not the report's minimum)
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

TEST_CASE("planner: refusals carry the VAL error and no trajectory, nothing moves", "[walker]") {
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
  INFO(p.result.error.detail);
  CHECK(p.result.error.detail.find("% of the path") != std::string::npos);
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

namespace {
// A cell's world with the broad phase and the reference without it (every pair at every pose),
// each with its own runtime (members in this order: the worlds borrow their cells' meshes).
Cell without_broad(Cell c) {
  c.collision.broad_phase = false;
  return c;
}
struct BroadPair {
  explicit BroadPair(const Cell& c) : cell(c), off(without_broad(c)), runtime(cell), runtime_off(off), world(cell), reference(off) {
    world.attach(runtime);
    reference.attach(runtime_off);
    world.build_engine(cell);
    reference.build_engine(off);
  }
  Cell cell, off;
  CellRuntime runtime, runtime_off;
  World world, reference;
};
}  // namespace

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
  BroadPair both(cell);
  World &world = both.world, &reference = both.reference;
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

// Parts on a stopped conveyor are still bodies like parts at rest: once a full query found
// them free, their pairs with other still parts leave pairs() (neither can move until the
// devices change); the belt starting takes them out of the tree and their near pairs back.
TEST_CASE("the broad phase leaves out pairs of still parts, a stopped belt's too", "[walker]") {
  Cell cell = wall_cell();
  cell.objects.clear();
  auto& w = cell.workcell;
  w.conveyors.push_back({"belt", {trans(-800, 0, -20, 0, 0, 0), {1000, 200, 40}}, collision::Vec3::UnitX(), 100, 1});
  cell.objects.push_back(test::box_object("belt", {1000, 200, 40}, {-800, 0, -20}));
  for (int i = 0; i < 4; ++i)  // on the belt (output 1 off: it stands)
    w.parts.push_back({"on_belt" + std::to_string(i), "", collision::make_box({20, 20, 20}), trans(-1100 + 150 * i, 80, 10, 0, 0, 0)});
  for (int i = 0; i < 6; ++i)  // on the floor beside it, 30 mm from the belt's parts
    w.parts.push_back({"rest" + std::to_string(i), "", collision::make_box({20, 20, 20}), trans(-1100 + 100 * i, 130, 10, 0, 0, 0)});
  BroadPair both(cell);
  World &world = both.world, &reference = both.reference;
  CellRuntime &runtime = both.runtime, &runtime_off = both.runtime_off;
  REQUIRE(world.broad_phase());
  const JointVector q = start_joints(cell);
  const auto name = [&](collision::BodyId id) { return world.engine()->body_name(id); };
  const auto still_pairs = [&](const World& x) {
    std::size_t n = 0;
    for (const collision::BodyPair& p : x.pairs())
      if (name(p.a).rfind("part:", 0) == 0 && name(p.b).rfind("part:", 0) == 0) ++n;
    return n;
  };
  constexpr double kKeep = 10;
  world.pose(q, 0);
  reference.pose(q, 0);
  world.broad_refresh(kKeep, 1);
  CHECK(still_pairs(reference) == 24);  // each belt part with each part on the floor
  CHECK(still_pairs(world) == 24);      // not tested yet: all kept
  collision::QueryResult r;
  world.query({}, r);
  REQUIRE(!r.collided);
  world.broad_refresh(kKeep, 1);
  CHECK(still_pairs(world) == 0);
  // Output 1 on: the belt runs; its parts' pairs with the floor parts near them come back.
  runtime.clock().set_signal(1, true);
  runtime_off.clock().set_signal(1, true);
  world.pose(q, 0.1);
  reference.pose(q, 0.1);
  world.broad_refresh(kKeep, 1);
  const std::vector<collision::BodyPair> kept(world.pairs().begin(), world.pairs().end());
  std::size_t near = 0;
  for (const collision::BodyPair& p : reference.pairs()) {
    if (name(p.a).rfind("part:", 0) != 0 || name(p.b).rfind("part:", 0) != 0) continue;
    if (world.engine()->distance(p.a, p.b, {.upper_mm = 100}).distance > 60) continue;
    ++near;
    CHECK(std::find(kept.begin(), kept.end(), p) != kept.end());
  }
  CHECK(near >= 4);
}

// The carried part is one of the broad phase's movers: its pairs with far still bodies leave
// pairs() by the same distance rule, its room (the last reach() slot) shrinks as the flange
// moves, and a grasp keeps all its pairs until the near lists are computed again.
TEST_CASE("the broad phase covers the carried part", "[walker]") {
  Cell cell = wall_cell();
  cell.objects.clear();
  for (int i = 0; i < 12; ++i)
    cell.workcell.parts.push_back({"p" + std::to_string(i), "", collision::make_box({40, 40, 40}),
                                   trans(-900 + 150 * i, 300, 200, 0, 0, 0)});
  cell.objects.push_back(test::box_object("post", {40, 40, 400}, {500, 0, 0}));
  const JointVector q = start_joints(cell);
  const Location flange = robots::flange_pose(cell.robot, q);
  cell.workcell.gripper.declared = true;
  cell.workcell.gripper.zone = {Location::Identity(), {30, 30, 30}};
  cell.workcell.parts.push_back({"held", "", collision::make_box({40, 40, 40}), flange});
  BroadPair both(cell);
  World &world = both.world, &reference = both.reference;
  CellRuntime &runtime = both.runtime, &runtime_off = both.runtime_off;
  REQUIRE(world.broad_phase());
  REQUIRE(runtime.close(flange, 1));
  REQUIRE(runtime_off.close(flange, 1));
  world.pose(q, 0);
  reference.pose(q, 0);
  collision::BodyId held = 0;
  while (held < world.engine()->body_count() && world.engine()->body_name(held) != "part:held") ++held;
  REQUIRE(held < world.engine()->body_count());
  CHECK(world.body_name(held) == "carried part:held");
  const auto with_held = [&](const World& w) {
    std::vector<collision::BodyPair> out;
    for (const collision::BodyPair& p : w.pairs())
      if (p.a == held || p.b == held) out.push_back(p);
    return out;
  };
  const std::vector<collision::BodyPair> all = with_held(reference);
  REQUIRE(all.size() >= 13);  // the other parts and the post (and the arm's bodies past the flange's)
  constexpr double kKeep = 10;
  // Before the near lists are computed (the grasp): every pair of the carried part is kept.
  CHECK(with_held(world) == all);
  CHECK(world.room().back() == INFINITY);
  for (const double room : {1.0, 150.0}) {
    CAPTURE(room);
    world.broad_refresh(kKeep, room);
    const std::vector<collision::BodyPair> kept = with_held(world);
    std::size_t left_out = 0;
    for (const collision::BodyPair& p : all) {
      if (std::find(kept.begin(), kept.end(), p) != kept.end()) continue;
      ++left_out;
      CHECK(world.engine()->distance(p.a, p.b, {.upper_mm = kKeep + room + 1}).distance > kKeep + room);
    }
    CHECK(left_out > 0);
    CHECK(kept.size() + left_out == all.size());
    CHECK(world.room().back() >= room);
    CHECK(world.room().back() < INFINITY);
  }
  // The flange moves 5 degrees about joint 1: the carried part's room is its motion bound less.
  const double before = world.room().back();
  JointVector q2 = q;
  q2[0] += 5 * std::numbers::pi / 180;
  world.pose(q2, 0.1);
  const double moved = robots::max_displacement(world.reach().back(), q2 - q);
  CHECK(moved > 1);
  CHECK(world.room().back() == Approx(before - moved).margin(1e-6));
}
