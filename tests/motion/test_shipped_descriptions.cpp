// Arms described as their ROS-Industrial packages describe them (tests/robots/descriptions/:
// written in the shape of the shipped files, not copied): a UR5 from a ur_description-shaped
// xacro package (four YAML files, !degrees limits, macros including macros), an IRB 6600-shaped
// URDF (J3 upper 1.04719755), an IRB 5400-shaped coupled wrist (a <mimic> joint on the chain)
// and the iiwa 14 (robots/data/redundant7.urdf). Each runs joint moves and straight lines where
// the pose is reachable, with the deviation within docs/robots.md's tolerance and the same joints
// whatever the step; the limits are the ones the files mean.
#include "asimov/motion/simulator.hpp"
#include "asimov/robots/urdf_loader.hpp"

#include "support/joints.hpp"
#include "support/result.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <numbers>

using namespace asimov;
using namespace asimov::motion;
using robots::JointVector;
using asimov::test::jv;
namespace fs = std::filesystem;

namespace {
const fs::path kDescriptions = fs::path(ASIMOV_SOURCE_DIR) / "tests/robots/descriptions";

robots::Robot ur5() {
  robots::UrdfOptions o;
  o.packages.add_root(kDescriptions);
  return asimov::test::must(robots::load_urdf((kDescriptions / "ur_description/urdf/ur5.xacro").string(), o));
}
robots::Robot urdf(const std::string& rel) {
  return asimov::test::must(robots::load_urdf((fs::path(ASIMOV_SOURCE_DIR) / rel).string()));
}

Cell cell_of(const robots::Robot& r, const JointVector& start, double step_mm) {
  Cell c;
  c.robot = r;
  c.start_joints = start;
  c.collision.step_mm = step_mm;
  c.collision.stepping = Stepping::fixed;  // the deviation figure is then between the line's samples
  return c;
}

struct Lines {
  std::vector<JointVector> ends;
  double deviation_mm = 0;
  double time_s = 0;
};

// Straight lines through the given tool offsets [mm] (world frame) from the start pose.
Lines run_lines(const robots::Robot& r, const JointVector& start, double step_mm, const std::vector<collision::Vec3>& offsets) {
  Simulator sim(cell_of(r, start, step_mm));
  const Location from = sim.here();
  Lines out;
  for (std::size_t k = 0; k < offsets.size(); ++k) {
    Location target = from;
    target.translation() += offsets[k];
    const MotionResult planned = sim.start_move(target, true, {}, static_cast<int>(k + 1));
    INFO(r.name << " line " << k << ": " << planned.error.message << "  " << planned.error.detail);
    REQUIRE(planned.status == MotionStatus::ok);
    const MotionResult done = sim.finish_motion();
    INFO(done.error.message << "  " << done.error.detail);
    REQUIRE(done.status == MotionStatus::ok);
    CHECK((sim.here().translation() - target.translation()).norm() < 1e-6);
    CHECK((sim.here().linear() - target.linear()).norm() < 1e-8);  // the IK's 1e-9 rad per solve
    out.ends.push_back(sim.joints());
  }
  out.deviation_mm = sim.recorders().accuracy.figures.line_deviation.position_mm;
  out.time_s = sim.time_s();
  return out;
}

// The lines at two steps end in the same joints; the deviation is within the tolerance.
void lines_hold(const robots::Robot& r, const JointVector& start, const std::vector<collision::Vec3>& offsets,
                double same_deg = 1e-6) {
  const Lines coarse = run_lines(r, start, 5.0, offsets);
  const Lines fine = run_lines(r, start, 0.5, offsets);
  REQUIRE(coarse.ends.size() == fine.ends.size());
  for (std::size_t k = 0; k < fine.ends.size(); ++k) {
    INFO(r.name << " line " << k);
    CHECK((coarse.ends[k] - fine.ends[k]).cwiseAbs().maxCoeff() < same_deg);
  }
  WARN(r.name << ": " << offsets.size() << " lines, largest deviation " << fine.deviation_mm << " mm at step 0.5, "
               << coarse.deviation_mm << " mm at step 5");
  CHECK(fine.deviation_mm < 1e-3);  // docs/robots.md: the straight-line tolerance
  CHECK(coarse.deviation_mm < 1e-3);
}

std::vector<collision::Vec3> square(double side) {
  return {{side, 0, 0}, {side, side, 0}, {0, side, 0}, {0, 0, 0}};
}

// A circle of radius r in the plane spanned by u and v, as n chords starting and ending at the
// start (the centre is r along -u).
std::vector<collision::Vec3> circle(double radius, int n, const collision::Vec3& u, const collision::Vec3& v) {
  std::vector<collision::Vec3> out;
  for (int i = 1; i <= n; ++i) {
    const double a = 2 * std::numbers::pi * i / n;
    out.push_back(radius * (std::cos(a) - 1) * u + radius * std::sin(a) * v);
  }
  return out;
}
}  // namespace

