// Closed-form PUMA IK, kinematics.md §5. Geometry constants are read from the robot's DH table
// (a2 = dh[1].a, d3 = dh[2].d, a3 = dh[2].a, d4 = dh[3].d), so scaled PUMA-type arms work too.
#include "robots/ik_puma.hpp"

#include <algorithm>
#include <array>
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
  if (a > -kPi && a <= kPi) return a;  // the common case, exact
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

namespace {
// Pose-level quantities shared by the four arm branches.
struct ArmGeometry {
  double d3 = 0, a2 = 0, a3 = 0, d4 = 0;
  Vec3 p;
  double phi = 0, alpha = 0, psi = 0;
};

IkStatus arm_geometry(const Robot& robot, const Pose& flange, ArmGeometry& g) {
  g.a2 = robot.dh[1].a, g.d3 = robot.dh[2].d, g.a3 = robot.dh[2].a, g.d4 = robot.dh[3].d;
  g.p = flange.translation();
  const double r = std::hypot(g.p.x(), g.p.y());
  if (r < g.d3 || r == 0) return IkStatus::out_of_reach;  // inside the shoulder cylinder
  g.phi = std::atan2(g.p.y(), g.p.x());
  g.alpha = std::asin(std::min(1.0, g.d3 / r));
  const double rho2 = r * r - g.d3 * g.d3 + g.p.z() * g.p.z();  // V^2 + pz^2 (same for both shoulders)
  const double rho = std::sqrt(rho2);
  if (rho == 0) return IkStatus::out_of_reach;
  double c = (g.a2 * g.a2 - g.d4 * g.d4 - g.a3 * g.a3 + rho2) / (2 * g.a2 * rho);
  if (std::abs(c) > 1 + kReachSlack) return IkStatus::out_of_reach;
  g.psi = std::acos(std::clamp(c, -1.0, 1.0));
  return IkStatus::ok;
}

// The two wrist solutions of one arm branch into out[0] (NOFLIP-side formula) and out[1].
// R03 = Rz(t1) Rx(90) Rz(t2 + t3) Rx(-90) = Rz(t1) Ry(-(t2 + t3)) for the PUMA alphas.
void arm_branch(const Robot& robot, const Pose& flange, const ArmGeometry& g, int shoulder, int elbow,
                double theta4_keep, IkCandidate* out) {
  const double ss = shoulder == 0 ? 1 : -1;  // sigma_s: +1 RIGHTY
  const double se = elbow == 0 ? 1 : -1;     // sigma_e: +1 ABOVE
  const double t1 = wrap_rad(shoulder == 0 ? g.phi + g.alpha : g.phi + kPi - g.alpha);
  const double c1 = std::cos(t1), s1 = std::sin(t1);
  const double V = g.p.x() * c1 + g.p.y() * s1;
  const double t2 = wrap_rad(std::atan2(g.p.z(), V) + ss * se * g.psi);
  const double u = V * std::cos(t2) + g.p.z() * std::sin(t2) - g.a2;
  const double w = g.p.z() * std::cos(t2) - V * std::sin(t2);
  const double t3 = wrap_rad(std::atan2(g.a3, g.d4) - std::atan2(u, w));
  const double c23 = std::cos(t2 + t3), s23 = std::sin(t2 + t3);
  collision::Mat3 r03;
  r03 << c1 * c23, -s1, -c1 * s23,  //
      s1 * c23, c1, -s1 * s23,      //
      s23, 0, c23;
  const collision::Mat3 m = r03.transpose() * flange.linear();
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
    IkCandidate& cand = out[flip];
    cand.dh.resize(6);
    cand.dh << t1, t2, t3, t4, t5, t6;
    cand.wrist_singular = singular;
    cand.config.righty = shoulder == 0;
    cand.config.above = elbow == 0;
    const double j5 = robot.mapping[4].sign * (t5 - robot.mapping[4].offset);
    cand.config.noflip = j5 >= 0;
    cand.valid = true;
  }
}
}  // namespace

// FK acceptance check of solve_puma: the DH chain with the nominal PUMA alphas, whose cos/sin
// are computed once (the general FK evaluates them per link; is_puma_type arms have these
// alphas to 1e-12, which moves the flange by < 1e-9 mm, far below the 1e-6 mm acceptance).
std::pair<double, double> fk_check(const Robot& robot, const JointVector& q, const Pose& target) {
  static const std::array<double, 6> ca = {std::cos(kPi / 2), 1, std::cos(-kPi / 2), std::cos(kPi / 2), std::cos(-kPi / 2), 1};
  static const std::array<double, 6> sa = {1, 0, -1, 1, -1, 0};
  Eigen::Matrix4d t = Eigen::Matrix4d::Identity();
  for (std::size_t k = 0; k < 6; ++k) {
    const double ct = std::cos(q[static_cast<Eigen::Index>(k)]), st = std::sin(q[static_cast<Eigen::Index>(k)]);
    const double a = robot.dh[k].a, d = robot.dh[k].d;
    Eigen::Matrix4d m;
    m << ct, -st * ca[k], st * sa[k], a * ct,  //
        st, ct * ca[k], -ct * sa[k], a * st,   //
        0, sa[k], ca[k], d,                    //
        0, 0, 0, 1;
    t = t * m;
  }
  return {(t.block<3, 1>(0, 3) - target.translation()).norm(), (t.block<3, 3>(0, 0) - target.linear()).norm()};
}

IkStatus puma_ik_all(const Robot& robot, const Pose& flange, double theta4_keep, IkCandidates& out) {
  for (auto& c : out) c.valid = false;
  ArmGeometry g;
  if (arm_geometry(robot, flange, g) != IkStatus::ok) return IkStatus::out_of_reach;
  for (int shoulder = 0; shoulder < 2; ++shoulder)
    for (int elbow = 0; elbow < 2; ++elbow)
      arm_branch(robot, flange, g, shoulder, elbow, theta4_keep, &out[static_cast<std::size_t>(4 * shoulder + 2 * elbow)]);
  return IkStatus::ok;
}

IkResult solve_puma(const Robot& robot, const Pose& flange, const JointVector& current_in,
                    const Configuration& want, bool single) {
  IkResult res;
  JointVector current = current_in;
  if (current.size() != 6) current = JointVector::Zero(6);
  const JointVector current_dh = display_to_dh(robot, current);
  ArmGeometry g;
  if (arm_geometry(robot, flange, g) != IkStatus::ok) {
    res.status = IkStatus::out_of_reach;
    return res;
  }
  IkCandidate cands[2];  // only the requested arm branch
  arm_branch(robot, flange, g, want.righty ? 0 : 1, want.above ? 0 : 1, current_dh[3], cands);
  const IkCandidate* pick = nullptr;
  for (const auto& c : cands) {
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
  const auto [ep, er] = fk_check(robot, display_to_dh(robot, sol), flange);
  if (!(ep <= kFkPositionTol && er <= kFkRotationTol)) {
    res.status = IkStatus::out_of_reach;
    return res;
  }
  res.joints = sol;
  return res;
}

}  // namespace asimov::robots
