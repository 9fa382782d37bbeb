// The walker: carries out a planned motion (trajectory.hpp) over its checked poses, querying
// the collision world at each (world.hpp), spacing them by the §6.3 step rule or by the
// engine's gaps (gap stepping), proving each stretch between two checked poses free or finding
// its earliest contact (continuous checking, docs/collision.md §12), bisecting the contact time
// when a checked pose collides (§6.4), stopping at an interrupt. Recorders watch it through WalkObserver; it keeps nothing of its own
// between walks but scratch space.
#pragma once
#include "asimov/motion/cell.hpp"
#include "asimov/motion/walk_observer.hpp"
#include "asimov/motion/world.hpp"

#include <atomic>
#include <functional>
#include <limits>
#include <memory>
#include <vector>

namespace asimov::motion {

class ContinuousChecker;

// Where the walk stands: the arm's joints and the simulated clock. walk() advances them.
struct WalkState {
  robots::JointVector joints;  // display [deg]
  double time_s = 0;
  bool start_checked = false;  // the start pose of the first motion was checked
  bool last_free = false;      // the last visited pose was checked and found free
};

// Step rule (docs/collision-method.md §6.3): pairs may move max(c, step_mm) relative to each
// other between checked poses. The one place the step is derived from the settings.
double step_mm(const CollisionSettings& settings);

class Walker {
 public:
  // `settings` is read at each walk (ENABLE / DISABLE COLLISION and the clearance change at run
  // time); robot, world and settings must outlive the walker.
  Walker(const robots::Robot& robot, World& world, const CollisionSettings& settings);
  ~Walker();

  // Observers are called in the order added; they must outlive the walker.
  void add_observer(WalkObserver& observer);
  // Read (relaxed) before each checked pose; when true the walk stops there (interrupted).
  void set_interrupt(const std::atomic<bool>* flag) { interrupt_ = flag; }
  // Asked with the time and joints of the last checked pose before each next one, after the
  // flag; when it answers true the walk stops there as for the flag (interrupted, the report's
  // by_condition set). Empty: never asked.
  void set_stop_condition(std::function<bool(double time_s, const robots::JointVector& joints)> condition) {
    stop_condition_ = std::move(condition);
  }

  // Carries `tr` out from `state` (its joints and time: the path at state.time_s, which is
  // tr.t0, or inside the motion when a walk up to `until_s` left it there). ok: the arm at
  // tr.to, the clock at tr.end_time(); or, when until_s is earlier (the next motion blends in
  // there, docs/blending.md), both on the path at until_s. collision: the arm at the last free
  // pose, the clock at the contact time. interrupted: the arm and clock at the last checked pose.
  MotionResult walk(const Trajectory& tr, WalkState& state, double until_s = std::numeric_limits<double>::infinity());
  // Time passing with the arm at rest from state.time_s to until_s (WAIT, DELAY, hand times):
  // parts carried by a running conveyor move and are checked like any moving body (the step
  // rule or gap stepping on their belt speed, continuous checking, the contact time bisected);
  // `step` is the program step reported with a contact. ok: the clock at until_s. collision:
  // the clock at the contact time. Without parts, or while nothing moves, no query.
  MotionResult dwell(WalkState& state, double until_s, int step);

 private:
  struct Walk;
  ContinuousChecker* checker(collision::Engine* engine);  // null: continuous checking off
  const robots::Robot& robot_;
  World& world_;
  const CollisionSettings& settings_;
  const std::atomic<bool>* interrupt_ = nullptr;
  std::function<bool(double, const robots::JointVector&)> stop_condition_;
  std::vector<WalkObserver*> observers_;
  // Scratch, reused across walks (no allocation per checked pose).
  std::vector<double> pair_mm_;
  GapScratch gap_scratch_;
  std::vector<double> gaps_here_, gaps_next_;  // container gaps at two checked poses (Walk)
  std::vector<double> window_mu_;              // per pair, its motion bound over a stretch (Walk)
  std::vector<collision::BodyPair> hit_pairs_, probe_pairs_;
  collision::QueryResult result_;
  // Continuous checking between checked poses (docs/collision.md §12), once the engine exists.
  std::unique_ptr<ContinuousChecker> continuous_;
};

}  // namespace asimov::motion
