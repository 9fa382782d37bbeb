// PUMA 560 data. Frames follow docs/kinematics.md §1 (origin at the shoulder, J1 = +Z, flange at the
// wrist centre). Link bodies are unions of boxes and cylinders, each in its own DH frame;
// dimensions are coarse but close to the real arm (upper arm 431.8 mm, forearm ~430 mm,
// column down to the floor at z = -670 mm).
#include "asimov/robots/puma560.hpp"

#include "link_shapes.hpp"

#include <algorithm>
#include <numbers>

namespace asimov::robots {
namespace {
constexpr double kPi = std::numbers::pi;

using collision::merged;
using shapes::box;
using shapes::cylinder;

std::vector<LinkBody> puma_bodies() {
  using namespace puma;
  std::vector<LinkBody> b;
  // link0, world frame: the fixed column from the floor (z = -670) to the trunk (z = -170).
  b.push_back({0, "link0", cylinder(2, 110, -670, -170)});
  // link1, frame 1 (y1 = up, z1 = J2 axis, toward -Y0 at J1 = 0): the rotating trunk and the
  // shoulder housing around the J2 axis. Overlaps link0 and link2 by 1 mm at the joints.
  b.push_back({1, "link1", merged(cylinder(1, 90, -171, 0), cylinder(2, 90, -110, 31))});
  // link2, frame 2 (elbow at the origin, x2 along the upper arm, z2 = J2/J3 axes): the upper
  // arm beside the trunk, z2 in [30, 100], hubs at the shoulder and the elbow.
  b.push_back({2, "link2",
               merged(merged(box(Vec3(-a2, -50, 30), Vec3(0, 50, 100)), cylinder(2, 85, 30, 100, -a2, 0)),
                      cylinder(2, 60, 30, 100, 0, 0))});
  // link3, frame 3 (z3 along the forearm to the wrist centre at z3 = d4, y3 = -z2, J3 axis
  // through x3 = -a3): elbow hub (overlaps link2 by 1 mm) and the forearm box.
  b.push_back({3, "link3",
               merged(cylinder(1, 60, -45, d3 - 99, -a3, 0), box(Vec3(-50, -40, 0), Vec3(40, 40, d4 - 71.8)))});
  // link4, frame 4 (wrist centre at the origin, forearm along -y4, z4 = J5 axis): a collar at the
  // forearm end and the two fork plates beside the J5 body.
  b.push_back({4, "link4",
               merged(merged(cylinder(1, 40, -72.8, -45), box(Vec3(-35, -45, 40), Vec3(35, 10, 50))),
                      box(Vec3(-35, -45, -50), Vec3(35, 10, -40)))});
  // link5, frame 5 (z5 = J6 axis, y5 = -z4): the J5 drum between the fork plates and a boss
  // toward the flange.
  b.push_back({5, "link5", merged(cylinder(1, 35, -41, 41), cylinder(2, 25, 0, 46))});
  // link6, frame 6: the flange disc (real flange face about 56 mm past the wrist centre).
  b.push_back({6, "link6", cylinder(2, 30, 45, 56)});
  return b;
}
}  // namespace

Robot puma560() {
  using namespace puma;
  Robot r;
  r.name = "puma560";
  r.dh = {{0, 0, kPi / 2}, {0, a2, 0}, {d3, a3, -kPi / 2}, {d4, 0, kPi / 2}, {0, 0, -kPi / 2}, {0, 0, 0}};
  const double signs[6] = {+1, -1, -1, +1, -1, +1};
  for (double s : signs) r.mapping.push_back({s, 0.0});
  // Limits set A (Corke mdl_puma560), DH degrees, converted to display once here.
  const double lo_dh[6] = {-160, -45, -225, -110, -100, -266};
  const double hi_dh[6] = {160, 225, 45, 170, 100, 266};
  r.lower.resize(6), r.upper.resize(6), r.max_velocity.resize(6), r.max_acceleration.resize(6);
  for (int i = 0; i < 6; ++i) {
    const double a = signs[i] * lo_dh[i], b = signs[i] * hi_dh[i];
    r.lower[i] = std::min(a, b);
    r.upper[i] = std::max(a, b);
    r.max_velocity[i] = i < 3 ? 90 : 180;
    r.max_acceleration[i] = i < 3 ? 360 : 720;
  }
  r.max_tool_speed = 500;
  r.max_tool_accel = 2000;
  r.max_tool_rot_speed = 90;
  r.max_tool_rot_accel = 360;
  r.bodies = puma_bodies();
  return r;
}

}  // namespace asimov::robots
