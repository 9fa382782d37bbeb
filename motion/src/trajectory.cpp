// The exact path of a planned motion at time t (docs/kinematics.md §7-§8).
#include "asimov/motion/trajectory.hpp"

#include "asimov/robots/ik_redundant.hpp"

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
  const robots::IkResult ik = robots::solve_line_ik(robot, flange, seed, tr.line.samples.front().joints, tr.config);
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

std::size_t sample_before(const std::vector<LineSample>& samples, double sigma) {
  if (samples.size() < 2) return 0;
  const auto next = std::upper_bound(samples.begin() + 1, samples.end() - 1, sigma,
                                     [](double v, const LineSample& x) { return v < x.s; });
  return static_cast<std::size_t>(next - samples.begin()) - 1;
}

namespace {

robots::JointVector line_joints(const std::vector<LineSample>& samples, double sigma) {
  if (samples.size() < 2) return samples.front().joints;
  const std::size_t i = sample_before(samples, sigma);
  const LineSample &a = samples[i], &b = samples[i + 1];
  return interpolate_joints(a.joints, b.joints, b.s > a.s ? std::clamp((sigma - a.s) / (b.s - a.s), 0.0, 1.0) : 1.0);
}
}  // namespace

robots::JointVector segment_joints_at(const Trajectory& tr, double t) {
  if (tr.kind == PathKind::joint) return joint_path_at(tr, t);
  return line_joints(tr.line.samples, tr.profile.sigma(t - tr.t0));
}

robots::JointVector segment_travel(const Trajectory& tr, double t1, double t2) {
  if (tr.kind == PathKind::joint || tr.line.samples.size() < 2)
    return (segment_joints_at(tr, t2) - segment_joints_at(tr, t1)).cwiseAbs();
  // Piecewise linear between samples: the sum of the pieces crossed.
  const auto& samples = tr.line.samples;
  const double s1 = tr.profile.sigma(t1 - tr.t0), s2 = tr.profile.sigma(t2 - tr.t0);
  const std::size_t i1 = sample_before(samples, s1), i2 = sample_before(samples, s2);
  if (i1 == i2) return (line_joints(samples, s2) - line_joints(samples, s1)).cwiseAbs();
  robots::JointVector sum = (samples[i1 + 1].joints - line_joints(samples, s1)).cwiseAbs();
  for (std::size_t i = i1 + 1; i < i2; ++i) sum += (samples[i + 1].joints - samples[i].joints).cwiseAbs();
  sum += (line_joints(samples, s2) - samples[i2].joints).cwiseAbs();
  return sum;
}

robots::JointVector blended_joints_at(const Trajectory& tr, double t) {
  if (!tr.previous) return segment_joints_at(tr, t);
  return segment_joints_at(*tr.previous, t) + segment_joints_at(tr, t) - tr.previous->to;
}

robots::JointVector blended_travel(const Trajectory& tr, double t1, double t2) {
  if (!tr.previous) return segment_travel(tr, t1, t2);
  return segment_travel(*tr.previous, t1, t2) + segment_travel(tr, t1, t2);
}

}  // namespace asimov::motion
