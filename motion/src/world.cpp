// The collision world of a cell (motion/README.md, collision scene).
#include "asimov/motion/world.hpp"

#include "asimov/motion/resting.hpp"
#include "asimov/motion/scene.hpp"

#include "broad_phase.hpp"

#include <algorithm>
#include <limits>

namespace asimov::motion {
namespace {
// A grasped or released part "touches" a body this close [mm]: the grip's rounding (flange^-1 .
// pose) can lift a part lying on the table by 1e-13 mm, which is no clearance to speak of.
constexpr double kTouchMm = 1e-6;

collision::BodyPair ordered(collision::BodyId a, collision::BodyId b) { return {std::min(a, b), std::max(a, b)}; }

// Broad phase (docs/collision.md §14): used from this many pairs of an arm body and a still body
// on (fewer cost less to test than the broad phase's own bookkeeping: the default cell has 16).
constexpr std::size_t kBroadMinPairs = 64;
// Skin [mm] beyond keep_mm within which still bodies are kept near an arm body: larger keeps
// more pairs, smaller recomputes them more often (bench/bench_workcell.cpp).
constexpr double kSkinMm = 50;
constexpr double kRefreshSkin = 0.5;  // the near lists are recomputed once this much of the skin is used
constexpr std::size_t kMaxMovers = 31;  // one bit each in Broad::mask
constexpr unsigned kHeldBit = 31;      // the carried part's bit in Broad::mask
// A part on a conveyor keeps the still bodies near it that its belt reaches in this time [s].
constexpr double kBeltHorizonS = 0.5;
}  // namespace

// The broad phase's state: the arm bodies it covers (movers), the still bodies in two trees
// (objects, built once; resting parts, rebuilt when they change), and per mover the still bodies
// near it when last computed, at joints q0, with the least gap bound of the others.
struct World::Broad {
  struct Mover {
    collision::BodyId id = 0;  // also its reach() index (an arm body)
    double lower = INFINITY;   // least gap bound of the still bodies not in `near` (at q0)
    std::vector<collision::BodyId> near, next;  // sorted
  };
  std::vector<Mover> movers;
  // The carried part, a mover while it is held (its reach: World's last reach() slot, which a
  // grasp or release changes, so they drop its near list until the next build).
  Mover held;
  bool held_ready = false;
  std::vector<int> mover_of;          // per BodyId: index in movers (kHeldBit: the carried part), -1
  std::vector<std::uint32_t> mask;    // per BodyId: bit m when near mover m
  std::vector<char> in_tree;          // per BodyId: a still body in a tree (objects; resting parts while unchanged)
  std::vector<Location> rest_at;      // per part slot: its pose when put in the tree
  StillTree objects, parts;
  bool parts_dirty = true;            // resting parts changed since the parts tree was built
  bool ready = false;                 // near lists computed (else every pair is kept)
  double keep = 0, radius = 0;
  robots::JointVector q0;
  // Per part slot, a part on a running conveyor (it moves at speed_mm_s until the devices' next
  // change, which recomputes it): the still bodies near it at time t0, and the least gap bound
  // of the others then.
  struct Belt {
    bool ready = false;
    double t0 = 0, lower = INFINITY, speed = 0;
    std::vector<collision::BodyId> near;  // sorted
  };
  std::vector<Belt> belts;
  // Per part slot: changed since a full contact query last found every pair free (World::query);
  // only tested parts lose their pairs with the robot's fixed bodies, so a part placed touching
  // the robot's base is still found.
  std::vector<char> untested;
  bool any_untested = false;
  std::vector<collision::BodyPair> fixed_pairs;  // cell pairs the broad phase never leaves out
  std::vector<collision::BodyPair> scratch;
  std::vector<collision::BodyId> scratch_ids;
  std::vector<double> room;           // per reach() index

