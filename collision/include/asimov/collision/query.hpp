// One collision query: what it asks (QueryRequest: clearance, pairs, contact and/or gaps) and
// what it answers (QueryResult: status, bodies, contact point, per-pair gaps, per-step counts).
#pragma once
#include "asimov/collision/participation.hpp"
#include "asimov/collision/types.hpp"
#include <optional>
#include <span>
#include <vector>

namespace asimov::collision {

struct StepCounts {
  std::uint64_t pairs_enabled = 0;      // pairs entering step 2
  std::uint64_t pairs_after_minimax = 0;// pairs whose world minimax boxes overlap
  std::uint64_t pairs_after_voxels = 0; // pairs with a non-empty voxel-pair buffer
  std::uint64_t voxel_pairs = 0;        // (A voxel, B voxel) pairs visited (up to the first hit)
  std::uint64_t face_pairs = 0;         // face pairs given to step 4: per B voxel, its faces times the
                                        //   A faces of the A voxels it meets (up to the voxel of the
                                        //   first hit; a pair met from several B voxels counts each
                                        //   time; step 4's bounding-box rejections included)
};

enum class ContactKind : std::uint8_t {
  faces,        // two faces meet (touching counts)
  clearance,    // no faces meet, but two are within the clearance: 0 < distance <= c
  containment,  // one body lies inside the other; point is a vertex of the inner one
};

struct Contact {
  ContactKind kind = ContactKind::faces;
  double distance = 0;                   // [mm] 0 unless kind == clearance
  std::uint32_t body_a = 0, body_b = 0;  // BodyId, body_a < body_b
  std::uint32_t face_a = 0, face_b = 0;  // triangle indices in each body's mesh (0 for containment)
  Vec3 point = Vec3::Zero();             // world point on both surfaces [mm] (reporting only)
};

// What a query asks, in the way Coal's CollisionRequest carries security_margin and
// break_distance: the query carries its own clearance, nothing is kept in the engine between
// queries.
struct QueryRequest {
  double clearance_mm = 0;  // contact when distance <= clearance (negative: 0)
  // Pairs to test, in this order (either body order; pairs that are not enabled are skipped).
  // nullopt: every enabled pair, in enabled_pairs() order.
  std::optional<std::span<const BodyPair>> pairs = std::nullopt;
  bool contact = true;      // run the four steps; stop at the first contact
  // Fill QueryResult::gaps: per tested pair, a lower bound [mm] on its bodies' distance from
  // their step-2 containers (world minimax boxes, vertex spheres, less the rounding margin
  // epsilon_r; 0 when they overlap). Gap stepping (docs/collision-method.md §6.3) spaces the
  // checked poses with it. Every pair gets its gap, also past a contact.
  bool gaps = false;
};

struct QueryResult {
  bool collided = false;
  Contact contact;
  StepCounts counts;
  std::vector<double> gaps;  // QueryRequest::gaps: one per tested pair, in request order
  void clear() {
    collided = false;
    contact = Contact{};
    counts = StepCounts{};
    gaps.clear();  // keeps its capacity: a reused result does not allocate
  }
};

}  // namespace asimov::collision
