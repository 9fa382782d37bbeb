// Straight-line timing: every joint's acceleration, curvature term included, stays within its
// limit, measured on the simulated trajectory (second differences in time of the traced poses).
#include "asimov/motion/simulator.hpp"
#include "asimov/robots/puma560.hpp"

#include "support/joints.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

using namespace asimov;
using namespace asimov::motion;
using robots::JointVector;

using asimov::test::jv;

namespace {
struct Measured {
  double accel = 0;  // largest |q''_j| / A_j over the trajectory
  double speed = 0;  // largest |q'_j| / V_j
  int joint = -1;    // joint of the largest acceleration ratio
  double duration = 0;
  std::size_t poses = 0;
};

// Runs the straight line from `start` to `target_of(here)` with tracing on and measures the joint
// speeds (secants) and accelerations (second differences over three consecutive traced poses).
template <class Target>
Measured run_line(const JointVector& start, Target target_of, double step_mm) {
  Cell c;
  c.robot = robots::puma560();
  c.start_joints = start;
  c.collision.enabled = false;
  c.collision.step_mm = step_mm;  // dense traced poses for the finite differences
  Simulator sim(std::move(c));
  sim.recorders().trace.on = true;
  const MotionResult r = sim.start_move(target_of(sim.here()), true, {}, 1);
  INFO(r.error.message << " " << r.error.detail);
  REQUIRE(r.status == MotionStatus::ok);
  REQUIRE(sim.finish_motion().status == MotionStatus::ok);
  const auto& tr = sim.recorders().trace.samples;
  const auto& robot = sim.robot();
  Measured m;
  m.duration = sim.time_s();
  m.poses = tr.size();
  for (std::size_t i = 1; i < tr.size(); ++i) {
    const double dt = tr[i].time_s - tr[i - 1].time_s;
    REQUIRE(dt > 0);
    for (int j = 0; j < 6; ++j)
      m.speed = std::max(m.speed, std::abs(tr[i].joints[j] - tr[i - 1].joints[j]) / dt / robot.max_velocity[j]);
  }
  for (std::size_t i = 1; i + 1 < tr.size(); ++i) {
    const double t0 = tr[i - 1].time_s, t1 = tr[i].time_s, t2 = tr[i + 1].time_s;
    for (int j = 0; j < 6; ++j) {
      const double v01 = (tr[i].joints[j] - tr[i - 1].joints[j]) / (t1 - t0);
      const double v12 = (tr[i + 1].joints[j] - tr[i].joints[j]) / (t2 - t1);
      const double a = std::abs(2 * (v12 - v01) / (t2 - t0)) / robot.max_acceleration[j];
      if (a > m.accel) m.accel = a, m.joint = j;
    }
  }
  return m;
}
}  // namespace

TEST_CASE("straight lines: every joint's acceleration, curvature included, stays within its limit", "[simulator][profile]") {
  // Near the wrist (J5 = 5 deg, not singular) a sideways line swings J4 and J6 through a sharp
  // turn: d2q/dsigma2 is large while the tool moves steadily. Timed from the joint speeds and
  // the profile's sigma'' alone (before fit_path_acceleration), J6 reached 1.31 of its limit.
  const auto sideways = [](const Location& here) { return trans(0, 60, 0, 0, 0, 0) * here; };
  const Measured wrist = run_line(jv({0, -60, 150, 0, 5, 0}), sideways, 0.05);
  WARN("wrist-near line: " << wrist.duration << " s, " << wrist.poses << " poses, worst joint acceleration "
                           << wrist.accel << " of its limit (J" << wrist.joint + 1 << "), worst speed " << wrist.speed);
  CHECK(wrist.accel <= 1.0 + 1e-6);
  CHECK(wrist.speed <= 1.0 + 1e-9);
  CHECK(wrist.accel > 0.7);  // the acceleration bound is what binds here, and not loosely
  // The same arm moving along x: J3's curvature term (1.085 of the limit before).
  const auto forward = [](const Location& here) { return trans(60, 0, 0, 0, 0, 0) * here; };
  const Measured elbow = run_line(jv({0, -60, 150, 0, 5, 0}), forward, 0.05);
  WARN("forward line: " << elbow.duration << " s, " << elbow.poses << " poses, worst joint acceleration "
                        << elbow.accel << " (J" << elbow.joint + 1 << "), worst speed " << elbow.speed);
  CHECK(elbow.accel <= 1.0 + 1e-6);
  CHECK(elbow.speed <= 1.0 + 1e-9);
  CHECK(elbow.accel > 0.7);
}
