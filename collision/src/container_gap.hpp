// Gap between two bodies' step-2 containers (docs/collision-method.md §6.3 gap stepping): the distance
// between their world minimax boxes. Nothing inside the two containers is closer than this, so a
// pair with gap g cannot meet while the two bodies together move less than g.
#pragma once
#include "minimax.hpp"

#include <algorithm>
#include <cmath>
#include <span>

namespace asimov::collision {

// Euclidean distance [mm] between two axis-aligned boxes (0 when they overlap or touch).
// Inline with container_gap below: gap stepping asks them for every pair at every checked pose.
inline double box_distance(const Box& a, const Box& b) {
  double sum = 0;
  for (int i = 0; i < 3; ++i) {
    const double d = std::max({0.0, a.lo[i] - b.hi[i], b.lo[i] - a.hi[i]});
    sum += d * d;
  }
  return std::sqrt(sum);
}

// A container placed at a pose, as the gap needs it: its world minimax box and the world centre
// of its vertex sphere (Container::radius). Computed once per body and pose, used by every pair.
struct PlacedContainer {
  Box box;
  Vec3 centre = Vec3::Zero();
  double radius = 0;
};
PlacedContainer place(const Container& c, const Pose& pose);

// Gap of two placed containers: the larger of two lower bounds on the bodies' distance (their
// world boxes' distance, their vertex spheres' distance; the spheres win for long bodies lying
// diagonally, whose world boxes are mostly empty), less `margin` for the rounding of the
// mapping (relative_margin), never below 0.
inline double container_gap(const PlacedContainer& a, const PlacedContainer& b, double margin) {
  const double spheres = (a.centre - b.centre).norm() - a.radius - b.radius;
  return std::max(0.0, std::max(box_distance(a.box, b.box), spheres) - margin);
}

// The same from the containers and their poses.
double container_gap(const Container& a, const Pose& pose_a, const Container& b, const Pose& pose_b);

}  // namespace asimov::collision

namespace asimov::collision {

// [ours] Lower bound [mm] on the distance between the convex hulls of two vertex sets, hence
// between the two bodies (each lies in its hull; a positive bound also rules out one inside the
// other): A's vertices in A's frame, B's mapped by a_from_b (B's frame into A's). For any unit
// direction n, min_a n.a - max_b n.b is such a bound (the separating-plane bound); GJK's
// iteration on the difference set A - B (the direction to the point of the support points'
// simplex nearest the origin; exact in a few steps for polytopes, where the older two-point
// Gilbert step crawled) chooses the directions, at most `iterations` of them,
// stopping once the bound reaches `enough`, is within 1e-3 of the hull distance, or the hull
// distance is known to be below `stop` (a point of A - B nearer than that). Rounding:
// `slack` (the pair's mapping margin) and a few ulps of the coordinates are subtracted. Each
// iteration is one pass over both vertex sets. Returns the best bound (<= 0: the hulls may meet).
// `guess` (A's frame; zero or null: none) is tried first, as a warm start: in coherent motion
// the last query's best direction is nearly the best one again, so one pass often reaches
// `enough`; its bound at or above `stop`, or below half of it (a near pair, which the caller
// measures anyway), ends the search. On return it holds the direction of the best bound (any direction gives a valid
// bound, so a stale guess costs a pass, never a wrong answer).
double hull_gap(std::span<const Vec3> a, std::span<const Vec3> b, const Pose& a_from_b, double slack, double enough,
                int iterations, double stop = 0, Vec3* guess = nullptr);

}  // namespace asimov::collision
