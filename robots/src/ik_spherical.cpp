// Paden-Kahan closed form for J1 _|_ J2 || J3 arms with a spherical wrist.
#include "asimov/robots/ik_spherical.hpp"

#include "asimov/robots/configuration.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace asimov::robots {
namespace {
constexpr double kParallel = 1e-9;   // |w1 . w2|, |w2 x w3|
constexpr double kMeet = 1e-6;       // [mm] wrist axes intersection
constexpr double kReachSlack = 1e-12;
constexpr double kWristSingular = 1e-10;

using Mat3 = collision::Mat3;

Mat3 rot(const Vec3& w, double t) { return Eigen::AngleAxisd(t, w).toRotationMatrix(); }

// Closest points of two lines (p + s u, q + t v); false when parallel.
bool closest(const Vec3& p, const Vec3& u, const Vec3& q, const Vec3& v, Vec3& a, Vec3& b) {
  const Vec3 r = p - q;
  const double uu = u.dot(u), uv = u.dot(v), vv = v.dot(v), ur = u.dot(r), vr = v.dot(r);
  const double den = uu * vv - uv * uv;
  if (den < 1e-12) return false;
  const double s = (uv * vr - vv * ur) / den, t = (uu * vr - uv * ur) / den;
  a = p + s * u, b = q + t * v;
  return true;
}

// Subproblem 1: angle about unit w (through r) taking point p to q (projections on the plane).
double sp1(const Vec3& w, const Vec3& r, const Vec3& p, const Vec3& q) {
  const Vec3 u = (p - r) - w * w.dot(p - r), v = (q - r) - w * w.dot(q - r);
  return std::atan2(w.dot(u.cross(v)), u.dot(v));
}

// Subproblem 3: angles about unit w (through r) putting p at distance d from q. n = 0, 1 or 2.
int sp3(const Vec3& w, const Vec3& r, const Vec3& p, const Vec3& q, double d, double out[2]) {
  const Vec3 u = (p - r) - w * w.dot(p - r), v = (q - r) - w * w.dot(q - r);
  const double h = w.dot(p - q);
  const double dp2 = d * d - h * h;
  const double nu = u.norm(), nv = v.norm();
  if (dp2 < 0 || nu == 0 || nv == 0) return 0;
  const double theta0 = std::atan2(w.dot(u.cross(v)), u.dot(v));
  double c = (nu * nu + nv * nv - dp2) / (2 * nu * nv);
  if (std::abs(c) > 1 + kReachSlack) return 0;
  c = std::clamp(c, -1.0, 1.0);
  const double a = std::acos(c);
  out[0] = theta0 + a, out[1] = theta0 - a;
  return 2;
}
}  // namespace

bool spherical_wrist_model(const Robot& robot, SphericalWristModel& m) {
  if (!robot.is_chain() || robot.joint_count() != 6 || has_coupled_joints(robot)) return false;
  for (const auto& j : robot.chain)
    if (j.type != JointType::revolute) return false;
  Pose f = Pose::Identity();
  for (int k = 0; k < 6; ++k) {
    const ChainJoint& j = robot.chain[static_cast<std::size_t>(k)];
    const Pose pre = f * j.origin;
    m.axis[static_cast<std::size_t>(k)] = (pre.linear() * j.axis).normalized();
    m.point[static_cast<std::size_t>(k)] = pre.translation();
    f = f * joint_transform(robot, k, 0.0);
  }
  m.zero_flange = f;
  const auto& w = m.axis;
  const auto& p = m.point;
  if (std::abs(w[0].dot(w[1])) > kParallel || w[1].cross(w[2]).norm() > kParallel) return false;
  if (w[3].cross(w[4]).norm() < 1e-6 || w[4].cross(w[5]).norm() < 1e-6) return false;
  Vec3 a, b, c, d;
  if (!closest(p[3], w[3], p[4], w[4], a, b) || !closest(p[4], w[4], p[5], w[5], c, d)) return false;
  if ((a - b).norm() > kMeet || (c - d).norm() > kMeet || (a - c).norm() > kMeet) return false;
  m.wrist = (a + b + c + d) / 4;
  m.wrist_in_flange = m.zero_flange.inverse() * m.wrist;
  // Forward = axis2 x axis1, signed so that the zero-pose wrist centre is in front.
  m.forward = (m.wrist - p[0]).dot(w[1].cross(w[0])) < 0 ? -1 : 1;
  return true;
}

// Same geometry as docs/kinematics.md §6: RIGHTY iff V = (wrist - J1 axis) . forward >= 0; ABOVE iff
// the elbow (a point of axis 3) lies on the J1-axis-direction side of the line from the
// shoulder (a point of axis 2) to the wrist centre, in the arm plane (for the PUMA exactly
// sigma_s * wrap(theta2 - atan2(pz, V)) >= 0); NOFLIP iff J5 >= 0.
Configuration spherical_configuration(const Robot& robot, const SphericalWristModel& m, const JointVector& display) {
  const JointVector q = display_to_dh(robot, display);
  std::array<Vec3, 3> axis, point;
  Pose f = Pose::Identity();
  for (int k = 0; k < 6; ++k) {
    if (k < 3) {
      const ChainJoint& j = robot.chain[static_cast<std::size_t>(k)];
      const Pose pre = f * j.origin;
      axis[static_cast<std::size_t>(k)] = pre.linear() * j.axis;
      point[static_cast<std::size_t>(k)] = pre.translation();
    }
    f = f * joint_transform(robot, k, q[k]);
  }
  const Vec3 wrist = f * m.wrist_in_flange;
  const Vec3 d = wrist - point[1];
  Configuration c;
  c.righty = m.forward * (wrist - point[0]).dot(axis[1].cross(axis[0])) >= 0;
  c.above = axis[1].dot(d.cross(point[2] - point[1])) * axis[1].dot(d.cross(axis[0])) >= 0;
  c.noflip = display[4] >= 0;
  return c;
}

