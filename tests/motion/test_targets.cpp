// Motion-instruction targets against hand-computed poses (dialect §5), DRIVE timing, the hand
// state machine, and a URDF arm moving in the simulator.
#include "asimov/motion/targets.hpp"
#include "asimov/robots/puma560.hpp"
#include "asimov/robots/urdf_loader.hpp"

#include "support/joints.hpp"
#include "support/result.hpp"

#include <catch2/catch.hpp>
#include <Eigen/Geometry>
#include <cmath>

using namespace asimov;
using asimov::test::must;
using namespace asimov::motion;
using robots::JointVector;

using asimov::test::jv;

namespace {
void check_loc(const Location& got, const Location& want, double tol = 1e-12) {
  INFO("got\n" << got.matrix() << "\nwant\n" << want.matrix());
  CHECK((got.matrix() - want.matrix()).cwiseAbs().maxCoeff() <= tol);
}

Cell free_cell(robots::Robot robot) {
  Cell c;
  c.start_joints = robots::ready_joints(robot);
  c.robot = std::move(robot);
  c.collision.enabled = false;
  return c;
}
}  // namespace

TEST_CASE("targets: APPRO and DEPART go back along the tool Z", "[targets]") {
  // Tool pointing down (a = 180): back along tool Z is up.
  check_loc(appro_target(trans(500, 100, 200, 0, 180, 0), 50), trans(500, 100, 250, 0, 180, 0));
  check_loc(appro_target(trans(500, 100, 200, 0, 180, 0), -20), trans(500, 100, 180, 0, 180, 0));
  // Rz(90) Ry(90): tool Z = world +Y, so DEPART 30 goes to y - 30.
  check_loc(depart_target(trans(400, 0, 300, 90, 90, 0), 30), trans(400, -30, 300, 90, 90, 0));
  // Oblique: tool Z = (sin 30, 0, cos 30); APPRO 100 is 100 mm back along it.
  check_loc(appro_target(trans(0, 0, 0, 0, 30, 0), 100), trans(-50, 0, -100 * std::sqrt(3.0) / 2, 0, 30, 0), 1e-12);
}

TEST_CASE("targets: DRAW shifts in world axes", "[targets]") {
  check_loc(draw_target(trans(400, 0, 300, 90, 90, 45), 10, -20, 30), trans(410, -20, 330, 90, 90, 45));
}

TEST_CASE("targets: ALIGN turns tool Z onto the nearest world axis", "[targets]") {
  // Tilted 20 deg about Y: nearest +Z, undone by -20 deg about Y.
  check_loc(align_target(trans(100, 200, 300, 0, 20, 0)), trans(100, 200, 300, 0, 0, 0), 1e-12);
  // Z = (0.6, 0.8, 0): nearest +Y, turned about world Z by atan2(0.6, 0.8): o becomes 90.
  const double o = std::atan2(0.8, 0.6) * 180 / std::numbers::pi;
  check_loc(align_target(trans(1, 2, 3, o, 90, 0)), trans(1, 2, 3, 90, 90, 0), 1e-12);
  // Tie X / Y (o = 45, a = 90): X wins; rotation -45 deg about world Z.
  check_loc(align_target(trans(1, 2, 3, 45, 90, 10)), trans(1, 2, 3, 0, 90, 10), 1e-12);
  // Tie Z / Y (o = 90, a = 45): Z wins.
  check_loc(align_target(trans(1, 2, 3, 90, 45, 0)), trans(1, 2, 3, 90, 0, 0), 1e-12);
  // Tool Z mostly along -X (o = 180, a = 80): -X, turned about world Y by -10 deg.
  check_loc(align_target(trans(0, 0, 0, 180, 80, 0)), trans(0, 0, 0, 180, 90, 0), 1e-12);
  // Pointing down (a = 170 about o = 0): -Z.
  check_loc(align_target(trans(5, 5, 5, 0, 170, 30)), trans(5, 5, 5, 0, 180, 30), 1e-12);
  // Already aligned: unchanged.
  check_loc(align_target(trans(7, 8, 9, 30, 180, 0)), trans(7, 8, 9, 30, 180, 0), 1e-15);
}

