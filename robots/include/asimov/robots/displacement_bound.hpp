// Displacement bound of a rigid body carried by a serial arm (docs/collision-method.md §6.3).
// For body k on link k and joint j <= k, R_jk bounds the distance from axis j to any point of
// the body, whatever the joint values: R_jk = sum_{i=j..k} sqrt(a_i^2 + d_i^2) + |s_k| + rho_k,
// where (s_k, rho_k) is a bounding sphere of the body in frame k. Over a joint step dq [rad]
// every point of the body moves at most sum_j |dq_j| * R_jk. For a chain robot the link offsets
// are link_offset_bound(); a prismatic joint j gets R_jk = 180/pi, so that |dq_j| [mm] * pi/180 *
// R_jk is its travel.
#pragma once
#include "asimov/robots/robot.hpp"
#include <array>

namespace asimov::robots {

struct BodyReach {
  std::array<double, kMaxJoints> radius{};  // R_jk per joint [mm]; 0 for joints after the link
};

// For a mesh given in DH frame `link` (0 = fixed base: all radii 0).
BodyReach body_reach(const Robot& robot, const collision::Polyhedron& mesh, int link);

// For one of the robot's bodies: body_reach of its mesh, or for a body moved by hand joints
// (LinkBody::hand) the larger of its open and closed places; a follower of arm joint j also
// turns (or slides) by |multiplier| dq_j on its own: the ball about its joint origin that holds
// the body at every joint value, and radius[j] grows by |multiplier| times that ball's radius
// (180/pi for a sliding follower). Pairs with such a body have no common frame
// (motion::GapPair: link -1).
BodyReach body_reach(const Robot& robot, const LinkBody& body);

// Upper bound [mm] of the displacement of any body point for a display joint step [deg].
double max_displacement(const BodyReach& reach, const JointVector& delta_display);

}  // namespace asimov::robots
