// A planned motion as plain data: what the planner hands the walker. Its segment (a joint move
// straight in joint space, or a straight line of the tool point), its speed profile and where
// it starts on the simulated clock; with continuous path (docs/blending.md) also the motion it
// blends out of (`previous`), which it overlaps from t0 until that one's end. The walker needs
// only the exact path at time t (path_at) and a bound on the joint travel over an interval
// (joint_travel), plus each segment's own checked-pose grid outside the overlap.
#pragma once
#include "asimov/motion/interpolation.hpp"
#include "asimov/motion/profile.hpp"
#include "asimov/motion/sampler.hpp"
#include "asimov/robots/configuration.hpp"

#include <memory>

namespace asimov::motion {

struct SpeedSettings {
  double monitor = 100;  // monitor speed [%]
  double program = 100;  // program speed for this motion [%]
  double rotation = -1;  // program speed of straight-line rotation [%]; < 0: same as program
  double duration_s = 0; // DURATION: minimum motion time [s]; 0 = off
  double accel = 100;    // ACCEL: acceleration [% of the robot's], (0, 100]
  double decel = 100;    // ACCEL: deceleration [%]
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
  // Continuous path: the motion this one blends out of, still decelerating on
  // [t0, previous->end_time()] (null: this motion starts at rest). Its own `previous` is
  // dropped: at most two motions overlap at any instant (docs/blending.md).
  std::shared_ptr<const Trajectory> previous;

  double end_time() const { return t0 + profile.duration; }
  // End of the overlap with `previous` (t0 when there is none).
  double blend_end() const { return previous ? previous->end_time() : t0; }
};

// Index of the last line sample at or before sigma (never the last of two or more samples).
std::size_t sample_before(const std::vector<LineSample>& samples, double sigma);

// One segment's joints at time t in joint space, as the overlap superposes them: joint moves
// q(sigma); straight lines the joints interpolated between the solved samples around sigma.
robots::JointVector segment_joints_at(const Trajectory& tr, double t);

// Per joint, a bound on how far the segment's joint moves over [t1, t2] (its total variation):
// |q(sigma2) - q(sigma1)| for joint moves, the sum over the samples crossed for straight lines.
robots::JointVector segment_travel(const Trajectory& tr, double t1, double t2);

// The blended path in the overlap t in [t0, blend_end()]: the displacements add,
// q(t) = Q_prev(t) + Q(t) - q_C with q_C = previous->to, where both were to meet.
robots::JointVector blended_joints_at(const Trajectory& tr, double t);

// Per joint, a bound on the travel of the blended path over [t1, t2] inside the overlap: the
// sum of both segments' travel (each joint's displacement is the sum of both).
robots::JointVector blended_travel(const Trajectory& tr, double t1, double t2);

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
