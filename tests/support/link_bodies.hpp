// Link bodies of a built-in arm at given joints: adjacent ones touch (joined at their joint),
// every other pair is apart (collision::brute_force_collides, the engine's reference).
#pragma once
#include "asimov/collision/engine.hpp"
#include "asimov/robots/robot.hpp"

#include <catch2/catch.hpp>
#include <vector>

namespace asimov::test {

inline void check_adjacent_joined_others_apart(const robots::Robot& r, const std::vector<robots::JointVector>& poses) {
  for (const auto& pose : poses) {
    std::vector<collision::Pose> f;
    robots::link_frames(r, pose, f);
    for (std::size_t a = 0; a < r.bodies.size(); ++a)
      for (std::size_t b = a + 1; b < r.bodies.size(); ++b) {
        INFO("pose " << pose.transpose() << ": " << r.bodies[a].name << " / " << r.bodies[b].name);
        const bool hit = collision::brute_force_collides(r.bodies[a].mesh, f[static_cast<std::size_t>(r.bodies[a].link)],
                                                         r.bodies[b].mesh, f[static_cast<std::size_t>(r.bodies[b].link)]);
        if (b == a + 1)
          CHECK(hit);
        else
          CHECK_FALSE(hit);
      }
  }
}

}  // namespace asimov::test
