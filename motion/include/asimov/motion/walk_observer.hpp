// The one interface through which recorders (trace, replay, accuracy, timing, counts) and
// hooks watch a walk. The walker calls every registered observer in registration order; an
// observer only reads what it is given (it cannot change the walk).
#pragma once
#include "asimov/collision/distance.hpp"
#include "asimov/collision/query.hpp"
#include "asimov/motion/motion_result.hpp"
#include "asimov/motion/sampler.hpp"
#include "asimov/motion/trajectory.hpp"

#include <chrono>
#include <cstdint>
#if defined(__x86_64__) || defined(__i386__)
#include <x86intrin.h>
#endif

namespace asimov::motion {

// Per-query timer: reading the time-stamp counter costs a few ns, clock_gettime ~20 ns, which
// at two reads per checked pose (~1 us each) was 7 % of a run. A recorder turns ticks into
// seconds with the steady_clock time of the whole walk.
#if defined(__x86_64__) || defined(__i386__)
inline std::uint64_t cpu_ticks() { return __rdtsc(); }
#else
inline std::uint64_t cpu_ticks() {
  return static_cast<std::uint64_t>(std::chrono::steady_clock::now().time_since_epoch().count());
}
#endif

// The clearance report's minimum [ours] (docs/collision.md §12): per pair, the least distance
// along the motion to within this [mm] (continuous checking refines its windows until every
// window's lower bound is at least the least found less this).
constexpr double kMinimumToleranceMm = 1e-3;

// The walk advancing from the last checked pose to the next one (before that one is checked).
struct Stretch {
  double t_from = 0, t_to = 0;          // simulated times of the two poses [s]
  double sigma_from = 0, sigma_to = 0;  // path parameters
  std::size_t sample_from = 0, sample_to = 0;  // lines: indices into trajectory.line.samples
  double bound_mm = 0;                  // §6.3 bound on any body point's displacement over it
  bool blended = false;                 // inside the overlap with the previous motion (blended_joints_at)
};

enum class QueryKind : std::uint8_t {
  checked_pose,    // the query of a checked pose
  bisection_pose,  // a contact-time bisection pose (midpoints, the halting pose's final check)
  probe,           // bisection: one enabled pair at the colliding pose (which pairs collide)
};

struct QueryCost {
  QueryKind kind = QueryKind::checked_pose;
  std::uint64_t ticks = 0;  // checked poses: cpu_ticks() spent in the engine
  bool built_grid = false;  // it built a lazy voxel grid (preprocessing)
};

// A distance measured by continuous checking (docs/collision.md §12).
struct DistanceCost {
  double t = 0;             // simulated time of the pose [s]
  bool probe = false;       // a pose between two checked poses (else a checked pose)
  int step = 0;             // program step of the motion
  std::uint64_t ticks = 0;  // cpu_ticks() spent in the engine
  bool minimum = false;     // refining the clearance report's minimum (not the contact search)
};

struct WalkObserver {
  virtual ~WalkObserver() = default;
  virtual void on_walk_begin(const Trajectory&) {}
  virtual void on_stretch(const Trajectory&, const Stretch&) {}
  // A checked pose, after its query: `contact` when it collides (unchecked poses: false).
  virtual void on_checked_pose(double /*t*/, const robots::JointVector& /*q*/, bool /*contact*/) {}
  virtual void on_query(const collision::QueryResult&, const QueryCost&) {}
  // Continuous checking measured the distance of `pair` (engine ids; the result may be a lower
  // bound, status beyond, when the pair is farther than the cut-off the proof needed).
  virtual void on_distance(const collision::BodyPair& /*pair*/, const collision::DistanceResult&, const DistanceCost&) {}
  // The clearance report's minimum of `pair` could not be refined to kMinimumToleranceMm within
  // its budget: its distance is only proven to stay at or above lower_mm (docs/collision.md §12).
  virtual void on_distance_bound(const collision::BodyPair& /*pair*/, double /*lower_mm*/) {}
  // IK solves (of the walk's exact straight-line path; the facade reports the planner's too).
  virtual void on_ik(const PoseError& /*residual*/, std::uint64_t /*solves*/) {}
  // The walk halts on a contact: the arm at `q_halt` (the pose of report.time_free_s);
  // `search_s`: wall time of the contact-time bisection.
  virtual void on_contact(const CollisionReport&, const robots::JointVector& /*q_halt*/, double /*search_s*/) {}
  virtual void on_walk_end() {}
};

}  // namespace asimov::motion
