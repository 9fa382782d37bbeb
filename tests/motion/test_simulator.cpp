// The simulated arm: planning errors before any pose is checked, free motions reaching their
// targets, a halt at the first contact with a point on both bodies, BASE/TOOL semantics, time.
#include "asimov/collision/engine.hpp"
#include "asimov/motion/simulator.hpp"
#include "asimov/robots/puma560.hpp"

#include "support/cell_bodies.hpp"
#include "support/geometry.hpp"
#include "support/joints.hpp"

#include <catch2/catch.hpp>
#include <cmath>

using namespace asimov;
using namespace asimov::motion;
using robots::JointVector;

using asimov::test::jv;

namespace {
Cell basic_cell(double step_mm = 2.0) {
  Cell c;
  c.robot = robots::puma560();
  c.start_joints = jv({0, -90, 90, 0, 0, 0});
  c.collision.step_mm = step_mm;
  return c;
}



}  // namespace

TEST_CASE("simulator: a free joint move reaches its target", "[simulator]") {
  Simulator sim(basic_cell());
  CHECK(sim.collision_engine_used());  // self-collision pairs are enabled
  const JointVector target = jv({30, -60, 150, 20, 40, 30});
  REQUIRE(sim.start_joint_move(target, {}, 7).status == MotionStatus::ok);
  CHECK(sim.motion_pending());
  CHECK(sim.time_s() == 0);
  const MotionResult r = sim.finish_motion();
  REQUIRE(r.status == MotionStatus::ok);
  CHECK((sim.joints() - target).norm() == 0);
  CHECK(sim.recorders().counts.poses > 10);
  // J3 moves 60 deg at 90 deg/s, 360 deg/s^2: T = 60/90 + 90/360.
  CHECK(sim.time_s() == Approx(60.0 / 90 + 0.25));
  CHECK(sim.here().isApprox(robots::flange_pose(sim.robot(), target), 1e-12));
  CHECK(sim.dest().isApprox(sim.here(), 1e-12));
  CHECK(sim.recorders().counts.counts.pairs_enabled > 0);
}

TEST_CASE("simulator: speed scales velocity only", "[simulator]") {
  Simulator sim(basic_cell(20));
  REQUIRE(sim.start_joint_move(jv({0, -90, 150, 0, 0, 0}), {50, 100, -1, 0}, 1).status == MotionStatus::ok);
  REQUIRE(sim.finish_motion().status == MotionStatus::ok);
  CHECK(sim.time_s() == Approx(60.0 / 45 + 45.0 / 360));  // V = 45, A = 360
  const double t0 = sim.time_s();
  REQUIRE(sim.start_joint_move(jv({0, -90, 151, 0, 0, 0}), {100, 100, -1, 3.0}, 1).status == MotionStatus::ok);
  REQUIRE(sim.finish_motion().status == MotionStatus::ok);
  CHECK(sim.time_s() - t0 == Approx(3.0));  // DURATION
}

