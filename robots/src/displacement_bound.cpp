#include "asimov/robots/displacement_bound.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace asimov::robots {

BodyReach body_reach(const Robot& robot, const collision::Polyhedron& mesh, int link) {
  BodyReach r;
  if (link <= 0 || mesh.vertices.empty()) return r;
  // Two bounding spheres, keep the smaller bound: centred at the frame origin, and centred at
  // the centre of the body's box.
  Vec3 lo = mesh.vertices.front(), hi = lo;
  for (const auto& v : mesh.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
  const Vec3 centre = (lo + hi) / 2;
  double rho_origin = 0, rho_centre = 0;
  for (const auto& v : mesh.vertices) {
    rho_origin = std::max(rho_origin, v.norm());
    rho_centre = std::max(rho_centre, (v - centre).norm());
  }
  const double sphere = std::min(rho_origin, centre.norm() + rho_centre);
  const int n = std::min(link, robot.joint_count());
  for (int j = 0; j < n; ++j) {  // joint j+1 turns about an axis through o_j (DH) or o_{j+1} (chain)
    double chain = 0;            // |o_j - o_link| <= sum of the link offsets in between
    for (int i = j; i < link; ++i) chain += link_offset_bound(robot, i);
    if (robot.prismatic(j)) {     // every point of the body moves by exactly |dq| [mm]
      r.radius[static_cast<std::size_t>(j)] = 180 / std::numbers::pi;
      if (robot.is_chain())  // coupled joints: per mm of the leader, |rate| mm or |rate| rad x the distance
        for (const CoupledJoint& c : robot.chain[static_cast<std::size_t>(j)].coupled)
          r.radius[static_cast<std::size_t>(j)] += std::abs(c.multiplier) * (c.type == JointType::prismatic ? 1.0 : chain + sphere) * 180 / std::numbers::pi;
      continue;
    }
    r.radius[static_cast<std::size_t>(j)] = chain + sphere;
    // Coupled joints turn (or slide) with joint j at their rates, about axes as near the body
    // as o_j's: each adds |rate| x that distance (a sliding one |rate| mm per rad).
    if (robot.is_chain())
      for (const CoupledJoint& c : robot.chain[static_cast<std::size_t>(j)].coupled)
        r.radius[static_cast<std::size_t>(j)] += std::abs(c.multiplier) * (c.type == JointType::prismatic ? 1.0 : chain + sphere);
  }
  return r;
}

BodyReach body_reach(const Robot& robot, const LinkBody& body) {
  if (body.hand < 0) return body_reach(robot, body.mesh, body.link);
  if (hand_follows_arm(robot, body.hand)) {
    // The loader allows such a follower only straight on the arm, with no hand joint on it.
    const HandJoint& h = robot.hand[static_cast<std::size_t>(body.hand)];
    const Vec3 o = h.origin.translation();
    double r = 0;
    for (const auto& v : body.mesh.vertices) r = std::max(r, (v - o).norm());
    collision::Polyhedron ball = collision::make_box(Vec3::Constant(2 * r));  // holds the ball about o
    for (auto& v : ball.vertices) v += o;
    BodyReach out = body_reach(robot, ball, body.link);
    out.radius[static_cast<std::size_t>(h.arm_joint)] +=
        std::abs(h.multiplier) * (h.type == JointType::prismatic ? 180 / std::numbers::pi : r);
    return out;
  }
  BodyReach out = body_reach(robot, body.mesh, body.link);
  for (const bool closed : {false, true}) {  // the hand jumps between the two places
    const BodyReach c = body_reach(robot, collision::transformed(body.mesh, hand_offset(robot, body.hand, closed)), body.link);
    for (std::size_t j = 0; j < out.radius.size(); ++j) out.radius[j] = std::max(out.radius[j], c.radius[j]);
  }
  return out;
}

double max_displacement(const BodyReach& reach, const JointVector& delta_display) {
  constexpr double kDeg = std::numbers::pi / 180;
  double s = 0;
  for (Eigen::Index j = 0; j < delta_display.size(); ++j)
    s += std::abs(delta_display[j]) * kDeg * reach.radius[static_cast<std::size_t>(j)];
  return s;
}

}  // namespace asimov::robots
