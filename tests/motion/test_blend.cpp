// Continuous-path blending (docs/blending.md): consecutive motions of a gantry (three prismatic
// joints, so joint values are the tool point in mm) overlap by tau = min(y_a, y_b); the corner is
// rounded by the closed form delta = v^2 / (4 a) * sin(theta / 2), the sequence is the sum of the
// overlaps shorter, and the collision check, the trace and the replay walk the rounded path.
#include "support/cell_bodies.hpp"
#include "support/result.hpp"
#include "asimov/collision/polyhedron.hpp"
#include "asimov/motion/simulator.hpp"
#include "asimov/robots/urdf_loader.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <numbers>

using namespace asimov;
using namespace asimov::motion;
using robots::JointVector;

namespace {

// 500 mm/s and (the loader's 4x) 2000 mm/s^2 on every axis.
const char* const kGantry = R"(<?xml version="1.0"?>
<robot name="gantry">
  <link name="base"/>
  <joint name="x" type="prismatic"><parent link="base"/><child link="cx"/><axis xyz="1 0 0"/>
    <limit lower="-1" upper="1" velocity="0.5" effort="1"/></joint>
  <link name="cx"/>
  <joint name="y" type="prismatic"><parent link="cx"/><child link="cy"/><axis xyz="0 1 0"/>
    <limit lower="-1" upper="1" velocity="0.5" effort="1"/></joint>
  <link name="cy"/>
  <joint name="z" type="prismatic"><parent link="cy"/><child link="cz"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" velocity="0.5" effort="1"/></joint>
  <link name="cz"/>
</robot>)";

constexpr double kV = 500, kA = 2000;  // mm/s, mm/s^2
constexpr double kY = kV / kA;         // acceleration time 0.25 s
constexpr double kL = 200;             // each leg [mm]
constexpr double kT = kL / kV + kY;    // one leg from rest to rest: 0.65 s

JointVector point(double x, double y) {
  JointVector q(3);
  q << x, y, 0;
  return q;
}

Cell gantry_cell(double step_mm) {
  Cell cell;
  cell.robot = test::must(robots::load_urdf_text(kGantry, "gantry.urdf"));
  cell.start_joints = JointVector::Zero(3);
  cell.collision.step_mm = step_mm;
  cell.tool_shape = collision::make_box({4, 4, 4});
  return cell;
}

// The corner (200, 0) -> (200, 200) from the origin, blended or stopped.
MotionResult corner(Simulator& sim, bool blend) {
  sim.settings().continuous_path = blend;
  REQUIRE(sim.start_joint_move(point(kL, 0), {}, 1).status == MotionStatus::ok);
  const MotionResult second = sim.start_joint_move(point(kL, kL), {}, 2);
  if (second.status != MotionStatus::ok) return second;
  return sim.finish_motion();
}

// Closest traced tool point to `p` and when.
std::pair<double, double> closest(const Simulator& sim, const Eigen::Vector3d& p) {
  double d = std::numeric_limits<double>::infinity(), at = -1;
  for (const TraceSample& s : sim.recorders().trace.samples)
    if (const double e = (s.tool.translation() - p).norm(); e < d) d = e, at = s.time_s;
  return {d, at};
}

}  // namespace

TEST_CASE("blend: the rounded corner deviates from the sharp one by v^2 / (4a) sin(theta/2)", "[blend]") {
  Cell cell = gantry_cell(0.05);
  cell.collision.enabled = false;
  Simulator sim(cell);
  sim.recorders().trace.on = true;
  REQUIRE(corner(sim, true).status == MotionStatus::ok);
  const double model = kV * kV / (4 * kA) * std::sin(std::numbers::pi / 4);  // 90 degree turn: 22.097 mm
  const auto [d, at] = closest(sim, Eigen::Vector3d(kL, 0, 0));
  CHECK(std::abs(d - model) < 0.01);
  CHECK(at == Approx(kT - kY / 2).margin(0.002));  // the middle of the overlap
  // The sequence is tau = y shorter than two stops, and ends at the target at rest.
  CHECK(sim.time_s() == Approx(2 * kT - kY).epsilon(1e-12));
  CHECK((sim.joints() - point(kL, kL)).norm() < 1e-9);
  Simulator stopped(cell);
  stopped.recorders().trace.on = true;
  REQUIRE(corner(stopped, false).status == MotionStatus::ok);
  CHECK(stopped.time_s() == Approx(2 * kT).epsilon(1e-12));
  CHECK(sim.time_s() < stopped.time_s());
  CHECK(closest(stopped, Eigen::Vector3d(kL, 0, 0)).first < 1e-9);  // the stopped path passes the corner
}