TEST_CASE("simulator: errors come before any pose is checked", "[simulator]") {
  Simulator sim(basic_cell());
  MotionResult r = sim.start_move(trans(2000, 0, 0, 0, 0, 0), false, {}, 1);
  CHECK(r.status == MotionStatus::error);
  CHECK(r.error.message == "*Location out of reach*");
  r = sim.start_move(trans(10, 10, 300, 0, 0, 0), false, {}, 1);  // inside the shoulder cylinder
  CHECK(r.error.message == "*Location out of reach*");
  r = sim.start_joint_move(jv({0, -90, 231, 0, 0, 0}), {}, 2);
  CHECK(r.status == MotionStatus::error);
  CHECK(r.error.message == "*Joint limit exceeded*");
  CHECK(r.error.detail == "J3 = 231.000 > 225.000");
  {  // A limit a hair below the value: enough digits to show the difference.
    Cell c = basic_cell();
    c.robot.upper[2] = 225 - 4e-8;
    Simulator near(c);
    const MotionResult n = near.start_joint_move(jv({0, -90, 225, 0, 0, 0}), {}, 2);
    CHECK(n.error.message == "*Joint limit exceeded*");
    CHECK(n.error.detail == "J3 = 225.00000000 > 224.99999996");
  }
  // A transformation whose solution in the current configuration needs J1 beyond 160.
  const Location behind = robots::flange_pose(sim.robot(), jv({175, -60, 150, 0, 30, 0}));
  r = sim.start_move(behind, false, {}, 3);
  CHECK(r.error.message == "*Joint limit exceeded*");
  CHECK(r.error.detail.rfind("J1 = ", 0) == 0);
  // Straight line from READY: singular.
  r = sim.start_move(trans(0, 0, -100, 0, 0, 0) * sim.here(), true, {}, 4);
  CHECK(r.error.message == "*Singularity on straight-line path*");
  // Non-finite targets and a zero speed are refused too.
  CHECK(sim.start_joint_move(jv({0, -90, std::nan(""), 0, 0, 0}), {}, 5).error.message == "*Joint limit exceeded*");
  Location bad = sim.here();
  bad.translation().x() = std::nan("");
  CHECK(sim.start_move(bad, false, {}, 6).error.message == "*Location out of reach*");
  CHECK(sim.start_joint_move(jv({0, -90, 100, 0, 0, 0}), {0, 100, -1, 0}, 7).error.message == "*Illegal value*");
  CHECK_FALSE(sim.motion_pending());
  CHECK(sim.recorders().counts.poses == 0);
  CHECK(sim.time_s() == 0);
}

TEST_CASE("simulator: a move into a box halts at the first contact", "[simulator][collision]") {
  Cell cell = basic_cell();
  // The forearm sweeps from vertical to horizontal-forward about the elbow (x = 0, z = 431.8).
  cell.objects.push_back(test::box_object("block", {100, 200, 100}, {220, -150, 660}));
  Simulator sim(cell);
  REQUIRE(sim.start_joint_move(jv({0, -90, 180, 0, 0, 0}), {}, 42).status == MotionStatus::ok);
  const MotionResult r = sim.finish_motion();
  REQUIRE(r.status == MotionStatus::collision);
  const CollisionReport& c = r.collision;
  CHECK(c.step == 42);
  CHECK((c.body_a == "block" || c.body_b == "block"));
  INFO("bodies " << c.body_a << " / " << c.body_b << ", point " << c.point.transpose());
  for (const auto& name : {c.body_a, c.body_b}) {
    const auto [mesh, pose] = test::body_in_world(cell, name, c.joints);
    CHECK(test::point_surface_distance(c.point, mesh, pose) < 0.01);
  }
  // Halted at the last free pose, before the colliding one, and the clock at the contact.
  CHECK(sim.joints()[2] < c.joints[2]);
  CHECK(sim.joints()[2] > 90);
  CHECK(c.joints[2] < 180);
  CHECK(sim.time_s() == c.time_s);
  CHECK(c.time_s > 0);
  CHECK_FALSE(sim.motion_pending());
  // The halting pose is collision-free for the reported pair.
  const auto [ma, pa] = test::body_in_world(cell, c.body_a, sim.joints());
  const auto [mb, pb] = test::body_in_world(cell, c.body_b, sim.joints());
  CHECK_FALSE(collision::brute_force_collides(ma, pa, mb, pb));
}

