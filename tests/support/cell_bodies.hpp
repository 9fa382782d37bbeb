// Cell bodies for tests: an axis-aligned box object, and any named body's mesh and world pose
// at given joints (links at cell.base * frames[link], the tool at the flange, objects as placed).
#pragma once
#include "asimov/motion/cell.hpp"

#include <catch2/catch.hpp>
#include <string>
#include <utility>
#include <vector>

namespace asimov::test {

inline motion::CellObject box_object(const std::string& name, const collision::Vec3& size, const collision::Vec3& at) {
  motion::CellObject o;
  o.name = name;
  o.mesh = collision::make_box(size);
  o.pose = motion::Location::Identity();
  o.pose.translation() = at;
  return o;
}

inline std::pair<collision::Polyhedron, collision::Pose> body_in_world(const motion::Cell& cell, const std::string& name,
                                                                       const robots::JointVector& joints) {
  std::vector<collision::Pose> frames;
  robots::link_frames(cell.robot, joints, frames);
  for (const auto& b : cell.robot.bodies)
    if (b.name == name) return {b.mesh, cell.base * frames[static_cast<std::size_t>(b.link)]};
  if (name == "tool" && cell.tool_shape) return {*cell.tool_shape, cell.base * frames.back()};
  for (const auto& o : cell.objects)
    if (o.name == name) return {o.mesh, o.pose};
  FAIL("no body named " << name);
  return {};
}

}  // namespace asimov::test