TEST_CASE("blend: at the overlap's middle the displacements of both ramps add", "[blend]") {
  // (200, 0) then (0, 200): a turn of 135 degrees; the second leg moves both axes, so its path
  // speed and acceleration are v sqrt 2 and a sqrt 2 (same ramp time y). At the overlap's
  // middle each leg is (y/2)^2 a_i / 2 from the corner along its direction u_i, so the arm is
  // |a2 u2 - a1 u1| y^2 / 8 = sqrt(a1^2 + a2^2 - 2 a1 a2 cos 135) y^2 / 8 from it.
  Cell cell = gantry_cell(0.5);
  cell.collision.enabled = false;
  Simulator sim(cell);
  sim.recorders().replay.grid_s = 0.001;
  sim.settings().continuous_path = true;
  REQUIRE(sim.start_joint_move(point(kL, 0), {}, 1).status == MotionStatus::ok);
  REQUIRE(sim.start_joint_move(point(0, kL), {}, 2).status == MotionStatus::ok);
  REQUIRE(sim.finish_motion().status == MotionStatus::ok);
  const double a1 = kA, a2 = kA * std::sqrt(2.0), theta = 3 * std::numbers::pi / 4;
  const double model = std::sqrt(a1 * a1 + a2 * a2 - 2 * a1 * a2 * std::cos(theta)) * kY * kY / 8;
  const double mid = kT - kY / 2;
  const ReplaySample* at = nullptr;
  for (const ReplaySample& s : sim.recorders().replay.samples)
    if (std::abs(s.time_s - mid) < 1e-9) at = &s;
  REQUIRE(at);
  CHECK(std::abs((at->joints - point(kL, 0)).norm() - model) < 0.01);
  CHECK(sim.time_s() == Approx(2 * kT - kY).epsilon(1e-12));
}

TEST_CASE("blend: three motions in a row overlap pairwise, never three at once", "[blend]") {
  Cell cell = gantry_cell(0.5);
  cell.collision.enabled = false;
  Simulator sim(cell);
  sim.settings().continuous_path = true;
  std::vector<MotionTiming> timings;
  for (const auto& [q, step] : {std::pair{point(kL, 0), 1}, {point(kL, kL), 2}, {point(0, kL), 3}}) {
    REQUIRE(sim.start_joint_move(q, {}, step).status == MotionStatus::ok);
    timings.push_back(*sim.pending_timing());
  }
  REQUIRE(sim.finish_motion().status == MotionStatus::ok);
  CHECK_FALSE(timings[0].blended);
  CHECK(timings[1].blended);
  CHECK(timings[2].blended);
  CHECK(timings[1].start_s == Approx(kT - kY));
  CHECK(timings[2].start_s == Approx(2 * (kT - kY)));
  CHECK(timings[2].start_s >= timings[0].start_s + timings[0].duration_s);  // motion 1 is over by then
  CHECK(sim.time_s() == Approx(3 * kT - 2 * kY).epsilon(1e-12));
  CHECK((sim.joints() - point(0, kL)).norm() < 1e-9);
}

TEST_CASE("blend: the overlap is the shorter of the two ramps", "[blend]") {
  Cell cell = gantry_cell(0.5);
  cell.collision.enabled = false;
  Simulator sim(cell);
  sim.settings().continuous_path = true;
  REQUIRE(sim.start_joint_move(point(kL, 0), {}, 1).status == MotionStatus::ok);
  // SPEED 20: v = 100 mm/s, the ramp lasts v / a = 0.05 s, the motion 2.05 s.
  SpeedSettings slow;
  slow.program = 20;
  REQUIRE(sim.start_joint_move(point(kL, kL), slow, 2).status == MotionStatus::ok);
  const MotionTiming t = *sim.pending_timing();
  CHECK(t.blended);
  CHECK(t.start_s == Approx(kT - 0.05));
  CHECK(t.duration_s == Approx(kL / 100 + 0.05));
  REQUIRE(sim.finish_motion().status == MotionStatus::ok);
  CHECK(sim.time_s() == Approx(kT + t.duration_s - 0.05));
}

TEST_CASE("blend: continuous path off, or a forced stop, keeps the motions apart", "[blend]") {
  Cell cell = gantry_cell(0.5);
  cell.collision.enabled = false;
  Simulator sim(cell);
  sim.settings().continuous_path = true;
  REQUIRE(sim.start_joint_move(point(kL, 0), {}, 1).status == MotionStatus::ok);
  REQUIRE(sim.finish_motion().status == MotionStatus::ok);  // BREAK
  REQUIRE(sim.start_joint_move(point(kL, kL), {}, 2).status == MotionStatus::ok);
  CHECK_FALSE(sim.pending_timing()->blended);
  CHECK(sim.pending_timing()->start_s == Approx(kT));
  sim.settings().continuous_path = false;
  REQUIRE(sim.start_joint_move(point(0, kL), {}, 3).status == MotionStatus::ok);
  CHECK_FALSE(sim.pending_timing()->blended);
  CHECK(sim.pending_timing()->start_s == Approx(2 * kT));
  REQUIRE(sim.wait(0).status == MotionStatus::ok);
  CHECK(sim.time_s() == Approx(3 * kT));
}

