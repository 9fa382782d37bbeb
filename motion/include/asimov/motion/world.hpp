// The cell's collision world as the motion layer drives it: one collision::Engine (the only
// copy of the bodies, their poses and their step-2 containers) and, per body, how it moves.
//
// One body-id space: the scene order of scene_bodies (robot bodies, "tool", objects) is the
// engine's BodyId and, for the arm's parts (robot bodies and tool), the index into reach().
// One pair type: collision::BodyPair over those ids.
#pragma once
#include "asimov/collision/engine.hpp"
#include "asimov/motion/cell.hpp"
#include "asimov/motion/sampler.hpp"
#include "asimov/robots/displacement_bound.hpp"

#include <optional>
#include <span>
#include <vector>

namespace asimov::motion {

// How one body moves. Today a body is fixed (objects, base-link bodies) or rides on an arm
// frame (links, the tool on the flange); carried parts and conveyors (#12) add kinds here.
struct BodyMount {
  int frame = -1;  // index into robots::link_frames (the tool: joint_count()); -1: fixed pose
};

class World {
 public:
  // The arm's reach is known at once; the engine is built now when collision is enabled in
  // the cell, else on the first build_engine().
  explicit World(const Cell& cell);

  // Builds the engine (bodies, participation, fixed poses) from `cell`; once.
  void build_engine(const Cell& cell);
  bool engine_built() const { return built_; }
  // Null when there is nothing to check (never built, or no enabled pair).
  collision::Engine* engine() { return engine_ ? &*engine_ : nullptr; }
  const collision::Engine* engine() const { return engine_ ? &*engine_ : nullptr; }

  // Displacement bounds of the arm's parts, indexed by BodyId (robot bodies, then the tool).
  std::span<const robots::BodyReach> reach() const { return reach_; }
  // Enabled pairs of two moving bodies (their relative motion bounds the step, §6.3).
  std::span<const collision::BodyPair> moving_pairs() const { return moving_pairs_; }
  // Gap stepping: per enabled pair (Engine::enabled_pairs() order) its moving bodies and links;
  // allow_mm is left 0 for the walker to fill from the engine's gaps.
  std::span<const GapPair> gap_pairs() const { return gap_pairs_; }

  // Poses every moving body in the engine for the arm at display joints q (cell.base . frame;
  // BASE moves neither robot nor cell). Needs the engine.
  void pose(const robots::JointVector& q);

  // True when the engine built a lazy voxel grid since the last call that returned true
  // (timing: that query was preprocessing, not collision). Cheap unless `r` reached step 3.
  bool grids_built(const collision::QueryResult& r);

 private:
  const robots::Robot* robot_;
  collision::Pose base_;
  std::vector<BodyMount> mounts_;  // per BodyId, once the engine is built
  std::vector<robots::BodyReach> reach_;
  std::vector<collision::BodyPair> moving_pairs_;
  std::vector<GapPair> gap_pairs_;
  std::vector<collision::Pose> frames_;           // link_frames scratch
  std::vector<collision::BodyId> moving_;         // ids with a frame (posed by pose())
  std::vector<collision::BodyId> unprepared_;     // bodies whose voxel grid is not built yet
  std::optional<collision::Engine> engine_;
  bool built_ = false;
};

}  // namespace asimov::motion
