// The simulated arm in its cell, the facade the interpreter (and app/, the monitor) drives:
// the arm's state, the hand, and the wiring of planner (planner.hpp: request -> trajectory),
// walker (walker.hpp: trajectory -> checked poses -> collision world) and recorders
// (recorders.hpp: trace, replay, accuracy, counts, timing, watching the walk).
//
// Forward processing (dialect §5): start_*() validates and plans a motion and returns at once;
// the motion is carried out (clock advances, poses are checked) by finish_motion(), which the
// interpreter calls at BREAK, WAIT, the immediate hand instructions and program end, and by the
// next start_*(). With continuous path on (settings().continuous_path, docs/blending.md) the next
// start_*() blends: it plans the new motion from the pending one's target, carries the pending
// one out only up to where the new one starts (its deceleration and the new acceleration
// overlap), and the new one, overlap included, becomes the pending motion.
//
// Interruption (Ctrl-C): finish_motion polls an optional flag (set_interrupt) before each
// checked pose; when it is set the arm stops at the last checked pose, the clock at that pose's
// time, and the rest of the motion is kept (halted_motion) until resume_motion carries it on.
#pragma once
#include "asimov/collision/query.hpp"
#include "asimov/motion/cell.hpp"
#include "asimov/motion/cell_runtime.hpp"
#include "asimov/motion/motion_result.hpp"
#include "asimov/motion/recorders.hpp"
#include "asimov/motion/trajectory.hpp"
#include "asimov/robots/configuration.hpp"
#include <atomic>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace asimov::motion {

// Hand (dialect §5): OPEN / CLOSE / RELAX take effect when the next motion starts; OPENI /
// CLOSEI / RELAXI wait for the current motion, set the hand, then wait HAND.TIME seconds.
enum class HandState { open, closed, relaxed };
constexpr double kDefaultHandTime = 0.05;  // PARAMETER HAND.TIME default [s]
struct Hand {
  HandState state = HandState::open;
  std::optional<HandState> pending;  // OPEN / CLOSE / RELAX waiting for the next motion
};

// BASE, TOOL and the pending configuration words (LEFTY, ABOVE, ...): the program's settings
// that shape the next motions and HERE.
struct ArmSettings {
  Location base = Location::Identity();
  Location tool = Location::Identity();
  robots::ConfigurationRequest request;
  // Continuous path (off by default here; the interpreter follows ENABLE / DISABLE CP, on by
  // default as on the controller): a motion started while another is pending blends with it.
  bool continuous_path = false;
};

class Simulator {
 public:
  explicit Simulator(Cell cell);
  ~Simulator();
  Simulator(Simulator&&) noexcept;

  const Cell& cell() const;
  const robots::Robot& robot() const;

  // State. HERE = settings().base . FK(joints) . settings().tool.
  const robots::JointVector& joints() const;
  Location here() const;
  Location dest() const;           // target of the current or last motion
  robots::Configuration configuration() const;  // derived from the current joints
  double time_s() const;                        // simulated clock
  // What the program sets for later motions (BASE, TOOL, configuration words); read and
  // written freely, used when the next motion is planned and by HERE.
  ArmSettings& settings();
  const ArmSettings& settings() const;

  // Motions. `step` identifies the instruction (the interpreter passes its step) and comes
  // back in collision reports. Targets are validated before anything moves.
  MotionResult start_joint_move(const robots::JointVector& target_display, SpeedSettings speed, int step);
  MotionResult start_move(const Location& target, bool straight, SpeedSettings speed, int step);
  MotionResult finish_motion();  // carries out the pending motion, if any
  // Where the arm will be when the pending motion ends (the arm's joints / HERE when none):
  // what relative motions (DEPART, DRAW, ALIGN, DRIVE) start from while one is pending.
  const robots::JointVector& planned_joints() const;
  Location planned_here() const;
  // The pending motion's place on the clock (nullopt: none pending).
  std::optional<MotionTiming> pending_timing() const;

