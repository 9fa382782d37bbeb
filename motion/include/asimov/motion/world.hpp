// The cell's collision world as the motion layer drives it: one collision::Engine (the only
// copy of the bodies, their poses and their step-2 containers) and, per body, how it moves.
//
// One body-id space: the scene order of scene_bodies (robot bodies, "tool", objects), then the
// movable parts (declared, then each feeder's parts in feeding order), is the engine's BodyId
// and, for the arm's parts (robot bodies and tool), the index into reach(). One pair type:
// collision::BodyPair over those ids.
//
// Parts (docs/cell-format.md "Parts and devices") are bodies "part:NAME" whose pairs follow
// their state: the pairs tested (pairs()) are the cell's enabled pairs plus, per present part,
// those that can change distance: a resting part against the arm; a part on a conveyor against
// the arm, the objects but its conveyor and the parts not on its conveyor; the carried part
// against everything but the bodies rigid with the flange (the gripper). A carried part moves
// with the flange: its displacement bound is a reach() entry of its own (the flange link's radii
// plus its reach from the flange), so step rules and gap stepping include it. In a cell with many
// pairs of a moving body and a still one, the broad phase leaves out of pairs() those whose gap
// provably stays beyond keep_mm while the moving body stays within its room() (broad_refresh).
#pragma once
#include "asimov/collision/engine.hpp"
#include "asimov/motion/cell.hpp"
#include "asimov/motion/cell_runtime.hpp"
#include "asimov/motion/sampler.hpp"
#include "asimov/robots/displacement_bound.hpp"

#include <algorithm>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace asimov::motion {

// How one body moves: fixed (objects, base-link bodies) or on an arm frame (links, the tool on
// the flange). Parts move as their state says (World: carried, on a running conveyor, resting).
struct BodyMount {
  int frame = -1;  // index into robots::link_frames (the tool: joint_count()); -1: fixed pose
  int hand = -1;   // a body off the arm chain: its robots::HandJoint (posed as the hand and the arm are)
  bool own_motion = false;  // it follows an arm joint on its own: no frame in common with others
};

// The carried part at a pose of the arm (trace, replay).
struct CarriedPose {
  std::string name;  // the part's name (without "part:")
  Location pose;     // world
};

class World {
 public:
  // The arm's reach is known at once; the engine is built now when collision is enabled in
  // the cell, else on the first build_engine(). The world borrows the cell (its robot, and its
  // objects' meshes, which the engine uses in place): the cell must outlive it unchanged.
  explicit World(const Cell& cell);
  ~World();
  World(World&&) noexcept;

  // Builds the engine (bodies, participation, fixed poses) from `cell`; once.
  void build_engine(const Cell& cell);
  bool engine_built() const { return built_; }
  // Null when there is nothing to check (never built, or no enabled pair).
  collision::Engine* engine() { return engine_ ? &*engine_ : nullptr; }
  const collision::Engine* engine() const { return engine_ ? &*engine_ : nullptr; }

  // The parts' states come from `runtime` (the simulator's; it must outlive the world).
  void attach(CellRuntime& runtime) { runtime_ = &runtime, live_of_ = nullptr; }
  // A cell with movable parts whose states come from a runtime (they can move without the arm).
  bool has_parts() const { return has_parts_ && runtime_ != nullptr; }
  // The joints and time of the last pose() (empty joints before the first).
  const robots::JointVector& posed_joints() const { return posed_q_; }
  double posed_time() const { return posed_t_; }
  // The next instant after the devices' clock at which a part or signal changes by itself
  // (+inf without parts): the parts' speeds are constant until then.
  double next_part_change() const;

  // Displacement bounds of the arm's parts, indexed by BodyId (robot bodies, then the tool),
  // then, in a cell with parts, the carried part's (zero radii while nothing is carried).
  std::span<const robots::BodyReach> reach() const { return reach_; }
  // Enabled pairs of two moving bodies (their relative motion bounds the step, §6.3), as reach()
  // indices: arm bodies, and the carried part against the arm.
  std::span<const collision::BodyPair> moving_pairs() const { return moving_pairs_; }
  // The pairs tested at the current state (the engine's enabled pairs in a cell without parts).
  std::span<const collision::BodyPair> pairs() const;
  // Gap stepping: per pair of pairs() (same order) its moving bodies (reach() indices), links
  // and the speed of its conveyor-borne parts; allow_mm is for the walker to fill from the gaps.
  std::span<GapPair> gap_pairs() { return own_list() ? std::span<GapPair>(part_gaps_) : std::span<GapPair>(gap_pairs_); }
  // Changes whenever pairs() changes (parts appear, leave, are grasped or released).
  std::uint64_t pairs_revision() const { return pairs_revision_; }

