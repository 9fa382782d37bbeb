// Recorders: what a run keeps of its walks, each a WalkObserver (walk_observer.hpp) that the
// Simulator registers with its walker: the trace of checked poses, the replay frames, the
// accuracy figures, the query counts and the wall time per phase.
#pragma once
#include "asimov/motion/device_clock.hpp"
#include "asimov/motion/walk_observer.hpp"

#include <chrono>
#include <limits>
#include <string>
#include <vector>

namespace asimov::motion {

struct TraceSample {
  double time_s = 0;
  robots::JointVector joints;   // display [deg]
  Location tool;                // world pose of the tool point (BASE . FK . TOOL)
  std::string part;             // the carried part's name ("" when the gripper holds none)
  Location part_pose = Location::Identity();  // its world pose
};

class World;
class CellRuntime;

// One pose of the replay recording (app/replay.*): the arm's joints at a simulated instant,
// on the path the simulator carries out.
struct ReplaySample {
  double time_s = 0;
  robots::JointVector joints;   // display [deg]
  int step = 0;                  // program step of the motion it belongs to
  bool checked = false;         // a checked pose (also in the trace)
  Eigen::Vector3d tool_mm = Eigen::Vector3d::Zero();  // world tool point (BASE . FK . TOOL): the page's tool path
};

// What the run's settings cost in accuracy, measured along the run (docs/cli.md "accuracy").
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
  double collision_s = 0;   // engine queries at checked poses, continuous checking, contact-time bisection
};

// Every checked pose with the tool's world pose, when `on`. BASE and TOOL are read at the
// pose (the program's, as HERE).
// Samples a run's trace and its replay recording keep, each (docs/limits.md): a trace sample is
// ~200 bytes in memory and ~300 in JSON, so a capped trace stays near 50 MB in memory and 75 MB
// on disk. 8,000 motions with both took 1.4 GB and wrote 430 MB; past the cap the first samples
// are kept and `truncated` says so (the commands print a warning).
constexpr std::size_t kMaxRecordedSamples = 250000;

struct TraceRecorder final : WalkObserver {
  TraceRecorder(const robots::Robot& robot, const Location& base, const Location& tool)
      : robot(robot), base(base), tool(tool) {}
  void on_checked_pose(double t, const robots::JointVector& q, bool contact) override;
  bool on = false;
  std::vector<TraceSample> samples;
  std::size_t max_samples = kMaxRecordedSamples;
  bool truncated = false;  // samples stopped at max_samples
  const World* world = nullptr;  // the carried part's pose comes from it (null: none)

 private:
  const robots::Robot& robot;
  const Location &base, &tool;
};

// One state of one part in the replay recording, in force from time_s until the part's next
// segment (the last one: to the end of the run). A part has no segment before it is fed.
struct PartSegment {
  int part = 0;                  // index into the devices' clock parts (declared, then fed in feeding order)
  double time_s = 0;             // the instant the state began (the clock's anchor_s)
  Holder holder = Holder::world;
  int conveyor = -1;             // index into the workcell's conveyors (holder conveyor)
  Location pose = Location::Identity();  // world pose at time_s; carried: the part in the flange frame
  collision::Vec3 velocity = collision::Vec3::Zero();  // mm/s while on a running belt
  double end_s = std::numeric_limits<double>::infinity();  // it stops there (the belt's end)
};

// The parts' states over a run: observe() appends a segment for every part whose state differs
// from its last one. Each state change of the clock stamps its instant (anchor_s), so a state is
// recorded from the instant it began however late it is observed; a state that began and ended
// between two observations is lost (a part can change at most once per checked pose that way).
struct PartHistory {
  std::vector<PartSegment> segments;  // per part in time order; parts interleaved
  void observe(const CellRuntime& runtime);

 private:
  std::vector<std::size_t> last_;     // per part, its last segment (index into segments)
};

// Replay frames, when grid_s > 0 (off: one branch per event). Every checked pose, the exact
// path at the simulated instants k * grid_s between them, and after a contact the halting pose
// at time_free_s (later samples dropped). Times strictly increase; a sample at the instant of
// the previous one replaces it. With a runtime, the parts' states too (PartHistory).
struct ReplayRecorder final : WalkObserver {
  // BASE and TOOL are read at each pose, as the trace reads them (the tool point's path).
  ReplayRecorder(const robots::Robot& robot, const Location& base, const Location& tool)
      : robot(robot), base(base), tool(tool) {}
  void on_walk_begin(const Trajectory& tr) override;
  void on_stretch(const Trajectory& tr, const Stretch& s) override;
  void on_checked_pose(double t, const robots::JointVector& q, bool contact) override;
  void on_contact(const CollisionReport& report, const robots::JointVector& q_halt, double search_s) override;
  double grid_s = 0;
  std::vector<ReplaySample> samples;
  std::size_t max_samples = kMaxRecordedSamples;
  bool truncated = false;  // samples stopped at max_samples
  // A cell with parts or devices: their states, observed at each walk's start, each checked pose
  // and a contact (the Simulator sets runtime; null: a static cell, nothing recorded).
  const CellRuntime* runtime = nullptr;
  PartHistory parts;

 private:
  void push(double t, const robots::JointVector& q, bool checked);
  const robots::Robot& robot;
  const Location &base, &tool;
  const Trajectory* current = nullptr;
};

