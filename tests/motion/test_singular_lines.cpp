// Straight-line motions that would cross a singularity stop with a clear error before moving
// (no pose checked, joints and clock unchanged): shoulder, elbow, wrist; and joint limits on
// a joint move name the joint.
#include "asimov/motion/simulator.hpp"
#include "asimov/robots/puma560.hpp"

#include "support/joints.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>

using namespace asimov;
using namespace asimov::motion;
using robots::JointVector;

using asimov::test::jv;

namespace {
Cell cell_at(const JointVector& start) {
  Cell c;
  c.robot = robots::puma560();
  c.start_joints = start;
  return c;
}

// Runs a refused straight line and checks nothing moved.
MotionResult refused_line(Simulator& sim, const Location& target) {
  const JointVector before = sim.joints();
  const std::uint64_t poses = sim.recorders().counts.poses;
  const MotionResult r = sim.start_move(target, true, {}, 9);
  CHECK(r.status == MotionStatus::error);
  CHECK_FALSE(sim.motion_pending());
  CHECK(sim.finish_motion().status == MotionStatus::ok);
  CHECK(sim.recorders().counts.poses == poses);
  CHECK(sim.joints() == before);
  CHECK(sim.time_s() == 0);
  return r;
}
}  // namespace

TEST_CASE("straight lines: shoulder singularity (path over the J1 axis)", "[simulator][singular]") {
  Simulator sim(cell_at(jv({0, -60, 150, 0, 40, 0})));
  Location through = sim.here();
  through.translation() = collision::Vec3(-through.translation().x(), -through.translation().y(), through.translation().z());
  const MotionResult r = refused_line(sim, through);
  CHECK(r.error.message == "*Singularity on straight-line path*");
  CHECK_THAT(r.error.detail, Catch::StartsWith("shoulder at"));
}

TEST_CASE("straight lines: elbow singularity (full stretch)", "[simulator][singular]") {
  const robots::Robot robot = robots::puma560();
  const double a2 = robot.dh[1].a, d3 = robot.dh[2].d, L = std::hypot(robot.dh[2].a, robot.dh[3].d);
  Simulator sim(cell_at(jv({0, -60, 150, 0, 40, 0})));
  // Wrist centre (= flange) 0.2 mm short of full stretch, straight out at the shoulder height.
  Location stretched = sim.here();
  stretched.translation() = collision::Vec3(a2 + L - 0.2, d3, 0);
  const MotionResult r = refused_line(sim, stretched);
  CHECK(r.error.message == "*Singularity on straight-line path*");
  CHECK_THAT(r.error.detail, Catch::StartsWith("elbow at"));
  // The same point as a joint move is fine (singular poses are reachable).
  CHECK(sim.start_move(stretched, false, {}, 1).status == MotionStatus::ok);
}

TEST_CASE("straight lines: wrist singularity (J5 through 0)", "[simulator][singular]") {
  Simulator sim(cell_at(jv({0, -60, 150, 0, 30, 0})));
  const MotionResult r = refused_line(sim, trans(0, 0, -300, 0, 0, 0) * sim.here());
  CHECK(r.error.message == "*Singularity on straight-line path*");
  CHECK_THAT(r.error.detail, Catch::StartsWith("joint jump at"));
  // The planner knows which joint jumped and by how much, and says so (J4 or J6 turning
  // through the wrist singularity).
  CHECK_THAT(r.error.detail, Catch::Matches(".*% of the path: J[46] by [0-9]+\\.[0-9] deg"));
}

TEST_CASE("joint moves: every joint past each limit is refused naming it", "[simulator][limits]") {
  Simulator sim(cell_at(jv({0, -90, 90, 0, 0, 0})));
  const robots::Robot& robot = sim.robot();
  for (int j = 0; j < 6; ++j)
    for (int side = 0; side < 2; ++side) {
      JointVector t = sim.joints();
      t[j] = side == 0 ? robot.lower[j] - 0.5 : robot.upper[j] + 0.5;
      const MotionResult r = sim.start_joint_move(t, {}, 1);
      INFO("J" << j + 1);
      CHECK(r.error.message == "*Joint limit exceeded*");
      char prefix[16];
      std::snprintf(prefix, sizeof prefix, "J%d = ", j + 1);
      CHECK_THAT(r.error.detail, Catch::StartsWith(prefix));
      t[j] = side == 0 ? robot.lower[j] : robot.upper[j];  // on the limit: accepted
      CHECK(sim.start_joint_move(t, {}, 1).status == MotionStatus::ok);
      sim.finish_motion();
      REQUIRE(sim.start_joint_move(jv({0, -90, 90, 0, 0, 0}), {}, 1).status == MotionStatus::ok);
      sim.finish_motion();
    }
}

TEST_CASE("straight lines: every joint's speed stays within its limit", "[simulator][profile]") {
  // Near the wrist singularity (J5 = 3 deg) a sideways line turns J4 and J6 fast: the joints,
  // not the tool speed, set the duration.
  Cell c = cell_at(jv({0, -60, 150, 0, 3, 0}));
  c.collision.enabled = false;
  Simulator sim(std::move(c));
  sim.recorders().trace.on = true;
  const Location target = trans(0, 60, 0, 0, 0, 0) * sim.here();
  const MotionResult r = sim.start_move(target, true, {}, 1);
  INFO(r.error.message << " " << r.error.detail);
  REQUIRE(r.status == MotionStatus::ok);
  REQUIRE(sim.finish_motion().status == MotionStatus::ok);
  const auto& trace = sim.recorders().trace.samples;
  REQUIRE(trace.size() > 10);
  double worst = 0;  // largest secant speed / limit over all joints and samples
  for (std::size_t i = 1; i < trace.size(); ++i) {
    const double dt = trace[i].time_s - trace[i - 1].time_s;
    if (dt <= 0) continue;
    for (int j = 0; j < 6; ++j)
      worst = std::max(worst, std::abs(trace[i].joints[j] - trace[i - 1].joints[j]) / dt / sim.robot().max_velocity[j]);
  }
  CHECK(worst <= 1 + 1e-9);
  CHECK(worst > 0.8);  // the joint limit is what binds
  const double tool_only = 60.0 / 500 + 500.0 / 2000;  // T = D/V + V/A if the tool speed bound
  CHECK(sim.time_s() > 1.5 * tool_only);
  WARN("wrist-near line: " << sim.time_s() << " s (tool-speed bound alone " << tool_only << " s), worst joint speed "
                           << worst << " of its limit");
}
