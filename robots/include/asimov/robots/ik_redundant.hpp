// Straight lines for redundant arms (n > 6 joints): the IK answer at a pose must not depend on
// how the path reached it, or a line sampled at two steps ends in two postures. For n > 6 the
// answer is the solution nearest a fixed reference (the line's start joints): min |q - q_ref|
// subject to FK(q) = pose, a function of the pose alone (docs/robots.md "Redundant arms").
#pragma once
#include "asimov/robots/ik.hpp"

namespace asimov::robots {

// n <= 6: solve_ik(robot, flange, seed, want, false) (the closed forms are already functions of
// the pose). n > 6: the joints nearest `reference` (revolute in rad, prismatic in mm divided by
// half the arm's reach) reaching `flange`, found from `seed` by the minimum-norm step towards the
// reference; out_of_reach when that does not converge to 1e-6 mm / 1e-9 rad (a singular or
// unreachable pose), joint_limit (joint, value) when the answer leaves a joint's limits.
IkResult solve_line_ik(const Robot& robot, const Pose& flange, const JointVector& seed, const JointVector& reference,
                       const Configuration& want);

// The redundant solver itself (n > 6; any n works).
IkResult solve_nearest_reference(const Robot& robot, const Pose& flange, const JointVector& seed,
                                 const JointVector& reference);

}  // namespace asimov::robots
