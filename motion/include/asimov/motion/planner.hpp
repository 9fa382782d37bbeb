// The planner: a motion request and the arm's current state -> a trajectory (trajectory.hpp),
// or the VAL error that refuses it before anything moves. Joint moves: limits checked, one
// synchronised profile over the joints, the checked-pose grid from the step rule. Transformation
// targets: IK in the current configuration overridden by the pending requests. Straight lines:
// solved over the whole path first (plan_line), profiled with the tool and every joint as axes,
// stretched for the path's curvature (fit_path_acceleration). Free functions, no state.
#pragma once
#include "asimov/motion/motion_result.hpp"
#include "asimov/motion/trajectory.hpp"
#include "asimov/robots/configuration.hpp"
#include "asimov/robots/displacement_bound.hpp"

#include <span>

namespace asimov::motion {

// What the planner needs of the arm and its cell, and where the arm stands.
struct PlanStart {
  const robots::Robot& robot;
  std::span<const robots::BodyReach> reach;             // World::reach()
  std::span<const collision::BodyPair> moving_pairs;    // World::moving_pairs()
  double step_mm = 1;                                   // step_mm(cell.collision)
  const robots::JointVector& joints;                    // display [deg]
  const Location& base;                                 // program BASE / TOOL
  const Location& tool;
  double time_s = 0;                                    // the trajectory starts here
};

struct Plan {
  MotionResult result;      // ok, or status error with the VAL message
  Trajectory trajectory;    // when ok
  PoseError ik_residual;    // IK solves of the planning (also when refused: straight lines)
  std::uint64_t ik_solves = 0;
};

// A joint move to display joints `target` (precision point, READY, DRIVE, resume).
Plan plan_joint_move(const PlanStart& start, const robots::JointVector& target, const SpeedSettings& speed, int step);

// A move to the transformation `target` (HERE = BASE . FK . TOOL): joint-interpolated, or a
// straight line of the tool point. A joint-interpolated move consumes the pending
// configuration words of `request` (RIGHTY, ABOVE, FLIP ...) when it is planned.
Plan plan_move(const PlanStart& start, robots::ConfigurationRequest& request, const Location& target, bool straight,
               const SpeedSettings& speed, int step);

// INRANGE: 0 reachable within limits in the requested configuration, 1 out of reach, 2 a joint
// limit in the way (same IK as a joint move to `target`).
int inrange(const PlanStart& start, const robots::ConfigurationRequest& request, const Location& target);

}  // namespace asimov::motion
