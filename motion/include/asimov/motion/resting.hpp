// Resting contact (docs/collision.md §15): whether two bodies of the engine that touch only rest
// on each other (the moved one separates from the other by a translation no longer than its
// resting tolerance) or one sinks into the other. Used by the collision world at run time and by
// the cell loader for parts placed in a cell.
#pragma once
#include "asimov/collision/engine.hpp"
#include "asimov/motion/location.hpp"
#include <functional>

namespace asimov::motion {

// The outward unit normal of face `face` of body `id` at its current pose (zero when unknown).
using FaceNormal = std::function<collision::Vec3(collision::BodyId id, std::uint32_t face)>;

// `pair` touches at the engine's current poses with `first` its contact (clearance 0). True
// when a translation of body `moved` (now at `pose`) by `tolerance_mm` along world up or along a
// normal (either sign) of faces found touching separates the pair: a resting contact, the
// penetration is below the tolerance. False for containment or deeper penetration. The engine
// keeps `moved` at `pose` afterwards.
bool resting_contact(collision::Engine& engine, const collision::BodyPair& pair, collision::BodyId moved,
                     const Location& pose, double tolerance_mm, const collision::Contact& first, const FaceNormal& normal,
                     collision::QueryResult& scratch);

}  // namespace asimov::motion
