// Gap between two bodies' step-2 containers (four-step.md §6.3 gap stepping): the distance
// between their world minimax boxes. Nothing inside the two containers is closer than this, so a
// pair with gap g cannot meet while the two bodies together move less than g.
#pragma once
#include "collision/minimax.hpp"

namespace asimov::collision {

// Euclidean distance [mm] between two axis-aligned boxes (0 when they overlap or touch).
double box_distance(const Box& a, const Box& b);

// Distance between the world minimax boxes of two containers at their poses, less a margin for
// the rounding of the mapping (relative_margin), never below 0: a lower bound on the distance
// between the two bodies.
double container_gap(const Container& a, const Pose& pose_a, const Container& b, const Pose& pose_b);

// The same from world boxes already computed (minimax_box) for the poses; `margin` as above.
double container_gap(const Box& world_a, const Box& world_b, double margin);

}  // namespace asimov::collision
