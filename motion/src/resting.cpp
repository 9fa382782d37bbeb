// Resting contact by trial translations (docs/collision.md §15).
#include "asimov/motion/resting.hpp"

#include <algorithm>
#include <vector>

namespace asimov::motion {

bool resting_contact(collision::Engine& engine, const collision::BodyPair& pair, collision::BodyId moved,
                     const Location& pose, double tolerance_mm, const collision::Contact& first, const FaceNormal& normal,
                     collision::QueryResult& scratch) {
  if (first.kind == collision::ContactKind::containment || !(tolerance_mm > 0)) return false;
  const collision::BodyId other = moved == pair.a ? pair.b : pair.a;
  // Candidate directions: up (what a set-down part rests against), then from each contact found
  // the other body's face normal and the moved body's, both signs (meshes may be wound either way).
  std::vector<collision::Vec3> dirs{collision::Vec3::UnitZ()};
  const auto add = [&](const collision::Contact& c) {
    if (c.kind != collision::ContactKind::faces) return;
    const bool moved_is_a = c.body_a == moved;
    const collision::Vec3 nm = normal(moved, moved_is_a ? c.face_a : c.face_b);
    const collision::Vec3 no = normal(other, moved_is_a ? c.face_b : c.face_a);
    for (const collision::Vec3& d : {no, collision::Vec3(-nm), collision::Vec3(-no), nm}) {
      if (d.isZero()) continue;
      if (std::none_of(dirs.begin(), dirs.end(), [&](const collision::Vec3& x) { return x.dot(d) > 1 - 1e-12; }))
        dirs.push_back(d);
    }
  };
  add(first);
  bool rests = false;
  constexpr std::size_t kMaxTries = 12;
  for (std::size_t k = 0; k < dirs.size() && k < kMaxTries && !rests; ++k) {
    Location shifted = pose;
    shifted.translation() += tolerance_mm * dirs[k];
    engine.set_pose(moved, shifted);
    engine.query({.clearance_mm = 0, .pairs = std::span(&pair, 1)}, scratch);
    if (!scratch.collided) rests = true;
    else add(scratch.contact);
  }
  engine.set_pose(moved, pose);
  return rests;
}

}  // namespace asimov::motion
