// Result of one collision query: status, bodies, contact point and per-step counts.
#pragma once
#include "asimov/collision/types.hpp"

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

struct QueryResult {
  bool collided = false;
  Contact contact;
  StepCounts counts;
  void clear() { *this = QueryResult{}; }
};

}  // namespace asimov::collision
