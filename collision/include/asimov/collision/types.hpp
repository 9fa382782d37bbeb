// Scalar and Eigen aliases shared by every layer. Lengths in mm, angles in radians here.
#pragma once
#include <Eigen/Geometry>
#include <array>
#include <cstdint>

namespace asimov::collision {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Pose = Eigen::Isometry3d;  // maps a body's local frame to the world
using Triangle = std::array<std::uint32_t, 3>;  // vertex indices, counter-clockwise seen from outside

}  // namespace asimov::collision
