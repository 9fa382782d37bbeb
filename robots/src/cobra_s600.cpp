// Adept Cobra s600 data (docs/robots.md). Link bodies: boxes and cylinders in the chain frames.
#include "asimov/robots/cobra_s600.hpp"

#include "link_shapes.hpp"

#include <Eigen/Geometry>

#include <numbers>

namespace asimov::robots {
namespace {
using collision::merged;
using shapes::box;
using shapes::cylinder;
using shapes::translation;

std::vector<LinkBody> cobra_bodies() {
  using namespace cobra;
  std::vector<LinkBody> b;
  // link0, world frame: the foot and the column up to the inner link (z = 282).
  b.push_back({0, "link0", merged(box(Vec3(-150, -110, 0), Vec3(110, 110, 40)), cylinder(2, 90, 0, h1 - 60))});
  // link1, frame 1 (origin on J1 at z = 342): the inner link below the frame, its J1 and J2 hubs
  // (the J2 hub reaches 1 mm into the outer link).
  b.push_back({1, "link1",
               merged(merged(box(Vec3(0, -70, -61), Vec3(l1, 70, 0)), cylinder(2, 90, -61, 0)),
                      cylinder(2, 75, -61, 61, l1, 0))});
  // link2, frame 2 (origin on J2): the outer link above, from z2 = 60, with the quill housing.
  b.push_back({2, "link2",
               merged(merged(box(Vec3(0, -60, 60), Vec3(l2, 60, 150)), cylinder(2, 75, 60, 150)),
                      cylinder(2, 60, 60, 150, l2, 0))});
  // link3, frame 3 (origin at the flange point, axes as frame 2): the quill shaft, 260 mm up.
  b.push_back({3, "link3", cylinder(2, 18, 0, 260)});
  // link4, frame 4 = flange (Z down): the flange disc behind the face.
  b.push_back({4, "link4", cylinder(2, 30, -10, 0)});
  return b;
}
}  // namespace

Robot cobra_s600() {
  using namespace cobra;
  Robot r;
  r.name = "cobra_s600";
  const auto joint = [](const char* name, const Pose& origin, const Vec3& axis, JointType type) {
    return ChainJoint{name, origin, axis, type, {}};
  };
  r.chain = {joint("J1", translation(0, 0, h1), Vec3::UnitZ(), JointType::revolute),
             joint("J2", translation(l1, 0, 0), Vec3::UnitZ(), JointType::revolute),
             joint("J3", translation(l2, 0, quill), -Vec3::UnitZ(), JointType::prismatic),
             joint("J4", Pose::Identity(), -Vec3::UnitZ(), JointType::revolute)};
  r.flange_offset = Pose::Identity();
  r.flange_offset.linear() = Eigen::AngleAxisd(std::numbers::pi, Vec3::UnitX()).toRotationMatrix();
  r.mapping.assign(4, JointMapping{});
  const double lo[4] = {-105, -150, 0, -360}, hi[4] = {105, 150, 210, 360};
  const double speed[4] = {386, 720, 1100, 1200};  // deg/s, deg/s, mm/s, deg/s
  shapes::set_ranges_and_speeds(r, lo, hi, speed, 4);
  r.ready.resize(4);
  r.ready << 0, 0, 0, 0;  // arm stretched along +X, quill up (a decision, docs/robots.md)
  r.bodies = cobra_bodies();
  return r;
}

}  // namespace asimov::robots
