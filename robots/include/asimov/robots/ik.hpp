// IK for any arm, as the simulator needs it: the closed form for a PUMA-type DH arm
// (is_puma_type), for a Viper-type DH arm (is_viper_type, ik_viper.hpp), for a SCARA chain
// (scara_model, ik_scara.hpp), the Paden-Kahan closed form for a 6R chain with J1 _|_ J2 || J3 and a
// spherical wrist (spherical_wrist_model; the solution in the requested configuration nearest
// the current joints within limits, J4 kept at the wrist singularity), the numeric solver seeded
// with the current joints otherwise. SINGLE / MULTIPLE govern the last revolute joint of any arm.
#pragma once
#include "asimov/robots/ik_numeric.hpp"
#include "asimov/robots/ik_puma.hpp"

#include <optional>

namespace asimov::robots {

// PUMA-type: solve_puma(robot, flange, current, want, single). Spherical-wrist chains: the
// closed form in configuration `want`. Other arms: configuration words do not apply;
// solve_numeric from `current` (nearest solution first, then restarts), revolute joints moved to
// the 2pi-equivalent nearest `current` inside the limits. SINGLE (`single`) applies to every
// arm: the last revolute joint (last_revolute_joint; the PUMA's J6) is taken in (-180, 180],
// joint_limit when that value is outside its limits; MULTIPLE (false) takes it like the others.
// When no solution within limits is found, a solve without limits tells joint_limit (naming
// the first joint outside, value as found) from out_of_reach.
IkResult solve_ik(const Robot& robot, const Pose& flange, const JointVector& current, const Configuration& want,
                  bool single, const NumericIkOptions& options = {});

// Distances [mm] of a flange position (in the base frame) from the arm's position singularities,
// for the families that know theirs (docs/kinematics.md §7): the shoulder's (the wrist centre
// reaching the J1 axis) and the elbow's (arm stretched or folded). Empty for other arms, whose
// straight lines are checked for joint jumps only.
struct ReachMargins {
  double shoulder_mm;
  double elbow_mm;
};
std::optional<ReachMargins> reach_margins(const Robot& robot, const Vec3& flange_position);

// Index of the last revolute joint (the one SINGLE / MULTIPLE govern), -1 if there is none.
int last_revolute_joint(const Robot& robot);

}  // namespace asimov::robots
