// Shared by the closed forms of 6R arms whose wrist rotation is R36 = Rz(t4) Ry(-t5) Rz(t6)
// (the PUMA and the Viper: alphas 4, 5 = +90, -90): angles read off unit (cos, sin) pairs without
// libm trigonometry, the wrist from M = R03^T R, and the display / limit / SINGLE step after it.
// Header-only so that each solver inlines it (the PUMA solve is ~0.1 us; a call costs).
#pragma once
#include "asimov/robots/ik_puma.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace asimov::robots::pairs {
constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180;
constexpr double kWristSingular = 1e-10;  // m = |(M13, M23)| below this: theta5 = 0
constexpr double kReachSlack = 1e-12;     // |c| up to 1 + this is clamped (rounding at full stretch)
constexpr double kFkPositionTol = 1e-6;   // [mm] FK acceptance of a solution
constexpr double kFkRotationTol = 1e-9;   // Frobenius norm of the rotation difference

// The angle of a unit (cos, sin) pair, |c^2 + s^2 - 1| of a few ulp (every pair the solvers build is
// one by construction in these solvers), without a division: the octant-folded pair (a, b) = (sin, cos) of an
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
inline bool nearest_equivalent(double v, double near, double lo, double hi, double& out) {
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


// One solution as angles [rad, DH] and the (cos, sin) pairs they were read from.
struct BranchSolution {
  double t[6];
  double c[6], s[6];  // normalised to rounding
  double c23 = 1, s23 = 0;
  double m[3][3];     // M = R03^T R, the wrist rotation to reach
  double mm = 0;      // |(M13, M23)| = |sin theta5|
  bool singular = false;
};


// Wrist joints 4-6 from M: flip 0 is theta5 = -atan2(m, M33) <= 0, flip 1 its mirror
// (theta4 + pi, -theta5, theta6 + pi), read off the negated pairs. At the singularity theta5 = 0,
// theta4 = theta4_keep and theta6 = atan2(M21, M11) - theta4 (both flips the same).
inline void wrist(BranchSolution& b, int flip, double theta4_keep) {
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

inline bool noflip_of(const Robot& robot, double t5) {
  return robot.mapping[4].sign * (t5 - robot.mapping[4].offset) >= 0;
}

inline double to_display(const Robot& robot, int i, double t) {  // dh_to_display, times 180/pi (no division)
  const auto& m = robot.mapping[static_cast<std::size_t>(i)];
  return (t - m.offset) * (180 / kPi) * m.sign;
}

// Both wrists of one arm branch as candidates 4*shoulder + 2*elbow + flip (puma_ik_all,
// viper_ik_all).
inline void store_branch(const Robot& robot, BranchSolution& b, int shoulder, int elbow, double theta4_keep,
                         IkCandidates& out) {
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

// After the arm joints of one branch (b.t[0..2], b.m, b.mm, b.singular): the wrist in the flip
// that gives the requested NOFLIP word, then display values, each the 2pi-equivalent nearest
// `current` inside the limits (the last joint in (-180, 180] when `single`; J4 kept at the wrist
// singularity). False, with res.status / joint / value set, when the flip is unreachable or a
// joint has no equivalent inside its limits.
inline bool wrist_and_joints(const Robot& robot, BranchSolution& b, const JointVector& current,
                             const Configuration& want, bool single, IkResult& res, JointVector& sol) {
  const double theta4_keep = robot.mapping[3].sign * current[3] * kDeg + robot.mapping[3].offset;
  int flip = 0;
  if (!b.singular) {
    // theta5 of flip 0 is in [-pi, 0) and flip 1 its negative: without a J5 offset the display
    // sign alone decides, no atan2 needed.
    const double t5 = robot.mapping[4].offset == 0 ? -b.mm : -angle_of(b.mm, b.m[2][2]);  // flip 0
    flip = static_cast<int>(noflip_of(robot, t5) != want.noflip);  // no branch: random per pose
    if (flip == 1 && noflip_of(robot, -t5) != want.noflip) {
      res.status = IkStatus::out_of_reach;
      return false;
    }
  }
  wrist(b, flip, theta4_keep);
  sol.resize(6);
  for (int i = 0; i < 6; ++i) {
    const double raw = to_display(robot, i, b.t[i]);
    double v = raw;
    bool ok;
    if (i == 5 && single) {
      if (!(v > -180 && v <= 180)) v = wrap_deg(v);
      ok = v >= limit_low(robot, i) - 1e-9 && v <= limit_high(robot, i) + 1e-9;
    } else if (b.singular && i == 3) {
      v = current[3];  // kept exactly at the wrist singularity
      ok = v >= limit_low(robot, i) - 1e-9 && v <= limit_high(robot, i) + 1e-9;
    } else {
      ok = nearest_equivalent(raw, current[i], limit_low(robot, i), limit_high(robot, i), v);
      if (!ok) v = raw + 360.0 * std::round((current[i] - raw) / 360.0);
    }
    if (!ok) {
      res.status = IkStatus::joint_limit;
      res.joint = i;
      res.value = v;
      return false;
    }
    sol[i] = v;
  }
  return true;
}

}  // namespace asimov::robots::pairs
