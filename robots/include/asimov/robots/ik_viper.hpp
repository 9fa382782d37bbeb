// Closed-form IK of 6R arms of the Viper type (docs/robots.md "viper_s650"): standard DH with
// alpha = (-90, 0, -90, 90, -90, 0) deg, d2 = d3 = d5 = 0, a4 = a5 = a6 = 0; a shoulder offset a1,
// a base height d1, a3, d4 and a flange distance d6 are free. All 8 solutions (index
// 4*lefty + 2*below + flip, as the PUMA's), or the requested one with limits and equivalents.
#pragma once
#include "asimov/robots/configuration.hpp"
#include "asimov/robots/ik_puma.hpp"
#include "asimov/robots/robot.hpp"

namespace asimov::robots {

bool is_viper_type(const Robot& robot);

// The 8 candidates for `flange` (robot frame). theta1_keep / theta4_keep [rad, DH]: used when the
// wrist centre is on the J1 axis (shoulder singular) / at the wrist singularity.
IkStatus viper_ik_all(const Robot& robot, const Pose& flange, double theta1_keep, double theta4_keep,
                      IkCandidates& out);

// As solve_puma: the requested configuration only, each joint the 2pi-equivalent nearest `current`
// inside the limits, the last joint in (-180, 180] when `single`; FK-checked (1e-6 mm / 1e-9).
IkResult solve_viper(const Robot& robot, const Pose& flange, const JointVector& current,
                     const Configuration& want, bool single);

// Configuration words at `display` joints: RIGHTY iff the wrist centre is in front of J1
// (rho = its distance along x1 >= 0), ABOVE iff the elbow lies on the upper side of the line from
// the J2 axis to the wrist centre (sign(R) * cross >= 0, R the wrist's reach past the J2 axis),
// NOFLIP iff displayed J5 >= 0 — the words of the PUMA and of spherical-wrist chains.
Configuration viper_configuration(const Robot& robot, const JointVector& display);

}  // namespace asimov::robots
