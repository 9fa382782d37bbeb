#include "examples.hpp"

#include "asimov/robots/ik.hpp"
#include "asimov/robots/puma560.hpp"

using namespace asimov::robots;

// FK of a PUMA 560 pose, then IK back from READY in the same configuration: the flange error.
double ik_round_trip_error_mm() {
  const Robot robot = puma560();
  JointVector q(6);
  q << 10, -80, 100, 20, 30, 40;                 // display joints [deg]
  const Pose flange = flange_pose(robot, q);     // FK, mm
  const IkResult ik = solve_ik(robot, flange, ready_joints(robot), configuration_of(robot, q), /*single=*/true);
  if (ik.status != IkStatus::ok) return -1;
  return (flange_pose(robot, ik.joints).translation() - flange.translation()).norm();
}
