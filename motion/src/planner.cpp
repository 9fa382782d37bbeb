// Motion planning (dialect §5, docs/kinematics.md §7-§8, docs/collision-method.md §6.3).
#include "asimov/motion/planner.hpp"

#include "asimov/robots/ik.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

namespace asimov::motion {
namespace {
using robots::JointVector;

Plan refused(const char* message, std::string detail = {}) {
  Plan p;
  p.result.status = MotionStatus::error;
  p.result.error.message = message;
  p.result.error.detail = std::move(detail);
  return p;
}

std::string fmt_limit(const robots::Robot& robot, int j, double v) {
  char buf[96];
  const double lo = robot.lower[j], hi = robot.upper[j];
  if (v > hi)
    std::snprintf(buf, sizeof buf, "J%d = %.3f > %.3f", j + 1, v, hi);
  else
    std::snprintf(buf, sizeof buf, "J%d = %.3f < %.3f", j + 1, v, lo);
  return buf;
}

std::string fmt_fraction(const char* what, double s) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "%s at %.1f %% of the path", what, 100 * s);
  return buf;
}

double speed_factor(const SpeedSettings& s) { return s.monitor / 100 * s.program / 100; }
Ramps ramps(const SpeedSettings& s) { return {s.accel / 100, s.decel / 100}; }
bool valid_ramps(const SpeedSettings& s) { return s.accel > 0 && s.accel <= 100 && s.decel > 0 && s.decel <= 100; }

Location here_at(const PlanStart& st, const JointVector& q) { return st.base * robots::flange_pose(st.robot, q) * st.tool; }

// The joint move, validated: one profile over the joints, the grid from the step rule.
Trajectory joint_trajectory(const PlanStart& st, const JointVector& target, const SpeedSettings& speed, int step) {
  const auto& robot = st.robot;
  const double f = speed_factor(speed);
  std::array<ProfileAxis, robots::kMaxJoints> axes{};
  for (int i = 0; i < robot.joint_count(); ++i)
    axes[static_cast<std::size_t>(i)] = {std::abs(target[i] - st.joints[i]), robot.max_velocity[i] * f,
                                         robot.max_acceleration[i]};
  Trajectory tr;
  tr.kind = PathKind::joint;
  tr.from = st.joints;
  tr.to = target;
  tr.intervals = joint_move_intervals(st.reach, st.joints, target, st.step_mm, st.moving_pairs);
  tr.profile = plan_profile(std::span(axes.data(), static_cast<std::size_t>(robot.joint_count())), speed.duration_s, ramps(speed));
  tr.speed = speed;
  tr.t0 = st.time_s;
  tr.step = step;
  tr.target = here_at(st, target);
  return tr;
}

// Straight-line profile. Axes: tool translation and rotation, and every joint with
// "distance" max |dq_j / dsigma| along the solved samples, so that its speed S_j * sigma'(t)
// stays within V_j; then the profile is stretched until every joint's acceleration
// d2q/dsigma2 * sigma'^2 + dq/dsigma * sigma'' (curvature + profile) stays within A_j
// (fit_path_acceleration).
Profile line_profile(const robots::Robot& robot, const LinePath& path, const LinePlan& plan, const SpeedSettings& speed) {
  const double f = speed_factor(speed);
  const double fr = (speed.rotation < 0 ? speed.program : speed.rotation) / 100 * speed.monitor / 100;
  std::array<ProfileAxis, 2 + robots::kMaxJoints> axes{};
  axes[0] = {path.length, robot.max_tool_speed * f, robot.max_tool_accel};
  axes[1] = {path.angle_deg(), robot.max_tool_rot_speed * fr, robot.max_tool_rot_accel};
  const int n = robot.joint_count();
  for (int j = 0; j < n; ++j) {
    double slope = 0;
    for (std::size_t i = 1; i < plan.samples.size(); ++i) {
      const double ds = plan.samples[i].s - plan.samples[i - 1].s;
      if (ds > 0) slope = std::max(slope, std::abs(plan.samples[i].joints[j] - plan.samples[i - 1].joints[j]) / ds);
    }
    axes[static_cast<std::size_t>(2 + j)] = {slope, robot.max_velocity[j] * f, robot.max_acceleration[j]};
  }
  std::vector<double> path_s(plan.samples.size()), path_q(plan.samples.size() * static_cast<std::size_t>(n));
  for (std::size_t i = 0; i < plan.samples.size(); ++i) {
    path_s[i] = plan.samples[i].s;
    for (int j = 0; j < n; ++j) path_q[i * static_cast<std::size_t>(n) + static_cast<std::size_t>(j)] = plan.samples[i].joints[j];
  }
  return fit_path_acceleration(plan_profile(std::span(axes.data(), static_cast<std::size_t>(2 + n)), speed.duration_s, ramps(speed)),
                               {path_s, path_q, n}, std::span(robot.max_acceleration.data(), static_cast<std::size_t>(n)));
}

