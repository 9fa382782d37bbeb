// Closed form or numeric IK, by the arm's geometry.
#include "robots/ik.hpp"

#include <cmath>

namespace asimov::robots {

IkResult solve_ik(const Robot& robot, const Pose& flange, const JointVector& current, const Configuration& want,
                  bool single, const NumericIkOptions& options) {
  if (is_puma_type(robot)) return solve_puma(robot, flange, current, want, single);
  IkResult res;
  const NumericIkResult num = solve_numeric(robot, flange, current, options);
  if (num.success) {
    res.joints = num.joints;
    for (int i = 0; i < res.joints.size(); ++i) {  // nearest 2pi-equivalent to the current value
      if (robot.prismatic(i) || current.size() != res.joints.size()) continue;
      const double v = res.joints[i] + 360.0 * std::round((current[i] - res.joints[i]) / 360.0);
      if (v >= robot.lower[i] && v <= robot.upper[i]) res.joints[i] = v;
    }
    return res;
  }
  NumericIkOptions free = options;
  free.respect_limits = false;
  const NumericIkResult unlimited = solve_numeric(robot, flange, current, free);
  if (!unlimited.success) {
    res.status = IkStatus::out_of_reach;
    return res;
  }
  for (int i = 0; i < unlimited.joints.size(); ++i) {
    double v = unlimited.joints[i];
    if (!robot.prismatic(i)) v = wrap_deg(v);  // report the equivalent nearest the range
    if (v < robot.lower[i] || v > robot.upper[i]) {
      res.status = IkStatus::joint_limit;
      res.joint = i;
      res.value = v;
      return res;
    }
  }
  res.status = IkStatus::joint_limit;  // every equivalent found is in range, but none converged within
  res.joint = 0;
  res.value = unlimited.joints[0];
  return res;
}

}  // namespace asimov::robots