  // Poses every moving body in the engine for the arm at display joints q (cell.base . frame;
  // BASE moves neither robot nor cell) and, with parts, the parts at simulated time t (the
  // devices' clock is advanced to t; earlier times, as contact-time bisection asks, are posed
  // from the state before the last advance). Needs the engine.
  void pose(const robots::JointVector& q, double t = 0);
  // A walk halted at a contact at t, before the last time the clock was advanced to (the
  // checked pose after the contact): the devices go back to t, so parts on a belt are reported
  // where they touched, and a change after t (a sensor, a timer) never happened. The parts are
  // posed at t.
  void rewind_to(double t);
  // The hand opened or closed (docs/robots.md "Grippers and side branches"): the fingers' bodies
  // are posed so from the next pose() on.
  void set_hand(bool closed);
  // The engine's query on pairs(): request.pairs nullopt means pairs(); a given list loses the
  // pairs of parts absent at the posed time.
  // Resting contact (docs/collision.md §15): a contact of a part with an object or another part
  // counts only when the part sinks in deeper than its resting tolerance (or lies inside); a
  // touching pair found by a query of pairs() (a checked pose) leaves pairs() for touching(),
  // whose pairs the query with `with_touching` (default: a query of pairs()) tests that way,
  // returning those found apart to pairs().
  void query(const collision::QueryRequest& request, collision::QueryResult& out);
  void query(const collision::QueryRequest& request, collision::QueryResult& out, bool with_touching);
  std::span<const collision::BodyPair> touching() const { return touching_; }
  // A pair of a part and an object or another part (its contacts may be resting ones).
  bool resting_pair(const collision::BodyPair& p) const;
  // A pair continuous checking found touching at time t (free by query()): it joins touching().
  void rest(const collision::BodyPair& pair, double t);
  // At a checked pose (the clock's present): the pairs rest() took that still touch here are
  // reported (event `resting`, at the instant they began); the others are forgotten.
  void confirm_resting();
  // After a pose found free: pairs excused at a grasp or release (touching then) that are
  // apart now are tested again (docs/cell-format.md "Gripping").
  void free_pose_seen();
  // Broad phase (a cell with many pairs of an arm body and a body that does not move: an object,
  // a resting part; docs/collision.md §14). The pairs of such a body k with the still bodies whose
  // container gap may be within keep_mm + a skin stay in pairs(); every other one is at least
  // room()[k] + keep_mm apart (its gap, less k's motion since) and leaves pairs() while k moves
  // less than room()[k] from the current poses: it can neither touch (keep_mm >= the clearance)
  // nor enter the clearance report (keep_mm >= report_within_mm). broad_refresh recomputes the
  // near bodies (at the current poses) when some room() is below room_mm, when keep_mm changed, or
  // when resting parts changed; pairs_revision() changes only when pairs() does. Walks call it
  // before each stretch and keep every arm body's motion over it below its room(). query() also
  // recomputes them when a room() is negative (a pose given from elsewhere) or the clearance
  // exceeds keep_mm, so any pose is checked against every pair that may matter.
  void broad_refresh(double keep_mm, double room_mm);
  // Per reach() index, at the current poses (+inf for a body the broad phase does not cover).
  std::span<const double> room();
  // The same for the parts on a running conveyor, as time [s]: the least room over their belt
  // speeds at the current time (+inf when none is covered). A dwell keeps its stretches within it.
  double belt_time() const;
  bool broad_phase() const { return broad_ != nullptr; }
  // Reported body name: "part:NAME", "carried part:NAME" for the part in the gripper.
  std::string body_name(collision::BodyId id) const;
  // The carried part's pose for the arm at q (nullopt: none carried).
  std::optional<CarriedPose> carried(const robots::JointVector& q) const;

  // True when the engine built a lazy voxel grid since the last call that returned true
  // (timing: that query was preprocessing, not collision). Cheap unless `r` reached step 3.
  bool grids_built(const collision::QueryResult& r);

