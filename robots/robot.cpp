// Serial-arm basics: the display <-> DH mapping (the only place that converts), standard-DH
// forward kinematics, link frames and the limit check.
#include "robots/robot.hpp"

#include <cmath>
#include <numbers>

namespace asimov::robots {
namespace {
constexpr double kDeg = std::numbers::pi / 180;
// Rounding slack of the limit check [deg]: IK results computed exactly on a limit pass.
constexpr double kLimitSlack = 1e-9;
}  // namespace

Pose dh_transform(const DhLink& l, double theta) {
  const double ct = std::cos(theta), st = std::sin(theta);
  const double ca = std::cos(l.alpha), sa = std::sin(l.alpha);
  Pose t = Pose::Identity();
  t.matrix() << ct, -st * ca, st * sa, l.a * ct,  //
      st, ct * ca, -ct * sa, l.a * st,            //
      0, sa, ca, l.d,                             //
      0, 0, 0, 1;
  return t;
}

double wrap_deg(double deg) {
  double w = std::remainder(deg, 360.0);  // [-180, 180]
  if (w <= -180) w += 360;
  return w;
}

JointVector display_to_dh(const Robot& robot, const JointVector& display) {
  JointVector q(display.size());
  for (Eigen::Index i = 0; i < display.size(); ++i) {
    const auto& m = robot.mapping[static_cast<std::size_t>(i)];
    q[i] = m.sign * display[i] * kDeg + m.offset;
  }
  return q;
}

JointVector dh_to_display(const Robot& robot, const JointVector& dh) {
  JointVector d(dh.size());
  for (Eigen::Index i = 0; i < dh.size(); ++i) {
    const auto& m = robot.mapping[static_cast<std::size_t>(i)];
    d[i] = (dh[i] - m.offset) / kDeg * m.sign;
  }
  return d;
}

void link_frames(const Robot& robot, const JointVector& display, std::vector<Pose>& frames) {
  const JointVector q = display_to_dh(robot, display);
  frames.resize(robot.dh.size() + 1);
  frames[0] = Pose::Identity();
  for (std::size_t k = 0; k < robot.dh.size(); ++k)
    frames[k + 1] = frames[k] * dh_transform(robot.dh[k], q[static_cast<Eigen::Index>(k)]);
}

Pose flange_pose_dh(const Robot& robot, const JointVector& q) {
  Pose t = Pose::Identity();
  for (std::size_t k = 0; k < robot.dh.size(); ++k)
    t = t * dh_transform(robot.dh[k], q[static_cast<Eigen::Index>(k)]);
  return t;
}

Pose flange_pose(const Robot& robot, const JointVector& display) {
  return flange_pose_dh(robot, display_to_dh(robot, display));
}

int first_limit_violation(const Robot& robot, const JointVector& display) {
  for (Eigen::Index i = 0; i < display.size(); ++i)  // written so that NaN fails
    if (!(display[i] >= robot.lower[i] - kLimitSlack && display[i] <= robot.upper[i] + kLimitSlack))
      return static_cast<int>(i);
  return -1;
}

}  // namespace asimov::robots