  // m's near list at its pose now (bit: its bit in mask); true when it changed.
  bool renear(Mover& m, unsigned bit, collision::Engine& engine) {
    const collision::Engine::PlacedBounds at = engine.placed_bounds(m.id);
    m.next.clear();
    m.lower = std::min(objects.query(at, radius, m.next), parts.query(at, radius, m.next));
    std::sort(m.next.begin(), m.next.end());
    if (m.next == m.near) return false;
    unmark(m, bit);
    for (const collision::BodyId o : m.next) mask[o] |= std::uint32_t{1} << bit;
    m.near.swap(m.next);
    return true;
  }
  void unmark(const Mover& m, unsigned bit) {
    for (const collision::BodyId o : m.near) mask[o] &= ~(std::uint32_t{1} << bit);
  }
};

World::~World() = default;
World::World(World&&) noexcept = default;

World::World(const Cell& cell) : cell_(&cell), robot_(&cell.robot), base_(cell.base) {
  const auto& robot = cell.robot;
  frames_.reserve(static_cast<std::size_t>(robot.joint_count()) + 1);
  for (const auto& b : robot.bodies) reach_.push_back(robots::body_reach(robot, b));  // fingers: both places
  if (cell.tool_shape) reach_.push_back(robots::body_reach(robot, *cell.tool_shape, robot.joint_count()));
  arm_bodies_ = reach_.size();
  flange_ = robot.joint_count();
  const Workcell& w = cell.workcell;
  has_parts_ = !w.parts.empty() || !w.feeders.empty();
  if (has_parts_) reach_.emplace_back();  // the carried part's slot
  if (cell.collision.enabled) build_engine(cell);
}

void World::build_engine(const Cell& cell) {
  if (built_) return;
  built_ = true;
  collision::Engine e;
  // Bodies, groups and joined pairs: motion/scene.hpp (shared with `asimov pairs`).
  // The objects' meshes are borrowed from the cell (the world never outlives it), not copied;
  // the generated pair matrix samples every body, so it gets the copies.
  Scene scene = scene_bodies(cell, cell.collision.generated_pairs);
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
  std::vector<std::string> object_names;
  for (SceneBody& b : scene.bodies) {  // ids are the scene indices (a fresh engine)
    // Robot bodies past the base, the tool, and a follower of an arm joint even on the base.
    const bool own = b.object < 0 && b.hand >= 0 && robots::hand_follows_arm(cell.robot, b.hand);
    const bool moves = b.object < 0 && (b.link > 0 || own);
    mounts.push_back({moves ? b.link : -1, moves ? b.hand : -1, own});
    if (b.object >= 0) object_names.push_back(b.name);
    const collision::Polyhedron* borrowed = b.object >= 0 ? &cell.objects[static_cast<std::size_t>(b.object)].mesh : nullptr;
    const collision::BodyId id =
        e.add_body({.name = std::move(b.name), .mesh = borrowed ? collision::Polyhedron{} : std::move(b.mesh),
                    .mesh_ref = borrowed, .group = b.group, .is_static = b.is_static, .halvings = cell.collision.halvings});
    if (!moves) e.set_pose(id, b.object >= 0 ? cell.objects[static_cast<std::size_t>(b.object)].pose : cell.base);
  }
  if (generated) {
    collision::apply_pairs(*generated, e);
  } else {
    for (const collision::BodyPair& p : scene.adjacent) e.set_pair_enabled(p.a, p.b, false);
    for (const auto* list : {&scene.srdf, &scene.start_contacts, &scene.ignored})
      for (const collision::BodyPair& p : *list) e.set_pair_enabled(p.a, p.b, false);
  }
  const std::vector<collision::BodyPair> cell_pairs(e.enabled_pairs().begin(), e.enabled_pairs().end());
  if (has_parts_) {
    // Every part a body of its own group, placed by refresh(); one body per part a feeder can
    // ever place, so a part's grid is built once whatever happens to it.
    first_part_ = static_cast<collision::BodyId>(e.body_count());
    const Workcell& w = cell.workcell;
    const auto add_part = [&](const PartDef& d, const std::string& name) {
      mounts.push_back({-1});
      e.add_body({.name = "part:" + name, .mesh = d.mesh, .halvings = cell.collision.halvings});
      slots_.emplace_back();
    };
    for (const PartDef& d : w.parts) add_part(d, d.name);
    for (const Feeder& f : w.feeders) {
      feeder_first_.push_back(static_cast<collision::BodyId>(e.body_count()));
      for (int k = 1; k <= f.count; ++k) add_part(f.part, f.prefix + std::to_string(k));
    }
    const std::size_t first_object = scene.bodies.size() - cell.objects.size();
    first_object_ = static_cast<collision::BodyId>(first_object);
    part_at_.assign(slots_.size(), Location::Identity());
    for (const Conveyor& c : w.conveyors) {
      const auto it = std::find(object_names.begin(), object_names.end(), c.name);
      object_of_conveyor_.push_back(it == object_names.end() ? -1
                                                              : static_cast<int>(first_object + (it - object_names.begin())));
    }
    absent_.assign(slots_.size(), 0);
    to_excuse_.assign(slots_.size(), 0);
    if (slots_.empty()) has_parts_ = false, reach_.pop_back();
  }
  if (cell_pairs.empty() && !has_parts_) return;  // never call the engine
  mounts_ = std::move(mounts);
  for (const collision::BodyPair& p : cell_pairs) {
    const BodyMount &a = mounts_[p.a], &b = mounts_[p.b];
    if (a.frame >= 0 && b.frame >= 0) arm_moving_pairs_.push_back(p);
    gap_pairs_.push_back(cell_gap(p));
  }
  moving_pairs_ = arm_moving_pairs_;
  // World's own list starts from the cell's pairs (parts, or the broad phase, change it).
  cell_pairs_ = cell_pairs, cell_gaps_ = gap_pairs_, part_pairs_ = cell_pairs_, part_gaps_ = cell_gaps_;
  for (collision::BodyId id = 0; id < mounts_.size(); ++id) {
    if (mounts_[id].frame >= 0) moving_.push_back(id);
    unprepared_.push_back(id);
  }
  engine_.emplace(std::move(e));
  // The broad phase: arm bodies on the chain (no motion of their own; fingers too: their reach
  // holds both hand states, and a hand change recomputes the near lists) against the
  // objects and resting parts, when there are enough such pairs.
  auto b = std::make_unique<Broad>();
  b->mover_of.assign(mounts_.size(), -1);
  for (collision::BodyId id = 0; id < arm_bodies_ && b->movers.size() < kMaxMovers; ++id)
    if (mounts_[id].frame >= 0 && !mounts_[id].own_motion) {
      b->mover_of[id] = static_cast<int>(b->movers.size());
      b->movers.emplace_back().id = id;
    }
  const collision::BodyId objects_end = has_parts_ ? first_part_ : static_cast<collision::BodyId>(mounts_.size());
  std::vector<collision::BodyId> objects;
  for (collision::BodyId id = static_cast<collision::BodyId>(arm_bodies_); id < objects_end; ++id) objects.push_back(id);
  const std::size_t still = objects.size() + slots_.size();
  if (cell.collision.broad_phase && !b->movers.empty() && b->movers.size() * still >= kBroadMinPairs) {
    b->mask.assign(mounts_.size(), 0);
    b->in_tree.assign(mounts_.size(), 0);
    b->rest_at.resize(slots_.size());
    b->belts.resize(slots_.size());
    b->untested.assign(slots_.size(), 0);
    for (const collision::BodyId o : objects) b->in_tree[o] = 1;
    b->objects.build(*engine_, objects);
    b->keep = report_distance_mm(cell.collision);
    b->room.assign(reach_.size(), INFINITY);
    for (const collision::BodyPair& p : cell_pairs)
      if (!((b->mover_of[p.a] >= 0 && b->in_tree[p.b]) || (b->mover_of[p.b] >= 0 && b->in_tree[p.a]))) b->fixed_pairs.push_back(p);
    broad_ = std::move(b);
    rebuild_pairs();  // every pair until the near lists are computed at the first pose
  }
}

GapPair World::cell_gap(const collision::BodyPair& p) const {
  const BodyMount &a = mounts_[p.a], &b = mounts_[p.b];
  return {a.frame >= 0 ? static_cast<int>(p.a) : -1, b.frame >= 0 ? static_cast<int>(p.b) : -1,
          a.own_motion ? -1 : std::max(a.frame, 0), b.own_motion ? -1 : std::max(b.frame, 0), 0};
}

bool World::broad_skips(collision::BodyId a, collision::BodyId b) const {
  if (!broad_ || !broad_->ready) return false;
  const Broad& s = *broad_;
  const auto skips = [&](collision::BodyId m, collision::BodyId o) {
    const int k = s.mover_of[m];
    return k >= 0 && s.in_tree[o] && !(s.mask[o] >> k & 1u);
  };
  const auto belt_skips = [&](collision::BodyId m, collision::BodyId o) {
    if (!part(m) || !s.in_tree[o] || !belt_valid(m - first_part_)) return false;
    const Broad::Belt& belt = s.belts[m - first_part_];
    return !std::binary_search(belt.near.begin(), belt.near.end(), o);
  };
  // A fixed robot body (the base link) and a resting part in the tree: neither moves, and the
  // part was tested at every pose since it came to rest (the tree takes tested parts only).
  const auto still_still = [&](collision::BodyId f, collision::BodyId o) {
    return f < arm_bodies_ && mounts_[f].frame < 0 && part(o) && s.in_tree[o] && !s.untested[o - first_part_];
  };
  // Two still bodies of the trees (objects; parts at rest, each tested at every pose since it
  // came to rest): their distance cannot change until one of them leaves the tree.
  const auto tested = [&](collision::BodyId x) { return s.in_tree[x] && !(part(x) && s.untested[x - first_part_]); };
  return skips(a, b) || skips(b, a) || belt_skips(a, b) || belt_skips(b, a) || still_still(a, b) || still_still(b, a) ||
         (tested(a) && tested(b));
}

bool World::still_part(const Slot& s) {
  return s.clock >= 0 && (s.holder == Holder::world || s.holder == Holder::conveyor) && s.speed_mm_s == 0;
}

bool World::belt_valid(std::size_t slot) const {
  const Broad::Belt& belt = broad_->belts[slot];
  return belt.ready && slots_[slot].holder == Holder::conveyor && slots_[slot].speed_mm_s == belt.speed;
}

// What is left of a belt-borne part's room [mm] at time t (as room() for the arm's bodies).
double World::belt_room(std::size_t slot, double t) const {
  const Broad::Belt& belt = broad_->belts[slot];
  if (!belt_valid(slot)) return INFINITY;
  const double moved = slots_[slot].speed_mm_s * std::abs(t - belt.t0) * (1 + 1e-9) + 1e-9;
  return belt.lower - broad_->keep - moved - 1e-9 * broad_->keep;
}

double World::belt_time() const {
  double t = INFINITY;
  if (!broad_) return t;
  for (std::size_t s = 0; s < broad_->belts.size(); ++s)
    if (belt_valid(s)) t = std::min(t, belt_room(s, posed_t_) / slots_[s].speed_mm_s);
  return t;
}

bool World::belts_need(double room_mm) const {
  for (std::size_t s = 0; s < broad_->belts.size(); ++s) {
    const Slot& slot = slots_[s];
    const bool moving = slot.clock >= 0 && slot.holder == Holder::conveyor && slot.speed_mm_s > 0 && !absent_[s];
    if (moving && (!belt_valid(s) || belt_room(s, posed_t_) < room_mm)) return true;
  }
  return false;
}

std::span<const double> World::room() {
  if (!broad_) return {};
  Broad& b = *broad_;
  if (!b.ready) {
    std::fill(b.room.begin(), b.room.end(), INFINITY);
    return b.room;
  }
  const robots::JointVector delta = posed_q_ - b.q0;
  for (const Broad::Mover& m : b.movers) {
    // Every left-out still body is >= lower - (k's motion since q0) apart; room is what is left
    // beyond keep, less room for the rounding of the bound.
    const double moved = robots::max_displacement(reach_[m.id], delta) * (1 + 1e-9) + 1e-9;
    b.room[m.id] = m.lower - b.keep - moved - 1e-9 * b.keep;
  }
  if (has_parts_) {
    const std::size_t slot = reach_.size() - 1;
    const double moved = b.held_ready ? robots::max_displacement(reach_[slot], delta) * (1 + 1e-9) + 1e-9 : 0;
    b.room[slot] = b.held_ready ? b.held.lower - b.keep - moved - 1e-9 * b.keep : INFINITY;
  }
  return b.room;
}

void World::broad_refresh(double keep_mm, double room_mm) {
  if (!broad_ || posed_q_.size() == 0) return;
  Broad& b = *broad_;
  bool need = !b.ready || (b.parts_dirty && has_parts_) || keep_mm != b.keep || held_wanted();
  // Recomputed once half the skin is used: gap stepping keeps each stretch within 0.9 of the
  // room, so a room run down to the step would cut the stretches short before it (the arm would
  // approach the left-out bodies as if they were there).
  const double low = std::max(room_mm, kRefreshSkin * kSkinMm);
  if (!need)
    for (const double r : room())
      if (r < low) need = true;
  if (need || belts_need(low)) broad_build(keep_mm, room_mm, true);
}

void World::broad_build(double keep_mm, double room_mm, bool parts_tree) {
  Broad& b = *broad_;
  bool changed = !b.ready;
  if (b.parts_dirty && parts_tree && has_parts_ && runtime_) {
    // The resting parts (on the table, a pallet, another part or a stopped belt) into the parts
    // tree, posed in the engine where the clock has them now (a bisection may have left one at an
    // earlier state's pose).
    std::vector<collision::BodyId> resting;
    const DeviceClock& clock = runtime_->clock();
    for (std::size_t s = 0; s < slots_.size(); ++s) {
      const collision::BodyId id = first_part_ + static_cast<collision::BodyId>(s);
      const Slot& slot = slots_[s];
      const bool rest = still_part(slot);
      b.in_tree[id] = rest;
      if (!rest) continue;
      b.rest_at[s] = clock.parts()[static_cast<std::size_t>(slot.clock)].pose_at(clock.time_s());
      set_part_pose(id, b.rest_at[s]);
      resting.push_back(id);
    }
    b.parts_dirty = false;
    b.parts.build(*engine_, resting);
    changed = true;
  }
  b.keep = keep_mm;
  b.radius = keep_mm + std::max(kSkinMm, 4 * room_mm);
  b.q0 = posed_q_;
  for (std::size_t k = 0; k < b.movers.size(); ++k)
    if (b.renear(b.movers[k], static_cast<unsigned>(k), *engine_)) changed = true;
  // The carried part, at its pose now (rigid with the flange: its reach is the last slot's).
  if (carried_ && !posed_earlier_) {
    Broad::Mover& m = b.held;
    if (b.held_ready && m.id != *carried_) drop_held();
    m.id = *carried_;
    if (b.renear(m, kHeldBit, *engine_) || !b.held_ready) changed = true;  // (ready: its pairs may leave)
    b.mover_of[m.id] = static_cast<int>(kHeldBit);
    b.held_ready = true;
  }
  // Parts on a running conveyor, at their poses now.
  for (std::size_t s = 0; s < b.belts.size(); ++s) {
    Broad::Belt& belt = b.belts[s];
    const Slot& slot = slots_[s];
    const bool moving = slot.clock >= 0 && slot.holder == Holder::conveyor && slot.speed_mm_s > 0 && !absent_[s];
    if (!moving) {
      changed = changed || belt.ready;
      belt.ready = false;
      continue;
    }
    const collision::Engine::PlacedBounds at = engine_->placed_bounds(first_part_ + static_cast<collision::BodyId>(s));
    const double radius = keep_mm + std::max({kSkinMm, 4 * room_mm, slot.speed_mm_s * kBeltHorizonS});
    b.scratch_ids.clear();
    belt.lower = std::min(b.objects.query(at, radius, b.scratch_ids), b.parts.query(at, radius, b.scratch_ids));
    std::sort(b.scratch_ids.begin(), b.scratch_ids.end());
    belt.t0 = posed_t_;
    belt.speed = slot.speed_mm_s;
    if (!belt.ready || b.scratch_ids != belt.near) changed = true;
    belt.near.swap(b.scratch_ids);
    belt.ready = true;
  }
  b.ready = true;
  if (changed) rebuild_pairs();
}

bool World::held_wanted() const {
  return carried_ && !broad_->held_ready && !posed_earlier_;
}

void World::drop_held() {
  Broad& b = *broad_;
  if (!b.held_ready) return;
  b.unmark(b.held, kHeldBit);
  b.held.near.clear();
  b.mover_of[b.held.id] = -1;
  b.held_ready = false;
}

void World::set_hand(bool closed) {
  // The fingers move without the joints: their near lists are recomputed (every pair meanwhile).
  if (broad_ && broad_->ready && closed != hand_closed_) {
    broad_->ready = false;
    rebuild_pairs();
  }
  hand_closed_ = closed;
}

std::span<const collision::BodyPair> World::pairs() const {
  if (own_list()) return part_pairs_;
  return engine_ ? engine_->enabled_pairs() : std::span<const collision::BodyPair>();
}

int World::link_of(collision::BodyId id) const {
  if (id < mounts_.size() && mounts_[id].frame >= 0) return mounts_[id].frame;
  return 0;
}

collision::BodyId World::part_body(const PartState& p) const {
  return p.feeder < 0 ? first_part_ + static_cast<collision::BodyId>(p.ordinal)
                      : feeder_first_[static_cast<std::size_t>(p.feeder)] + static_cast<collision::BodyId>(p.ordinal);
}

double World::next_part_change() const {
  return has_parts() ? runtime_->clock().next_change() : std::numeric_limits<double>::infinity();
}

void World::pose(const robots::JointVector& q, double t) {
  posed_q_ = q;
  posed_t_ = t;
  posed_earlier_ = false;
  robots::link_frames(*robot_, q, frames_);
  for (const collision::BodyId id : moving_) {
    const BodyMount& m = mounts_[id];
    if (m.hand < 0) engine_->set_pose(id, base_ * frames_[static_cast<std::size_t>(m.frame)]);
    else engine_->set_pose(id, base_ * frames_[static_cast<std::size_t>(m.frame)] * robots::hand_offset(*robot_, m.hand, hand_closed_, q));
  }
  if (!has_parts_ || !runtime_) return;
  DeviceClock& clock = runtime_->clock();
  if (t >= clock.time_s()) {
    any_absent_ = false;
    // Keep the state before a change, for the poses bisection may ask between the two (and
    // for rewind_to). A pose at the clock's own time advances nothing: the copy stays.
    if (t > clock.time_s()) {
      if (clock.next_change() <= t) saved_ = clock;
      else saved_.reset();
    }
    clock.advance_to(t);
    const bool changed = clock.revision() != seen_revision_;
    if (changed) refresh(clock);
    pose_parts(clock, t, changed);
    if (changed)
      for (std::size_t s = 0; s < slots_.size(); ++s)
        if (to_excuse_[s]) {
          to_excuse_[s] = 0;
          if (slots_[s].holder != Holder::removed) excuse_touching(first_part_ + static_cast<collision::BodyId>(s));
        }
    return;
  }
  // Earlier than the clock: the state then is the one before the last advance (or the current
  // one when nothing changed in between), advanced to t on a copy.
  if (!saved_ || saved_->time_s() > t) {
    pose_parts(clock, t, false);
    return;
  }
  scratch_ = *saved_;
  scratch_->advance_to(t);
  pose_parts(*scratch_, t, true);
  // The carried part may not be on the flange then (before its grasp): all its pairs are kept.
  posed_earlier_ = true;
  if (broad_ && broad_->held_ready) {
    drop_held();
    rebuild_pairs();
  }
  any_absent_ = false;
  std::vector<char> present(slots_.size(), 0);
  for (const PartState& p : scratch_->parts())
    if (p.holder != Holder::removed) present[part_body(p) - first_part_] = 1;
  for (std::size_t s = 0; s < slots_.size(); ++s)
    if (slots_[s].clock >= 0 && slots_[s].holder != Holder::removed && !present[s]) any_absent_ = true;
  if (any_absent_)
    for (std::size_t s = 0; s < slots_.size(); ++s) absent_[s] = !present[s];
}

void World::rewind_to(double t) {
  if (!has_parts_ || !runtime_ || !engine_) return;
  DeviceClock& clock = runtime_->clock();
  if (!(t < clock.time_s())) return;
  if (!clock.rewind(t)) {
    // Something changed after t: the copy from before the last advance, advanced to t. (Walks
    // advance the clock only to checked poses, and a contact lies after the one before.)
    if (!saved_ || saved_->time_s() > t) return;
    clock = *saved_;
    clock.advance_to(t);
    live_of_ = nullptr;  // its revisions may repeat those of the future it replaced
  }
  saved_.reset();
  scratch_.reset();
  const bool changed = clock.revision() != seen_revision_;
  if (changed) refresh(clock);
  pose_parts(clock, t, true);
}

void World::pose_parts(const DeviceClock& clock, double t, bool all) {
  const auto& parts = clock.parts();
  const auto moving = [](const PartState& p) { return p.holder == Holder::carried || (p.holder != Holder::removed && !p.velocity.isZero()); };
  if (!all && (live_of_ != &clock || live_revision_ != clock.revision())) {
    // Holders and velocities change only with the revision (DeviceClock::revision).
    live_.clear();
    for (std::size_t i = 0; i < parts.size(); ++i)
      if (moving(parts[i])) live_.push_back(i);
    live_of_ = &clock, live_revision_ = clock.revision();
  }
  bool left_tree = false;
  const std::size_t n = all ? parts.size() : live_.size();
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t i = all ? k : live_[k];
    const PartState& p = parts[i];
    const collision::BodyId id = part_body(p);
    if (p.holder == Holder::carried) {
      set_part_pose(id, base_ * frames_[static_cast<std::size_t>(flange_)] * runtime_->grip_of(i));
    } else if (p.holder != Holder::removed && (all || !p.velocity.isZero())) {
      const Location at = p.pose_at(t);
      set_part_pose(id, at);
      // A part of the broad phase's tree posed elsewhere (an earlier state, for bisection) is
      // no longer where the tree has it: all its pairs are kept until the tree is rebuilt.
      if (broad_ && broad_->in_tree[id] && !(at.matrix() == broad_->rest_at[id - first_part_].matrix())) {
        broad_->in_tree[id] = 0;
        broad_->untested[id - first_part_] = broad_->any_untested = left_tree = true;
      }
    }
  }
  if (left_tree) rebuild_pairs();
}

