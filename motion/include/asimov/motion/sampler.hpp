// Checked poses of a motion, spaced so that no point of any arm body (links and tool) moves
// more than step_mm between two consecutive ones (docs/collision-method.md §6.3 displacement bound).
//
// Joint moves are straight in joint space, so the bound is linear in sigma: n equal intervals.
// Straight lines are validated and solved first (docs/kinematics.md §7: 1 mm / 0.5 deg samples, IK in
// the start configuration nearest the previous sample, reach / limit / singularity checks), then
// every interval whose bound between consecutive IK solutions exceeds 0.9 * step_mm is subdivided.
//
// Gap stepping (docs/collision-method.md §6.3) checks a subset of those poses: a pair whose step-2 gap is g
// allows delta_A + delta_B <= max(c, step_mm, g - c), and the next checked pose is the farthest one
// every pair allows (gap_intervals, gap_next_sample).
#pragma once
#include "asimov/collision/participation.hpp"
#include "asimov/motion/interpolation.hpp"
#include "asimov/robots/configuration.hpp"
#include "asimov/robots/displacement_bound.hpp"
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

namespace asimov::motion {

// Two moving bodies (BodyIds, which index the reach list: motion/world.hpp) that are tested
// against each other: their relative displacement is bounded by delta_a + delta_b
// (docs/collision-method.md §6.3 step rule). The engine's pair type, not a copy of it.
using collision::BodyPair;

// Bound [mm] for a display joint step: max over bodies of delta_k and over `pairs` of
// delta_a + delta_b (static bodies have delta = 0, so body-vs-static pairs need only delta_k).
// `body_max`, when given, receives the largest single-body bound max_k delta_k.
double max_body_displacement(std::span<const robots::BodyReach> reach, const robots::JointVector& delta,
                             std::span<const BodyPair> pairs = {}, double* body_max = nullptr);

// Position [mm] and rotation angle [rad] between two poses (accuracy reports).
struct PoseError {
  double position_mm = 0;
  double rotation_rad = 0;
  void merge(const PoseError& o);  // componentwise max
};
PoseError pose_error(const Location& a, const Location& b);

// Gap stepping. One enabled pair: its bodies' BodyIds, which index the reach list (-1: a body
// that never moves, delta = 0), their links (frame index, 0 for fixed bodies; -1 for a body with
// a motion of its own, a follower of an arm joint: then delta_A + delta_B) and what the pair allows, gap_allowance(g, c, step_mm) with g the engine's gap (QueryRequest::gaps).
struct GapPair {
  int a = -1, b = -1;
  int link_a = 0, link_b = 0;
  double allow_mm = 0;
  double speed_mm_s = 0;  // conveyor-borne parts: the most their motion adds per second
};
double gap_allowance(double gap_mm, double clearance_mm, double step_mm);

// Bound [mm] on how much a pair's distance can change over a display joint step: delta of the
// moving body against a fixed one; for two arm bodies only the joints between their links move
// one relative to the other (a common motion changes no distance), so sum over those joints of
// |dq_j| R_jk of the body on the outer link. Never more than delta_A + delta_B.
double pair_displacement(std::span<const robots::BodyReach> reach, const GapPair& pair,
                         const robots::JointVector& delta);

// Joint moves: grid intervals (>= 1, <= remaining) to the next checked pose, when one interval
// changes pair i's distance by at most pair_mm[i]: the most that keeps every pair within its
// allowance. The checked poses stay on the fixed-stepping grid, so they are a subset of its poses.
int gap_intervals(std::span<const double> pair_mm, std::span<const GapPair> pairs, int remaining);

// Number of equal sigma intervals of a joint move from `from` to `to` (>= 1).
int joint_move_intervals(std::span<const robots::BodyReach> reach, const robots::JointVector& from,
                         const robots::JointVector& to, double step_mm, std::span<const BodyPair> pairs = {});

enum class LineStatus { ok, out_of_reach, joint_limit, singularity };
enum class SingularityKind { none, joint_jump, shoulder, elbow, unresolved };

struct LineSample {
  double s = 0;               // path parameter sigma in [0, 1]
  robots::JointVector joints; // display [deg]
  double bound_mm = 0;        // max_k delta_k from the previous sample (docs/collision-method.md §6.3 bound)
};

struct LinePlan {
  LineStatus status = LineStatus::ok;
  std::vector<LineSample> samples;  // s = 0 (the start joints) ... s = 1, increasing
  double fail_fraction = 0;         // sigma of the first bad sample
  SingularityKind singularity = SingularityKind::none;
  int joint = -1;                   // joint_limit / joint_jump: 0-based joint index
  double value = 0;                 // its value [deg] (joint_limit) or jump [deg] (joint_jump)
  PoseError ik_residual;            // largest |FK(IK(sample)) - sample| over the solved samples
  std::uint64_t ik_solves = 0;
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

// Straight lines, gap stepping: index of the next checked sample after samples[from] (the last
// checked one): the farthest j such that, for every pair, the sum of its pair_displacement over
// the sample intervals from `from` to j is <= kLineSafety * allow; at least from + 1. Sets
// `bound_mm` to the largest single-body bound over that stretch (sum of the samples' bound_mm
// would overstate it: max_k of the per-body sums). On return scratch.sums[reach.size() + i] is
// pair i's sum from `from` to the returned sample (its motion bound over that stretch, the one
// continuous checking's line_motion computes).
struct GapScratch {
  std::vector<double> sums;            // per body, then per pair (see above)
  std::vector<double> limit;           // per body: the least allowance of its pairs with a fixed body
  std::vector<std::uint32_t> moving;   // the pairs of two moving bodies
};
// `room` (empty, or one per reach body): a further limit per body, as the least allowance of its
// pairs with a fixed body is (the broad phase's room, World::room()).
std::size_t gap_next_sample(std::span<const robots::BodyReach> reach, std::span<const LineSample> samples,
                            std::size_t from, std::span<const GapPair> pairs, GapScratch& scratch, double& bound_mm,
                            std::span<const double> room = {});

}  // namespace asimov::motion
