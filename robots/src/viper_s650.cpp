// Adept Viper s650 data (docs/robots.md): lengths from ViSP vpViper650 and the adept_experimental
// URDF (the two agree), limits and speeds from Adept's published ranges as both carry them. Link
// bodies are unions of boxes and cylinders in the DH frames, coarse but of the arm's size.
#include "asimov/robots/viper_s650.hpp"

#include "link_shapes.hpp"

#include <algorithm>
#include <numbers>

namespace asimov::robots {
namespace {
constexpr double kPi = std::numbers::pi;
using collision::merged;
using shapes::box;
using shapes::cylinder;

std::vector<LinkBody> viper_bodies() {
  using namespace viper;
  std::vector<LinkBody> b;
  // link0, world frame: the base from the mounting surface to the J1 flange (z = 203).
  b.push_back({0, "link0", cylinder(2, 90, 0, 203)});
  // link1, frame 1 (origin on the J2 axis, x1 forward, y1 = down, z1 = J2 axis): the turret
  // around J1 (x1 = -a1) from z = 202 to 405, and the J2 housing.
  b.push_back({1, "link1", merged(cylinder(1, 85, -70, d1 - 202, -a1, 0), cylinder(2, 75, -95, 95))});
  // link2, frame 2 (elbow at the origin, x2 along the upper arm, z2 = J3 axis): the upper arm
  // and its hubs.
  b.push_back({2, "link2",
               merged(merged(box(Vec3(-a2, -40, -45), Vec3(0, 40, 45)), cylinder(2, 65, -50, 50, -a2, 0)),
                      cylinder(2, 55, -50, 50, 0, 0))});
  // link3, frame 3 (z3 along the forearm to the wrist centre at z3 = d4, J3 axis along y3
  // through x3 = -a3): elbow hub, elbow block and the forearm tube to 72 mm before the wrist.
  b.push_back({3, "link3",
               merged(merged(cylinder(1, 55, -50, 50, -a3, 0), box(Vec3(-a3, -45, -45), Vec3(40, 45, 45))),
                      cylinder(2, 42, 0, d4 - 72))});
  // link4, frame 4 (wrist centre at the origin, forearm along -y4, z4 = J5 axis): collar and
  // the two fork plates beside the J5 body.
  b.push_back({4, "link4",
               merged(merged(cylinder(1, 42, -73, -45), box(Vec3(-38, -45, 40), Vec3(38, 10, 50))),
                      box(Vec3(-38, -45, -50), Vec3(38, 10, -40)))});
  // link5, frame 5 (z5 = J6 axis): the J5 drum between the plates and the boss to the flange.
  b.push_back({5, "link5", merged(cylinder(1, 35, -41, 41), cylinder(2, 28, 0, d6 - 11))});
  // link6, frame 6 (origin on the flange face): the flange disc behind the face.
  b.push_back({6, "link6", cylinder(2, 32, -12, 0)});
  return b;
}
}  // namespace

Robot viper_s650() {
  using namespace viper;
  Robot r;
  r.name = "viper_s650";
  r.dh = {{d1, a1, -kPi / 2}, {0, a2, 0}, {0, a3, -kPi / 2}, {d4, 0, kPi / 2}, {0, 0, -kPi / 2}, {d6, 0, 0}};
  r.mapping = {{1, 0}, {1, 0}, {1, kPi}, {1, 0}, {1, 0}, {1, kPi}};
  // V+ joint ranges [deg] and maximum joint speeds [deg/s] (Adept's published values).
  const double lo[6] = {-170, -190, -29, -190, -120, -360};
  const double hi[6] = {170, 45, 256, 190, 120, 360};
  const double speed[6] = {328, 300, 375, 375, 375, 600};
  shapes::set_ranges_and_speeds(r, lo, hi, speed, 6);
  r.ready.resize(6);
  // READY: upper arm vertical, forearm horizontal forward (a decision, docs/robots.md).
  r.ready << 0, -90, 180, 0, 0, 0;
  r.bodies = viper_bodies();
  return r;
}

}  // namespace asimov::robots
