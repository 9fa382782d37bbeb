// The simulated arm in its cell: current state, motion planning (IK, profiles), sampling of
// checked poses and the collision check at each of them. The interpreter drives it.
//
// Forward processing (dialect §5): start_*() validates and plans a motion and returns at once;
// the motion is carried out (clock advances, poses are checked) by finish_motion(), which the
// interpreter calls before the next motion, at BREAK and at program end.
//
// Interruption (Ctrl-C): finish_motion polls an optional flag (set_interrupt) before each
// checked pose; when it is set the arm stops at the last checked pose, the clock at that pose's
// time, and the rest of the motion is kept (halted_motion) until resume_motion carries it on.
#pragma once
#include "asimov/collision/query.hpp"
#include "asimov/motion/cell.hpp"
#include "asimov/motion/sampler.hpp"
#include "asimov/robots/configuration.hpp"
#include <atomic>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace asimov::motion {

enum class MotionStatus { ok, error, collision, interrupted };

struct MotionError {
  std::string message;  // VAL text: "*Location out of reach*", "*Joint limit exceeded*", ...
  std::string detail;   // short detail, e.g. "J3 = 231.000 > 225.000"
};

// Contact time (docs/collision-method.md §6.4): when the checked pose at t_{k+1} collides and the one at
// t_k was found free, the time is bisected on the exact path between them with the pairs that
// collide at t_{k+1}, until time_s - time_free_s <= CollisionSettings::toc_tolerance_s. The arm
// halts at the pose of time_free_s (collision-free); body names, point, faces and joints are
// those of the contact at time_s.
struct CollisionReport {
  std::string body_a, body_b;
  collision::Vec3 point = collision::Vec3::Zero();  // world [mm], on both bodies' surfaces
  double time_s = 0;                                // contact time t_hit [s] (simulated clock)
  double time_free_s = 0;                           // time of the halting pose t_free [s] (= time_s when
                                                    //   the start pose already collides)
  robots::JointVector joints;                       // display [deg] at t_hit
  std::uint32_t face_a = 0, face_b = 0;             // triangle indices in body_a's / body_b's mesh
                                                    //   (0 for a containment contact)
  int step = 0;                                     // program step of the motion instruction
};

// Where an interrupted motion stopped: at its last checked pose (collision-free when checking
// is on), which is also where the simulated clock stopped.
struct InterruptReport {
  double time_s = 0;         // time of the halting pose [s] (simulated clock)
  double path_fraction = 0;  // path parameter there: 0 = start, 1 = target
  robots::JointVector joints;  // display [deg]
  int step = 0;              // program step of the motion instruction
};

struct TraceSample {
  double time_s = 0;
  robots::JointVector joints;   // display [deg]
  Location tool;                // world pose of the tool point (BASE . FK . TOOL)
};

// One pose of the replay recording (set_replay; app/replay.*): the arm's joints at a simulated
// instant, on the path the simulator carries out.
struct ReplaySample {
  double time_s = 0;
  robots::JointVector joints;   // display [deg]
  int step = 0;                 // program step of the motion it belongs to
  bool checked = false;         // a checked pose (also in trace())
};

struct MotionResult {
  MotionStatus status = MotionStatus::ok;
  MotionError error;            // when status == error
  CollisionReport collision;    // when status == collision
  InterruptReport interrupt;    // when status == interrupted
};

struct SpeedSettings {
  double monitor = 100;  // monitor speed [%]
  double program = 100;  // program speed for this motion [%]
  double rotation = -1;  // program speed of straight-line rotation [%]; < 0: same as program
  double duration_s = 0; // DURATION: minimum motion time [s]; 0 = off
};

// What the run's settings cost in accuracy, measured along the run (README "accuracy").
struct RunAccuracy {
  // Largest docs/collision-method.md §6.3 bound on the displacement of any body point (links, tool) between
  // two consecutive checked poses [mm]: an upper bound, real points move less.
  double step_displacement_mm = 0;
  std::uint64_t contacts = 0;     // contacts reported (collision results)
  double contact_bracket_s = 0;   // largest t_hit - t_free of those contacts
  PoseError ik_residual;          // largest |FK(IK(target)) - target| (flange) over every IK solve
  std::uint64_t ik_solves = 0;    //   of motion targets, straight-line samples and their bisection
  PoseError line_deviation;       // straight lines: largest deviation of the tool pose at the joint
                                  //   midpoint of two checked poses from the line at the mid sigma
  std::uint64_t line_intervals = 0;
  std::uint64_t motions = 0;      // motions carried out (finish_motion with a pending motion)
};