TEST_CASE("blend: a refused motion leaves the pending one to finish at rest", "[blend]") {
  Cell cell = gantry_cell(0.5);
  cell.collision.enabled = false;
  Simulator sim(cell);
  sim.settings().continuous_path = true;
  REQUIRE(sim.start_joint_move(point(kL, 0), {}, 1).status == MotionStatus::ok);
  const MotionResult r = sim.start_joint_move(point(5000, 0), {}, 2);  // beyond the 1 m limit
  CHECK(r.status == MotionStatus::error);
  CHECK(r.error.message == "*Joint limit exceeded*");
  CHECK(sim.motion_pending());
  REQUIRE(sim.finish_motion().status == MotionStatus::ok);
  CHECK(sim.time_s() == Approx(kT));
  CHECK((sim.joints() - point(kL, 0)).norm() < 1e-9);
}

TEST_CASE("blend: a contact on the stopped path only, and one on the blended path only", "[blend][collision]") {
  // A box on the sharp corner: the stopped path runs into it, the rounded one passes 22 mm inside.
  Cell at_corner = gantry_cell(0.5);
  at_corner.objects.push_back(test::box_object("corner", collision::Vec3(10, 10, 10), collision::Vec3(kL, 0, 0)));
  {
    Simulator stopped(at_corner);
    const MotionResult r = corner(stopped, false);
    REQUIRE(r.status == MotionStatus::collision);
    CHECK(r.collision.body_a == "tool");
    CHECK(r.collision.body_b == "corner");
    CHECK(r.collision.step == 1);
    CHECK(r.collision.time_s < kT);  // on the first leg, before the corner
    CHECK(r.collision.time_s - r.collision.time_free_s <= 1e-6);
    Simulator blended(at_corner);
    CHECK(corner(blended, true).status == MotionStatus::ok);
  }
  // A box where the rounded path passes closest to the corner: the legs pass 8.6 mm beside it.
  const double inside = kV * kV / (8 * kA);  // 15.625 mm from each leg
  Cell on_curve = gantry_cell(0.5);
  on_curve.objects.push_back(test::box_object("curve", collision::Vec3(10, 10, 10), collision::Vec3(kL - inside, inside, 0)));
  Simulator stopped(on_curve);
  CHECK(corner(stopped, false).status == MotionStatus::ok);
  Simulator blended(on_curve);
  const MotionResult r = corner(blended, true);
  REQUIRE(r.status == MotionStatus::collision);
  CHECK(r.collision.body_b == "curve");
  CHECK(r.collision.step == 2);  // found in the overlap, which the second motion started
  CHECK(r.collision.time_s > kT - kY);
  CHECK(r.collision.time_s < kT);
  CHECK(r.collision.time_s - r.collision.time_free_s <= 1e-6);
  // The arm halted on the rounded path, off both legs, at the contact time.
  CHECK(blended.joints()[0] < kL - 1);
  CHECK(blended.joints()[1] > 1);
  CHECK(blended.time_s() == r.collision.time_s);
}

TEST_CASE("blend: the replay and the trace follow the rounded path in time order", "[blend]") {
  Cell cell = gantry_cell(1);
  cell.collision.enabled = false;
  Simulator sim(cell);
  sim.recorders().trace.on = true;
  sim.recorders().replay.grid_s = 0.01;
  REQUIRE(corner(sim, true).status == MotionStatus::ok);
  double t = -1;
  for (const TraceSample& s : sim.recorders().trace.samples) {
    CHECK(s.time_s > t);
    t = s.time_s;
  }
  t = -1;
  bool inside_corner = false;
  for (const ReplaySample& s : sim.recorders().replay.samples) {
    CHECK(s.time_s > t);
    t = s.time_s;
    inside_corner = inside_corner || (s.joints[0] < kL - 10 && s.joints[1] > 10);  // cut the corner
  }
  CHECK(inside_corner);
}

TEST_CASE("blend: the checked poses of the overlap keep the step rule", "[blend]") {
  Cell cell = gantry_cell(0.5);
  cell.collision.enabled = false;
  Simulator sim(cell);
  sim.recorders().trace.on = true;
  REQUIRE(corner(sim, true).status == MotionStatus::ok);
  // The gantry's tool point moves as the joints: consecutive checked poses within 0.5 mm.
  double worst = 0;
  for (std::size_t i = 1; i < sim.recorders().trace.samples.size(); ++i)
    worst = std::max(worst, (sim.recorders().trace.samples[i].joints - sim.recorders().trace.samples[i - 1].joints).cwiseAbs().sum());
  CHECK(worst <= 0.5 + 1e-9);
  CHECK(worst > 0.2);  // and not needlessly dense
}
