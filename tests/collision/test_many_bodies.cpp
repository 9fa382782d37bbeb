// Many static bodies (issue 17): adding them one by one costs each static body the bodies that
// may move, not all bodies (static-static pairs are never tested); the participation matrix is
// sparse (a set of the enabled pairs), pairs are appended and tidied once when read, pair
// counts are kept up to date; and the matrix and the pair list stay exact. Speed: bench/.
#include "asimov/collision/engine.hpp"
#include "asimov/collision/participation.hpp"
#include "asimov/collision/polyhedron.hpp"

#include <catch2/catch.hpp>

#include <algorithm>

using namespace asimov::collision;

TEST_CASE("participation: pairs set out of order read back sorted, growth keeps every flag", "[participation][hostile]") {
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
  p.resize(41);
  CHECK(p.enabled(1, 2));
  CHECK_FALSE(p.enabled(40, 0));
  // Disabled and enabled again before a read: listed once.
  p.set(1, 2, false);
  p.set(2, 1, true);
  p.set(0, 40, true);
  p.set(0, 40, false);
  CHECK(p.pairs() == std::vector<BodyPair>{{0, 1}, {1, 2}, {5, 39}});
  // Toggled many times without a read: the list does not grow without bound.
  for (int k = 0; k < 10000; ++k) p.set(3, 4, k % 2 == 0);
  CHECK(p.pairs() == std::vector<BodyPair>{{0, 1}, {1, 2}, {5, 39}});
}

TEST_CASE("a moving body added after the static ones pairs with all of them, groups never pair", "[engine][hostile]") {
  Engine e;
  const Polyhedron box = make_box({1, 1, 1});
  const auto s1 = e.add_body({.name = "s1", .mesh = box, .is_static = true});
  const auto s2 = e.add_body({.name = "s2", .mesh = box, .is_static = true});
  const auto l1 = e.add_body({.name = "l1", .mesh = box, .group = 0});
  const auto l2 = e.add_body({.name = "l2", .mesh = box, .group = 0});
  const auto s3 = e.add_body({.name = "s3", .mesh = box, .is_static = true});
  const auto part = e.add_body({.name = "part", .mesh = box});
  CHECK_FALSE(e.pair_enabled(s1, s2));
  CHECK_FALSE(e.pair_enabled(l1, l2));  // one rigid group
  for (const auto m : {l1, l2, part})
    for (const auto st : {s1, s2, s3}) CHECK(e.pair_enabled(m, st));
  CHECK(e.pair_enabled(l1, part));
  CHECK(e.pair_enabled(l2, part));
  CHECK(e.enabled_pairs().size() == 3 * 3 + 2);
  e.set_pair_enabled(s1, s3, true);  // static-static: refused
  CHECK_FALSE(e.pair_enabled(s1, s3));
}

TEST_CASE("100,000 static boxes and two moving ones: every robot-object pair enabled, no static-static one",
          "[engine][hostile]") {
  Engine e;
  const Polyhedron box = make_box({1, 1, 1});
  const auto arm = e.add_body({.name = "arm", .mesh = box});
  const auto hand = e.add_body({.name = "hand", .mesh = box});
  for (int i = 0; i < 100000; ++i) e.add_body({.name = "o", .mesh = box, .is_static = true});
  e.set_pair_enabled(arm, 7, false);
  e.set_pair_enabled(arm, 7, false);  // twice: no change
  const auto pairs = e.enabled_pairs();
  CHECK(pairs.size() == 1 + 2 * 100000 - 1);  // arm-hand, each with every box, less arm-7
  CHECK(std::is_sorted(pairs.begin(), pairs.end()));
  CHECK(e.pair_enabled(hand, 100001));
  CHECK_FALSE(e.pair_enabled(5, 6));  // static-static: never tested
  CHECK_FALSE(e.pair_enabled(arm, 7));
}
