// Closed-form Viper-type IK (docs/robots.md "viper_s650"). In the arm plane (x1 forward, z up,
// origin on the J2 axis) the wrist centre is at (R, Z) = (a2 c2 + a3 c23 - d4 s23,
// -a2 s2 - a3 s23 - d4 c23) [DH angles]. Then K = (R^2 + Z^2 - a2^2 - L^2) / (2 a2) = a3 c3 - d4 s3
// with L^2 = a3^2 + d4^2, V = a3 s3 + d4 c3 = +-sqrt(L^2 - K^2), and with P = a2 + K:
// (c2, s2) = (P R - V Z, -(V R + P Z)) / (R^2 + Z^2). The elbow's cross product with the wrist
// direction is a2 V, so ABOVE (elbow on the upper side) is V R >= 0: the elbow branch is chosen by
// the sign of V alone. The wrist is the PUMA's (R36 = Rz(t4) Ry(-t5) Rz(t6)); every angle comes
// from a unit (cos, sin) pair (ik_pairs.hpp), trigonometry only at the singularities.
#include "asimov/robots/ik_viper.hpp"
#include "ik_family.hpp"

#include "ik_pairs.hpp"

#include <cmath>
#include <numbers>

namespace asimov::robots {
namespace {
using namespace pairs;

struct ViperGeometry {
  double a1 = 0, d1 = 0, a2 = 0, a3 = 0, d4 = 0, d6 = 0;
  double wx = 0, wy = 0, wz = 0;  // wrist centre = flange - d6 * approach
  double h = 0;                   // |(wx, wy)|: 0 on the J1 axis (shoulder singular)
};

ViperGeometry viper_geometry(const Robot& robot, const Pose& flange) {
  ViperGeometry g;
  g.a1 = robot.dh[0].a, g.d1 = robot.dh[0].d, g.a2 = robot.dh[1].a, g.a3 = robot.dh[2].a;
  g.d4 = robot.dh[3].d, g.d6 = robot.dh[5].d;
  const Vec3 w = flange.translation() - g.d6 * flange.linear().col(2);
  g.wx = w.x(), g.wy = w.y(), g.wz = w.z();
  g.h = std::sqrt(g.wx * g.wx + g.wy * g.wy);
  return g;
}

// Arm joints 1-3 of one branch and M = R03^T R; false when out of reach. (c1k, s1k): theta1 to
// keep on the J1 axis. R03 = Rz(t1) Rx(-90) Rz(t2 + t3) Rx(-90), columns (c1 c23, s1 c23, -s23),
// (s1, -c1, 0), (-c1 s23, -s1 s23, -c23).
bool viper_branch(const ViperGeometry& g, const Pose& flange, bool righty, bool above, double c1k, double s1k,
                  BranchSolution& b) {
  const double sigma = righty ? 1 : -1;
  double c1 = c1k, s1 = s1k, rho = 0;
  if (g.h > 0) {
    const double inv = 1 / g.h;
    c1 = sigma * g.wx * inv, s1 = sigma * g.wy * inv, rho = sigma * g.h;
  }
  const double R = rho - g.a1, Z = g.wz - g.d1;
  const double l2 = g.a3 * g.a3 + g.d4 * g.d4;
  const double n2 = R * R + Z * Z;
  const double K = (n2 - g.a2 * g.a2 - l2) * (0.5 / g.a2);
  double v2 = l2 - K * K;
  const bool clamped = v2 < 0;
  if (clamped) {
    if (K * K > l2 * (1 + kReachSlack)) return false;  // beyond full stretch / inside the fold
    v2 = 0;
  }
  const double V = ((R >= 0) == above ? 1 : -1) * std::sqrt(v2);
  const double inv_l2 = 1 / l2;
  double c3 = (g.a3 * K + g.d4 * V) * inv_l2, s3 = (g.a3 * V - g.d4 * K) * inv_l2;
  const double P = g.a2 + K;
  const double inv_n2 = 1 / n2;
  double c2 = (P * R - V * Z) * inv_n2, s2 = -(V * R + P * Z) * inv_n2;
  if (clamped) {  // |(K, V)| = L only to the reach slack
    const double n3 = 1 / std::sqrt(c3 * c3 + s3 * s3), nn2 = 1 / std::sqrt(c2 * c2 + s2 * s2);
    c3 *= n3, s3 *= n3, c2 *= nn2, s2 *= nn2;
  }
  const double c23 = c2 * c3 - s2 * s3, s23 = s2 * c3 + c2 * s3;
  b.c[0] = c1, b.s[0] = s1, b.c[1] = c2, b.s[1] = s2, b.c[2] = c3, b.s[2] = s3, b.c23 = c23, b.s23 = s23;
  b.t[0] = angle_of(s1, c1), b.t[1] = angle_of(s2, c2), b.t[2] = angle_of(s3, c3);
  const auto& r = flange.linear();
  for (int j = 0; j < 3; ++j) {
    const double hh = c1 * r(0, j) + s1 * r(1, j);
    b.m[0][j] = c23 * hh - s23 * r(2, j);
    b.m[1][j] = s1 * r(0, j) - c1 * r(1, j);
    b.m[2][j] = -s23 * hh - c23 * r(2, j);
  }
  b.mm = std::sqrt(b.m[0][2] * b.m[0][2] + b.m[1][2] * b.m[1][2]);
  b.singular = b.mm <= kWristSingular;
  return true;
}

// FK of a branch solution from its pairs: flange position error [mm] and |R36 - M| (Frobenius).
std::pair<double, double> viper_fk_check(const ViperGeometry& g, const BranchSolution& b, const Pose& flange) {
  const double c1 = b.c[0], s1 = b.s[0], c2 = b.c[1], s2 = b.s[1], c4 = b.c[3], s4 = b.s[3], c5 = b.c[4],
               s5 = b.s[4], c6 = b.c[5], s6 = b.s[5], c23 = b.c23, s23 = b.s23;
  const double r36[3][3] = {{c4 * c5 * c6 - s4 * s6, -c4 * c5 * s6 - s4 * c6, -c4 * s5},
                            {s4 * c5 * c6 + c4 * s6, -s4 * c5 * s6 + c4 * c6, -s4 * s5},
                            {s5 * c6, -s5 * s6, c5}};
  double er2 = 0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) er2 += (r36[i][j] - b.m[i][j]) * (r36[i][j] - b.m[i][j]);
  // Wrist centre, then + d6 * approach, approach = R03 (R36 e3).
  const double rho = g.a1 + g.a2 * c2 + g.a3 * c23 - g.d4 * s23;
  const double z = g.d1 - g.a2 * s2 - g.a3 * s23 - g.d4 * c23;
  const double ax = r36[0][2], ay = r36[1][2], az = r36[2][2];
  const double x = c1 * rho + g.d6 * (c1 * c23 * ax + s1 * ay - c1 * s23 * az);
  const double y = s1 * rho + g.d6 * (s1 * c23 * ax - c1 * ay - s1 * s23 * az);
  const double zz = z + g.d6 * (-s23 * ax - c23 * az);
  const auto& p = flange.translation();
  const double dx = x - p.x(), dy = y - p.y(), dz = zz - p.z();
  return {std::sqrt(dx * dx + dy * dy + dz * dz), std::sqrt(er2)};
}
}  // namespace

