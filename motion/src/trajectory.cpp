// The exact path of a planned motion at time t (docs/kinematics.md §7-§8).
#include "asimov/motion/trajectory.hpp"

#include "asimov/robots/ik.hpp"

#include <algorithm>

namespace asimov::motion {

robots::JointVector joint_path_at(const Trajectory& tr, double t) {
  return interpolate_joints(tr.from, tr.to, tr.profile.sigma(t - tr.t0));
}

LinePoint line_path_at(const robots::Robot& robot, const Trajectory& tr, const LineSample& a, const LineSample& b,
                       double t, const robots::JointVector& seed) {
  const double sigma = std::clamp(tr.profile.sigma(t - tr.t0), a.s, b.s);
  const robots::JointVector lin = interpolate_joints(a.joints, b.joints, b.s > a.s ? (sigma - a.s) / (b.s - a.s) : 1.0);
  const Location flange = tr.base_inv * line_pose(tr.path, sigma) * tr.tool_inv;
  const robots::IkResult ik = robots::solve_ik(robot, flange, seed, tr.config, false);
  const bool ik_used = ik.status == robots::IkStatus::ok && (ik.joints - lin).cwiseAbs().maxCoeff() <= kMaxJointJumpDeg;
  return {ik_used ? ik.joints : lin, flange, ik_used};
}

LinePoint line_path_between(const robots::Robot& robot, const Trajectory& tr, std::size_t i, std::size_t j, double t,
                            const robots::JointVector* seed) {
  const auto& samples = tr.line.samples;
  const double sigma = std::clamp(tr.profile.sigma(t - tr.t0), samples[i].s, samples[j].s);
  const auto next = std::upper_bound(samples.begin() + static_cast<std::ptrdiff_t>(i) + 1,
                                     samples.begin() + static_cast<std::ptrdiff_t>(j), sigma,
                                     [](double v, const LineSample& x) { return v < x.s; });
  return line_path_at(robot, tr, *(next - 1), *next, t, seed ? *seed : (next - 1)->joints);
}

}  // namespace asimov::motion