// Wall time [s] (steady_clock) spent in each phase. parse and the cell file part of preprocess
// are added by the caller (add_parse_time, add_preprocess_time).
struct RunTiming {
  double parse_s = 0;       // program files: load and check
  double preprocess_s = 0;  // cell load, engine preprocessing (incl. the checks that built a lazy grid)
  double motion_s = 0;      // planning, IK, sampling, FK
  double collision_s = 0;   // engine queries at checked poses and contact-time bisection
};

// Hand (dialect §5): OPEN / CLOSE / RELAX take effect when the next motion starts; OPENI /
// CLOSEI / RELAXI wait for the current motion, set the hand, then wait HAND.TIME seconds.
enum class HandState { open, closed, relaxed };
constexpr double kDefaultHandTime = 0.05;  // PARAMETER HAND.TIME default [s]

class Simulator {
 public:
  explicit Simulator(Cell cell);
  ~Simulator();
  Simulator(Simulator&&) noexcept;

  const Cell& cell() const;
  const robots::Robot& robot() const;

  // State. HERE = BASE . FK(joints) . TOOL.
  const robots::JointVector& joints() const;
  Location here() const;
  Location dest() const;           // target of the current or last motion
  Location base() const;
  Location tool() const;
  void set_base(const Location& base);
  void set_tool(const Location& tool);
  robots::Configuration configuration() const;  // derived from the current joints
  robots::ConfigurationRequest& request();      // pending configuration words
  double time_s() const;                        // simulated clock
  std::uint64_t poses_checked() const;

  // Motions. `step` is the program step of the instruction (the interpreter's; the simulator
  // only carries it) and comes back in collision, interrupt and replay reports. Targets are
  // validated before anything moves.
  MotionResult start_joint_move(const robots::JointVector& target_display, SpeedSettings speed, int step);
  MotionResult start_move(const Location& target, bool straight, SpeedSettings speed, int step);
  MotionResult finish_motion();  // carries out the pending motion, if any

  // Interruption. `flag` (null: none) is read (relaxed) before each checked pose of
  // finish_motion; when it is true the motion stops there (status interrupted). The caller owns
  // the flag and clears it; the simulator only reads it.
  void set_interrupt(const std::atomic<bool>* flag);
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
  MotionResult hand_immediate(HandState state, double hand_time_s = kDefaultHandTime);
  HandState hand() const;
  bool hand_pending() const;
  // WAIT / WAIT.EVENT: finishes the pending motion (its failure or interruption is returned,
  // the clock then where the motion stopped), then advances the clock by `seconds` (negative:
  // 0) without motion.
  MotionResult wait(double seconds);
  // ENABLE / DISABLE COLLISION and PARAMETER COLLISION.CLEARANCE at run time (dialect §6):
  // the cell's settings, applied from the next checked pose.
  void set_collision_enabled(bool on);
  bool collision_enabled() const;
  void set_clearance(double clearance_mm);
  double clearance_mm() const;
  // INRANGE: 0 reachable within limits in the requested configuration, 1 out of reach, 2 a joint
  // limit in the way (same IK as a joint motion to `target`).
  int inrange(const Location& target) const;
  bool motion_pending() const;

  // Every checked pose is appended here when tracing is on.
  void set_trace(bool on);
  const std::vector<TraceSample>& trace() const;
  // Replay recording, off by default (then it costs one branch per checked pose). With
  // grid_s > 0: every checked pose, the exact path at the simulated instants k * grid_s between
  // them, and after a contact the halting pose at time_free_s (later samples dropped). Times
  // strictly increase; a sample at the instant of the previous one replaces it.
  void set_replay(double grid_s);
  const std::vector<ReplaySample>& replay() const;

  // Collision counts summed over all engine queries (checked poses and contact-time bisection).
  const collision::StepCounts& collision_counts() const;
  // Poses checked by contact-time bisection (not in poses_checked() nor in the trace): one
  // engine query per pose, on the pairs that collided at the first colliding checked pose.
  std::uint64_t bisection_checks() const;
  bool collision_engine_used() const;  // false when the cell has no enabled pair

  const RunAccuracy& accuracy() const;
  const RunTiming& timing() const;
  void add_parse_time(double seconds);
  void add_preprocess_time(double seconds);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace asimov::motion
