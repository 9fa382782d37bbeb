#include "collision/container_gap.hpp"

#include <algorithm>
#include <cmath>

namespace asimov::collision {

double box_distance(const Box& a, const Box& b) {
  double sum = 0;
  for (int i = 0; i < 3; ++i) {
    const double d = std::max({0.0, a.lo[i] - b.hi[i], b.lo[i] - a.hi[i]});
    sum += d * d;
  }
  return std::sqrt(sum);
}

double container_gap(const Box& world_a, const Box& world_b, double margin) {
  return std::max(0.0, box_distance(world_a, world_b) - margin);
}

double container_gap(const Container& a, const Pose& pose_a, const Container& b, const Pose& pose_b) {
  return container_gap(minimax_box(a, pose_a), minimax_box(b, pose_b), relative_margin(a, pose_a, b, pose_b));
}

}  // namespace asimov::collision