// The parts' holders changed: new pairs, and the grasped or released part's contacts excused.
void World::refresh(const DeviceClock& clock) {
  seen_revision_ = clock.revision();
  if (broad_) drop_held();  // a grasp or release changes the carried part's reach (below)
  carried_.reset();
  for (std::size_t i = 0; i < clock.parts().size(); ++i) {
    const PartState& p = clock.parts()[i];
    const collision::BodyId id = part_body(p);
    Slot& s = slots_[id - first_part_];
    const bool was_carried = s.holder == Holder::carried, placed = s.clock >= 0;
    const bool was_still = placed && still_part(s);
    s.clock = static_cast<int>(i);
    s.conveyor = p.holder == Holder::conveyor ? p.conveyor : -1;
    s.speed_mm_s = p.velocity.norm();
    // A grasp or a release: the pairs that touch then are excused (marked here, tested once posed).
    if (placed && was_carried != (p.holder == Holder::carried)) to_excuse_[id - first_part_] = 1;
    // A part placed, moved, stopped or taken leaves the broad phase's tree and is untested: all
    // its pairs are kept until the tree is rebuilt (at the next stretch, whose poses are all at
    // or after this change) and a full query found them free. One still before and after, in
    // the same holder, stays.
    const bool still_now = (p.holder == Holder::world || p.holder == Holder::conveyor) && p.velocity.isZero();
    if (broad_ && !(was_still && still_now && p.holder == s.holder)) {
      // (It stays an item of the tree until the next rebuild: harmless, only in_tree counts.)
      if (still_now) broad_->parts_dirty = true;
      broad_->untested[id - first_part_] = broad_->any_untested = true;
      broad_->in_tree[id] = 0;
    }
    if (placed && p.holder == Holder::removed && s.holder != Holder::removed)
      std::erase_if(excused_, [id](const collision::BodyPair& x) { return x.a == id || x.b == id; });
    s.holder = p.holder;
  }
  if (runtime_->carried()) carried_ = part_body(clock.parts()[*runtime_->carried()]);
  reach_.back() = robots::BodyReach{};
  if (carried_) {
    // The flange link's radii with the carried parts' meshes (the grasped one and those resting
    // on it) in the flange frame: their reach from the flange.
    collision::Polyhedron in_flange;
    for (std::size_t i = 0; i < clock.parts().size(); ++i) {
      if (clock.parts()[i].holder != Holder::carried) continue;
      const Location g = runtime_->grip_of(i);
      for (const auto& v : clock.parts()[i].def->mesh.vertices) in_flange.vertices.push_back(g * v);
    }
    reach_.back() = robots::body_reach(*robot_, in_flange, flange_);
  }
  rebuild_pairs();
}

