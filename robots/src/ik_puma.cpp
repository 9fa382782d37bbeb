// Closed-form PUMA IK, docs/kinematics.md §5. Geometry constants are read from the robot's DH table
// (a2 = dh[1].a, d3 = dh[2].d, a3 = dh[2].a, d4 = dh[3].d), so scaled PUMA-type arms work too.
//
// Speed (bench/bench_ik.cpp): every joint is carried as a unit (cos, sin) pair obtained with
// sums, products, 4 square roots and a few reciprocals (angle sums become pair rotations), and
// each angle is read off its pair at the end by angle_of (table + series, no division, no
// branch on the data): no libm trigonometry on the way (sin/cos only at the wrist singularity),
// no heap. The FK acceptance check reuses the same pairs. Branches on per-pose data (arm
// branch, flip, octant) are arithmetic: mispredictions cost as much as the arithmetic.
#include "asimov/robots/ik_puma.hpp"
#include "ik_family.hpp"

#include "ik_pairs.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

namespace asimov::robots {
namespace {
using namespace pairs;


// DH constants of the closed form and the pose-level quantities shared by the four arm branches.
// psi = angle at the shoulder between the wrist direction (V, pz) and link 2; rho = |(V, pz)|.
// rho cos psi and rho sin psi need no square root of rho2 (one sqrt less on the critical path).
struct ArmGeometry {
  double a2 = 0, d3 = 0, a3 = 0, d4 = 0, a6 = 0, d6 = 0;
  double px = 0, py = 0, pz = 0;
  double inv_r2 = 0;   // 1 / (px^2 + py^2)
  double vr = 0;       // sqrt(r^2 - d3^2) = |V|, the wrist centre's reach in the arm plane
  double inv_rho2 = 0; // 1 / (V^2 + pz^2)
  double crho = 0;     // rho cos psi = (a2^2 - a3^2 - d4^2 + rho^2) / (2 a2)
  double srho = 0;     // rho sin psi >= 0
  bool clamped = false;  // |cos psi| was clamped to 1 (full stretch / fold within the reach slack)
};

IkStatus arm_geometry(const Robot& robot, const Pose& flange, ArmGeometry& g) {
  g.a2 = robot.dh[1].a, g.d3 = robot.dh[2].d, g.a3 = robot.dh[2].a, g.d4 = robot.dh[3].d;
  g.a6 = robot.dh[5].a, g.d6 = robot.dh[5].d;
  const auto& p = flange.translation();
  g.px = p.x(), g.py = p.y(), g.pz = p.z();
  const double r2 = g.px * g.px + g.py * g.py;
  const double v2 = r2 - g.d3 * g.d3;
  if (v2 < 0 || r2 == 0) return IkStatus::out_of_reach;  // inside the shoulder cylinder
  const double rho2 = v2 + g.pz * g.pz;                    // V^2 + pz^2 (same for both shoulders)
  if (rho2 == 0) return IkStatus::out_of_reach;
  g.crho = (g.a2 * g.a2 - g.d4 * g.d4 - g.a3 * g.a3 + rho2) * (0.5 / g.a2);
  const double rho = std::sqrt(rho2);
  double s2 = (rho - g.crho) * (rho + g.crho);  // rho^2 sin^2 psi
  if (s2 < 0) {
    // |cos psi| = |crho| / rho beyond 1 + slack: out of reach; within: full stretch / fold.
    if (std::abs(g.crho) > rho * (1 + kReachSlack)) return IkStatus::out_of_reach;
    g.crho = std::copysign(rho, g.crho), s2 = 0, g.clamped = true;
  }
  g.srho = std::sqrt(s2);
  g.vr = std::sqrt(v2);
  g.inv_r2 = 1 / r2;
  g.inv_rho2 = 1 / rho2;
  return IkStatus::ok;
}


// Arm joints 1-3 of one branch and the wrist matrix M. Angle sums are pair rotations:
// theta1 = phi + alpha (RIGHTY) or phi + pi - alpha, with cos alpha = V/r, sin alpha = d3/r;
// theta2 = atan2(pz, V) + sigma_s sigma_e psi; theta3 = atan2(a3, d4) - atan2(u, w), |(u, w)| = L.
// R03 = Rz(t1) Rx(90) Rz(t2 + t3) Rx(-90) = Rz(t1) Ry(-(t2 + t3)) for the PUMA alphas.
void arm_branch(const ArmGeometry& g, const Pose& flange, bool righty, bool above, BranchSolution& b) {
  // Signs by arithmetic, not branches (the requested configuration varies pose to pose).
  const double sigma_s = 1 - 2 * static_cast<double>(!righty), sigma_e = 1 - 2 * static_cast<double>(!above);
  const double V = sigma_s * g.vr;
  const double c1 = (g.px * V - g.py * g.d3) * g.inv_r2, s1 = (g.py * V + g.px * g.d3) * g.inv_r2;
  const double sr = sigma_s * sigma_e * g.srho;  // sigma_s sigma_e rho sin psi
  const double c2 = (V * g.crho - g.pz * sr) * g.inv_rho2, s2 = (g.pz * g.crho + V * sr) * g.inv_rho2;
  const double u = V * c2 + g.pz * s2 - g.a2, w = g.pz * c2 - V * s2;
  const double inv_l2 = 1 / (g.a3 * g.a3 + g.d4 * g.d4);
  double c3 = (g.d4 * w + g.a3 * u) * inv_l2, s3 = (g.a3 * w - g.d4 * u) * inv_l2;
  if (g.clamped) {  // |(u, w)| = rho - a2 or a2 - rho, L only to the reach slack
    const double n = 1 / std::sqrt(c3 * c3 + s3 * s3);
    c3 *= n, s3 *= n;
  }
  const double c23 = c2 * c3 - s2 * s3, s23 = s2 * c3 + c2 * s3;
  b.c[0] = c1, b.s[0] = s1, b.c[1] = c2, b.s[1] = s2, b.c[2] = c3, b.s[2] = s3, b.c23 = c23, b.s23 = s23;
  b.t[0] = angle_of(s1, c1), b.t[1] = angle_of(s2, c2), b.t[2] = angle_of(s3, c3);
  // M = R03^T R row by row: R03 columns are (c1 c23, s1 c23, s23), (-s1, c1, 0), (-c1 s23, -s1 s23, c23).
  const auto& r = flange.linear();
  for (int j = 0; j < 3; ++j) {
    const double h = c1 * r(0, j) + s1 * r(1, j);
    b.m[0][j] = c23 * h + s23 * r(2, j);
    b.m[1][j] = c1 * r(1, j) - s1 * r(0, j);
    b.m[2][j] = c23 * r(2, j) - s23 * h;
  }
  b.mm = std::sqrt(b.m[0][2] * b.m[0][2] + b.m[1][2] * b.m[1][2]);
  b.singular = b.mm <= kWristSingular;
}


// FK acceptance check of a branch solution from its pairs (atan2 of a pair is accurate to
// 2 ulp, so this is the FK of the returned angles to ~1e-15): flange position against the
// target [mm] and |R36 - M| (= |R06 - R|, R03 being orthonormal to rounding). It catches
// what the closed form ignores or clamps: the reach slack, the wrist singular threshold, and
// a6 / d6 (is_puma_type does not constrain link 6; the formulas put the flange at the wrist
// centre). The nominal alphas are used; is_puma_type arms have them to 1e-12.
std::pair<double, double> pair_fk_check(const ArmGeometry& g, const BranchSolution& b) {
  const double c1 = b.c[0], s1 = b.s[0], c2 = b.c[1], s2 = b.s[1], c4 = b.c[3], s4 = b.s[3], c5 = b.c[4],
               s5 = b.s[4], c6 = b.c[5], s6 = b.s[5];
  // R36 = Rz(t4) Ry(-t5) Rz(t6).
  const double r36[3][3] = {{c4 * c5 * c6 - s4 * s6, -c4 * c5 * s6 - s4 * c6, -c4 * s5},
                            {s4 * c5 * c6 + c4 * s6, -s4 * c5 * s6 + c4 * c6, -s4 * s5},
                            {s5 * c6, -s5 * s6, c5}};
  double er2 = 0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) er2 += (r36[i][j] - b.m[i][j]) * (r36[i][j] - b.m[i][j]);
  // Wrist centre: frame-1 coordinates (X, Y, d3), frame 1 axes (c1, s1, 0), (0, 0, 1), (s1, -c1, 0).
  const double X = g.a2 * c2 + g.a3 * b.c23 - g.d4 * b.s23, Y = g.a2 * s2 + g.a3 * b.s23 + g.d4 * b.c23;
  double x = X * c1 + g.d3 * s1, y = X * s1 - g.d3 * c1, z = Y;
  if (g.a6 != 0 || g.d6 != 0) {  // flange = wrist + R03 R36 (a6, 0, d6)
    const double lx = g.a6 * r36[0][0] + g.d6 * r36[0][2], ly = g.a6 * r36[1][0] + g.d6 * r36[1][2],
                 lz = g.a6 * r36[2][0] + g.d6 * r36[2][2];
    const double c23 = b.c23, s23 = b.s23;
    x += c1 * c23 * lx - s1 * ly - c1 * s23 * lz;
    y += s1 * c23 * lx + c1 * ly - s1 * s23 * lz;
    z += s23 * lx + c23 * lz;
  }
  const double dx = x - g.px, dy = y - g.py, dz = z - g.pz;
  return {std::sqrt(dx * dx + dy * dy + dz * dz), std::sqrt(er2)};
}
}  // namespace

