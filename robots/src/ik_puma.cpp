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

#include <algorithm>
#include <array>
#include <cfloat>
#include <cmath>
#include <limits>
#include <numbers>

namespace asimov::robots {
namespace {
constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180;
constexpr double kWristSingular = 1e-10;  // m = |(M13, M23)| below this: theta5 = 0
constexpr double kReachSlack = 1e-12;     // |c| up to 1 + this is clamped (rounding at full stretch)
constexpr double kFkPositionTol = 1e-6;   // [mm] FK acceptance of a solution
constexpr double kFkRotationTol = 1e-9;   // Frobenius norm of the rotation difference

// The angle of a unit (cos, sin) pair, |c^2 + s^2 - 1| of a few ulp (every pair in this file is
// one by construction), without a division: the octant-folded pair (a, b) = (sin, cos) of an
// angle in [0, pi/4] is rotated back by the nearest theta_k = asin(k/16) (cos theta_k from a
// table, sin theta_k = k/16 exact), leaving sin(theta - theta_k) <= 0.045, whose arcsine series
// to x^11 is below 2e-18 relative. Measured against long double atan2l on 4e6 random unit
// pairs: <= 1.9 ulp, |error| <= 4.9e-16 rad (libm atan2: 0.5 ulp), about a third of libm's
// time. A pair that is not unit (or NaN) goes to std::atan2.
// Tables: cos theta_k, and theta_k split into a double and its remainder (200-bit mpmath).
constexpr double kCosK[12] = {1.0, 0.998044963916957, 0.9921567416492215, 0.982264602843857,
                              0.9682458365518543, 0.9499177595981665, 0.9270248108869579, 0.899218410621135,
                              0.8660254037844386, 0.8267972847076845, 0.7806247497997998, 0.7261843774138906};
constexpr double kThetaHi[12] = {0.0, 0.06254076179649139, 0.1253278311680654, 0.1886163861754041,
                                 0.25268025514207865, 0.31782370392788073, 0.3843967744956391, 0.4528165947449256,
                                 0.5235987755982989, 0.5974064166453502, 0.6751315329370317, 0.758040765426236};
constexpr double kThetaLo[12] = {0.0, 3.797152289847936e-18, 1.2906010488810617e-18, -8.788406305681407e-18,
                                 6.584019697419058e-18, 2.3525133417051565e-17, 1.0793527747925466e-18,
                                 -1.0732687972848396e-17, -5.360408832255455e-17, 9.246927897333234e-19,
                                 -5.931934973320855e-18, -3.575909213900065e-17};
constexpr double kPio2Hi = 1.5707963267948966, kPio2Lo = 6.123233995736766e-17;
constexpr double kPiHi = 3.141592653589793, kPiLo = 1.2246467991473532e-16;

// Octant composition, index 2 * (|s| > |c|) + (c < 0): angle = base + sign * octant angle.
constexpr double kBaseHi[4] = {0.0, kPiHi, kPio2Hi, kPio2Hi};
constexpr double kBaseLo[4] = {0.0, kPiLo, kPio2Lo, kPio2Lo};
constexpr double kBaseSign[4] = {1, -1, -1, 1};

// Branch-free but for the never-taken guard: the solver's inputs are random per pose, and a
// mispredicted branch costs as much as the arithmetic here.
inline double angle_of(double s, double c) {
  const double ac = std::abs(c), as = std::abs(s);
  const double a = std::min(ac, as), b = std::max(ac, as);  // sin, cos of the octant angle
  if (!(a <= 0.71)) return std::atan2(s, c);                  // not a unit pair (1/sqrt2 = 0.7071), or NaN
  const int k = static_cast<int>(a * 16 + 0.5);               // 0..11
  const double x = a * kCosK[k] - b * (k * (1.0 / 16));       // sin(theta - theta_k)
  const double x1 = x * x, x2 = x1 * x1, x4 = x2 * x2;
  const double p = (1.0 / 6 + x1 * (3.0 / 40)) + x2 * (5.0 / 112 + x1 * (35.0 / 1152)) + x4 * (63.0 / 2816);
  const double t = kThetaHi[k] + ((x + x * x1 * p) + kThetaLo[k]);
  const int q = 2 * static_cast<int>(as > ac) + static_cast<int>(std::signbit(c));
  const double v = (kBaseHi[q] + kBaseSign[q] * t) + kBaseLo[q];
  const double r = std::copysign(v, s);
  return r == -kPiHi ? kPiHi : r;  // s = -0: +pi, angles stay in (-pi, pi]
}

// Nearest 2pi-equivalent (display degrees) of v to `near` inside [lo, hi]; false if none.
bool nearest_equivalent(double v, double near, double lo, double hi, double& out) {
  // Common case: the equivalent nearest `near` overall (rounded to an integer number of turns
  // by the 1.5 * 2^52 trick, no libm call) is in range and strictly within 180 of it; then it
  // is what the search below returns.
  constexpr double kRound = 6755399441055744.0;  // 1.5 * 2^52
  const double c0 = v + 360.0 * (((near - v) * (1 / 360.0) + kRound) - kRound);
  if (std::abs(c0 - near) < 180 && c0 >= lo - 1e-9 && c0 <= hi + 1e-9) {
    out = std::clamp(c0, lo, hi);
    return true;
  }
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

// One solution as angles [rad, DH] and the (cos, sin) pairs they were read from.
struct BranchSolution {
  double t[6];
  double c[6], s[6];  // normalised to rounding
  double c23 = 1, s23 = 0;
  double m[3][3];     // M = R03^T R, the wrist rotation to reach
  double mm = 0;      // |(M13, M23)| = |sin theta5|
  bool singular = false;
};

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

// Wrist joints 4-6 from M: flip 0 is theta5 = -atan2(m, M33) <= 0, flip 1 its mirror
// (theta4 + pi, -theta5, theta6 + pi), read off the negated pairs. At the singularity theta5 = 0,
// theta4 = theta4_keep and theta6 = atan2(M21, M11) - theta4 (both flips the same).
void wrist(BranchSolution& b, int flip, double theta4_keep) {
  const auto& m = b.m;
  if (b.singular) {
    const double c4 = std::cos(theta4_keep), s4 = std::sin(theta4_keep);
    const double c6 = m[0][0] * c4 + m[1][0] * s4, s6 = m[1][0] * c4 - m[0][0] * s4;
    const double n6 = 1 / std::sqrt(c6 * c6 + s6 * s6);
    b.t[3] = theta4_keep, b.t[4] = 0, b.t[5] = angle_of(s6 * n6, c6 * n6);
    b.c[3] = c4, b.s[3] = s4, b.c[4] = 1, b.s[4] = 0, b.c[5] = c6 * n6, b.s[5] = s6 * n6;
    return;
  }
  const double f = 1 - 2 * static_cast<double>(flip);
  const double inv = 1 / b.mm;
  const double c4 = f * m[0][2] * inv, s4 = f * m[1][2] * inv;
  const double c5 = m[2][2], s5 = -f * b.mm;
  double c6, s6;
  if (c5 >= 0) {
    // theta6 = (theta4 + theta6) - theta4: the sum is well conditioned near theta5 = 0, where
    // theta4 and theta6 alone are not (errors of M / m each); M11 + M22 = (1 + c5) cos(t4 + t6),
    // M21 - M12 = (1 + c5) sin(t4 + t6).
    const double k = 1 / (1 + c5);
    const double cs = (m[0][0] + m[1][1]) * k, ss = (m[1][0] - m[0][1]) * k;
    c6 = cs * c4 + ss * s4, s6 = ss * c4 - cs * s4;
  } else {
    c6 = -f * m[2][0] * inv, s6 = f * m[2][1] * inv;
  }
  b.t[3] = angle_of(s4, c4), b.t[4] = angle_of(s5, c5), b.t[5] = angle_of(s6, c6);
  b.c[3] = c4, b.s[3] = s4, b.c[4] = c5, b.s[4] = s5, b.c[5] = c6, b.s[5] = s6;
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

bool noflip_of(const Robot& robot, double t5) {
  return robot.mapping[4].sign * (t5 - robot.mapping[4].offset) >= 0;
}

double to_display(const Robot& robot, int i, double t) {  // dh_to_display, times 180/pi (no division)
  const auto& m = robot.mapping[static_cast<std::size_t>(i)];
  return (t - m.offset) * (180 / kPi) * m.sign;
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
      for (int flip = 0; flip < 2; ++flip) {
        wrist(b, flip, theta4_keep);
        IkCandidate& cand = out[static_cast<std::size_t>(4 * shoulder + 2 * elbow + flip)];
        cand.dh.resize(6);
        cand.dh << b.t[0], b.t[1], b.t[2], b.t[3], b.t[4], b.t[5];
        cand.wrist_singular = b.singular;
        cand.config.righty = shoulder == 0;
        cand.config.above = elbow == 0;
        cand.config.noflip = noflip_of(robot, b.t[4]);
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
  ArmGeometry g;
  if (arm_geometry(robot, flange, g) != IkStatus::ok) {
    res.status = IkStatus::out_of_reach;
    return res;
  }
  // Only the requested arm branch; of its two wrists the one in the requested flip.
  BranchSolution b;
  arm_branch(g, flange, want.righty, want.above, b);
  const double theta4_keep = robot.mapping[3].sign * current[3] * kDeg + robot.mapping[3].offset;
  int flip = 0;
  if (!b.singular) {
    // theta5 of flip 0 is in [-pi, 0) and flip 1 its negative: without a J5 offset the display
    // sign alone decides, no atan2 needed.
    const double t5 = robot.mapping[4].offset == 0 ? -b.mm : -angle_of(b.mm, b.m[2][2]);  // flip 0
    flip = static_cast<int>(noflip_of(robot, t5) != want.noflip);  // no branch: random per pose
    if (flip == 1 && noflip_of(robot, -t5) != want.noflip) {
      res.status = IkStatus::out_of_reach;
      return res;
    }
  }
  wrist(b, flip, theta4_keep);
  JointVector sol(6);
  for (int i = 0; i < 6; ++i) {
    const double raw = to_display(robot, i, b.t[i]);
    double v = raw;
    bool ok;
    if (i == 5 && single) {
      if (!(v > -180 && v <= 180)) v = wrap_deg(v);
      ok = v >= robot.lower[i] - 1e-9 && v <= robot.upper[i] + 1e-9;
    } else if (b.singular && i == 3) {
      v = current[3];  // kept exactly at the wrist singularity
      ok = v >= robot.lower[i] - 1e-9 && v <= robot.upper[i] + 1e-9;
    } else {
      ok = nearest_equivalent(raw, current[i], robot.lower[i], robot.upper[i], v);
      if (!ok) v = raw + 360.0 * std::round((current[i] - raw) / 360.0);
    }
    if (!ok) {
      res.status = IkStatus::joint_limit;
      res.joint = i;
      res.value = v;
      return res;
    }
    sol[i] = v;
  }
  const auto [ep, er] = pair_fk_check(g, b);
  if (!(ep <= kFkPositionTol && er <= kFkRotationTol)) {
    res.status = IkStatus::out_of_reach;
    return res;
  }
  res.joints = sol;
  return res;
}

}  // namespace asimov::robots
