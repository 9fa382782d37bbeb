// The four-step collision engine (Garcia-Alonso): participation -> minimax -> voxels -> faces.
// Bodies are added once (preprocessing); each checked pose sets body poses and calls query()
// (contact, and the per-pair gaps of gap stepping), the one world every caller shares.
#pragma once
#include "asimov/collision/distance.hpp"
#include "asimov/collision/participation.hpp"
#include "asimov/collision/polyhedron.hpp"
#include "asimov/collision/query.hpp"
#include <memory>
#include <span>
#include <string>

namespace asimov::collision {

using BodyId = std::uint32_t;

constexpr int kAutoHalvings = -1;  // BodyDef::halvings: let the cost model choose M

struct BodyDef {
  std::string name;       // reported in contacts ("link3", "tool", "table")
  Polyhedron mesh;        // local frame
  // When set, the body's mesh instead of `mesh` (left empty), not copied: it must outlive the
  // engine and not change. A cell's objects are kept so (motion::World borrows its cell): a
  // copy of a 10M-face mesh was 240 MB.
  const Polyhedron* mesh_ref = nullptr;
  int group = -1;         // rigid group: bodies of one group are never tested together (-1: own group)
  bool is_static = false; // static bodies never move after the first set_pose
  int halvings = 9;       // M: the voxel grid has 2^M cells; kAutoHalvings (-1): cost model
};

class Engine {
 public:
  Engine();
  ~Engine();
  Engine(Engine&&) noexcept;
  Engine& operator=(Engine&&) noexcept;

  // Precondition: def.mesh as validate_mesh (mesh_io.hpp) leaves it: finite vertices, indices
  // in range. Every path from user input validates first; a violation is the caller's bug and
  // throws std::invalid_argument (docs/design.md "Errors": preconditions are not errors).
  BodyId add_body(BodyDef def);
  std::size_t body_count() const;
  const std::string& body_name(BodyId id) const;
  // Closed mesh (every edge shared by two faces in opposite directions). Only closed bodies
  // have an inside for the containment test (docs/collision-method.md §6.1); callers should warn on false.
  bool body_closed(BodyId id) const;
  // M in use for the body: BodyDef::halvings, or the cost model's choice for kAutoHalvings
  // (auto_halvings in voxel_grid.hpp). Known from add_body on, for reports.
  int body_halvings(BodyId id) const;
  // True once the body's voxel grid is built: only bodies of an enabled pair that reached
  // step 3 are ever preprocessed (lazy).
  bool body_preprocessed(BodyId id) const;

  // Step 1, the participation matrix. All pairs of different groups start enabled.
  void set_pair_enabled(BodyId a, BodyId b, bool enabled);
  bool pair_enabled(BodyId a, BodyId b) const;
  bool has_enabled_pairs() const;
  std::span<const BodyPair> enabled_pairs() const;  // sorted, a < b

  void set_pose(BodyId id, const Pose& local_to_world);

  // Step 2's container of a body at its current pose, as the per-pair gaps (QueryRequest::gaps)
  // bound distances: its world minimax box, its vertex sphere, and `magnitude`, the body's share
  // of a pair's rounding margin (a pair's margin is 64 ulp of the sum of its two bodies' shares).
  // For broad phases over many bodies (motion/src/broad_phase.hpp, docs/collision.md §14).
  struct PlacedBounds {
    Vec3 lo = Vec3::Zero(), hi = Vec3::Zero(), centre = Vec3::Zero();
    double radius = 0, magnitude = 0;
  };
  PlacedBounds placed_bounds(BodyId id);

  // The query at the current poses (QueryRequest: clearance, pairs, contact and/or gaps).
  // Pairs are tested in a fixed order, so the answer is deterministic. The second form reuses
  // `out` (its gaps keep their capacity): after the first queries it does not allocate.
  QueryResult query(const QueryRequest& request);
  void query(const QueryRequest& request, QueryResult& out);

  // Shorthands with the default clearance (set_default_clearance; 0 unless set): check() runs
  // the four steps over every enabled pair; check_pairs() over a subset, in the order given
  // (contact-time bisection re-checks only the pairs that collided at the later pose,
  // docs/collision-method.md §6.4).
  void set_default_clearance(double clearance_mm);
  QueryResult check();
  QueryResult check_pairs(std::span<const BodyPair> pairs);

  // Minimum distance between two bodies at the current poses, with witness points
  // (docs/collision.md §11): the four steps' containers and halvings trees cull, the face
  // distance decides; zero only from the exact face test or containment (status contact).
  // Any two different bodies (the participation matrix is not consulted); the clearance is not
  // applied. Bodies nearer than request.upper_mm cost what their distance needs, farther ones little.
  DistanceResult distance(BodyId a, BodyId b, const DistanceRequest& request = {});

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Reference answer: every face of every enabled pair against every face, same exact predicate.
// Used by tests to cross-check the four steps.
// Includes the containment test of docs/collision-method.md §6.1 (a shell of one mesh inside the other,
// closed, mesh), as the engine does; `clearance` > 0 adds the face distance test.
bool brute_force_collides(const Polyhedron& a, const Pose& pose_a,
                          const Polyhedron& b, const Pose& pose_b);
// Reference distance: every face pair (exact intersection test, then the face distance), then
// containment as brute_force_collides; body_a / body_b are left 0.
DistanceResult brute_force_distance(const Polyhedron& a, const Pose& pose_a, const Polyhedron& b, const Pose& pose_b);
bool brute_force_collides(const Polyhedron& a, const Pose& pose_a,
                          const Polyhedron& b, const Pose& pose_b, double clearance);

}  // namespace asimov::collision
