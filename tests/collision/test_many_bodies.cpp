// Many static bodies (issue 17): adding them one by one is linear per body (the participation
// matrix grows by doubling, pairs are appended and sorted once, pair counts are kept up to
// date), and the matrix and the pair list stay exact.
#include "asimov/collision/engine.hpp"
#include "asimov/collision/participation.hpp"
#include "asimov/collision/polyhedron.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <chrono>

using namespace asimov::collision;

TEST_CASE("participation: pairs set out of order read back sorted; growth keeps every flag", "[participation][hostile]") {
  Participation p;
  p.resize(3);
  p.set(1, 2, true);
  p.set(0, 2, true);
  p.resize(40);  // grows the storage: the flags move
  p.set(5, 39, true);
  p.set(0, 1, true);
  CHECK(p.enabled(2, 1));
  CHECK(p.enabled(0, 2));
  CHECK(p.enabled(39, 5));
  CHECK_FALSE(p.enabled(1, 5));
  CHECK(p.pairs() == std::vector<BodyPair>{{0, 1}, {0, 2}, {1, 2}, {5, 39}});
  p.set(0, 2, false);
  CHECK(p.pairs() == std::vector<BodyPair>{{0, 1}, {1, 2}, {5, 39}});
  p.resize(41);  // within the capacity
  CHECK(p.enabled(1, 2));
  CHECK_FALSE(p.enabled(40, 0));
}

TEST_CASE("20,000 static boxes and two moving ones: set up in seconds, every robot-object pair enabled",
          "[engine][hostile]") {
  const auto t0 = std::chrono::steady_clock::now();
  Engine e;
  const Polyhedron box = make_box({1, 1, 1});
  const auto arm = e.add_body({.name = "arm", .mesh = box});
  const auto hand = e.add_body({.name = "hand", .mesh = box});
  for (int i = 0; i < 20000; ++i) e.add_body({.name = "o", .mesh = box, .is_static = true});
  e.set_pair_enabled(arm, 7, false);
  e.set_pair_enabled(arm, 7, false);  // twice: no change
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  CHECK(s < 10);
  const auto pairs = e.enabled_pairs();
  CHECK(pairs.size() == 1 + 2 * 20000 - 1);  // arm-hand, each with every box, less arm-7
  CHECK(std::is_sorted(pairs.begin(), pairs.end()));
  CHECK(e.pair_enabled(hand, 20001));
  CHECK_FALSE(e.pair_enabled(5, 6));  // static-static: never tested
  CHECK_FALSE(e.pair_enabled(arm, 7));
}
