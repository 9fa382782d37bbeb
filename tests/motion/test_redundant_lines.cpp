// Straight lines of a 7-axis arm (robots/data/redundant7.urdf, the iiwa 14's kinematics): the
// joints at a pose are the solution nearest the line's start whatever the step that reached it,
// so a 50 mm line and a square of lines complete, on the line, with the same joints at every
// step_mm; the same answers from the robots layer directly (solve_line_ik).
#include "asimov/motion/simulator.hpp"
#include "asimov/robots/ik_redundant.hpp"
#include "asimov/robots/urdf_loader.hpp"

#include "support/joints.hpp"
#include "support/result.hpp"

#include <catch2/catch.hpp>

#include <filesystem>

using namespace asimov;
using namespace asimov::motion;
using robots::JointVector;
using asimov::test::jv;

namespace {
robots::Robot redundant7() {
  return asimov::test::must(robots::load_urdf((std::filesystem::path(ASIMOV_SOURCE_DIR) / "robots/data/redundant7.urdf").string()));
}

const JointVector kStart = jv({10, 35, 20, -70, 15, 60, 5});

Cell cell(double step_mm) {
  Cell c;
  c.robot = redundant7();
  c.start_joints = kStart;
  c.collision.step_mm = step_mm;
  // Fixed stepping: the checked poses are the line's samples, so the deviation figure is the
  // joint interpolation between the samples the walk checks (gap stepping strides farther).
  c.collision.stepping = Stepping::fixed;
  return c;
}

// Runs straight lines through the given tool offsets [mm] (world frame) from the start; the
// joints at the end of each.
std::vector<JointVector> run_lines(double step_mm, const std::vector<collision::Vec3>& offsets, double* deviation = nullptr) {
  Simulator sim(cell(step_mm));
  const Location start = sim.here();
  std::vector<JointVector> ends;
  for (std::size_t k = 0; k < offsets.size(); ++k) {
    Location target = start;
    target.translation() += offsets[k];
    const MotionResult planned = sim.start_move(target, true, {}, static_cast<int>(k + 1));
    INFO("line " << k << ": " << planned.error.message << "  " << planned.error.detail);
    REQUIRE(planned.status == MotionStatus::ok);
    REQUIRE(sim.finish_motion().status == MotionStatus::ok);
    CHECK((sim.here().translation() - target.translation()).norm() < 1e-6);
    ends.push_back(sim.joints());
  }
  if (deviation) *deviation = sim.recorders().accuracy.figures.line_deviation.position_mm;
  return ends;
}
}  // namespace

TEST_CASE("redundant arms: the line IK depends on the pose, not on the path to it", "[redundant]") {
  const robots::Robot r = redundant7();
  REQUIRE(r.joint_count() == 7);
  const collision::Pose p0 = robots::flange_pose(r, kStart);
  const robots::Configuration config = robots::configuration_of(r, kStart);
  // The pose 1 mm along x, reached in one step and in 512 sub-steps.
  auto pose_at = [&](double mm) {
    collision::Pose p = p0;
    p.translation().x() += mm;
    return p;
  };
  const robots::IkResult direct = robots::solve_line_ik(r, pose_at(1), kStart, kStart, config);
  REQUIRE(direct.status == robots::IkStatus::ok);
  JointVector q = kStart;
  for (int i = 1; i <= 512; ++i) {
    const robots::IkResult step = robots::solve_line_ik(r, pose_at(i / 512.0), q, kStart, config);
    REQUIRE(step.status == robots::IkStatus::ok);
    q = step.joints;
  }
  CHECK((q - direct.joints).cwiseAbs().maxCoeff() < 1e-9);  // deg
  CHECK((robots::flange_pose(r, q).translation() - pose_at(1).translation()).norm() < 1e-6);
  // At the reference's own pose the answer is the reference.
  const robots::IkResult same = robots::solve_line_ik(r, p0, jv({12, 33, 25, -68, 10, 62, 0}), kStart, config);
  REQUIRE(same.status == robots::IkStatus::ok);
  CHECK((same.joints - kStart).cwiseAbs().maxCoeff() < 1e-8);
  // Out of reach (2 m away) and a limit (J4 cannot pass -120 to fold this far) are told apart.
  CHECK(robots::solve_line_ik(r, pose_at(2000), kStart, kStart, config).status == robots::IkStatus::out_of_reach);
}

TEST_CASE("redundant arms: a 50 mm line ends in the same joints at every step", "[redundant][simulator]") {
  double deviation = 0;
  const JointVector fine = run_lines(0.1, {{50, 0, 0}}, &deviation).back();
  for (double step : {0.37, 1.0, 5.0}) {
    INFO("step_mm " << step);
    const JointVector other = run_lines(step, {{50, 0, 0}}).back();
    CHECK((other - fine).cwiseAbs().maxCoeff() < 1e-8);
  }
  WARN("redundant7 50 mm line, step_mm 0.1: largest deviation " << deviation << " mm");
  CHECK(deviation < 1e-3);  // docs/robots.md "Redundant arms": joint interpolation between checked poses
}

TEST_CASE("redundant arms: a square of lines completes, the same at every step", "[redundant][simulator]") {
  const std::vector<collision::Vec3> square = {{100, 0, 0}, {100, 100, 0}, {0, 100, 0}, {0, 0, 0}};
  double deviation = 0;
  const auto a = run_lines(1.0, square, &deviation);
  const auto b = run_lines(0.25, square);
  REQUIRE(a.size() == 4);
  for (std::size_t k = 0; k < a.size(); ++k) CHECK((a[k] - b[k]).cwiseAbs().maxCoeff() < 1e-8);
  WARN("redundant7 square of 100 mm lines, step_mm 1: largest deviation " << deviation << " mm");
  CHECK(deviation < 1e-3);
}