bool is_viper_type(const Robot& robot) {
  if (robot.is_chain() || robot.dh.size() != 6 || robot.mapping.size() != 6) return false;
  constexpr double h = std::numbers::pi / 2, tol = 1e-12;
  const double alpha[6] = {-h, 0, -h, h, -h, 0};
  for (std::size_t i = 0; i < 6; ++i)
    if (std::abs(robot.dh[i].alpha - alpha[i]) > tol) return false;
  const auto& d = robot.dh;
  return d[1].d == 0 && d[2].d == 0 && d[4].d == 0 && d[3].a == 0 && d[4].a == 0 && d[5].a == 0 && d[1].a > 0 &&
         (d[2].a != 0 || d[3].d != 0);
}

IkStatus viper_ik_all(const Robot& robot, const Pose& flange, double theta1_keep, double theta4_keep,
                      IkCandidates& out) {
  for (auto& c : out) c.valid = false;
  const ViperGeometry g = viper_geometry(robot, flange);
  const double c1k = std::cos(theta1_keep), s1k = std::sin(theta1_keep);
  bool any = false;
  for (int shoulder = 0; shoulder < 2; ++shoulder) {
    for (int elbow = 0; elbow < 2; ++elbow) {
      BranchSolution b;
      if (!viper_branch(g, flange, shoulder == 0, elbow == 0, c1k, s1k, b)) continue;
      store_branch(robot, b, shoulder, elbow, theta4_keep, out);
      any = true;
    }
  }
  return any ? IkStatus::ok : IkStatus::out_of_reach;
}

IkResult solve_viper(const Robot& robot, const Pose& flange, const JointVector& current_in,
                     const Configuration& want, bool single) {
  IkResult res;
  JointVector current = current_in;
  if (current.size() != 6) current = JointVector::Zero(6);
  const ViperGeometry g = viper_geometry(robot, flange);
  double c1k = 1, s1k = 0;
  if (!(g.h > 0)) {  // wrist centre on the J1 axis: J1 stays
    const double t1 = robot.mapping[0].sign * current[0] * kDeg + robot.mapping[0].offset;
    c1k = std::cos(t1), s1k = std::sin(t1);
  }
  BranchSolution b;
  if (!flange.matrix().allFinite() || !viper_branch(g, flange, want.righty, want.above, c1k, s1k, b)) {
    res.status = IkStatus::out_of_reach;
    return res;
  }
  JointVector sol;
  if (!wrist_and_joints(robot, b, current, want, single, res, sol)) return res;
  const auto [ep, er] = viper_fk_check(g, b, flange);
  if (!(ep <= kFkPositionTol && er <= kFkRotationTol)) {
    res.status = IkStatus::out_of_reach;
    return res;
  }
  res.joints = sol;
  return res;
}

Configuration viper_configuration(const Robot& robot, const JointVector& display) {
  const JointVector q = display_to_dh(robot, display);
  std::vector<Pose> frames;
  frames.reserve(7);
  link_frames(robot, display, frames);
  const double c1 = std::cos(q[0]), s1 = std::sin(q[0]);
  const double a1 = robot.dh[0].a, d1 = robot.dh[0].d;
  const Vec3 w = frames[4].translation(), e = frames[2].translation();  // wrist centre, elbow
  const double rho = w.x() * c1 + w.y() * s1;
  const double R = rho - a1, Z = w.z() - d1;
  const double er = e.x() * c1 + e.y() * s1 - a1, ez = e.z() - d1;
  Configuration c;
  c.righty = rho >= 0;
  c.above = (R * ez - Z * er) * R >= 0;
  c.noflip = display[4] >= 0;
  return c;
}

const IkFamily viper_family{"viper", is_viper_type, solve_viper, viper_configuration, every_word_applies};

}  // namespace asimov::robots