void World::rebuild_pairs() {
  ++pairs_revision_;
  if (broad_ && broad_->ready) {
    // The cell's pairs in their order (sorted): those the broad phase never leaves out, and the
    // enabled pairs of each arm body with the objects near it.
    Broad& b = *broad_;
    b.scratch = b.fixed_pairs;
    for (const Broad::Mover& m : b.movers)
      for (const collision::BodyId o : m.near)
        if ((!has_parts_ || o < first_part_) && engine_->pair_enabled(m.id, o)) b.scratch.push_back(ordered(m.id, o));
    std::sort(b.scratch.begin(), b.scratch.end());
    part_pairs_.assign(b.scratch.begin(), b.scratch.end());
    part_gaps_.clear();
    for (const collision::BodyPair& p : part_pairs_) part_gaps_.push_back(cell_gap(p));
  } else {  // every pair of the cell (no broad phase, or its near lists not computed yet)
    part_pairs_ = cell_pairs_;
    part_gaps_ = cell_gaps_;
  }
  moving_pairs_ = arm_moving_pairs_;
  if (!has_parts_) return;
  const int slot = static_cast<int>(reach_.size() - 1);
  const collision::BodyId parts_end = first_part_ + static_cast<collision::BodyId>(slots_.size());
  const auto present = [&](collision::BodyId id) { return slots_[id - first_part_].clock >= 0 && slots_[id - first_part_].holder != Holder::removed; };
  const auto excused = [&](const collision::BodyPair& p) { return std::find(excused_.begin(), excused_.end(), p) != excused_.end(); };
  // Reach index and link of body `id` in a pair (the carried part: its slot on the flange).
  const auto mover = [&](collision::BodyId id) -> std::pair<int, int> {
    if (id < arm_bodies_)
      return mounts_[id].frame >= 0 ? std::pair{static_cast<int>(id), mounts_[id].own_motion ? -1 : mounts_[id].frame} : std::pair{-1, 0};
    if (part(id) && slots_[id - first_part_].holder == Holder::carried) return {slot, flange_};
    return {-1, 0};
  };
  touching_live_.clear();
  const auto add = [&](collision::BodyId a, collision::BodyId b) {
    const collision::BodyPair p = ordered(a, b);
    if (std::find(touching_.begin(), touching_.end(), p) != touching_.end()) {  // tested by classify()
      touching_live_.push_back(p);
      return;
    }
    if (excused(p) || broad_skips(p.a, p.b)) return;
    const auto [ra, la] = mover(p.a);
    const auto [rb, lb] = mover(p.b);
    double speed = 0;
    for (const collision::BodyId id : {p.a, p.b})
      if (part(id)) speed += slots_[id - first_part_].speed_mm_s;
    part_pairs_.push_back(p);
    part_gaps_.push_back({ra, rb, la, lb, 0, speed});
    if (ra >= 0 && rb >= 0) moving_pairs_.push_back({static_cast<std::uint32_t>(ra), static_cast<std::uint32_t>(rb)});
  };
  for (collision::BodyId p = first_part_; p < parts_end; ++p) {
    if (!present(p)) continue;
    const Slot& s = slots_[p - first_part_];
    const bool carried = s.holder == Holder::carried, belt = s.holder == Holder::conveyor;
    for (collision::BodyId b = 0; b < arm_bodies_; ++b)  // the gripper (rigid with the flange) holds it
      if (!(carried && mounts_[b].frame == flange_)) add(b, p);
    if (carried || belt) {
      const int own = belt ? object_of_conveyor_[static_cast<std::size_t>(s.conveyor)] : -1;
      for (collision::BodyId o = static_cast<collision::BodyId>(arm_bodies_); o < first_part_; ++o)
        if (static_cast<int>(o) != own) add(o, p);
    }
    for (collision::BodyId q = p + 1; q < parts_end; ++q) {
      if (!present(q)) continue;
      const Slot& r = slots_[q - first_part_];
      const bool q_carried = r.holder == Holder::carried, q_belt = r.holder == Holder::conveyor;
      // Resting parts keep their distance; parts on one conveyor move together, and so do the
      // carried ones (the grasped part and those resting on it).
      if (carried && q_carried) continue;
      if (carried || q_carried || (belt != q_belt) || (belt && q_belt && s.conveyor != r.conveyor)) add(p, q);
    }
  }
  touching_.swap(touching_live_);
}

