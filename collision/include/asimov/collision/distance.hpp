// Minimum distance between two bodies, with witness points (Engine::distance, docs/collision.md
// §11). Zero is decided by the exact face test (and the containment test), never by a rounded
// distance, so touching bodies are "in contact" exactly as check() says.
#pragma once
#include "asimov/collision/query.hpp"

#include <limits>

namespace asimov::collision {

struct DistanceRequest {
  // Cut-off [mm]: a pair at least this far apart costs little, and the answer is only that it is
  // (status beyond). Infinity: always the exact distance.
  double upper_mm = std::numeric_limits<double>::infinity();
  // Warm start (as Coal's cached GJK guess): an earlier answer's `guess` for the same pair, tried
  // first by the convex-hull bound; in coherent motion it proves a far pair in one pass over the
  // vertices. Only a speed-up: any direction gives a valid bound. Zero: none.
  Vec3 guess = Vec3::Zero();
  // Exact only below this [mm] (when below upper_mm): a pair whose cheap bounds (containers,
  // hulls) already prove it at least this far apart is answered `beyond` with that bound, still
  // below the cut-off, without the exact search. For a caller that needs the distance only below
  // one threshold but keeps a bound up to a larger cut-off (continuous checking: the clearance
  // report's threshold, and the anchors' room above it). Infinity: exact below upper_mm.
  double exact_below_mm = std::numeric_limits<double>::infinity();
};

enum class DistanceStatus : std::uint8_t {
  exact,    // distance is the minimum distance between the two surfaces (double, see below)
  contact,  // the bodies touch or overlap: faces meet (exact test) or one lies inside the other
  beyond,   // the distance is at least min(upper_mm, exact_below_mm); `distance` is a lower bound >= that
};

struct DistanceResult {
  DistanceStatus status = DistanceStatus::beyond;
  double distance = 0;                   // [mm]; 0 on contact (no penetration depth)
  ContactKind kind = ContactKind::faces; // on contact: faces or containment
  std::uint32_t body_a = 0, body_b = 0;  // as asked
  std::uint32_t face_a = 0, face_b = 0;  // exact / contact by faces: the closest (meeting) faces
  Vec3 point_a = Vec3::Zero();           // world witness points: on body_a's face_a and body_b's
  Vec3 point_b = Vec3::Zero();           //   face_b, |point_a - point_b| = distance (contact: the
                                         //   contact point, or the inner body's vertex)
  Vec3 guess = Vec3::Zero();             // the hull bound's best direction (body_a's frame), for the next request
  std::uint64_t face_pairs = 0;          // face pairs whose distance was computed (cost)
  std::uint64_t node_pairs = 0;          // box pairs of the two distance trees bounded (cost)
};

}  // namespace asimov::collision
