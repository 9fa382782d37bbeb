// Closed form or numeric IK, by the arm's geometry.
#include "asimov/robots/ik.hpp"

#include "asimov/robots/ik_scara.hpp"
#include "asimov/robots/ik_spherical.hpp"
#include "asimov/robots/ik_viper.hpp"
#include "ik_family.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace asimov::robots {
namespace {
constexpr double kFkPositionTol = 1e-6;  // [mm], as solve_puma
constexpr double kFkRotationTol = 1e-9;  // [rad]

// 2pi-equivalent of v [deg] nearest `near` inside [lo, hi]; false if none.
bool nearest_in_range(double v, double near, double lo, double hi, double& out) {
  const double k0 = std::round((near - v) / 360.0);
  double best = std::numeric_limits<double>::infinity();
  for (int dk = -2; dk <= 2; ++dk) {
    const double c = v + 360.0 * (k0 + dk);
    if (c < lo - 1e-9 || c > hi + 1e-9 || std::abs(c - near) >= best) continue;
    best = std::abs(c - near), out = std::clamp(c, lo, hi);
  }
  return best < std::numeric_limits<double>::infinity();
}

// Closed form for a chain arm with a spherical wrist: the solution in configuration `want`
// nearest `current` within limits (FLIP / NOFLIP merge at the wrist singularity), the last
// revolute joint in (-180, 180] when `single`. Returns false when the geometry does not apply or
// the FK check fails (then numeric).
bool solve_spherical(const Robot& robot, const Pose& flange, const JointVector& current, const Configuration& want,
                     bool single, IkResult& res) {
  SphericalWristModel model;
  if (current.size() != 6 || !spherical_wrist_model(robot, model)) return false;
  const JointVector cur_internal = display_to_dh(robot, current);
  SphericalIkSolutions sols;
  spherical_ik_all(model, flange, cur_internal[3], sols, &want);
  if (sols.count == 0) {
    res.status = IkStatus::out_of_reach;
    return true;
  }
  double best = std::numeric_limits<double>::infinity(), best_bad = best;
  JointVector pick;
  bool any = false;
  const int last = single ? last_revolute_joint(robot) : -1;
  for (int k = 0; k < sols.count; ++k) {
    const JointVector raw = dh_to_display(robot, sols.q[static_cast<std::size_t>(k)]);
    const auto slot = static_cast<std::size_t>(k);
    if (sols.righty[slot] != want.righty || sols.above[slot] != want.above) continue;
    if (!sols.wrist_singular[slot] && (raw[4] >= 0) != want.noflip) continue;
    any = true;
    JointVector sol(6);
    int bad = -1;
    double bad_value = 0;
    for (int i = 0; i < 6 && bad < 0; ++i) {
      if (i == last) {  // SINGLE
        sol[i] = wrap_deg(raw[i]);
        if (sol[i] < limit_low(robot, i) - 1e-9 || sol[i] > limit_high(robot, i) + 1e-9) bad = i, bad_value = sol[i];
      } else if (sols.wrist_singular[static_cast<std::size_t>(k)] && i == 3) {
        sol[i] = current[3];  // kept exactly at the wrist singularity
        if (sol[i] < limit_low(robot, i) - 1e-9 || sol[i] > limit_high(robot, i) + 1e-9) bad = i, bad_value = sol[i];
      } else if (!nearest_in_range(raw[i], current[i], limit_low(robot, i), limit_high(robot, i), sol[i])) {
        bad = i, bad_value = raw[i] + 360.0 * std::round((current[i] - raw[i]) / 360.0);
      }
    }
    if (bad >= 0) {
      const double dist = (raw - current).squaredNorm();
      if (dist < best_bad) best_bad = dist, res.joint = bad, res.value = bad_value;
      continue;
    }
    const double dist = (sol - current).squaredNorm();
    if (dist < best) best = dist, pick = sol;
  }
  if (!any) {  // the requested configuration does not reach the pose (as solve_puma)
    res.status = IkStatus::out_of_reach;
    return true;
  }
  if (!(best < std::numeric_limits<double>::infinity())) {
    res.status = IkStatus::joint_limit;
    return true;
  }
  double ep, er;
  pose_error(robot, pick, flange, ep, er);
  if (!(ep <= kFkPositionTol && er <= kFkRotationTol)) return false;
  res.status = IkStatus::ok;
  res.joints = pick;
  return true;
}
}  // namespace

const IkFamily* ik_family_of(const Robot& robot) {
  if (has_coupled_joints(robot)) return nullptr;  // the closed forms know no coupled joints: numeric
#define ASIMOV_IK_FAMILY(NAME) &NAME##_family,
  static constexpr const IkFamily* kFamilies[] = {
#include "arm_families.def"
  };
  for (const IkFamily* f : kFamilies)
    if (f->matches(robot)) return f;
  return nullptr;
}

std::optional<ReachMargins> reach_margins(const Robot& robot, const Vec3& flange_position) {
  const IkFamily* f = ik_family_of(robot);
  if (f == nullptr || f->margins == nullptr) return std::nullopt;
  return f->margins(robot, flange_position);
}

int last_revolute_joint(const Robot& robot) {
  for (int i = robot.joint_count() - 1; i >= 0; --i)
    if (!robot.prismatic(i)) return i;
  return -1;
}

IkResult solve_ik(const Robot& robot, const Pose& flange, const JointVector& current, const Configuration& want,
                  bool single, const NumericIkOptions& options) {
  if (const IkFamily* f = ik_family_of(robot)) return f->solve(robot, flange, current, want, single);
  IkResult res;
  if (solve_spherical(robot, flange, current, want, single, res)) return res;
  const NumericIkResult num = solve_numeric(robot, flange, current, options);
  if (num.success) {
    res.joints = num.joints;
    const int last = single ? last_revolute_joint(robot) : -1;
    for (int i = 0; i < res.joints.size(); ++i) {
      if (i == last) {  // SINGLE: (-180, 180], as the PUMA's J6
        const double v = wrap_deg(res.joints[i]);
        if (v < limit_low(robot, i) - 1e-9 || v > limit_high(robot, i) + 1e-9) {
          res.status = IkStatus::joint_limit;
          res.joint = i;
          res.value = v;
          res.joints = JointVector();
          return res;
        }
        res.joints[i] = std::clamp(v, limit_low(robot, i), limit_high(robot, i));
        continue;
      }
      // Otherwise the 2pi-equivalent nearest the current value.
      if (robot.prismatic(i) || current.size() != res.joints.size()) continue;
      const double v = res.joints[i] + 360.0 * std::round((current[i] - res.joints[i]) / 360.0);
      if (v >= limit_low(robot, i) && v <= limit_high(robot, i)) res.joints[i] = v;
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
    if (v < limit_low(robot, i) || v > limit_high(robot, i)) {
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