void World::excuse_touching(collision::BodyId id) {
  for (std::size_t i = 0; i < part_pairs_.size();) {
    const collision::BodyPair p = part_pairs_[i];
    if (p.a != id && p.b != id) {
      ++i;
      continue;
    }
    // A part and an object or part: excused only when it sinks in already (a feeder refilling
    // its spot while the grasped part is still there); a resting contact is tested as such.
    const bool rests = resting_pair(p);
    engine_->query({.clearance_mm = rests ? 0 : kTouchMm, .pairs = std::span(&p, 1)}, scratch_result_);
    if (!scratch_result_.collided || (rests && classify(p, collision::Contact(scratch_result_.contact)) == Touch::resting)) {
      ++i;
      continue;
    }
    excused_.push_back(p);
    part_pairs_.erase(part_pairs_.begin() + static_cast<std::ptrdiff_t>(i));
    part_gaps_.erase(part_gaps_.begin() + static_cast<std::ptrdiff_t>(i));
    ++pairs_revision_;
  }
}

void World::free_pose_seen() {
  if (excused_.empty()) return;
  const std::size_t before = excused_.size();
  std::erase_if(excused_, [this](const collision::BodyPair& p) {
    engine_->query({.clearance_mm = kTouchMm, .pairs = std::span(&p, 1)}, scratch_result_);
    return !scratch_result_.collided;
  });
  if (excused_.size() != before) rebuild_pairs();
}

