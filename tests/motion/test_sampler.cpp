// Checked-pose spacing: real vertex displacements of every arm body (links and a tool) between
// consecutive checked poses never exceed step_mm, for joint and straight-line moves.
#include "asimov/motion/sampler.hpp"
#include "asimov/robots/puma560.hpp"

#include "support/joints.hpp"

#include <catch2/catch.hpp>
#include <random>

using namespace asimov;
using namespace asimov::motion;
using robots::JointVector;

using asimov::test::jv;

namespace {
struct Arm {
  robots::Robot robot = robots::puma560();
  collision::Polyhedron tool = collision::transformed(collision::make_box(collision::Vec3(50, 80, 140)),
                                                      collision::Pose(Eigen::Translation3d(0, 0, 130)));
  std::vector<robots::BodyReach> reach;
  Arm() {
    for (const auto& b : robot.bodies) reach.push_back(robots::body_reach(robot, b.mesh, b.link));
    reach.push_back(robots::body_reach(robot, tool, 6));
  }
  // Largest displacement of any vertex of body k (tool = bodies.size()) between two joint vectors.
  double measured_body(std::size_t k, const JointVector& a, const JointVector& b) const {
    std::vector<collision::Pose> fa, fb;
    robots::link_frames(robot, a, fa);
    robots::link_frames(robot, b, fb);
    const auto& mesh = k < robot.bodies.size() ? robot.bodies[k].mesh : tool;
    const auto l = static_cast<std::size_t>(k < robot.bodies.size() ? robot.bodies[k].link : 6);
    double m = 0;
    for (const auto& v : mesh.vertices) m = std::max(m, (fa[l] * v - fb[l] * v).norm());
    return m;
  }
  // Largest displacement of any vertex of any body between two joint vectors.
  double measured(const JointVector& a, const JointVector& b) const {
    std::vector<collision::Pose> fa, fb;
    robots::link_frames(robot, a, fa);
    robots::link_frames(robot, b, fb);
    double m = 0;
    for (const auto& body : robot.bodies)
      for (const auto& v : body.mesh.vertices) {
        const auto k = static_cast<std::size_t>(body.link);
        m = std::max(m, (fa[k] * v - fb[k] * v).norm());
      }
    for (const auto& v : tool.vertices) m = std::max(m, (fa[6] * v - fb[6] * v).norm());
    return m;
  }
};
}  // namespace

TEST_CASE("joint moves: measured displacement between checked poses <= step_mm", "[sampler]") {
  const Arm arm;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0, 1);
  double worst = 0;
  long poses = 0;
  for (double step : {1.0, 5.0}) {
    for (int n = 0; n < 20; ++n) {
      JointVector a(6), b(6);
      for (int i = 0; i < 6; ++i) {
        a[i] = arm.robot.lower[i] + u(rng) * (arm.robot.upper[i] - arm.robot.lower[i]);
        b[i] = arm.robot.lower[i] + u(rng) * (arm.robot.upper[i] - arm.robot.lower[i]);
      }
      const int k = joint_move_intervals(arm.reach, a, b, step);
      poses += k;
      JointVector prev = a;
      for (int i = 1; i <= k; ++i) {
        const JointVector q = a + (b - a) * (static_cast<double>(i) / k);
        const double m = arm.measured(prev, q);
        worst = std::max(worst, m / step);
        prev = q;
      }
    }
  }
  WARN("joint moves: " << poses << " checked poses, max measured displacement / step_mm = " << worst);
  CHECK(worst <= 1.0);
  CHECK(worst > 0.3);  // the bound is not absurdly loose
}

TEST_CASE("pair rule: two moving bodies together move at most step_mm", "[sampler]") {
  const Arm arm;
  std::vector<BodyPair> pairs;
  for (int a = 1; a < 8; ++a)
    for (int b = a + 2; b < 8; ++b) pairs.push_back({std::uint32_t(a), std::uint32_t(b)});  // non-adjacent links and the tool
  const JointVector from = jv({-40, -120, 60, -90, -60, 100}), to = jv({60, -30, 200, 80, 70, -120});
  const double step = 2.0;
  const int n = joint_move_intervals(arm.reach, from, to, step, pairs);
  CHECK(n > joint_move_intervals(arm.reach, from, to, step));
  double worst = 0;
  JointVector prev = from;
  for (int i = 1; i <= n; ++i) {
    const JointVector q = from + (to - from) * (static_cast<double>(i) / n);
    for (const auto& [a, b] : pairs)
      worst = std::max(worst, arm.measured_body(static_cast<std::size_t>(a), prev, q) +
                                  arm.measured_body(static_cast<std::size_t>(b), prev, q));
    prev = q;
  }
  WARN("pair rule: " << n << " poses, max measured delta_a + delta_b / step_mm = " << worst / step);
  CHECK(worst <= step);
}