Plan plan_line_move(const PlanStart& st, const Location& target, const SpeedSettings& speed, int step) {
  const auto& robot = st.robot;
  LineRequest req;
  req.path = make_line(here_at(st, st.joints), target);
  req.base = st.base;
  req.tool = st.tool;
  req.start = st.joints;
  req.config = robots::configuration_of(robot, st.joints);
  req.step_mm = st.step_mm;
  req.pairs = st.moving_pairs;
  LinePlan line;
  const LineStatus planned = plan_line(robot, st.reach, req, line);
  Plan p;
  switch (planned) {
    case LineStatus::ok: break;
    case LineStatus::out_of_reach: p = refused("*Location out of reach*", fmt_fraction("no solution", line.fail_fraction)); break;
    case LineStatus::joint_limit:
      p = refused("*Joint limit exceeded*",
                  fmt_limit(robot, line.joint, line.value) + ", " + fmt_fraction("", line.fail_fraction).substr(1));
      break;
    case LineStatus::singularity: {
      const char* what = line.singularity == SingularityKind::shoulder     ? "shoulder"
                         : line.singularity == SingularityKind::elbow      ? "elbow"
                         : line.singularity == SingularityKind::joint_jump ? "joint jump"
                                                                           : "unresolved step";
      std::string detail = fmt_fraction(what, line.fail_fraction);
      // Singular where the line starts (the PUMA at READY: elbow straight): no straight line can
      // leave that pose, a joint move can. Learners meet this on their first MOVES.
      if (line.fail_fraction < 0.0005) detail += "; the start pose is singular: MOVE (joint-interpolated) away from it first";
      p = refused("*Singularity on straight-line path*", detail);
      break;
    }
  }
  p.ik_residual = line.ik_residual;
  p.ik_solves = line.ik_solves;
  if (planned != LineStatus::ok) return p;
  Trajectory& tr = p.trajectory;
  tr.kind = PathKind::line;
  tr.profile = line_profile(robot, req.path, line, speed);
  tr.from = st.joints;
  tr.to = line.samples.back().joints;
  tr.line = std::move(line);
  tr.path = req.path;
  tr.base_inv = st.base.inverse();
  tr.tool_inv = st.tool.inverse();
  tr.base = st.base;
  tr.tool = st.tool;
  tr.config = req.config;
  tr.speed = speed;
  tr.t0 = st.time_s;
  tr.step = step;
  tr.target = target;
  return p;
}
}  // namespace

Plan plan_joint_move(const PlanStart& st, const JointVector& target, const SpeedSettings& speed, int step) {
  if (!(speed_factor(speed) > 0)) return refused("*Illegal value*", "speed must be > 0");
  if (!valid_ramps(speed)) return refused("*Illegal value*", "ACCEL must be in (0, 100]");
  if (target.size() != st.robot.joint_count()) return refused("*Illegal value*", "wrong number of joints");
  if (const int j = robots::first_limit_violation(st.robot, target); j >= 0)
    return refused("*Joint limit exceeded*", fmt_limit(st.robot, j, target[j]));
  Plan p;
  p.trajectory = joint_trajectory(st, target, speed, step);
  return p;
}

Plan plan_move(const PlanStart& st, robots::ConfigurationRequest& request, const Location& target, bool straight,
               const SpeedSettings& speed, int step) {
  if (!(speed_factor(speed) > 0)) return refused("*Illegal value*", "speed must be > 0");
  if (!valid_ramps(speed)) return refused("*Illegal value*", "ACCEL must be in (0, 100]");
  if (straight) return plan_line_move(st, target, speed, step);
  const auto& robot = st.robot;
  const Location flange = st.base.inverse() * target * st.tool.inverse();
  const robots::Configuration want = robots::requested_configuration(robots::configuration_of(robot, st.joints), request);
  const robots::IkResult ik = robots::solve_ik(robot, flange, st.joints, want, request.single);
  if (ik.status == robots::IkStatus::out_of_reach) return refused("*Location out of reach*");
  if (ik.status == robots::IkStatus::joint_limit) return refused("*Joint limit exceeded*", fmt_limit(robot, ik.joint, ik.value));
  Plan p;
  p.ik_residual = pose_error(robots::flange_pose(robot, ik.joints), flange);
  p.ik_solves = 1;
  request.righty = request.above = request.noflip = -1;  // consumed by this motion
  p.trajectory = joint_trajectory(st, ik.joints, speed, step);
  p.trajectory.target = target;
  return p;
}

int inrange(const PlanStart& st, const robots::ConfigurationRequest& request, const Location& target) {
  const auto& robot = st.robot;
  const Location flange = st.base.inverse() * target * st.tool.inverse();
  const robots::Configuration want = robots::requested_configuration(robots::configuration_of(robot, st.joints), request);
  const robots::IkResult ik = robots::solve_ik(robot, flange, st.joints, want, request.single);
  return ik.status == robots::IkStatus::ok ? 0 : ik.status == robots::IkStatus::out_of_reach ? 1 : 2;
}

}  // namespace asimov::motion