std::pair<double, double> fk_error(const Robot& robot, const JointVector& dh, const Pose& target) {
  const Pose f = flange_pose_dh(robot, dh);
  return {(f.translation() - target.translation()).norm(), (f.linear() - target.linear()).norm()};
}

IkStatus puma_ik_all(const Robot& robot, const Pose& flange, double theta4_keep, IkCandidates& out) {
  for (auto& c : out) c.valid = false;
  ArmGeometry g;
  if (arm_geometry(robot, flange, g) != IkStatus::ok) return IkStatus::out_of_reach;
  for (int shoulder = 0; shoulder < 2; ++shoulder) {
    for (int elbow = 0; elbow < 2; ++elbow) {
      BranchSolution b;
      arm_branch(g, flange, shoulder == 0, elbow == 0, b);
      store_branch(robot, b, shoulder, elbow, theta4_keep, out);
    }
  }
  return IkStatus::ok;
}

IkResult solve_puma(const Robot& robot, const Pose& flange, const JointVector& current_in,
                    const Configuration& want, bool single) {
  IkResult res;
  JointVector current = current_in;
  if (current.size() != 6) current = JointVector::Zero(6);
  ArmGeometry g;
  if (arm_geometry(robot, flange, g) != IkStatus::ok) {
    res.status = IkStatus::out_of_reach;
    return res;
  }
  // Only the requested arm branch; of its two wrists the one in the requested flip.
  BranchSolution b;
  arm_branch(g, flange, want.righty, want.above, b);
  JointVector sol;
  if (!wrist_and_joints(robot, b, current, want, single, res, sol)) return res;
  const auto [ep, er] = pair_fk_check(g, b);
  if (!(ep <= kFkPositionTol && er <= kFkRotationTol)) {
    res.status = IkStatus::out_of_reach;
    return res;
  }
  res.joints = sol;
  return res;
}