TEST_CASE("simulator: a straight line into a box halts too", "[simulator][collision]") {
  Cell cell = basic_cell();
  Simulator probe(cell);
  REQUIRE(probe.start_joint_move(jv({0, -60, 150, 0, 70, 0}), {}, 1).status == MotionStatus::ok);
  REQUIRE(probe.finish_motion().status == MotionStatus::ok);
  const Location start = probe.here();
  // A thin plate 150 mm below the flange, across the path of a 300 mm downward line.
  cell.objects.push_back(test::box_object("plate", {400, 400, 10}, start.translation() + collision::Vec3(0, 0, -150)));
  Simulator sim(cell);
  REQUIRE(sim.start_joint_move(jv({0, -60, 150, 0, 70, 0}), {}, 1).status == MotionStatus::ok);
  REQUIRE(sim.finish_motion().status == MotionStatus::ok);
  const MotionResult planned = sim.start_move(trans(0, 0, -300, 0, 0, 0) * start, true, {}, 9);
  INFO(planned.error.message << " " << planned.error.detail << " from " << start.translation().transpose());
  REQUIRE(planned.status == MotionStatus::ok);
  const MotionResult r = sim.finish_motion();
  REQUIRE(r.status == MotionStatus::collision);
  CHECK(r.collision.step == 9);
  CHECK((r.collision.body_a == "plate" || r.collision.body_b == "plate"));
  for (const auto& name : {r.collision.body_a, r.collision.body_b}) {
    const auto [mesh, pose] = test::body_in_world(cell, name, r.collision.joints);
    CHECK(test::point_surface_distance(r.collision.point, mesh, pose) < 0.01);
  }
  // Stopped on the line, above the plate.
  const double drop = start.translation().z() - sim.here().translation().z();
  CHECK(drop > 50);
  CHECK(drop < 150);
  CHECK((sim.here().translation() - start.translation()).head<2>().norm() < 1e-6);
}

TEST_CASE("simulator: the start pose of the first motion is checked", "[simulator][collision]") {
  Cell cell = basic_cell();
  cell.objects.push_back(test::box_object("pole", {300, 30, 30}, {20, -150, 700}));  // through the READY forearm
  Simulator sim(cell);
  REQUIRE(sim.start_joint_move(jv({0, -90, 95, 0, 0, 0}), {}, 5).status == MotionStatus::ok);
  const MotionResult r = sim.finish_motion();
  REQUIRE(r.status == MotionStatus::collision);
  CHECK(r.collision.time_s == 0);
  CHECK((r.collision.joints - jv({0, -90, 90, 0, 0, 0})).norm() == 0);
  CHECK(sim.recorders().counts.poses == 1);
}

TEST_CASE("simulator: straight line, BASE and TOOL", "[simulator]") {
  Cell cell = basic_cell(5);
  cell.tool = trans(0, 0, 100, 0, 0, 0);
  cell.tool_shape = collision::transformed(collision::make_box({40, 40, 80}), collision::Pose(Eigen::Translation3d(0, 0, 100)));
  cell.objects.push_back(test::box_object("table", {700, 1200, 40}, {750, 0, -420}));
  Simulator sim(cell);
  sim.recorders().trace.on = true;
  REQUIRE(sim.start_joint_move(jv({10, -60, 150, 20, 40, 30}), {}, 1).status == MotionStatus::ok);
  REQUIRE(sim.finish_motion().status == MotionStatus::ok);
  const Location target = trans(-80, 60, -100, 0, 0, 0) * sim.here() * trans(0, 0, 0, 0, 20, 0);
  REQUIRE(sim.start_move(target, true, {}, 2).status == MotionStatus::ok);
  REQUIRE(sim.finish_motion().status == MotionStatus::ok);
  CHECK((sim.here().translation() - target.translation()).norm() < 1e-6);
  CHECK((sim.here().linear() - target.linear()).norm() < 1e-9);
  // Every traced tool point of the line lies on the segment, times increase.
  const auto& tr = sim.recorders().trace.samples;
  REQUIRE(tr.size() > 10);
  CHECK(tr.back().time_s == Approx(sim.time_s()));
  const collision::Vec3 p1 = target.translation();
  const collision::Vec3 p0 = tr.front().tool.translation();  // first checked pose: start of the joint move
  double off_line = 0;
  bool increasing = true;
  std::size_t line_start = 0;
  for (std::size_t i = 0; i < tr.size(); ++i)
    if (tr[i].time_s > 0 && (tr[i].joints - jv({10, -60, 150, 20, 40, 30})).norm() == 0) line_start = i;
  const collision::Vec3 a = tr[line_start].tool.translation();
  for (std::size_t i = line_start + 1; i < tr.size(); ++i) {
    const collision::Vec3 p = tr[i].tool.translation();
    const collision::Vec3 d = (p1 - a).normalized();
    off_line = std::max(off_line, ((p - a) - d * d.dot(p - a)).norm());
    increasing = increasing && tr[i].time_s > tr[i - 1].time_s;
  }
  (void)p0;
  CHECK(line_start > 0);
  CHECK(off_line < 1e-6);
  CHECK(increasing);
  // BASE changes the interpretation of locations, not where the robot is.
  const JointVector before = sim.joints();
  const Location h0 = sim.here();
  sim.settings().base = trans(1000, 0, 0, 90, 0, 0);
  CHECK(sim.here().isApprox(trans(1000, 0, 0, 90, 0, 0) * h0, 1e-9));
  REQUIRE(sim.start_move(sim.here(), false, {}, 3).status == MotionStatus::ok);
  REQUIRE(sim.finish_motion().status == MotionStatus::ok);
  CHECK((sim.joints() - before).norm() < 1e-9);
}

