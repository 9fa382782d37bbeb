// Closed-form IK of SCARA chains (docs/robots.md "cobra_s600"): four joints revolute, revolute,
// prismatic, revolute whose axes (and the prismatic direction) are all parallel. The flange can
// only turn about that axis: a target tilted off it is out of reach. RIGHTY/LEFTY is the elbow;
// ABOVE/BELOW and FLIP/NOFLIP have no meaning on such an arm.
#pragma once
#include "asimov/robots/configuration.hpp"
#include "asimov/robots/ik_puma.hpp"
#include "asimov/robots/robot.hpp"

namespace asimov::robots {

// The arm at its zero pose, in the robot frame.
struct ScaraModel {
  Vec3 up = Vec3::UnitZ();        // the common axis direction, signed towards the base's +Z
  Vec3 e1 = Vec3::UnitX(), e2 = Vec3::UnitY();  // basis of the plane normal to `up`
  double sign[4] = {1, 1, 1, 1};  // axis_k . up
  double bx = 0, by = 0;          // J1 axis -> J2 axis, in the plane (e1, e2) [mm]
  double cx = 0, cy = 0;          // J2 axis -> J4 axis
  Vec3 p1 = Vec3::Zero(), p4 = Vec3::Zero();  // points on the J1 and J4 axes
  Vec3 p4_in_flange = Vec3::Zero();           // p4 in the zero-pose flange frame
  collision::Mat3 zero_rotation = collision::Mat3::Identity();  // flange rotation at zero
};

// True (and `out` filled) for a chain R, R, P, R with parallel axes (1e-9) and links > 0.
bool scara_model(const Robot& robot, ScaraModel& out);

// The solution with the requested elbow (want.righty; the other words are ignored), each revolute
// joint the 2pi-equivalent nearest `current` inside the limits, J4 in (-180, 180] when `single`.
// FK-checked (1e-6 mm / 1e-9 rad). out_of_reach also when the target's approach is tilted.
IkResult solve_scara(const Robot& robot, const ScaraModel& model, const Pose& flange, const JointVector& current,
                     const Configuration& want, bool single);

// RIGHTY iff the elbow turns counterclockwise seen from `up` (link 1 x link 2 . up >= 0: the
// elbow lies right of the line from J1 to the quill); ABOVE and NOFLIP are reported true.
Configuration scara_configuration(const Robot& robot, const ScaraModel& model, const JointVector& display);

}  // namespace asimov::robots
