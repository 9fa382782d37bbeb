// SCARA closed form: the flange rotation is Rot(up, phi) . R0 with phi = sum of sign_k q_k over
// the revolute joints, the quill point p4 moves along `up` by sign_3 q3, and in the plane the
// J4 axis is at p1 + Rot(psi1) (B + Rot(psi2) C). With d = |D|, b = |B|, c = |C|:
// cos beta = (d^2 - b^2 - c^2) / (2 b c), 2 b c sin beta = sqrt(((b + c)^2 - d^2)(d^2 - (b - c)^2))
// (well conditioned at full stretch), beta = psi2 + gamma the elbow angle, RIGHTY = beta in [0, pi].
// Angles are carried as unit (cos, sin) pairs and read off once (ik_pairs.hpp), no libm trigonometry.
#include "asimov/robots/ik_scara.hpp"
#include "ik_family.hpp"

#include "ik_pairs.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

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
  using pairs::angle_of;
  IkResult res;
  res.status = IkStatus::out_of_reach;
  JointVector current = current_in;
  if (current.size() != 4) current = ready_joints(robot);
  if (!flange.matrix().allFinite()) return res;
  // Orientation: a rotation about `up` only; (cf, sf) its angle phi.
  const collision::Mat3 rel = flange.linear() * m.zero_rotation.transpose();
  if ((rel * m.up - m.up).norm() > kTilt) return res;
  const Vec3 re1 = rel * m.e1;
  double cf = re1.dot(m.e1), sf = re1.dot(m.e2);
  const double nf = 1 / std::sqrt(cf * cf + sf * sf);
  cf *= nf, sf *= nf;
  // The J4 axis point: height gives the quill, the plane the two links.
  const Vec3 t4 = flange * m.p4_in_flange;
  const double lift = m.up.dot(t4 - m.p4);
  const Vec3 dv = t4 - m.p1;
  const double dx = dv.dot(m.e1), dy = dv.dot(m.e2);
  const double b2 = m.bx * m.bx + m.by * m.by, c2 = m.cx * m.cx + m.cy * m.cy, d2 = dx * dx + dy * dy;
  const double b = std::sqrt(b2), c = std::sqrt(c2);
  const double outer = (b + c) * (b + c) - d2, inner = d2 - (b - c) * (b - c);
  if (outer < -1e-9 * (b + c) * (b + c) || inner < -1e-9 * (b + c) * (b + c)) return res;
  // Elbow angle beta as a unit pair (x 2bc), then psi2 = beta - gamma, gamma the zero-pose angle B -> C.
  double sb = std::sqrt(std::max(0.0, outer) * std::max(0.0, inner)), cb = d2 - b2 - c2;
  if (!want.righty) sb = -sb;
  const double nb = 1 / std::sqrt(cb * cb + sb * sb);
  cb *= nb, sb *= nb;
  const double ig = 1 / (b * c);
  const double cg = (m.bx * m.cx + m.by * m.cy) * ig, sg = (m.bx * m.cy - m.by * m.cx) * ig;
  const double c2p = cb * cg + sb * sg, s2p = sb * cg - cb * sg;
  // psi1 turns e = B + Rot(psi2) C onto D (|e| = |D|); kept at the current J1 when both vanish.
  const double ex = m.bx + c2p * m.cx - s2p * m.cy, ey = m.by + s2p * m.cx + c2p * m.cy;
  double c1p, s1p;
  const double ee = ex * ex + ey * ey;
  if (ee > 1e-18 * b2 && d2 > 1e-18 * b2) {
    c1p = ex * dx + ey * dy, s1p = ex * dy - ey * dx;
    const double n1 = 1 / std::sqrt(c1p * c1p + s1p * s1p);
    c1p *= n1, s1p *= n1;
  } else {
    const double t = m.sign[0] * display_to_dh(robot, current)[0];
    c1p = std::cos(t), s1p = std::sin(t);
  }
  // psi3 = phi - psi1 - psi2 (J4 takes the rest of the roll).
  const double c12 = c1p * c2p - s1p * s2p, s12 = s1p * c2p + c1p * s2p;
  const double c3p = cf * c12 + sf * s12, s3p = sf * c12 - cf * s12;
  JointVector q(4);
  q[0] = m.sign[0] * angle_of(s1p, c1p);
  q[1] = m.sign[1] * angle_of(s2p, c2p);
  q[2] = m.sign[2] * lift;
  q[3] = m.sign[3] * angle_of(s3p, c3p);
  const JointVector raw = dh_to_display(robot, q);
  JointVector sol(4);
  for (int i = 0; i < 4; ++i) {
    double v = raw[i];
    bool ok;
    if (i == 2) {
      ok = v >= limit_low(robot, i) - 1e-9 && v <= limit_high(robot, i) + 1e-9;
      v = std::clamp(v, limit_low(robot, i), limit_high(robot, i));
    } else if (i == 3 && single) {
      v = wrap_deg(v);
      ok = v >= limit_low(robot, i) - 1e-9 && v <= limit_high(robot, i) + 1e-9;
    } else {
      ok = pairs::nearest_equivalent(raw[i], current[i], limit_low(robot, i), limit_high(robot, i), v);
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
  // FK check from the pairs: the J4 axis point in the plane (catches the reach clamps) and the
  // tilt (the rotation is Rot(up, phi) R0 exactly otherwise).
  const double fx = c1p * ex - s1p * ey - dx, fy = s1p * ex + c1p * ey - dy;
  const double ep = std::sqrt(fx * fx + fy * fy), er = (rel * m.up - m.up).norm();
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

namespace {
// scara_model of the arm of the previous call on this thread (the simulator solves for one arm
// again and again; building the model costs as much as the solve), the chain compared by value.
bool cached_scara_model(const Robot& robot, ScaraModel& out) {
  if (!robot.is_chain() || robot.joint_count() != 4) return false;
  thread_local std::vector<ChainJoint> key;
  thread_local Pose key_flange = Pose::Identity();
  thread_local bool key_is_scara = false;
  thread_local ScaraModel model;
  bool same = key.size() == robot.chain.size() && key_flange.matrix() == robot.flange_offset.matrix();
  for (std::size_t k = 0; same && k < key.size(); ++k)
    same = key[k].type == robot.chain[k].type && key[k].axis == robot.chain[k].axis &&
           key[k].origin.matrix() == robot.chain[k].origin.matrix();
  if (!same) {
    key = robot.chain, key_flange = robot.flange_offset;
    key_is_scara = scara_model(robot, model);
  }
  if (key_is_scara) out = model;
  return key_is_scara;
}

bool is_scara(const Robot& robot) {
  ScaraModel m;
  return cached_scara_model(robot, m);
}
IkResult solve_scara_family(const Robot& robot, const Pose& flange, const JointVector& current, const Configuration& want,
                            bool single) {
  ScaraModel m;
  cached_scara_model(robot, m);
  return solve_scara(robot, m, flange, current, want, single);
}
Configuration scara_family_configuration(const Robot& robot, const JointVector& display) {
  ScaraModel m;
  cached_scara_model(robot, m);
  return scara_configuration(robot, m, display);
}
// LEFTY / RIGHTY is the elbow of a SCARA; ABOVE / BELOW and FLIP / NOFLIP mean nothing there.
bool scara_word_applies(ConfigurationWord word) { return word == ConfigurationWord::arm; }
}  // namespace

const IkFamily scara_family{"scara", is_scara, solve_scara_family, scara_family_configuration, scara_word_applies};

}  // namespace asimov::robots