TEST_CASE("targets: READY, DRIVE and its speed", "[targets]") {
  CHECK(ready_target(robots::puma560()) == jv({0, -90, 90, 0, 0, 0}));
  JointVector out;
  REQUIRE(drive_target(jv({0, -90, 90, 0, 0, 0}), 2, -10, out));
  CHECK(out == jv({0, -100, 90, 0, 0, 0}));
  CHECK_FALSE(drive_target(out, 0, 1, out));
  CHECK_FALSE(drive_target(out, 7, 1, out));
  CHECK_FALSE(drive_target(out, 1, std::nan(""), out));
  CHECK(drive_speed(50, 30).monitor == 50);
  CHECK(drive_speed(50, 30).program == 30);
  CHECK(drive_speed(50, 0).program == 0);
  CHECK(drive_speed(50, 150).program == 0);
  CHECK(movet_hand(1) == HandState::open);
  CHECK(movet_hand(-2) == HandState::open);
  CHECK(movet_hand(0) == HandState::closed);

  // DRIVE 1, 90, 50 at monitor speed 100: V = 45 deg/s, A = 360 deg/s^2: T = 90/45 + 45/360.
  Simulator sim(free_cell(robots::puma560()));
  REQUIRE(drive_target(sim.joints(), 1, 90, out));
  REQUIRE(sim.start_joint_move(out, drive_speed(100, 50), 1).status == MotionStatus::ok);
  REQUIRE(sim.finish_motion().status == MotionStatus::ok);
  CHECK(sim.time_s() == Approx(2.125));
  CHECK(sim.joints()[0] == 90);
  // Out of range speed is refused before anything moves; a DRIVE past a limit names the joint.
  CHECK(sim.start_joint_move(out, drive_speed(100, 0), 1).error.message == "*Illegal value*");
  REQUIRE(drive_target(sim.joints(), 1, 100, out));
  const MotionResult r = sim.start_joint_move(out, drive_speed(100, 50), 1);
  CHECK(r.error.message == "*Joint limit exceeded*");
  CHECK(r.error.detail == "J1 = 190.000 > 160.000");
}

TEST_CASE("targets: APPRO / DEPART / DRAW / ALIGN reached by the simulator", "[targets][simulator]") {
  Simulator sim(free_cell(robots::puma560()));
  sim.settings().tool = trans(0, 0, 100, 0, 0, 0);
  const Location loc = trans(450, 150, -100, 0, 180, 0);
  REQUIRE(sim.start_move(appro_target(loc, 80), false, {}, 1).status == MotionStatus::ok);
  REQUIRE(sim.finish_motion().status == MotionStatus::ok);
  check_loc(sim.here(), trans(450, 150, -20, 0, 180, 0), 1e-9);
  REQUIRE(sim.start_move(loc, true, {}, 2).status == MotionStatus::ok);  // APPROS-like final approach
  REQUIRE(sim.finish_motion().status == MotionStatus::ok);
  check_loc(sim.here(), loc, 1e-9);
  REQUIRE(sim.start_move(depart_target(sim.here(), 60), true, {}, 3).status == MotionStatus::ok);
  REQUIRE(sim.finish_motion().status == MotionStatus::ok);
  check_loc(sim.here(), trans(450, 150, -40, 0, 180, 0), 1e-9);
  REQUIRE(sim.start_move(draw_target(sim.here(), 0, -100, 20), true, {}, 4).status == MotionStatus::ok);
  REQUIRE(sim.finish_motion().status == MotionStatus::ok);
  check_loc(sim.here(), trans(450, 50, -20, 0, 180, 0), 1e-9);
  // Tilt the tool, then ALIGN brings tool Z back to -Z at the same tool point.
  REQUIRE(sim.start_move(trans(450, 50, -20, 0, 165, 0), false, {}, 5).status == MotionStatus::ok);
  REQUIRE(sim.finish_motion().status == MotionStatus::ok);
  REQUIRE(sim.start_move(align_target(sim.here()), false, {}, 6).status == MotionStatus::ok);
  REQUIRE(sim.finish_motion().status == MotionStatus::ok);
  check_loc(sim.here(), trans(450, 50, -20, 0, 180, 0), 1e-9);
  REQUIRE(sim.start_joint_move(ready_target(sim.robot()), {}, 7).status == MotionStatus::ok);
  REQUIRE(sim.finish_motion().status == MotionStatus::ok);
  CHECK(sim.joints() == jv({0, -90, 90, 0, 0, 0}));
}

TEST_CASE("hand: OPEN/CLOSE/RELAX at the next motion start, OPENI waits HAND.TIME", "[targets][hand]") {
  Simulator sim(free_cell(robots::puma560()));
  CHECK(sim.hand().state == HandState::open);
  sim.request_hand(HandState::closed);
  CHECK(sim.hand().state == HandState::open);
  CHECK(sim.hand().pending.has_value());
  REQUIRE(sim.start_joint_move(jv({0, -90, 120, 0, 0, 0}), {}, 1).status == MotionStatus::ok);
  CHECK(sim.hand().state == HandState::closed);  // as the motion starts
  CHECK_FALSE(sim.hand().pending.has_value());
  // A refused motion does not start, so the request stays pending.
  sim.request_hand(HandState::relaxed);
  REQUIRE(sim.finish_motion().status == MotionStatus::ok);
  CHECK(sim.start_joint_move(jv({0, -90, 300, 0, 0, 0}), {}, 2).status == MotionStatus::error);
  CHECK(sim.hand().state == HandState::closed);
  CHECK(sim.hand().pending.has_value());
  // OPENI: waits for the motion, then HAND.TIME seconds; the pending RELAX is superseded.
  REQUIRE(sim.start_joint_move(jv({0, -90, 90, 0, 0, 0}), {}, 3).status == MotionStatus::ok);
  CHECK(sim.hand().state == HandState::relaxed);
  REQUIRE(sim.motion_pending());
  sim.request_hand(HandState::closed);
  REQUIRE(sim.hand_immediate(HandState::open, 0.2).status == MotionStatus::ok);
  CHECK_FALSE(sim.motion_pending());
  const double t_motion = 30.0 / 90 + 0.25;
  CHECK(sim.time_s() == Approx(2 * t_motion + 0.2));
  CHECK(sim.hand().state == HandState::open);
  CHECK_FALSE(sim.hand().pending.has_value());
  REQUIRE(sim.hand_immediate(HandState::closed).status == MotionStatus::ok);
  CHECK(sim.time_s() == Approx(2 * t_motion + 0.2 + kDefaultHandTime));
}

