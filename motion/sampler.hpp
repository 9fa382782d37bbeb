// Checked poses of a motion, spaced so that no point of any arm body (links and tool) moves
// more than step_mm between two consecutive ones (four-step.md §6.3 displacement bound).
//
// Joint moves are straight in joint space, so the bound is linear in sigma: n equal intervals.
// Straight lines are validated and solved first (kinematics.md §7: 1 mm / 0.5 deg samples, IK in
// the start configuration nearest the previous sample, reach / limit / singularity checks), then
// every interval whose bound between consecutive IK solutions exceeds 0.9 * step_mm is subdivided.
#pragma once
#include "motion/interpolation.hpp"
#include "robots/configuration.hpp"
#include "robots/displacement_bound.hpp"
#include <span>
#include <utility>
#include <vector>

namespace asimov::motion {

// Two moving bodies (indices into the reach list) that are tested against each other: their
// relative displacement is bounded by delta_a + delta_b (four-step.md §6.3 step rule).
using BodyPair = std::pair<int, int>;

// Bound [mm] for a display joint step: max over bodies of delta_k and over `pairs` of
// delta_a + delta_b (static bodies have delta = 0, so body-vs-static pairs need only delta_k).
double max_body_displacement(std::span<const robots::BodyReach> reach, const robots::JointVector& delta,
                             std::span<const BodyPair> pairs = {});

// Number of equal sigma intervals of a joint move from `from` to `to` (>= 1).
int joint_move_intervals(std::span<const robots::BodyReach> reach, const robots::JointVector& from,
                         const robots::JointVector& to, double step_mm, std::span<const BodyPair> pairs = {});

enum class LineStatus { ok, out_of_reach, joint_limit, singularity };
enum class SingularityKind { none, joint_jump, shoulder, elbow, unresolved };

struct LineSample {
  double s = 0;               // path parameter sigma in [0, 1]
  robots::JointVector joints; // display [deg]
};

struct LinePlan {
  LineStatus status = LineStatus::ok;
  std::vector<LineSample> samples;  // s = 0 (the start joints) ... s = 1, increasing
  double fail_fraction = 0;         // sigma of the first bad sample
  SingularityKind singularity = SingularityKind::none;
  int joint = -1;                   // joint_limit / joint_jump: 0-based joint index
  double value = 0;                 // its value [deg] (joint_limit) or jump [deg] (joint_jump)
};

struct LineRequest {
  LinePath path;                                 // tool-point poses in the BASE-frame world
  Location base = Location::Identity();          // program BASE
  Location tool = Location::Identity();          // program TOOL
  robots::JointVector start;                     // display joints at s = 0
  robots::Configuration config;                  // kept along the path
  double step_mm = 1.0;                          // collision step
  std::span<const BodyPair> pairs;               // moving-vs-moving pairs (see max_body_displacement)
};

constexpr double kLineSafety = 0.9;          // straight lines: bound <= 0.9 * step_mm
constexpr double kLineSampleMm = 1.0;        // validation spacing [mm]
constexpr double kLineSampleDeg = 0.5;       // validation spacing [deg]
constexpr double kMaxJointJumpDeg = 5.0;     // larger jump between samples: singularity
constexpr double kShoulderMarginMm = 1.0;    // r - d3 below this: singularity
constexpr double kElbowMarginMm = 0.5;       // elbow reach margin below this: singularity

LineStatus plan_line(const robots::Robot& robot, std::span<const robots::BodyReach> reach,
                     const LineRequest& request, LinePlan& out);

}  // namespace asimov::motion