void World::query(const collision::QueryRequest& request, collision::QueryResult& out) {
  query(request, out, !request.pairs && request.contact);
}

void World::query(const collision::QueryRequest& request, collision::QueryResult& out, bool with_touching) {
  if (broad_ && posed_q_.size() != 0) {
    // Any pose: the near lists are recomputed when a left-out pair may be nearer than keep now.
    const double keep = std::max(broad_->keep, request.clearance_mm);
    bool need = !broad_->ready || keep != broad_->keep || held_wanted();
    if (!need)
      for (const double r : room())
        if (r < 0) need = true;
    if (need || belts_need(0)) broad_build(keep, 0, false);  // changed parts keep all their pairs meanwhile
  }
  if (!own_list()) return engine_->query(request, out);
  collision::QueryRequest r = request;
  const auto gone = [this](const collision::BodyPair& p) {
    return (part(p.a) && absent_[p.a - first_part_]) || (part(p.b) && absent_[p.b - first_part_]);
  };
  if (!r.pairs) r.pairs = std::span<const collision::BodyPair>(part_pairs_);
  if (any_absent_) {
    filtered_.clear();
    for (const collision::BodyPair& p : *r.pairs)
      if (!gone(p)) filtered_.push_back(p);
    r.pairs = std::span<const collision::BodyPair>(filtered_);
  }
  engine_->query(r, out);
  // Resting contact (docs/collision.md §15): a part touching an object or another part without
  // sinking in beyond its tolerance is no contact; the query goes on after that pair. Found by a
  // query of the current pairs (a checked pose), the pair is kept as touching and leaves pairs().
  const bool full = !request.pairs && request.contact && !any_absent_;
  std::vector<collision::BodyPair> now_touching;
  if (has_parts_ && request.contact) {
    const std::span<const collision::BodyPair> list = *r.pairs;
    std::size_t from = 0;
    while (out.collided && resting_pair(ordered(out.contact.body_a, out.contact.body_b))) {
      const collision::BodyPair hit = ordered(out.contact.body_a, out.contact.body_b);
      if (out.contact.kind != collision::ContactKind::clearance && classify(hit, out.contact) == Touch::penetrating) break;
      if (full) now_touching.push_back(hit);
      std::size_t k = from;
      while (k < list.size() && ordered(list[k].a, list[k].b) != hit) ++k;
      from = k + 1;
      const collision::StepCounts counts = out.counts;
      out.collided = false;
      out.contact = {};
      if (from >= list.size()) break;
      engine_->query({.clearance_mm = r.clearance_mm, .pairs = list.subspan(from), .contact = true}, scratch_result_);
      out.collided = scratch_result_.collided;
      out.contact = scratch_result_.contact;
      out.counts = counts;
      out.counts.pairs_enabled += scratch_result_.counts.pairs_enabled;
      out.counts.pairs_after_minimax += scratch_result_.counts.pairs_after_minimax;
      out.counts.pairs_after_voxels += scratch_result_.counts.pairs_after_voxels;
      out.counts.voxel_pairs += scratch_result_.counts.voxel_pairs;
      out.counts.face_pairs += scratch_result_.counts.face_pairs;
    }
  }
  if (!now_touching.empty()) {
    const bool with_gaps = out.gaps.size() == part_pairs_.size();
    for (const collision::BodyPair& p : now_touching) {
      const auto it = std::find(part_pairs_.begin(), part_pairs_.end(), p);
      if (it == part_pairs_.end()) continue;
      const auto k = it - part_pairs_.begin();
      if (with_gaps) out.gaps.erase(out.gaps.begin() + k);
      part_pairs_.erase(it);
      part_gaps_.erase(part_gaps_.begin() + k);
      begin_touching(p, posed_t_, !posed_earlier_ && runtime_ && posed_t_ >= runtime_->clock().time_s());
    }
    ++pairs_revision_;
  }
  if (with_touching && !out.collided && !touching_.empty()) test_touching(r.clearance_mm, out, full);
  if (!unreported_.empty() && full && !out.collided) confirm_resting();
  // Every pair of the changed parts was tested here and found free: they may enter the tree.
  if (broad_ && broad_->any_untested && !request.pairs && request.contact && !out.collided && !any_absent_) {
    for (std::size_t s = 0; s < slots_.size(); ++s)
      if (broad_->untested[s] && still_part(slots_[s])) broad_->parts_dirty = true;
    std::fill(broad_->untested.begin(), broad_->untested.end(), 0);
    broad_->any_untested = false;
  }
}

