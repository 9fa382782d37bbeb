// A planned motion as plain data: what the planner hands the walker. One segment today (a
// joint move straight in joint space, or a straight line of the tool point), its speed profile
// and where it starts on the simulated clock; the exact path at any time t (path_joints).
//
// Blending (#16) makes this a list of overlapping segments; the walker only needs the exact
// path, the checked-pose grid and the stepping bounds from it (motion/README.md, extensions).
#pragma once
#include "asimov/motion/interpolation.hpp"
#include "asimov/motion/profile.hpp"
#include "asimov/motion/sampler.hpp"
#include "asimov/robots/configuration.hpp"

namespace asimov::motion {

struct SpeedSettings {
  double monitor = 100;  // monitor speed [%]
  double program = 100;  // program speed for this motion [%]
  double rotation = -1;  // program speed of straight-line rotation [%]; < 0: same as program
  double duration_s = 0; // DURATION: minimum motion time [s]; 0 = off
};

enum class PathKind { joint, line };

struct Trajectory {
  PathKind kind = PathKind::joint;
  robots::JointVector from, to;   // display joints at sigma = 0 and 1
  int intervals = 1;              // joint moves: equal sigma intervals of the checked-pose grid
  LinePlan line;                  // lines: the solved samples (the checked-pose grid)
  LinePath path;                  // lines: the tool-point line, and what maps it to the flange,
  Location base_inv, tool_inv;    //   for poses between samples
  Location base, tool;            // program BASE / TOOL when planned (line deviation)
  robots::Configuration config;   // lines: kept along the path
  Profile profile;
  SpeedSettings speed;
  double t0 = 0;                  // start on the simulated clock [s]
  int step = 0;                    // program step of the motion instruction
  Location target;                // DEST: the location the motion goes to

  double end_time() const { return t0 + profile.duration; }
};

// Joint moves: the joints at time t, q(sigma(t - t0)).
robots::JointVector joint_path_at(const Trajectory& tr, double t);

// A straight line's joints at time t between its samples a and b: the line's pose at sigma(t),
// IK in the motion's configuration seeded with `seed`, as plan_line solves its samples; where
// that fails or jumps, the joints interpolated between a and b (ik_used false).
struct LinePoint {
  robots::JointVector joints;
  Location flange;  // the line's flange pose at sigma(t)
  bool ik_used = false;
};
LinePoint line_path_at(const robots::Robot& robot, const Trajectory& tr, const LineSample& a, const LineSample& b,
                       double t, const robots::JointVector& seed);

// The same between checked samples i < j that may skip samples (gap stepping): t is bracketed
// by the nearest samples of the plan.
LinePoint line_path_between(const robots::Robot& robot, const Trajectory& tr, std::size_t i, std::size_t j, double t,
                            const robots::JointVector* seed);

}  // namespace asimov::motion
