// PUMA 560 link bodies: joined at the joints, apart elsewhere at READY and the safe pose.
#include "asimov/collision/engine.hpp"
#include "asimov/robots/puma560.hpp"

#include "support/joints.hpp"

#include <catch2/catch.hpp>

using namespace asimov;
using namespace asimov::robots;

using asimov::test::jv;

namespace {
bool bodies_collide(const Robot& r, const std::vector<Pose>& f, std::size_t a, std::size_t b) {
  const auto& ba = r.bodies[a];
  const auto& bb = r.bodies[b];
  return collision::brute_force_collides(ba.mesh, f[static_cast<std::size_t>(ba.link)], bb.mesh,
                                         f[static_cast<std::size_t>(bb.link)]);
}
}  // namespace

TEST_CASE("link bodies: adjacent joined, non-adjacent apart at READY and the safe pose", "[puma560][bodies]") {
  const Robot r = puma560();
  for (const auto& pose : {jv({0, -90, 90, 0, 0, 0}), jv({0, -90, 180, 0, 0, 0}), jv({30, -60, 150, 45, 60, -30})}) {
    std::vector<Pose> f;
    link_frames(r, pose, f);
    for (std::size_t a = 0; a < r.bodies.size(); ++a)
      for (std::size_t b = a + 1; b < r.bodies.size(); ++b) {
        INFO("pose " << pose.transpose() << ": " << r.bodies[a].name << " / " << r.bodies[b].name);
        if (b == a + 1)
          CHECK(bodies_collide(r, f, a, b));
        else
          CHECK_FALSE(bodies_collide(r, f, a, b));
      }
  }
}

TEST_CASE("wrist bodies stay apart over the J5 range", "[puma560][bodies]") {
  const Robot r = puma560();
  for (double j5 = -100; j5 <= 100; j5 += 10) {
    std::vector<Pose> f;
    link_frames(r, jv({0, -90, 180, 20, j5, 40}), f);
    INFO("J5 = " << j5);
    CHECK_FALSE(bodies_collide(r, f, 3, 5));
    CHECK_FALSE(bodies_collide(r, f, 4, 6));
    CHECK_FALSE(bodies_collide(r, f, 3, 6));
  }
}