TEST_CASE("shipped shapes: a UR5 from a ur_description-shaped xacro package keeps its limits and speeds",
          "[urdf][xacro][simulator][shipped]") {
  const robots::Robot r = ur5();
  REQUIRE(r.joint_count() == 6);
  CHECK(r.name == "ur5_robot");
  for (int j = 0; j < 6; ++j) {
    INFO("J" << j + 1);
    CHECK(r.max_velocity[j] == Approx(180));
    CHECK(r.upper[j] == Approx(j == 2 ? 180 : 360));
    CHECK(r.lower[j] == Approx(j == 2 ? -180 : -360));
  }
  CHECK(r.warnings.empty());
  // MOVE #PPOINT(180,...) takes at least a second at 180 deg/s; 400 deg is refused.
  Simulator sim(cell_of(r, jv({0, -90, 90, -90, -90, 0}), 1.0));
  REQUIRE(sim.start_joint_move(jv({180, -90, 90, -90, -90, 0}), {}, 1).status == MotionStatus::ok);
  REQUIRE(sim.finish_motion().status == MotionStatus::ok);
  CHECK(sim.time_s() >= 1.0);
  const MotionResult past = sim.start_joint_move(jv({400, 0, 0, 0, 0, 0}), {}, 2);
  CHECK(past.error.message == "*Joint limit exceeded*");
  CHECK(past.error.detail == "J1 = 400.000 > 360.000");
  const MotionResult elbow = sim.start_joint_move(jv({0, -90, 181, -90, -90, 0}), {}, 3);
  CHECK(elbow.error.detail == "J3 = 181.000 > 180.000");
}

TEST_CASE("shipped shapes: the UR5 runs straight lines, the same at every step", "[urdf][xacro][simulator][shipped]") {
  const robots::Robot r = ur5();
  const JointVector start = jv({10, -100, 80, -70, -90, 20});
  lines_hold(r, start, {{50, 0, 0}});
  lines_hold(r, start, square(100));
  lines_hold(r, start, circle(60, 24, {1, 0, 0}, {0, 0, 1}));
}

TEST_CASE("shipped shapes: an IRB 6600-shaped URDF moves J3 to 60 and runs straight lines", "[urdf][limits][simulator][shipped]") {
  const robots::Robot r = urdf("tests/robots/descriptions/abb/irb6600_like.urdf");
  REQUIRE(r.joint_count() == 6);
  Simulator sim(cell_of(r, jv({0, 0, 0, 0, 30, 0}), 1.0));
  const MotionResult to60 = sim.start_joint_move(jv({0, 0, 60, 0, 30, 0}), {}, 1);
  INFO(to60.error.message << "  " << to60.error.detail);
  REQUIRE(to60.status == MotionStatus::ok);
  REQUIRE(sim.finish_motion().status == MotionStatus::ok);
  CHECK(sim.joints()[2] == Approx(60).margin(1e-9));
  const MotionResult past = sim.start_joint_move(jv({0, 0, 60.001, 0, 30, 0}), {}, 2);
  CHECK(past.error.message == "*Joint limit exceeded*");
  CHECK(past.error.detail == "J3 = 60.001 > 60.000");
  const JointVector start = jv({15, 20, -10, 30, 40, -20});
  lines_hold(r, start, {{50, 0, 0}});
  lines_hold(r, start, square(200));
  lines_hold(r, start, circle(150, 24, {0, 1, 0}, {0, 0, 1}));
}

TEST_CASE("shipped shapes: an IRB 5400-shaped coupled wrist moves and runs straight lines", "[urdf][mimic][simulator][shipped]") {
  const robots::Robot r = urdf("tests/robots/descriptions/abb/irb5400_like.urdf");
  REQUIRE(r.joint_count() == 6);  // joint_5b is no joint of its own
  Simulator sim(cell_of(r, jv({0, 0, 0, 0, 20, 0}), 1.0));
  REQUIRE(sim.start_joint_move(jv({30, 10, -20, 40, 30, 50}), {}, 1).status == MotionStatus::ok);
  REQUIRE(sim.finish_motion().status == MotionStatus::ok);
  const JointVector start = jv({10, 15, -15, 20, 25, 10});
  lines_hold(r, start, {{50, 0, 0}}, 1e-4);
  lines_hold(r, start, square(150), 1e-4);
}

TEST_CASE("shipped shapes: the iiwa 14 runs a circle of lines and a line along its far reach", "[redundant][simulator][shipped]") {
  const robots::Robot r = urdf("robots/data/redundant7.urdf");
  const JointVector start = jv({10, 35, 20, -70, 15, 60, 5});
  lines_hold(r, start, circle(80, 36, {1, 0, 0}, {0, 1, 0}), 1e-8);
  lines_hold(r, start, circle(80, 36, {0, 1, 0}, {0, 0, 1}), 1e-8);
  // Stretched out: the flange 934 mm from the shoulder (946 at full stretch), a 200 mm line across.
  const JointVector far = jv({0, 70, 0, -15, 0, 10, 0});
  Simulator at(cell_of(r, far, 1.0));
  const collision::Vec3 wrist = robots::flange_pose(r, far).translation() - collision::Vec3(0, 0, 360);
  WARN("iiwa far pose: flange " << wrist.norm() << " mm from the shoulder");
  CHECK(wrist.norm() > 930);
  lines_hold(r, far, {{0, 100, 0}, {0, -100, 0}, {0, 0, 0}}, 1e-8);
  // Outward past the reach: refused as out of reach, not as a singularity.
  Location out = at.here();
  out.translation() += 400 * wrist.normalized();
  const MotionResult beyond = at.start_move(out, true, {}, 9);
  MotionResult result = beyond;
  if (beyond.status == MotionStatus::ok) result = at.finish_motion();
  CHECK(result.status == MotionStatus::error);
  CHECK(result.error.message == "*Location out of reach*");
}