TEST_CASE("simulator: collision checking off never uses the engine", "[simulator]") {
  Cell cell = basic_cell();
  cell.collision.enabled = false;
  cell.objects.push_back(test::box_object("pole", {60, 60, 60}, {20, -150, 700}));
  Simulator sim(cell);
  CHECK_FALSE(sim.collision_engine_used());
  REQUIRE(sim.start_joint_move(jv({0, -90, 95, 0, 0, 0}), {}, 5).status == MotionStatus::ok);
  CHECK(sim.finish_motion().status == MotionStatus::ok);
  CHECK(sim.recorders().counts.counts.pairs_enabled == 0);
}

TEST_CASE("simulator: configuration requests and INRANGE", "[simulator]") {
  Cell cell = basic_cell(20);
  cell.collision.enabled = false;
  Simulator sim(cell);
  REQUIRE(sim.start_joint_move(jv({20, -30, 100, -40, -50, 60}), {}, 1).status == MotionStatus::ok);
  REQUIRE(sim.finish_motion().status == MotionStatus::ok);
  const robots::Configuration c0 = sim.configuration();
  CHECK(c0.righty);
  CHECK_FALSE(c0.noflip);
  const Location target = sim.here();
  CHECK(sim.inrange(target) == 0);
  CHECK(sim.inrange(trans(3000, 0, 0, 0, 0, 0)) == 1);
  // Request NOFLIP: same tool pose, other wrist.
  sim.settings().request.noflip = 1;
  REQUIRE(sim.start_move(target, false, {}, 2).status == MotionStatus::ok);
  REQUIRE(sim.finish_motion().status == MotionStatus::ok);
  CHECK(sim.configuration().noflip);
  CHECK(sim.configuration().righty);
  CHECK(sim.here().isApprox(target, 1e-9));
  CHECK(sim.settings().request.noflip == -1);  // consumed by the motion
  CHECK(sim.joints()[3] == Approx(140));
  CHECK(sim.joints()[4] == Approx(50));
  // The configuration reached is kept by the next motion.
  REQUIRE(sim.start_move(trans(0, 0, -50, 0, 0, 0) * target, false, {}, 3).status == MotionStatus::ok);
  REQUIRE(sim.finish_motion().status == MotionStatus::ok);
  CHECK(sim.configuration().noflip);
  // FLIP needs J4 = 140 + 180 = 320 or -40 ... -40 is fine; J4 = 200 would not be.
  sim.settings().request.noflip = 0;
  CHECK(sim.inrange(sim.here()) == 0);
}

TEST_CASE("clearance set at run time: the report's distance follows it down as well as up", "[simulator][clearance]") {
  // COLLISION.CLEARANCE raised to 50 mm widens the clearance report to 50 mm; lowered to 0 it
  // returns to report_within_mm (10 mm) by the same rule the cell's own settings use.
  Cell cell = basic_cell();
  cell.collision.report_within_mm = 10;
  Simulator sim(cell);
  CHECK(sim.recorders().clearance.within_mm == 10);
  sim.set_clearance(50);
  CHECK(sim.recorders().clearance.within_mm == 50);
  CHECK(sim.recorders().clearance.clearance_mm == 50);
  sim.set_clearance(0);
  CHECK(sim.recorders().clearance.within_mm == 10);
  CHECK(report_distance_mm(sim.cell().collision) == 10);
}