bool World::resting_pair(const collision::BodyPair& p) const {
  return has_parts_ && p.a >= arm_bodies_ && p.b >= arm_bodies_ && (part(p.a) || part(p.b));
}

void World::set_part_pose(collision::BodyId id, const Location& pose) {
  engine_->set_pose(id, pose);
  part_at_[id - first_part_] = pose;
}

double World::resting_tolerance_of(const collision::BodyPair& p) const {
  double tol = 0;
  for (const collision::BodyId id : {p.a, p.b})
    if (part(id) && slots_[id - first_part_].clock >= 0)
      tol = std::max(tol, runtime_->clock().parts()[static_cast<std::size_t>(slots_[id - first_part_].clock)].tolerance_mm);
  return tol;
}

// The outward normal of face f of body id at its current pose (unit; zero for a degenerate face).
collision::Vec3 World::face_normal(collision::BodyId id, std::uint32_t f) const {
  const collision::Polyhedron* mesh = nullptr;
  Location pose = Location::Identity();
  if (part(id)) {
    const Slot& s = slots_[id - first_part_];
    if (s.clock < 0) return collision::Vec3::Zero();
    mesh = &runtime_->clock().parts()[static_cast<std::size_t>(s.clock)].def->mesh;
    pose = part_at_[id - first_part_];
  } else if (id >= first_object_ && id - first_object_ < cell_->objects.size()) {
    mesh = &cell_->objects[id - first_object_].mesh;
    pose = cell_->objects[id - first_object_].pose;
  }
  if (!mesh || f >= mesh->triangles.size()) return collision::Vec3::Zero();
  const auto& t = mesh->triangles[f];
  const collision::Vec3 n = pose.linear() * (mesh->vertices[t[1]] - mesh->vertices[t[0]]).cross(mesh->vertices[t[2]] - mesh->vertices[t[0]]);
  const double len = n.norm();
  return len > 0 ? collision::Vec3(n / len) : collision::Vec3::Zero();
}

