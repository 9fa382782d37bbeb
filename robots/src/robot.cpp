// Serial-arm basics: the display <-> DH mapping (the only place that converts), standard-DH
// forward kinematics, link frames and the limit check.
#include "asimov/robots/robot.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace asimov::robots {
namespace {
constexpr double kDeg = std::numbers::pi / 180;
// Rounding slack of the limit check [deg]: IK results computed exactly on a limit pass.
constexpr double kLimitSlack = 1e-9;
}  // namespace

Pose dh_transform(const DhLink& l, double theta) {
  const double ct = std::cos(theta), st = std::sin(theta);
  const double ca = std::cos(l.alpha), sa = std::sin(l.alpha);
  Pose t = Pose::Identity();
  t.matrix() << ct, -st * ca, st * sa, l.a * ct,  //
      st, ct * ca, -ct * sa, l.a * st,            //
      0, sa, ca, l.d,                             //
      0, 0, 0, 1;
  return t;
}

void update_hand_followers(Robot& robot) {
  // A follower's leader may come later in the list: repeat until nothing changes (a chain of
  // followers is at most the list long; the loader refuses mimic cycles).
  for (std::size_t pass = 0; pass <= robot.hand.size(); ++pass)
    for (HandJoint& h : robot.hand)
      if (h.leader >= 0 && h.arm_joint < 0) {
        const HandJoint& l = robot.hand[static_cast<std::size_t>(h.leader)];
        h.open = h.multiplier * l.open + h.offset;
        h.closed = h.multiplier * l.closed + h.offset;
      }
}

bool hand_follows_arm(const Robot& robot, int k) {
  for (std::size_t guard = 0; k >= 0 && guard <= robot.hand.size(); ++guard) {
    const HandJoint& h = robot.hand[static_cast<std::size_t>(k)];
    if (h.arm_joint >= 0) return true;
    k = h.parent;
  }
  return false;
}

Pose hand_offset(const Robot& robot, int k, bool closed, const JointVector& q) {
  Pose out = Pose::Identity();
  // Parents first in the list, so the walk up ends; the depth is bounded by the list's size.
  for (std::size_t guard = 0; k >= 0 && guard <= robot.hand.size(); ++guard) {
    const HandJoint& h = robot.hand[static_cast<std::size_t>(k)];
    const double leader = h.arm_joint >= 0 && h.arm_joint < q.size() ? q[h.arm_joint] : 0.0;
    const double v = h.arm_joint >= 0 ? h.multiplier * leader + h.offset : closed ? h.closed : h.open;
    Pose m = Pose::Identity();
    if (h.type == JointType::prismatic) m.translation() = h.axis * v;
    else m.linear() = Eigen::AngleAxisd(v * kDeg, h.axis).toRotationMatrix();
    out = h.origin * m * h.origin.inverse() * out;
    k = h.parent;
  }
  return out;
}

double wrap_deg(double deg) {
  double w = std::remainder(deg, 360.0);  // [-180, 180]
  if (w <= -180) w += 360;
  return w;
}

JointVector display_to_dh(const Robot& robot, const JointVector& display) {
  JointVector q(display.size());
  for (Eigen::Index i = 0; i < display.size(); ++i) {
    const auto& m = robot.mapping[static_cast<std::size_t>(i)];
    const double unit = robot.prismatic(static_cast<int>(i)) ? 1.0 : kDeg;
    q[i] = m.sign * display[i] * unit + m.offset;
  }
  return q;
}

JointVector dh_to_display(const Robot& robot, const JointVector& dh) {
  JointVector d(dh.size());
  for (Eigen::Index i = 0; i < dh.size(); ++i) {
    const auto& m = robot.mapping[static_cast<std::size_t>(i)];
    const double unit = robot.prismatic(static_cast<int>(i)) ? 1.0 : kDeg;
    d[i] = (dh[i] - m.offset) / unit * m.sign;
  }
  return d;
}

JointVector ready_joints(const Robot& robot) {
  const int n = robot.joint_count();
  if (robot.ready.size() == n) return robot.ready;
  JointVector j = JointVector::Zero(n);
  if (n >= 3) j[1] = -90, j[2] = 90;
  return j;
}

bool is_puma_type(const Robot& robot) {
  if (robot.is_chain() || robot.dh.size() != 6 || robot.mapping.size() != 6) return false;
  constexpr double h = std::numbers::pi / 2, tol = 1e-12;
  const double alpha[6] = {h, 0, -h, h, -h, 0};
  for (std::size_t i = 0; i < 6; ++i)
    if (std::abs(robot.dh[i].alpha - alpha[i]) > tol) return false;
  const auto& d = robot.dh;
  return d[0].d == 0 && d[0].a == 0 && d[1].d == 0 && d[3].a == 0 && d[4].a == 0 && d[4].d == 0;
}

