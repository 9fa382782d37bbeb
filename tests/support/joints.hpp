// Joint vectors for tests: literals and uniform random samples within a robot's limits.
#pragma once
#include "asimov/robots/robot.hpp"

#include <initializer_list>
#include <random>

namespace asimov::test {

// jv({0, -90, 90, 0, 0, 0}): a JointVector from a literal list.
inline robots::JointVector jv(std::initializer_list<double> v) {
  robots::JointVector j(static_cast<Eigen::Index>(v.size()));
  Eigen::Index i = 0;
  for (double x : v) j[i++] = x;
  return j;
}

// Uniform within the display limits of `r`.
inline robots::JointVector random_joints(const robots::Robot& r, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(0, 1);
  robots::JointVector q(r.joint_count());
  for (int i = 0; i < r.joint_count(); ++i) q[i] = r.lower[i] + u(rng) * (r.upper[i] - r.lower[i]);
  return q;
}

}  // namespace asimov::test
