// Step 2: containers (local axis-aligned boxes given by basic axes) and world minimax boxes.
#pragma once
#include "asimov/collision/types.hpp"
#include <cfloat>
#include <vector>

namespace asimov::collision {

struct Box {
  Vec3 lo = Vec3::Zero(), hi = Vec3::Zero();
};

// A body's container as basic axes: corner `origin` and edges size.x*e_x, size.y*e_y, size.z*e_z.
// Every vertex v satisfies origin <= v <= origin + size in double arithmetic.
struct Container {
  Vec3 origin = Vec3::Zero();  // local corner O [mm]
  Vec3 size = Vec3::Ones();    // edge lengths [mm], > 0 (thin sides padded)
  double scale = 1;            // largest |coordinate| of the container, for relative margins
  double radius = 0;           // [ours] every vertex lies within radius of the container's centre
  Vec3 centre() const { return origin + 0.5 * size; }
};

Container make_container(const std::vector<Vec3>& vertices);

// The thesis's minimax formula on basic axes already mapped: corner `origin`, edges
// r.col(k) * size[k]; lo_i = origin_i - grow + sum_k min(0, edge_k,i), hi likewise.
Box basic_axes_box(const Vec3& origin, const Mat3& r, const Vec3& size, double grow = 0);

// Minimax box of the container mapped by `pose`: O' = M O, v'_k = R v_k, and
// min_i = O'_i + sum_k min(0, v'_k,i), max_i likewise; no corner is transformed.
Box minimax_box(const Container& c, const Pose& pose);

Box grown(const Box& b, double margin);

// The six separation tests: true when some axis has lo_A > hi_B + margin or the reverse.
bool separated(const Box& a, const Box& b, double margin);

// B's frame in A's: pose_a^-1 pose_b (maps B-local coordinates to A-local ones).
Pose relative_pose(const Pose& pose_a, const Pose& pose_b);

// Step 2, second test [ours]: the two containers as oriented boxes, separating-axis test on
// the 15 axes (3 + 3 face normals, 9 edge cross products), B placed by a_from_b =
// relative_pose(pose_a, pose_b). True only when some axis separates them by more than `grow`
// plus a bound on the rounding of the test, so it errs only toward "maybe" (the rounding of
// a_from_b itself is within ε_r, which `grow` includes). The world minimax boxes are loose for
// rotated bodies; this is not.
bool containers_separated(const Container& a, const Container& b, const Pose& a_from_b, double grow);

// Step 2, sphere test [ours]: the spheres about two container centres (world) holding each
// body's vertices are farther apart than `grow` (with a bound on the rounding of the test).
// Tighter than the boxes at their corners (a ring's box corners are empty), looser elsewhere:
// a cheap extra rejection between the minimax boxes and the oriented boxes.
bool spheres_separated(const Vec3& centre_a, double radius_a, const Vec3& centre_b, double radius_b, double grow);

// Largest positive separation along an axis (0 when the boxes overlap): a lower bound on
// the distance between anything inside a and anything inside b.
double box_gap(const Box& a, const Box& b);

// Relative margin epsilon_r for a pair: generous multiple of the rounding in mapping local
// coordinates of containers of scale s_a, s_b through poses with translations t_a, t_b.
// Each mapped coordinate carries a few ulps of (|t| + sqrt(3) * scale); a pair mapping
// world -> local -> other local compounds a handful of those. 64 ulps covers it with room.
// A body's share, |t|_inf + 2 scale, is also what Engine::placed_bounds gives broad phases.
inline double margin_share(const Container& c, const Pose& pose) {
  return pose.translation().cwiseAbs().maxCoeff() + 2 * c.scale;
}
inline double relative_margin(double share_a, double share_b) { return 64 * DBL_EPSILON * (share_a + share_b); }
inline double relative_margin(const Container& a, const Pose& pose_a, const Container& b, const Pose& pose_b) {
  return relative_margin(margin_share(a, pose_a), margin_share(b, pose_b));
}

}  // namespace asimov::collision