void spherical_ik_all(const SphericalWristModel& m, const Pose& flange, double q4_keep, SphericalIkSolutions& out,
                      const Configuration* arm) {
  out.count = 0;
  const auto& w = m.axis;
  const auto& p = m.point;
  if (!flange.matrix().allFinite()) return;
  // Wrist centre of the target: the zero-pose wrist centre carried by the flange motion.
  const Vec3 wc = flange * m.wrist_in_flange;
  // q1: the component of (wc - p1) along axis 2 (turned by q1) is fixed by the geometry.
  const Vec3 v = wc - p[0];
  const Vec3 u = w[1], uxw = w[0].cross(w[1]);
  const double A = u.dot(v), B = uxw.dot(v), k = u.dot(m.wrist - p[0]);
  const double rho = std::hypot(A, B);
  if (rho == 0 || std::abs(k) > rho * (1 + kReachSlack)) return;  // inside the shoulder cylinder
  const double phi = std::atan2(B, A), alpha = std::acos(std::clamp(k / rho, -1.0, 1.0));
  const double q1s[2] = {phi + alpha, phi - alpha};
  for (double q1 : q1s) {
    const Mat3 r1 = rot(w[0], q1);
    const Vec3 n = r1 * w[1];  // axis 2 after q1
    const bool righty = m.forward * (wc - p[0]).dot(n.cross(w[0])) >= 0;
    if (arm && arm->righty != righty) continue;
    const Vec3 wc1 = p[0] + r1.transpose() * (wc - p[0]);  // wrist centre in the q1 = 0 arm
    double q3s[2];
    if (sp3(w[2], p[2], m.wrist, p[1], (wc1 - p[1]).norm(), q3s) == 0) continue;
    for (double q3 : q3s) {
      const Mat3 r3 = rot(w[2], q3);
      const Vec3 c3 = p[2] + r3 * (m.wrist - p[2]);
      const double q2 = sp1(w[1], p[1], c3, wc1);
      const Mat3 r2 = rot(w[1], q2);
      const Mat3 r13 = r1 * r2 * r3;
      // Configuration words of this branch from the same geometry as spherical_configuration.
      const Vec3 shoulder = p[0] + r1 * (p[1] - p[0]);
      const Vec3 elbow = p[0] + r1 * (p[1] + r2 * (p[2] - p[1]) - p[0]);
      const Vec3 dw = wc - shoulder;
      const bool above = n.dot(dw.cross(elbow - shoulder)) * n.dot(dw.cross(w[0])) >= 0;
      if (arm && arm->above != above) continue;
      const Mat3 rw = r13.transpose() * flange.linear() * m.zero_flange.linear().transpose();
      // Subproblem 2 on directions: R4 R5 w6 = rw w6.
      const Vec3 pd = w[5], qd = rw * w[5];
      const double c45 = w[3].dot(w[4]);
      const double den = c45 * c45 - 1;
      const double al = (c45 * w[4].dot(pd) - w[3].dot(qd)) / den;
      const double be = (c45 * w[3].dot(qd) - w[4].dot(pd)) / den;
      const Vec3 n45 = w[3].cross(w[4]);
      const double g2 = (1 - al * al - be * be - 2 * al * be * c45) / n45.squaredNorm();
      const double g = std::sqrt(std::max(0.0, g2));
      for (int flip = 0; flip < 2; ++flip) {
        const Vec3 cvec = al * w[3] + be * w[4] + (flip == 0 ? g : -g) * n45;
        const Vec3 qperp = qd - w[3] * w[3].dot(qd);
        const bool singular = qperp.norm() <= kWristSingular;  // axes 4 and 6 aligned
        double q4 = singular ? q4_keep : sp1(w[3], Vec3::Zero(), cvec, qd);
        double q5 = singular ? sp1(w[4], Vec3::Zero(), pd, rot(w[3], q4).transpose() * qd) : sp1(w[4], Vec3::Zero(), pd, cvec);
        const Mat3 r45 = rot(w[3], q4) * rot(w[4], q5);
        Vec3 x = w[5].unitOrthogonal();
        const double q6 = sp1(w[5], Vec3::Zero(), x, r45.transpose() * rw * x);
        JointVector q(6);
        q << q1, q2, q3, q4, q5, q6;
        for (int i = 0; i < 6; ++i)
          if (!(q[i] > -std::numbers::pi && q[i] <= std::numbers::pi)) q[i] = std::remainder(q[i], 2 * std::numbers::pi);
        if (!q.allFinite()) continue;
        const auto slot = static_cast<std::size_t>(out.count);
        out.q[slot] = q;
        out.wrist_singular[slot] = singular;
        out.righty[slot] = righty;
        out.above[slot] = above;
        ++out.count;
        if (singular) break;  // both flips coincide
      }
    }
  }
}

}  // namespace asimov::robots
