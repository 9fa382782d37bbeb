#include "robots/robot.hpp"

#include <cmath>
#include <numbers>

namespace asimov::robots {
namespace {
constexpr double kDeg = std::numbers::pi / 180;

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
}  // namespace

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

Pose flange_pose(const Robot& robot, const JointVector& display) {
  const JointVector q = display_to_dh(robot, display);
  Pose t = Pose::Identity();
  for (std::size_t k = 0; k < robot.dh.size(); ++k) t = t * dh_transform(robot.dh[k], q[static_cast<Eigen::Index>(k)]);
  return t;
}

int first_limit_violation(const Robot& robot, const JointVector& display) {
  for (Eigen::Index i = 0; i < display.size(); ++i)
    if (display[i] < robot.lower[i] || display[i] > robot.upper[i]) return static_cast<int>(i);
  return -1;
}

}  // namespace asimov::robots