namespace {
// RIGHTY: the wrist centre in front of J1's axis; ABOVE: the elbow above the shoulder-wrist line
// on that side; NOFLIP: J5 >= 0 (docs/kinematics.md §6).
Configuration puma_configuration(const Robot& robot, const JointVector& display) {
  const JointVector q = display_to_dh(robot, display);
  std::vector<Pose> frames;
  frames.reserve(robot.dh.size() + 1);
  link_frames(robot, display, frames);
  const Vec3 p = frames[4].translation();  // wrist centre
  const double V = p.x() * std::cos(q[0]) + p.y() * std::sin(q[0]);
  Configuration c;
  c.righty = V >= 0;
  const double sigma_s = c.righty ? 1 : -1;
  const double diff = std::remainder(q[1] - std::atan2(p.z(), V), 2 * std::numbers::pi);
  c.above = sigma_s * diff >= 0;
  c.noflip = display[4] >= 0;
  return c;
}

// Shoulder (r - d3) and elbow reach margins of a wrist-centre position (docs/kinematics.md §7);
// the PUMA's flange is at its wrist centre (d6 = 0 in these formulas).
std::optional<ReachMargins> puma_margins(const Robot& r, const Vec3& p) {
  const double a2 = r.dh[1].a, d3 = r.dh[2].d, a3 = r.dh[2].a, d4 = r.dh[3].d;
  const double rr = std::hypot(p.x(), p.y());
  const double rho = std::sqrt(std::max(0.0, rr * rr - d3 * d3) + p.z() * p.z());
  const double L = std::hypot(a3, d4);
  return ReachMargins{rr - d3, std::min(a2 + L - rho, rho - std::abs(a2 - L))};
}
}  // namespace

const IkFamily puma_family{"puma", is_puma_type, solve_puma, puma_configuration, every_word_applies, puma_margins};

}  // namespace asimov::robots