// Accuracy figures: step bounds, straight-line deviation, IK residuals, contact brackets.
struct AccuracyRecorder final : WalkObserver {
  explicit AccuracyRecorder(const robots::Robot& robot) : robot(robot) {}
  void on_walk_begin(const Trajectory&) override { ++figures.motions; }
  void on_stretch(const Trajectory& tr, const Stretch& s) override;
  void on_ik(const PoseError& residual, std::uint64_t solves) override;
  void on_contact(const CollisionReport& report, const robots::JointVector& q_halt, double search_s) override;
  RunAccuracy figures;

 private:
  const robots::Robot& robot;
};

// Engine work: poses checked, bisection poses, step counts summed over every query.
struct CountRecorder final : WalkObserver {
  void on_checked_pose(double, const robots::JointVector&, bool) override { ++poses; }
  void on_query(const collision::QueryResult& r, const QueryCost& cost) override;
  void on_distance(const collision::BodyPair&, const collision::DistanceResult&, const DistanceCost& cost) override {
    bisection += cost.probe && !cost.minimum;
    minimum += cost.minimum;
    ++distances;
  }
  std::uint64_t poses = 0;
  std::uint64_t bisection = 0;  // contact-time bisection poses and continuous-checking probes
  std::uint64_t distances = 0;  // distance queries of continuous checking
  std::uint64_t minimum = 0;    //   of which refining the clearance report's minimum
  collision::StepCounts counts;
};

// Clearance report (docs/collision.md §12): per enabled pair that came nearer than within_mm
// (the cell's report_within_mm, or clearance_mm when larger), its least distance along the run:
// the minimum continuous checking refined to kMinimumToleranceMm (a distance measured at its
// pose), when, in which motion, the two witnesses, and what is proven below it.
struct ClearanceApproach {
  collision::BodyPair pair;  // engine ids (World: the scene order)
  double distance_mm = 0;    // 0: in contact
  double time_s = 0;
  int step = 0;              // program step of the motion
  collision::Vec3 point_a = collision::Vec3::Zero(), point_b = collision::Vec3::Zero();  // on pair.a, pair.b [mm]
  // The pair's distance never went below this along the run: distance_mm - kMinimumToleranceMm,
  // lower where a refinement ran out of budget (WalkObserver::on_distance_bound); 0 in contact.
  double lower_bound_mm = 0;
};

// Distances of a stretch are measured before its contact (if any) is known, so they are held
// until the stretch is over and only those up to the contact instant are kept.
struct ClearanceRecorder final : WalkObserver {
  void on_distance(const collision::BodyPair& pair, const collision::DistanceResult& r, const DistanceCost& cost) override;
  void on_stretch(const Trajectory&, const Stretch&) override { commit(std::numeric_limits<double>::infinity()); }
  // At clearance 0 the contact pair came to 0 mm at the contact instant, however the contact
  // was found (a checked pose, a probe, a graze); with a clearance the contact is a distance
  // below it, which continuous checking measures.
  void on_contact(const CollisionReport& report, const robots::JointVector&, double) override;
  void on_walk_end() override { commit(std::numeric_limits<double>::infinity()); }
  void on_distance_bound(const collision::BodyPair& pair, double lower_mm) override;
  double within_mm = 10;
  double clearance_mm = 0;  // the run's: a contact is a distance <= this
  std::vector<ClearanceApproach> pairs;  // in the order first met; per pair the least distance, earliest at ties
  // The pairs nearest first (ties: first met first).
  std::vector<ClearanceApproach> nearest_first() const;

 private:
  void commit(double until_s);  // keeps the held distances measured at or before until_s
  std::vector<ClearanceApproach> held_;
  std::vector<std::pair<collision::BodyPair, double>> bounds_;  // on_distance_bound, least per pair
  double bound_of(const collision::BodyPair& pair) const;
};

// Wall time per phase. A walk's checked-pose queries go to collision (or preprocessing when
// they built a lazy grid), converted from ticks with the walk's steady_clock time; its contact
// search to collision; the rest of it to motion. The facade times planning and engine building
// itself (ScopeTimer).
struct TimingRecorder final : WalkObserver {
  using Clock = std::chrono::steady_clock;
  void on_walk_begin(const Trajectory&) override;
  void on_query(const collision::QueryResult& r, const QueryCost& cost) override;
  void on_distance(const collision::BodyPair&, const collision::DistanceResult&, const DistanceCost& cost) override {
    query_ticks_ += cost.ticks;
  }
  void on_contact(const CollisionReport&, const robots::JointVector&, double search_s) override;
  void on_walk_end() override;
  RunTiming timing;

 private:
  Clock::time_point t0_;
  std::uint64_t k0_ = 0, query_ticks_ = 0, grid_ticks_ = 0;
  double other0_ = 0;
};

// The recorders a Simulator keeps, registered with its walker in this order (timing first: the
// constructor's preprocessing is timed into it). Read them after (or during) a run; switch trace
// and replay on by setting trace.on and replay.grid_s.
struct Recorders {
  Recorders(const robots::Robot& robot, const Location& base, const Location& tool)
      : trace(robot, base, tool), replay(robot, base, tool), accuracy(robot) {}
  TimingRecorder timing;
  CountRecorder counts;
  TraceRecorder trace;
  ReplayRecorder replay;
  AccuracyRecorder accuracy;
  ClearanceRecorder clearance;
};

// Adds the wall time of a scope to `acc`.
struct ScopeTimer {
  double& acc;
  std::chrono::steady_clock::time_point t0 = std::chrono::steady_clock::now();
  ~ScopeTimer() { acc += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); }
};

}  // namespace asimov::motion
