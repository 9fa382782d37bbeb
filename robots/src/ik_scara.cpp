// SCARA closed form: the flange rotation is Rot(up, phi) . R0 with phi = sum of sign_k q_k over
// the revolute joints, the quill point p4 moves along `up` by sign_3 q3, and in the plane the
// J4 axis is at p1 + Rot(psi1) (B + Rot(psi2) C). With d = |D|, b = |B|, c = |C|:
// cos beta = (d^2 - b^2 - c^2) / (2 b c), 2 b c sin beta = sqrt(((b + c)^2 - d^2)(d^2 - (b - c)^2))
// (well conditioned at full stretch), beta = psi2 + gamma the elbow angle, RIGHTY = beta in [0, pi].
#include "asimov/robots/ik_scara.hpp"

#include "ik_pairs.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace asimov::robots {
namespace {
using pairs::kFkPositionTol;
using pairs::kFkRotationTol;
constexpr double kParallel = 1e-9;
constexpr double kTilt = 1e-9;  // |R up - up| of a target the quill can reach
}  // namespace

bool scara_model(const Robot& robot, ScaraModel& m) {
  if (!robot.is_chain() || robot.joint_count() != 4) return false;
  const JointType want[4] = {JointType::revolute, JointType::revolute, JointType::prismatic, JointType::revolute};
  Vec3 axis[4], point[4];
  Pose f = Pose::Identity();
  for (int k = 0; k < 4; ++k) {
    const ChainJoint& j = robot.chain[static_cast<std::size_t>(k)];
    if (j.type != want[k]) return false;
    const Pose pre = f * j.origin;
    axis[k] = (pre.linear() * j.axis).normalized();
    point[k] = pre.translation();
    f = f * joint_transform(robot, k, 0.0);
  }
  for (int k = 1; k < 4; ++k)
    if (axis[k].cross(axis[0]).norm() > kParallel) return false;
  m.up = axis[0].z() < -kParallel ? Vec3(-axis[0]) : axis[0];
  m.e1 = m.up.unitOrthogonal();
  if (std::abs(m.up.z()) > 0.5) {  // e1 along the base's X where it can be (readable angles)
    const Vec3 x = Vec3::UnitX() - m.up * m.up.x();
    if (x.norm() > 1e-6) m.e1 = x.normalized();
  }
  m.e2 = m.up.cross(m.e1);
  for (int k = 0; k < 4; ++k) m.sign[k] = axis[k].dot(m.up) > 0 ? 1 : -1;
  const Vec3 b = point[1] - point[0], c = point[3] - point[1];
  m.bx = b.dot(m.e1), m.by = b.dot(m.e2), m.cx = c.dot(m.e1), m.cy = c.dot(m.e2);
  if (std::hypot(m.bx, m.by) < 1e-6 || std::hypot(m.cx, m.cy) < 1e-6) return false;
  m.p1 = point[0], m.p4 = point[3];
  m.p4_in_flange = f.inverse() * point[3];
  m.zero_rotation = f.linear();
  return true;
}

IkResult solve_scara(const Robot& robot, const ScaraModel& m, const Pose& flange, const JointVector& current_in,
                     const Configuration& want, bool single) {
  IkResult res;
  res.status = IkStatus::out_of_reach;
  JointVector current = current_in;
  if (current.size() != 4) current = ready_joints(robot);
  if (!flange.matrix().allFinite()) return res;
  // Orientation: a rotation about `up` only.
  const collision::Mat3 rel = flange.linear() * m.zero_rotation.transpose();
  if ((rel * m.up - m.up).norm() > kTilt) return res;
  const Vec3 re1 = rel * m.e1;
  const double phi = std::atan2(re1.dot(m.e2), re1.dot(m.e1));
  // The J4 axis point: height gives the quill, the plane the two links.
  const Vec3 t4 = flange * m.p4_in_flange;
  const double lift = m.up.dot(t4 - m.p4);
  const Vec3 dv = t4 - m.p1;
  const double dx = dv.dot(m.e1), dy = dv.dot(m.e2);
  const double b2 = m.bx * m.bx + m.by * m.by, c2 = m.cx * m.cx + m.cy * m.cy, d2 = dx * dx + dy * dy;
  const double b = std::sqrt(b2), c = std::sqrt(c2);
  const double outer = (b + c) * (b + c) - d2, inner = d2 - (b - c) * (b - c);
  if (outer < -1e-9 * (b + c) * (b + c) || inner < -1e-9 * (b + c) * (b + c)) return res;
  const double sb = std::sqrt(std::max(0.0, outer) * std::max(0.0, inner)), cb = d2 - b2 - c2;  // x 2bc
  const double beta = std::atan2(want.righty ? sb : -sb, cb);
  const double gamma = std::atan2(m.bx * m.cy - m.by * m.cx, m.bx * m.cx + m.by * m.cy);
  const double psi2 = beta - gamma;
  // psi1 turns B + Rot(psi2) C onto D (kept at the current J1 when D = 0 and b = c).
  const double cs = std::cos(psi2), sn = std::sin(psi2);
  const double ex = m.bx + cs * m.cx - sn * m.cy, ey = m.by + sn * m.cx + cs * m.cy;
  double psi1;
  if (ex * ex + ey * ey > 1e-18 * b2)
    psi1 = std::atan2(dy, dx) - std::atan2(ey, ex);
  else
    psi1 = m.sign[0] * display_to_dh(robot, current)[0];
  JointVector q(4);
  q[0] = m.sign[0] * psi1;
  q[1] = m.sign[1] * psi2;
  q[2] = m.sign[2] * lift;
  q[3] = m.sign[3] * (phi - psi1 - psi2);
  for (int i : {0, 1, 3}) q[i] = std::remainder(q[i], 2 * std::numbers::pi);
  const JointVector raw = dh_to_display(robot, q);
  JointVector sol(4);
  for (int i = 0; i < 4; ++i) {
    double v = raw[i];
    bool ok;
    if (i == 2) {
      ok = v >= robot.lower[i] - 1e-9 && v <= robot.upper[i] + 1e-9;
      v = std::clamp(v, robot.lower[i], robot.upper[i]);
    } else if (i == 3 && single) {
      v = wrap_deg(v);
      ok = v >= robot.lower[i] - 1e-9 && v <= robot.upper[i] + 1e-9;
    } else {
      ok = pairs::nearest_equivalent(raw[i], current[i], robot.lower[i], robot.upper[i], v);
      if (!ok) v = raw[i] + 360.0 * std::round((current[i] - raw[i]) / 360.0);
    }
    if (!ok) {
      res.status = IkStatus::joint_limit;
      res.joint = i;
      res.value = i == 2 ? raw[i] : v;
      return res;
    }
    sol[i] = v;
  }
  const Pose f = flange_pose(robot, sol);
  const double ep = (f.translation() - flange.translation()).norm(), er = (f.linear() - flange.linear()).norm();
  if (!(ep <= kFkPositionTol && er <= kFkRotationTol)) return res;
  res.status = IkStatus::ok;
  res.joints = sol;
  return res;
}

Configuration scara_configuration(const Robot& robot, const ScaraModel& m, const JointVector& display) {
  const JointVector q = display_to_dh(robot, display);
  const double gamma = std::atan2(m.bx * m.cy - m.by * m.cx, m.bx * m.cx + m.by * m.cy);
  Configuration c;
  c.righty = std::sin(m.sign[1] * q[1] + gamma) >= 0;
  return c;
}

}  // namespace asimov::robots