// Resting or sinking in (docs/collision.md §15): a part touching an object or another part
// rests when a translation by its tolerance separates them, along world up or a normal of the
// faces that touch (each contact found adds its faces' normals, both signs); else it sinks in
// deeper than the tolerance (or lies inside: containment) and that is a collision.
World::Touch World::classify(const collision::BodyPair& pair, const collision::Contact& first) {
  // The body moved for the test: a part, the moving one of two parts.
  const auto moving = [&](collision::BodyId id) {
    return part(id) && (slots_[id - first_part_].holder == Holder::carried || slots_[id - first_part_].speed_mm_s > 0);
  };
  const collision::BodyId p = part(pair.b) && (!part(pair.a) || (moving(pair.b) && !moving(pair.a))) ? pair.b : pair.a;
  const auto normal = [this](collision::BodyId id, std::uint32_t f) { return face_normal(id, f); };
  return resting_contact(*engine_, pair, p, part_at_[p - first_part_], resting_tolerance_of(pair), first, normal, scratch_result_)
             ? Touch::resting
             : Touch::penetrating;
}

void World::begin_touching(const collision::BodyPair& p, double t, bool event) {
  touching_.push_back(p);
  // An event when a checked pose (the clock's present) sees it resting; one found between two
  // checked poses waits for the next checked pose to see it still resting, and takes the
  // instant it began (so a touch that a collision follows at once is not one).
  if (!runtime_) return;
  if (!event) {
    unreported_.push_back({p, t});
    return;
  }
  touching_event(p, t);
}

// A pair of a part at the current poses: apart (farther than the resting tolerance), resting
// (within it, not sinking in deeper), or penetrating (its contact in touch_contact_).
World::Touch World::touch_state(const collision::BodyPair& p) {
  engine_->query({.clearance_mm = 0, .pairs = std::span(&p, 1)}, scratch_result_);
  if (scratch_result_.collided) {
    touch_contact_ = scratch_result_.contact;
    return classify(p, touch_contact_);
  }
  engine_->query({.clearance_mm = resting_tolerance_of(p), .pairs = std::span(&p, 1)}, scratch_result_);
  return scratch_result_.collided ? Touch::resting : Touch::apart;
}

void World::confirm_resting() {
  if (unreported_.empty() || posed_earlier_ || !runtime_ || posed_t_ < runtime_->clock().time_s()) return;
  for (const auto& [p, t] : unreported_) {
    if (std::find(touching_.begin(), touching_.end(), p) == touching_.end()) continue;
    if (touch_state(p) == Touch::resting) touching_event(p, t);
  }
  unreported_.clear();
}

void World::touching_event(const collision::BodyPair& p, double t) {
  const collision::BodyId part_id = part(p.b) && !part(p.a) ? p.b : (part(p.a) && slots_[p.a - first_part_].holder == Holder::carried) || !part(p.b) ? p.a : p.b;
  const collision::BodyId other = part_id == p.a ? p.b : p.a;
  const auto strip = [](const std::string& n) { return n.rfind("part:", 0) == 0 ? n.substr(5) : n; };
  runtime_->clock().note({t, "resting", strip(engine_->body_name(part_id)), strip(engine_->body_name(other)), 0});
}

void World::rest(const collision::BodyPair& pair, double t) {
  const collision::BodyPair p = ordered(pair.a, pair.b);
  const auto it = std::find(part_pairs_.begin(), part_pairs_.end(), p);
  if (it == part_pairs_.end()) return;
  part_gaps_.erase(part_gaps_.begin() + (it - part_pairs_.begin()));
  part_pairs_.erase(it);
  begin_touching(p, t, false);
  ++pairs_revision_;
}

// The pairs in resting contact, at the current poses: one sinking in deeper than its tolerance
// is the query's contact; with `update`, pairs found apart are tested as any other again.
void World::test_touching(double clearance_mm, collision::QueryResult& out, bool update) {
  (void)clearance_mm;
  bool apart = false;
  for (std::size_t k = 0; k < touching_.size(); ++k) {
    const collision::BodyPair p = touching_[k];
    if (any_absent_ && ((part(p.a) && absent_[p.a - first_part_]) || (part(p.b) && absent_[p.b - first_part_]))) continue;
    const Touch state = touch_state(p);
    if (state == Touch::apart) {
      if (update) touching_[k] = {~0u, ~0u}, apart = true;
      continue;
    }
    if (state == Touch::penetrating) {
      out.collided = true;
      out.contact = touch_contact_;
      break;
    }
  }
  if (apart) {
    std::erase(touching_, collision::BodyPair{~0u, ~0u});
    rebuild_pairs();
  }
}

std::string World::body_name(collision::BodyId id) const {
  const std::string& name = engine_->body_name(id);
  return part(id) && slots_[id - first_part_].holder == Holder::carried ? "carried " + name : name;
}

std::optional<CarriedPose> World::carried(const robots::JointVector& q) const {
  if (!runtime_ || !runtime_->carried()) return std::nullopt;
  const std::size_t i = *runtime_->carried();
  return CarriedPose{runtime_->clock().parts()[i].def->name,
                     base_ * robots::flange_pose(*robot_, q) * runtime_->grip()};
}

bool World::grids_built(const collision::QueryResult& r) {
  // Grids are built only for pairs that pass step 2, so most queries need no look at the bodies.
  if (r.counts.pairs_after_minimax == 0 || unprepared_.empty()) return false;
  const std::size_t before = unprepared_.size();
  std::erase_if(unprepared_, [this](collision::BodyId id) { return engine_->body_preprocessed(id); });
  return unprepared_.size() != before;
}

}  // namespace asimov::motion