TEST_CASE("straight lines: measured displacement between checked poses <= 0.9 step_mm", "[sampler]") {
  const Arm arm;
  const JointVector start = jv({10, -60, 150, 20, 40, 30});
  const Location here = robots::flange_pose(arm.robot, start);
  double worst = 0;
  for (double step : {1.0, 4.0}) {
    for (const auto& delta : {trans(150, 80, -120, 0, 0, 0), trans(-100, 40, 60, 20, 30, -40), trans(0, 0, 0, 0, 60, 0)}) {
      LineRequest req;
      req.path = make_line(here, delta * here);
      req.start = start;
      req.config = robots::configuration_of(arm.robot, start);
      req.step_mm = step;
      LinePlan plan;
      REQUIRE(plan_line(arm.robot, arm.reach, req, plan) == LineStatus::ok);
      REQUIRE(plan.samples.size() > 2);
      CHECK(plan.samples.front().s == 0);
      CHECK(plan.samples.back().s == 1);
      for (std::size_t i = 1; i < plan.samples.size(); ++i) {
        CHECK(plan.samples[i].s > plan.samples[i - 1].s);
        worst = std::max(worst, arm.measured(plan.samples[i - 1].joints, plan.samples[i].joints) / step);
      }
      // Path really is the line: every sample's flange on the interpolated pose.
      for (const auto& s : plan.samples) {
        const Location f = robots::flange_pose(arm.robot, s.joints);
        CHECK((f.translation() - line_pose(req.path, s.s).translation()).norm() < 1e-6);
      }
    }
  }
  WARN("straight lines: max measured displacement / step_mm = " << worst);
  CHECK(worst <= kLineSafety);
}

TEST_CASE("straight lines: validation errors", "[sampler]") {
  const Arm arm;
  auto plan_to = [&](const JointVector& start, const Location& target, LinePlan& plan) {
    LineRequest req;
    req.path = make_line(robots::flange_pose(arm.robot, start), target);
    req.start = start;
    req.config = robots::configuration_of(arm.robot, start);
    return plan_line(arm.robot, arm.reach, req, plan);
  };
  LinePlan plan;
  // From READY: elbow and shoulder nearly singular.
  const JointVector ready = jv({0, -90, 90, 0, 0, 0});
  CHECK(plan_to(ready, trans(100, 0, -200, 0, 0, 0) * robots::flange_pose(arm.robot, ready), plan) ==
        LineStatus::singularity);
  CHECK(plan.fail_fraction < 0.05);
  // Beyond reach.
  const JointVector start = jv({0, -60, 150, 0, 40, 0});
  const Location h = robots::flange_pose(arm.robot, start);
  CHECK(plan_to(start, trans(900, 0, 0, 0, 0, 0) * h, plan) != LineStatus::ok);
  CHECK(plan.fail_fraction > 0.1);
  // Through the shoulder cylinder (line passing the J1 axis).
  Location through = h;
  through.translation() = collision::Vec3(-h.translation().x(), -h.translation().y(), h.translation().z());
  CHECK(plan_to(start, through, plan) != LineStatus::ok);
  CHECK(plan.fail_fraction > 0.2);
  CHECK(plan.fail_fraction < 0.8);
  // Down through the wrist singularity (J5 reaches 0, J4 would turn by 180 deg).
  const JointVector wrist = jv({0, -60, 150, 0, 30, 0});
  CHECK(plan_to(wrist, trans(0, 0, -300, 0, 0, 0) * robots::flange_pose(arm.robot, wrist), plan) ==
        LineStatus::singularity);
  CHECK(plan.singularity == SingularityKind::joint_jump);
  CHECK(plan.joint == 3);
}
