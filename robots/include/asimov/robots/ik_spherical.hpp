// Closed-form IK of 6R arms with J1 perpendicular to J2, J2 parallel to J3 and a spherical
// wrist (axes 4, 5, 6 meet in one point), the common industrial geometry (PUMA, generic6, most
// 6-axis arms with shoulder offsets), by Paden-Kahan subproblems on the product of
// exponentials FK(q) = exp(xi1 q1) ... exp(xi6 q6) M taken at the zero pose. Up to 8 solutions.
#pragma once
#include "asimov/robots/robot.hpp"
#include <array>

namespace asimov::robots {

// Joint axes at the zero pose (robot frame), the wrist centre and the flange at zero.
struct SphericalWristModel {
  std::array<Vec3, 6> axis;   // unit directions
  std::array<Vec3, 6> point;  // a point on each axis [mm]
  Vec3 wrist = Vec3::Zero();  // where axes 4, 5, 6 meet [mm]
  Pose zero_flange = Pose::Identity();
  Vec3 wrist_in_flange = Vec3::Zero();  // the wrist centre in the flange frame [mm]
  double forward = 1;  // sign making the zero-pose wrist centre "in front" (configuration words)
};

// True (and `out` filled) when the robot has 6 revolute joints in this geometry (tolerances:
// 1e-9 on direction products, 1e-6 mm on the wrist intersection).
bool spherical_wrist_model(const Robot& robot, SphericalWristModel& out);

// Configuration words of such an arm at `display` joints (see configuration.hpp); no heap.
struct Configuration;
Configuration spherical_configuration(const Robot& robot, const SphericalWristModel& model, const JointVector& display);

struct SphericalIkSolutions {
  std::array<JointVector, 8> q;  // internal values [rad]
  std::array<bool, 8> wrist_singular{};
  std::array<bool, 8> righty{}, above{};  // configuration words of the arm branch (as spherical_configuration)
  int count = 0;
};

// All solutions for `flange` (robot frame). At the wrist singularity (axes 4 and 6 aligned) q4
// is `q4_keep` [rad, internal] and q6 takes the rest. count = 0: out of reach.
// With `arm` set, only the arm branch with those RIGHTY / ABOVE words is solved (its two wrist
// solutions; the NOFLIP word is left to the caller).
void spherical_ik_all(const SphericalWristModel& model, const Pose& flange, double q4_keep, SphericalIkSolutions& out,
                      const Configuration* arm = nullptr);

}  // namespace asimov::robots