double link_offset_bound(const Robot& robot, int k) {
  const auto i = static_cast<std::size_t>(k);
  if (!robot.is_chain()) return std::hypot(robot.dh[i].a, robot.dh[i].d);
  const ChainJoint& j = robot.chain[i];
  double b = j.origin.translation().norm();
  const double travel = std::max(std::abs(robot.lower[k]), std::abs(robot.upper[k]));  // display
  if (j.type == JointType::prismatic) b += travel;
  for (const CoupledJoint& c : j.coupled) {
    b += c.origin.translation().norm();
    if (c.type == JointType::prismatic)  // its travel: |multiplier| x the leader's (internal) + |offset|
      b += std::abs(c.multiplier) * (j.type == JointType::prismatic ? travel : travel * std::numbers::pi / 180) + std::abs(c.offset);
  }
  if (k + 1 == robot.joint_count()) b += robot.flange_offset.translation().norm();
  return b;
}

Pose joint_transform(const Robot& robot, int k, double q) {
  const auto i = static_cast<std::size_t>(k);
  if (!robot.is_chain()) return dh_transform(robot.dh[i], q);
  const ChainJoint& j = robot.chain[i];
  Pose t = j.origin;
  if (j.type == JointType::revolute)
    t.rotate(Eigen::AngleAxisd(q, j.axis));
  else
    t.translate(q * j.axis);
  for (const CoupledJoint& c : j.coupled) {
    t = t * c.origin;
    const double v = c.multiplier * q + c.offset;
    if (c.type == JointType::revolute) t.rotate(Eigen::AngleAxisd(v, c.axis));
    else t.translate(v * c.axis);
  }
  if (k + 1 == robot.joint_count()) t = t * robot.flange_offset;
  return t;
}

bool has_coupled_joints(const Robot& robot) {
  return std::any_of(robot.chain.begin(), robot.chain.end(), [](const ChainJoint& j) { return !j.coupled.empty(); });
}

Pose joint_screws(const Robot& robot, int k, double q, const Pose& frame_k, JointScrews& out) {
  out.count = 0;
  if (!robot.is_chain()) {
    out.screw[0] = {frame_k.linear().col(2), frame_k.translation(), 1.0, JointType::revolute};
    out.count = 1;
    return frame_k * joint_transform(robot, k, q);
  }
  const ChainJoint& j = robot.chain[static_cast<std::size_t>(k)];
  Pose f = frame_k * j.origin;
  out.screw[0] = {f.linear() * j.axis, f.translation(), 1.0, j.type};
  out.count = 1;
  if (j.type == JointType::revolute) f.rotate(Eigen::AngleAxisd(q, j.axis));
  else f.translate(q * j.axis);
  for (const CoupledJoint& c : j.coupled) {
    f = f * c.origin;
    if (out.count < static_cast<int>(out.screw.size())) out.screw[static_cast<std::size_t>(out.count++)] = {f.linear() * c.axis, f.translation(), c.multiplier, c.type};
    const double v = c.multiplier * q + c.offset;
    if (c.type == JointType::revolute) f.rotate(Eigen::AngleAxisd(v, c.axis));
    else f.translate(v * c.axis);
  }
  if (k + 1 == robot.joint_count()) f = f * robot.flange_offset;
  return f;
}

void link_frames(const Robot& robot, const JointVector& display, std::vector<Pose>& frames) {
  const JointVector q = display_to_dh(robot, display);
  const auto n = static_cast<std::size_t>(robot.joint_count());
  frames.resize(n + 1);
  frames[0] = Pose::Identity();
  for (std::size_t k = 0; k < n; ++k)
    frames[k + 1] = frames[k] * joint_transform(robot, static_cast<int>(k), q[static_cast<Eigen::Index>(k)]);
}

Pose flange_pose_dh(const Robot& robot, const JointVector& q) {
  Pose t = Pose::Identity();
  const int n = robot.joint_count();
  for (int k = 0; k < n; ++k) t = t * joint_transform(robot, k, q[k]);
  return t;
}

Pose flange_pose(const Robot& robot, const JointVector& display) {
  return flange_pose_dh(robot, display_to_dh(robot, display));
}

double limit_low(const Robot& robot, int j) {
  return robot.lower[j] - (j < robot.limit_tolerance.size() ? robot.limit_tolerance[j] : 0.0);
}
double limit_high(const Robot& robot, int j) {
  return robot.upper[j] + (j < robot.limit_tolerance.size() ? robot.limit_tolerance[j] : 0.0);
}

int first_limit_violation(const Robot& robot, const JointVector& display) {
  for (Eigen::Index i = 0; i < display.size(); ++i) {  // written so that NaN fails
    const int j = static_cast<int>(i);
    if (!(display[i] >= limit_low(robot, j) - kLimitSlack && display[i] <= limit_high(robot, j) + kLimitSlack)) return j;
  }
  return -1;
}

}  // namespace asimov::robots
