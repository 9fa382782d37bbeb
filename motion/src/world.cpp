// The collision world of a cell (motion/README.md, collision scene).
#include "asimov/motion/world.hpp"

#include "asimov/motion/scene.hpp"

namespace asimov::motion {

World::World(const Cell& cell) : robot_(&cell.robot), base_(cell.base) {
  const auto& robot = cell.robot;
  frames_.reserve(static_cast<std::size_t>(robot.joint_count()) + 1);
  for (const auto& b : robot.bodies) reach_.push_back(robots::body_reach(robot, b.mesh, b.link));
  if (cell.tool_shape) reach_.push_back(robots::body_reach(robot, *cell.tool_shape, robot.joint_count()));
  if (cell.collision.enabled) build_engine(cell);
}

void World::build_engine(const Cell& cell) {
  if (built_) return;
  built_ = true;
  collision::Engine e;
  // Bodies, groups and joined pairs: motion/scene.hpp (shared with `asimov pairs`).
  Scene scene = scene_bodies(cell);
  std::optional<collision::AutoPairs> generated;
  if (cell.collision.generated_pairs) {
    const collision::AutoPairsInput in = auto_pairs_input(cell, scene, cell.collision.pair_samples);
    try {
      generated = cell.collision.pairs_cache.empty() ? collision::generate_pairs(in)
                                                    : collision::generate_pairs_cached(in, cell.collision.pairs_cache);
    } catch (const std::exception&) {  // the cache could not be written: the matrix is still good
      generated = collision::generate_pairs(in);
    }
  }
  std::vector<BodyMount> mounts;
  for (SceneBody& b : scene.bodies) {  // ids are the scene indices (a fresh engine)
    const bool moves = b.object < 0 && b.link > 0;  // robot bodies past the base, the tool
    mounts.push_back({moves ? b.link : -1});
    const collision::BodyId id = e.add_body({.name = std::move(b.name), .mesh = std::move(b.mesh), .group = b.group,
                                             .is_static = b.is_static, .halvings = cell.collision.halvings});
    if (!moves) e.set_pose(id, b.object >= 0 ? cell.objects[static_cast<std::size_t>(b.object)].pose : cell.base);
  }
  if (generated) {
    collision::apply_pairs(*generated, e);
  } else {
    for (const collision::BodyPair& p : scene.adjacent) e.set_pair_enabled(p.a, p.b, false);
    for (const collision::BodyPair& p : scene.ignored) e.set_pair_enabled(p.a, p.b, false);
  }
  if (!e.has_enabled_pairs()) return;  // never call the engine
  mounts_ = std::move(mounts);
  for (const collision::BodyPair& p : e.enabled_pairs()) {
    const BodyMount &a = mounts_[p.a], &b = mounts_[p.b];
    if (a.frame >= 0 && b.frame >= 0) moving_pairs_.push_back(p);
    gap_pairs_.push_back({a.frame >= 0 ? static_cast<int>(p.a) : -1, b.frame >= 0 ? static_cast<int>(p.b) : -1,
                          std::max(a.frame, 0), std::max(b.frame, 0), 0});
  }
  for (collision::BodyId id = 0; id < mounts_.size(); ++id) {
    if (mounts_[id].frame >= 0) moving_.push_back(id);
    unprepared_.push_back(id);
  }
  engine_.emplace(std::move(e));
}

void World::pose(const robots::JointVector& q) {
  robots::link_frames(*robot_, q, frames_);
  for (const collision::BodyId id : moving_)
    engine_->set_pose(id, base_ * frames_[static_cast<std::size_t>(mounts_[id].frame)]);
}

bool World::grids_built(const collision::QueryResult& r) {
  // Grids are built only for pairs that pass step 2, so most queries need no look at the bodies.
  if (r.counts.pairs_after_minimax == 0 || unprepared_.empty()) return false;
  const std::size_t before = unprepared_.size();
  std::erase_if(unprepared_, [this](collision::BodyId id) { return engine_->body_preprocessed(id); });
  return unprepared_.size() != before;
}

}  // namespace asimov::motion