  // Interruption. `flag` (null: none) is read (relaxed) before each checked pose of
  // finish_motion; when it is true the motion stops there (status interrupted). The caller owns
  // the flag and clears it; the simulator only reads it.
  void set_interrupt(const std::atomic<bool>* flag);
  // A second cause of interruption (REACTI, docs/val2-dialect.md §7c): asked with the time and
  // joints of each checked pose before the next one; true stops the motion there as the flag
  // does (the report's by_condition set). Empty: none.
  void set_stop_condition(std::function<bool(double time_s, const robots::JointVector& joints)> condition);
  // The interrupted motion whose rest is kept: where it stopped. Any new motion drops it.
  const std::optional<InterruptReport>& halted_motion() const;
  // Starts the rest of the halted motion from the current pose, accelerating from rest, with
  // the same speeds and step (DURATION: what was left of it): a joint move to the same joint
  // target, a straight line to the same location. Without a halted motion: *No motion to resume*.
  // `monitor_speed`: the monitor speed now in effect (default: the one the motion had).
  MotionResult resume_motion(std::optional<double> monitor_speed = {});
  void drop_halted_motion();
  // Called at each checked pose found free (tests set the interrupt flag from here after N
  // poses; empty: nothing is called).
  void set_pose_hook(std::function<void(double time_s, const robots::JointVector& joints)> hook);

  // Hand. request_hand: OPEN/CLOSE/RELAX (pending until a motion starts; a later request
  // replaces it). hand_immediate: OPENI/CLOSEI/RELAXI: finishes the pending motion (its result
  // is returned, the hand untouched, when it fails or is interrupted), sets the hand (dropping
  // a pending request) and advances the clock by hand_time_s (negative: 0).
  void request_hand(HandState state);
  MotionResult hand_immediate(HandState state, double hand_time_s = kDefaultHandTime, int step = 0);
  Hand hand() const;
  // Parts and devices of the cell (null for a cell without any): the collision world poses
  // the parts from it at every checked pose and advances its clock with the walk.
  CellRuntime* cell_runtime();
  const CellRuntime* cell_runtime() const;
  // WAIT / WAIT.EVENT: finishes the pending motion (its failure or interruption is returned,
  // the clock then where the motion stopped), then advances the clock by `seconds` (negative:
  // 0) without motion. The hand time and the wait are walked (Walker::dwell): a part that a
  // running conveyor carries into something meanwhile is a collision at program step `step`.
  MotionResult wait(double seconds, int step = 0);
  // ENABLE / DISABLE COLLISION and PARAMETER COLLISION.CLEARANCE at run time (dialect §6):
  // the cell's settings (read them as cell().collision), applied from the next checked pose.
  void set_collision_enabled(bool on);
  void set_clearance(double clearance_mm);
  // INRANGE: 0 reachable within limits in the requested configuration, 1 out of reach, 2 a joint
  // limit in the way (same IK as a joint motion to `target`).
  int inrange(const Location& target) const;
  bool motion_pending() const;
  int motion_step() const;  // program step of the motion pending or being carried out (0: none)

  // What the run keeps of its walks (recorders.hpp): trace (on: trace.on = true), replay
  // (replay.grid_s > 0), accuracy, query counts (poses checked, bisection poses, step counts),
  // wall time per phase (the caller adds parse and cell-file time to timing.timing).
  Recorders& recorders();
  const Recorders& recorders() const;
  // Another observer of the walks, told after the recorders (tests and tools: the executed path,
  // what continuous checking measured). It must outlive the simulator's motions.
  void add_observer(WalkObserver& observer);
  bool collision_engine_used() const;  // false when the cell has no enabled pair
  // Name of a collision body (ClearanceApproach::pair); empty without an engine.
  std::string body_name(std::uint32_t id) const;  // collision::BodyId

 private:
  MotionResult dwell(double seconds, int step);
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace asimov::motion
