#include "container_gap.hpp"

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

PlacedContainer place(const Container& c, const Pose& pose) {
  return {minimax_box(c, pose), pose * c.centre(), c.radius};
}

double container_gap(const PlacedContainer& a, const PlacedContainer& b, double margin) {
  const double spheres = (a.centre - b.centre).norm() - a.radius - b.radius;
  return std::max(0.0, std::max(box_distance(a.box, b.box), spheres) - margin);
}

double container_gap(const Container& a, const Pose& pose_a, const Container& b, const Pose& pose_b) {
  return container_gap(place(a, pose_a), place(b, pose_b), relative_margin(a, pose_a, b, pose_b));
}

}  // namespace asimov::collision