TEST_CASE("simulator: a URDF arm moves (numeric IK, straight lines, READY = zero pose)", "[targets][urdf]") {
  robots::Robot r = must(robots::load_urdf(std::string(ASIMOV_SOURCE_DIR) + "/robots/data/generic6.urdf"));
  Cell cell = free_cell(r);
  cell.collision.enabled = true;
  CellObject block;
  block.name = "block";
  block.mesh = collision::make_box({200, 200, 200});
  block.pose = Location::Identity();
  block.pose.translation() = collision::Vec3(700, 0, 300);
  cell.objects.push_back(block);
  Simulator sim(std::move(cell));
  CHECK(sim.joints() == JointVector::Zero(6));
  CHECK(sim.collision_engine_used());
  // Tool pointing down above the block, then a straight line down to 50 mm above it.
  const Location above = trans(700, 0, 600, 0, 180, 0);
  REQUIRE(sim.start_move(above, false, {}, 1).status == MotionStatus::ok);
  REQUIRE(sim.finish_motion().status == MotionStatus::ok);
  check_loc(sim.here(), above, 1e-6);
  REQUIRE(sim.start_move(draw_target(sim.here(), 0, 0, -150), true, {}, 2).status == MotionStatus::ok);
  REQUIRE(sim.finish_motion().status == MotionStatus::ok);
  check_loc(sim.here(), trans(700, 0, 450, 0, 180, 0), 1e-6);
  // Into the block: halts at the first contact, link_6 (flange) or link_5 against the block.
  const MotionResult hit = sim.start_move(draw_target(sim.here(), 0, 0, -100), true, {}, 3);
  REQUIRE(hit.status == MotionStatus::ok);
  const MotionResult r2 = sim.finish_motion();
  REQUIRE(r2.status == MotionStatus::collision);
  CHECK(r2.collision.body_b == "block");
  CHECK(r2.collision.step == 3);
  // Out of reach.
  CHECK(sim.start_move(trans(3000, 0, 0, 0, 0, 0), false, {}, 4).error.message == "*Location out of reach*");
  CHECK(sim.inrange(trans(3000, 0, 0, 0, 0, 0)) == 1);
  CHECK(sim.inrange(above) == 0);
}

TEST_CASE("cells: the generic6 demo sequence completes without contact", "[targets][urdf][cell]") {
  // Mirrors programs/cells/generic6_cell.yaml and programs/cells/generic6_demo.v2.
  Cell cell;
  cell.robot = must(robots::load_urdf(std::string(ASIMOV_SOURCE_DIR) + "/robots/data/generic6.urdf"));
  cell.start_joints = robots::ready_joints(cell.robot);
  cell.tool = trans(0, 0, 150, 0, 0, 0);
  cell.tool_shape = collision::transformed(collision::make_box({40, 60, 120}), trans(0, 0, 70, 0, 0, 0));
  const auto object = [](const char* name, collision::Vec3 size, collision::Vec3 at) {
    CellObject o;
    o.name = name;
    o.mesh = collision::make_box(size);
    o.pose = trans(at.x(), at.y(), at.z(), 0, 0, 0);
    return o;
  };
  cell.objects.push_back(object("table", {600, 1000, 40}, {750, 0, 380}));
  cell.objects.push_back(object("crate", {150, 150, 200}, {700, 350, 500}));
  Simulator sim(std::move(cell));
  const Location down = trans(0, 0, 0, 0, 180, 0);
  const Location points[] = {trans(650, -250, 500, 0, 0, 0) * down, trans(800, 0, 500, 0, 0, 0) * down,
                             trans(550, 150, 520, 0, 0, 0) * down};
  int step = 0;
  for (const auto& p : points) {
    const MotionResult s = sim.start_move(p, false, {}, ++step);
    INFO("point " << step << ": " << s.error.message << " " << s.error.detail);
    REQUIRE(s.status == MotionStatus::ok);
    const MotionResult f = sim.finish_motion();
    INFO(f.collision.body_a << " / " << f.collision.body_b);
    REQUIRE(f.status == MotionStatus::ok);
    check_loc(sim.here(), p, 1e-6);
  }
  REQUIRE(sim.start_joint_move(JointVector::Zero(6), {}, ++step).status == MotionStatus::ok);
  REQUIRE(sim.finish_motion().status == MotionStatus::ok);
  WARN("generic6 demo: " << sim.recorders().counts.poses << " poses checked, " << sim.time_s() << " s simulated");
}
