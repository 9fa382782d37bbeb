// Motion-instruction targets (dialect §5).
#include "asimov/motion/targets.hpp"

#include <Eigen/Geometry>

#include <cmath>

namespace asimov::motion {

Location appro_target(const Location& loc, double d) { return loc * trans(0, 0, -d, 0, 0, 0); }

Location depart_target(const Location& here, double d) { return here * trans(0, 0, -d, 0, 0, 0); }

Location draw_target(const Location& here, double dx, double dy, double dz) {
  Location t = here;
  t.translation() += collision::Vec3(dx, dy, dz);
  return t;
}

Location align_target(const Location& here) {
  const collision::Vec3 z = here.linear().col(2);
  // Largest |component|; ties go to Z, then X, then Y.
  int axis = 2;
  if (std::abs(z.x()) > std::abs(z[axis])) axis = 0;
  if (std::abs(z.y()) > std::abs(z[axis])) axis = 1;
  collision::Vec3 goal = collision::Vec3::Zero();
  goal[axis] = z[axis] >= 0 ? 1 : -1;
  const collision::Vec3 c = z.cross(goal);
  const double angle = std::atan2(c.norm(), z.dot(goal));  // < 90 deg: the axis is the nearest
  Location t = here;
  if (c.norm() > 0) t.linear() = Eigen::AngleAxisd(angle, c.normalized()).toRotationMatrix() * here.linear();
  t.linear().col(2) = goal;  // exact
  t.linear().col(0) -= goal * goal.dot(t.linear().col(0));
  t.linear().col(0).normalize();
  t.linear().col(1) = goal.cross(t.linear().col(0));
  return t;
}

robots::JointVector ready_target(const robots::Robot& robot) { return robots::ready_joints(robot); }

bool drive_target(const robots::JointVector& current, int joint, double change, robots::JointVector& out) {
  if (joint < 1 || joint > current.size() || !std::isfinite(change)) return false;
  out = current;
  out[joint - 1] += change;
  return true;
}

SpeedSettings drive_speed(double monitor_pct, double speed_pct) {
  SpeedSettings s;
  s.monitor = monitor_pct;
  s.program = speed_pct > 0 && speed_pct <= 100 ? speed_pct : 0;
  return s;
}

HandState movet_hand(double h) { return h != 0 ? HandState::open : HandState::closed; }

}  // namespace asimov::motion