 private:
  enum class Touch { apart, resting, penetrating };
  Touch classify(const collision::BodyPair& pair, const collision::Contact& first);  // resting or penetrating
  Touch touch_state(const collision::BodyPair& pair);
  collision::Contact touch_contact_;
  void test_touching(double clearance_mm, collision::QueryResult& out, bool update);
  void begin_touching(const collision::BodyPair& p, double t, bool event);
  void touching_event(const collision::BodyPair& p, double t);
  void set_part_pose(collision::BodyId id, const Location& pose);
  double resting_tolerance_of(const collision::BodyPair& p) const;
  collision::Vec3 face_normal(collision::BodyId id, std::uint32_t face) const;
  struct Slot {  // one part body
    int clock = -1;  // index into the clock's parts; -1: not placed yet
    Holder holder = Holder::removed;
    int conveyor = -1;
    double speed_mm_s = 0;  // on a running conveyor
  };
  // A placed part that does not move: resting in the world or on a stopped conveyor.
  static bool still_part(const Slot& s);
  void refresh(const DeviceClock& clock);
  void rebuild_pairs();
  void excuse_touching(collision::BodyId part);
  void pose_parts(const DeviceClock& clock, double t, bool all);
  collision::BodyId part_body(const PartState& p) const;
  bool part(collision::BodyId id) const { return has_parts_ && id >= first_part_; }
  int link_of(collision::BodyId id) const;  // arm bodies: frame; others 0
  // pairs() is World's own list (parts, or the broad phase), not the engine's enabled pairs.
  bool own_list() const { return has_parts_ || broad_ != nullptr; }
  GapPair cell_gap(const collision::BodyPair& p) const;
  struct Broad;
  std::unique_ptr<Broad> broad_;  // null: no broad phase
  void broad_build(double keep_mm, double room_mm, bool parts_tree);
  bool broad_skips(collision::BodyId a, collision::BodyId b) const;  // a pair the broad phase leaves out
  bool held_wanted() const;  // a carried part without its near list, at a pose of the clock's state
  void drop_held();  // the carried part's near list is no more (it is kept whole until the next build)
  double belt_room(std::size_t slot, double t) const;
  bool belt_valid(std::size_t slot) const;
  bool belts_need(double room_mm) const;  // some belt-borne part has less room than room_mm now
  robots::JointVector posed_q_;   // the joints and time of the last pose()
  double posed_t_ = 0;

  const Cell* cell_;
  const robots::Robot* robot_;
  collision::Pose base_;
  std::vector<BodyMount> mounts_;  // per BodyId, once the engine is built
  std::vector<robots::BodyReach> reach_;
  std::vector<collision::BodyPair> moving_pairs_, arm_moving_pairs_;
  std::vector<GapPair> gap_pairs_;
  std::vector<collision::Pose> frames_;           // link_frames scratch
  bool hand_closed_ = false;                      // V+ starts with the hand open
  std::vector<collision::BodyId> moving_;         // ids with a frame (posed by pose())
  std::vector<collision::BodyId> unprepared_;     // bodies whose voxel grid is not built yet
  std::optional<collision::Engine> engine_;
  bool built_ = false;

  // Parts (has_parts_ only).
  bool has_parts_ = false;
  CellRuntime* runtime_ = nullptr;
  collision::BodyId first_part_ = 0;
  std::size_t arm_bodies_ = 0;                   // robot bodies and tool: BodyIds below it
  int flange_ = 0;                               // joint_count(): the flange frame
  std::vector<collision::BodyId> feeder_first_;  // per feeder, the BodyId of its first part
  std::vector<int> object_of_conveyor_;          // per conveyor, the BodyId of its body (-1: none)
  std::vector<Slot> slots_;                      // per part body
  std::vector<collision::BodyPair> cell_pairs_;  // enabled pairs without parts
  std::vector<GapPair> cell_gaps_;
  std::vector<collision::BodyPair> part_pairs_;  // pairs(): cell_pairs_ then the parts'
  std::vector<GapPair> part_gaps_;
  std::vector<collision::BodyPair> excused_, filtered_;
  std::vector<char> absent_;                     // per slot, at a pose earlier than the clock
  std::vector<char> to_excuse_;                  // per slot: grasped or released since the last pose
  bool any_absent_ = false;
  std::optional<collision::BodyId> carried_;  // the grasped part (others may rest on it)
  std::vector<collision::BodyPair> touching_, touching_live_;  // resting contacts (not in pairs())
  std::vector<std::pair<collision::BodyPair, double>> unreported_;  // resting since t, no checked pose saw it yet
  std::vector<Location> part_at_;                 // per slot: its pose in the engine
  collision::BodyId first_object_ = 0;            // the cell's objects: BodyIds from here
  bool posed_earlier_ = false;  // the last pose() was at a state before the clock's (bisection)
  std::uint64_t seen_revision_ = ~std::uint64_t{0};
  // pose_parts' moving parts (carried, or with a velocity), as clock indices, for the clock
  // live_of_ at revision live_revision_: a pose re-poses only them (the others stay where they
  // were; 50 resting parts made every pose walk them all). Invalid after rewind_to and attach.
  std::vector<std::size_t> live_;
  const DeviceClock* live_of_ = nullptr;
  std::uint64_t live_revision_ = 0;
  std::uint64_t pairs_revision_ = 0;
  std::optional<DeviceClock> saved_, scratch_;   // the clock before the last advance; a copy at t
  collision::QueryResult scratch_result_;
};

}  // namespace asimov::motion
