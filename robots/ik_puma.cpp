// Closed-form PUMA IK, kinematics.md §5. Geometry constants are read from the robot's DH table
// (a2 = dh[1].a, d3 = dh[2].d, a3 = dh[2].a, d4 = dh[3].d), so scaled PUMA-type arms work too.
#include "robots/ik_puma.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace asimov::robots {
namespace {
constexpr double kPi = std::numbers::pi;
constexpr double kWristSingular = 1e-10;  // m = |(M13, M23)| below this: theta5 = 0
constexpr double kReachSlack = 1e-12;     // |c| up to 1 + this is clamped (rounding at full stretch)
constexpr double kFkPositionTol = 1e-6;   // [mm] FK acceptance of a solution
constexpr double kFkRotationTol = 1e-9;   // Frobenius norm of the rotation difference

double wrap_rad(double a) {
  double w = std::remainder(a, 2 * kPi);
  if (w <= -kPi) w += 2 * kPi;
  return w;
}

// Nearest 2pi-equivalent (display degrees) of v to `near` inside [lo, hi]; false if none.
bool nearest_equivalent(double v, double near, double lo, double hi, double& out) {
  const double k0 = std::round((near - v) / 360.0);
  double best = std::numeric_limits<double>::infinity();
  bool found = false;
  for (int dk = -2; dk <= 2; ++dk) {
    const double c = v + 360.0 * (k0 + dk);
    if (c < lo - 1e-9 || c > hi + 1e-9) continue;
    if (std::abs(c - near) < best) best = std::abs(c - near), out = std::clamp(c, lo, hi), found = true;
  }
  return found;
}
}  // namespace

std::pair<double, double> fk_error(const Robot& robot, const JointVector& dh, const Pose& target) {
  const Pose f = flange_pose_dh(robot, dh);
  return {(f.translation() - target.translation()).norm(), (f.linear() - target.linear()).norm()};
}

IkStatus puma_ik_all(const Robot& robot, const Pose& flange, double theta4_keep, IkCandidates& out) {
  const double a2 = robot.dh[1].a, d3 = robot.dh[2].d, a3 = robot.dh[2].a, d4 = robot.dh[3].d;
  for (auto& c : out) c.valid = false;
  const Vec3 p = flange.translation();
  const double r = std::hypot(p.x(), p.y());
  if (r < d3 || r == 0) return IkStatus::out_of_reach;  // inside the shoulder cylinder
  const double phi = std::atan2(p.y(), p.x());
  const double alpha = std::asin(std::min(1.0, d3 / r));
  const double rho2 = r * r - d3 * d3 + p.z() * p.z();  // V^2 + pz^2 (same for both shoulders)
  const double rho = std::sqrt(rho2);
  if (rho == 0) return IkStatus::out_of_reach;
  double c = (a2 * a2 - d4 * d4 - a3 * a3 + rho2) / (2 * a2 * rho);
  if (std::abs(c) > 1 + kReachSlack) return IkStatus::out_of_reach;
  c = std::clamp(c, -1.0, 1.0);
  const double psi = std::acos(c);
  JointVector dh(6);
  for (int shoulder = 0; shoulder < 2; ++shoulder) {
    const double ss = shoulder == 0 ? 1 : -1;  // sigma_s: +1 RIGHTY
    const double t1 = wrap_rad(shoulder == 0 ? phi + alpha : phi + kPi - alpha);
    const double V = p.x() * std::cos(t1) + p.y() * std::sin(t1);
    for (int elbow = 0; elbow < 2; ++elbow) {
      const double se = elbow == 0 ? 1 : -1;  // sigma_e: +1 ABOVE
      const double t2 = wrap_rad(std::atan2(p.z(), V) + ss * se * psi);
      const double u = V * std::cos(t2) + p.z() * std::sin(t2) - a2;
      const double w = p.z() * std::cos(t2) - V * std::sin(t2);
      const double t3 = wrap_rad(std::atan2(a3, d4) - std::atan2(u, w));
      dh << t1, t2, t3, 0, 0, 0;
      const Pose a03 = dh_transform(robot.dh[0], t1) * dh_transform(robot.dh[1], t2) * dh_transform(robot.dh[2], t3);
      const collision::Mat3 m = a03.linear().transpose() * flange.linear();
      const double mm = std::hypot(m(0, 2), m(1, 2));
      const bool singular = mm <= kWristSingular;
      for (int flip = 0; flip < 2; ++flip) {
        double t4, t5, t6;
        if (singular) {
          t4 = theta4_keep, t5 = 0, t6 = wrap_rad(std::atan2(m(1, 0), m(0, 0)) - t4);
        } else {
          t4 = std::atan2(m(1, 2), m(0, 2));
          t5 = -std::atan2(mm, m(2, 2));
          t6 = std::atan2(m(2, 1), -m(2, 0));
          if (flip == 1) t4 = wrap_rad(t4 + kPi), t5 = -t5, t6 = wrap_rad(t6 + kPi);
        }
        IkCandidate& cand = out[static_cast<std::size_t>(4 * shoulder + 2 * elbow + flip)];
        cand.dh = dh;
        cand.dh[3] = t4, cand.dh[4] = t5, cand.dh[5] = t6;
        cand.wrist_singular = singular;
        cand.config.righty = shoulder == 0;
        cand.config.above = elbow == 0;
        const double j5 = robot.mapping[4].sign * (t5 - robot.mapping[4].offset);
        cand.config.noflip = j5 >= 0;
        cand.valid = true;
      }
    }
  }
  return IkStatus::ok;
}

IkResult solve_puma(const Robot& robot, const Pose& flange, const JointVector& current_in,
                    const Configuration& want, bool single) {
  IkResult res;
  JointVector current = current_in;
  if (current.size() != 6) current = JointVector::Zero(6);
  const JointVector current_dh = display_to_dh(robot, current);
  IkCandidates cands;
  if (puma_ik_all(robot, flange, current_dh[3], cands) != IkStatus::ok) {
    res.status = IkStatus::out_of_reach;
    return res;
  }
  const IkCandidate* pick = nullptr;
  for (const auto& c : cands) {
    if (!c.valid || c.config.righty != want.righty || c.config.above != want.above) continue;
    if (c.wrist_singular || c.config.noflip == want.noflip) { pick = &c; break; }
  }
  if (!pick) {
    res.status = IkStatus::out_of_reach;
    return res;
  }
  const JointVector raw = dh_to_display(robot, pick->dh);
  JointVector sol(6);
  for (int i = 0; i < 6; ++i) {
    double v = raw[i];
    bool ok;
    if (i == 5 && single) {
      v = wrap_deg(v);
      ok = v >= robot.lower[i] - 1e-9 && v <= robot.upper[i] + 1e-9;
    } else if (pick->wrist_singular && i == 3) {
      v = current[3];  // kept exactly at the wrist singularity
      ok = v >= robot.lower[i] - 1e-9 && v <= robot.upper[i] + 1e-9;
    } else {
      ok = nearest_equivalent(v, current[i], robot.lower[i], robot.upper[i], v);
      if (!ok) v = raw[i] + 360.0 * std::round((current[i] - raw[i]) / 360.0);
    }
    if (!ok) {
      res.status = IkStatus::joint_limit;
      res.joint = i;
      res.value = v;
      return res;
    }
    sol[i] = v;
  }
  const auto [ep, er] = fk_error(robot, display_to_dh(robot, sol), flange);
  if (!(ep <= kFkPositionTol && er <= kFkRotationTol)) {
    res.status = IkStatus::out_of_reach;
    return res;
  }
  res.joints = sol;
  return res;
}

}  // namespace asimov::robots
