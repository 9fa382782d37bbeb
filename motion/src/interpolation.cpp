#include "asimov/motion/interpolation.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace asimov::motion {

robots::JointVector interpolate_joints(const robots::JointVector& from, const robots::JointVector& to, double s) {
  return from + s * (to - from);
}

double LinePath::angle_deg() const { return 2 * omega * 180 / std::numbers::pi; }

LinePath make_line(const Location& from, const Location& to) {
  LinePath p;
  p.from = from, p.to = to;
  p.q0 = Eigen::Quaterniond(from.linear()).normalized();
  p.q1 = Eigen::Quaterniond(to.linear()).normalized();
  if (p.q0.dot(p.q1) < 0) p.q1.coeffs() = -p.q1.coeffs();  // shortest arc
  p.omega = std::acos(std::clamp(p.q0.dot(p.q1), -1.0, 1.0));
  p.length = (to.translation() - from.translation()).norm();
  return p;
}

Location line_pose(const LinePath& p, double s) {
  Location t = Location::Identity();
  t.translation() = p.from.translation() + s * (p.to.translation() - p.from.translation());
  const double so = std::sin(p.omega);
  Eigen::Quaterniond q;
  if (so < 1e-9) {
    q.coeffs() = (1 - s) * p.q0.coeffs() + s * p.q1.coeffs();
  } else {
    q.coeffs() = (std::sin((1 - s) * p.omega) * p.q0.coeffs() + std::sin(s * p.omega) * p.q1.coeffs()) / so;
  }
  q.normalize();
  t.linear() = q.toRotationMatrix();
  return t;
}

}  // namespace asimov::motion
