// Closed-form inverse kinematics of a PUMA-type arm (docs/kinematics.md §5, Paul & Zhang 1986):
// all 8 solutions in a fixed array, then selection by configuration, 2pi-equivalents and limits.
#pragma once
#include "asimov/robots/configuration.hpp"
#include "asimov/robots/robot.hpp"
#include <array>
#include <utility>

namespace asimov::robots {

struct IkCandidate {
  JointVector dh;              // DH angles [rad], theta in (-pi, pi] except theta4 when singular
  Configuration config;        // RIGHTY/ABOVE/NOFLIP of this branch
  bool wrist_singular = false; // theta5 = 0: FLIP and NOFLIP merge, theta4 kept
  bool valid = false;
};
using IkCandidates = std::array<IkCandidate, 8>;  // index = 4*lefty + 2*below + flip

enum class IkStatus { ok, out_of_reach, joint_limit };

struct IkResult {
  IkStatus status = IkStatus::ok;
  JointVector joints;   // display [deg] when ok
  int joint = -1;       // joint_limit: 0-based index of the joint that breaks its limit
  double value = 0;     // joint_limit: its display value [deg] (the equivalent nearest the range)
};

// The 8 solutions for a flange pose in the robot frame. `theta4_keep` [rad, DH] is used at the
// wrist singularity. Returns out_of_reach (no candidate valid) or ok.
IkStatus puma_ik_all(const Robot& robot, const Pose& flange, double theta4_keep, IkCandidates& out);

// Solution in configuration `want`, joints taken as the 2pi-equivalent nearest `current`
// (display) inside the limits; J6 in (-180, 180] when `single`. FK-checked.
IkResult solve_puma(const Robot& robot, const Pose& flange, const JointVector& current,
                    const Configuration& want, bool single);

// Maximum FK error of a DH solution against the target: position [mm] and rotation (Frobenius).
std::pair<double, double> fk_error(const Robot& robot, const JointVector& dh, const Pose& target);

}  // namespace asimov::robots
