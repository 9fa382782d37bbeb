// Lower bounds on the engine's per-pair gap (QueryRequest::gaps, the step-2 containers' distance
// less the pair's rounding margin) from placed bounds alone, for broad phases over many bodies
// (motion/src/broad_phase.hpp, docs/collision.md §14): the engine's own arithmetic, so a broad
// phase never drifts from what the query measures.
#pragma once
#include "asimov/collision/engine.hpp"

namespace asimov::collision {

// The gap bound of two placed bodies: never above the gap the engine's query gives the pair.
double gap_bound(const Engine::PlacedBounds& a, const Engine::PlacedBounds& b);
// The same for a body and any body whose world box lies inside [lo, hi] and whose margin share
// is at most `share` (a group's box: the box distance and the margin are monotone in both).
double gap_bound(const Engine::PlacedBounds& a, const Vec3& lo, const Vec3& hi, double share);

}  // namespace asimov::collision
