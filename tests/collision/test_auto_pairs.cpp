// Step 1 generated automatically: every reason on a synthetic scene of boxes whose poses a
// callback draws, user overrides, the cache keyed by content, and the text for `asimov pairs`.
#include "support/scratch.hpp"
#include "asimov/collision/auto_pairs.hpp"

#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <unistd.h>

using namespace asimov::collision;

namespace {

Pose at(double x, double y, double z) {
  Pose p = Pose::Identity();
  p.translation() = Vec3(x, y, z);
  return p;
}

// base (static, sampled), link1, link2, link3 (sampled), table (static cell object).
//   base-link1 adjacent; link1-link2 touch only at the default pose (DEFAULT); link1-link3
//   overlap in 97 % of random poses (ALWAYS); base-link3 in the other 3 % (ENABLED); link2
//   is far from everything at random poses (NEVER); table pairs are robot-cell (ENABLED),
//   base-table both static (RIGID).
AutoPairsInput scene(int* random_calls = nullptr) {
  AutoPairsInput in;
  in.names = {"base", "link1", "link2", "link3", "table"};
  for (int i = 0; i < 5; ++i) in.meshes.push_back(make_box(Vec3(10, 10, 10)));
  in.groups = {100, 1, 2, 3, 100};
  in.is_static = {true, false, false, false, true};
  in.sampled = {true, true, true, true, false};
  in.adjacent = {{1, 0}};
  in.pose_default = [](std::vector<Pose>& p) {
    p = {at(0, 0, 0), at(0, 0, 20), at(0, 0, 25), at(0, 0, 200), at(0, 300, 0)};
  };
  in.pose_random = [random_calls](std::mt19937_64& rng, std::vector<Pose>& p) {
    if (random_calls) ++*random_calls;
    const double q = std::uniform_real_distribution<double>(0, 1)(rng);
    p = {at(0, 0, 0), at(0, 0, 20), at(500, 0, 0), q < 0.97 ? at(0, 0, 22) : at(0, 0, 5), at(0, 300, 0)};
  };
  in.pose_source = "synthetic boxes v1";
  in.samples = 2000;
  return in;
}

std::string temp_file(const std::string& name) {
  return (asimov::test::scratch_dir() / ("pairs_" + name)).string();
}

}  // namespace

TEST_CASE("automatic participation: every reason", "[auto_pairs]") {
  const AutoPairs p = generate_pairs(scene());
  CHECK(p.entries.size() == 10);
  CHECK(p.entry(0, 1).reason == PairReason::adjacent);
  CHECK(p.entry(1, 2).reason == PairReason::default_pose);
  CHECK(p.entry(1, 3).reason == PairReason::always);
  CHECK(p.entry(3, 1).reason == PairReason::always);  // either order
  CHECK(p.entry(0, 3).reason == PairReason::enabled);
  CHECK(p.entry(0, 3).contacts > 0);
  CHECK(p.entry(0, 2).reason == PairReason::never);
  CHECK(p.entry(2, 3).reason == PairReason::never);
  CHECK(p.entry(0, 4).reason == PairReason::rigid);
  for (const std::uint32_t robot : {1u, 2u, 3u}) CHECK(p.entry(robot, 4).reason == PairReason::enabled);
  CHECK(p.samples >= 2000);
  CHECK(p.samples % 200 == 0);
  CHECK(p.tested(0, 3));
  CHECK_FALSE(p.tested(1, 3));

  // Deterministic: the same input gives the same matrix.
  const AutoPairs again = generate_pairs(scene());
  for (std::size_t k = 0; k < p.entries.size(); ++k) {
    CHECK(again.entries[k].reason == p.entries[k].reason);
    CHECK(again.entries[k].contacts == p.entries[k].contacts);
  }

  const std::string text = format_pairs(p);
  CHECK_THAT(text, Catch::Contains("link1") && Catch::Contains("ALWAYS") && Catch::Contains("DEFAULT") &&
                       Catch::Contains("NEVER") && Catch::Contains("ADJACENT") && Catch::Contains("RIGID"));

  Engine e;
  const AutoPairsInput in = scene();
  for (std::size_t i = 0; i < in.meshes.size(); ++i)
    e.add_body({.name = in.names[i], .mesh = in.meshes[i], .group = in.groups[i], .is_static = in.is_static[i]});
  apply_pairs(p, e);
  CHECK(e.pair_enabled(0, 3));
  CHECK_FALSE(e.pair_enabled(1, 3));
  CHECK_FALSE(e.pair_enabled(0, 1));
  CHECK(e.pair_enabled(2, 4));
}

TEST_CASE("automatic participation: user overrides win", "[auto_pairs]") {
  AutoPairsInput in = scene();
  in.user_ignore = {{3, 0}};
  in.user_check = {{1, 3}, {0, 4}};  // 0-4 is rigid (both static): not an override target
  const AutoPairs p = generate_pairs(in);
  CHECK(p.entry(0, 3).reason == PairReason::user_ignore);
  CHECK(p.entry(1, 3).reason == PairReason::user_check);
  CHECK(p.entry(0, 4).reason == PairReason::rigid);
  CHECK(p.tested(1, 3));
  CHECK_FALSE(p.tested(0, 3));
}

TEST_CASE("automatic participation: cache keyed by content", "[auto_pairs]") {
  const std::string path = temp_file("cell.pairs");
  std::filesystem::remove(path);
  int calls = 0;
  bool cached = true;
  const AutoPairs first = generate_pairs_cached(scene(&calls), path, &cached);
  CHECK_FALSE(cached);
  CHECK(calls > 0);
  REQUIRE(std::filesystem::exists(path));

  calls = 0;
  const AutoPairs second = generate_pairs_cached(scene(&calls), path, &cached);
  CHECK(cached);
  CHECK(calls == 0);  // no pose drawn
  REQUIRE(second.entries.size() == first.entries.size());
  for (std::size_t k = 0; k < first.entries.size(); ++k) {
    CHECK(second.entries[k].pair == first.entries[k].pair);
    CHECK(second.entries[k].reason == first.entries[k].reason);
    CHECK(second.entries[k].contacts == first.entries[k].contacts);
  }
  CHECK(second.names == first.names);
  CHECK(format_pairs(second) == format_pairs(first));

  // Any content change gives another key: a moved vertex, an override, the pose source.
  AutoPairsInput changed = scene(&calls);
  changed.meshes[2].vertices[0].x() += 1e-9;
  CHECK(content_key(changed) != content_key(scene()));
  AutoPairsInput overridden = scene();
  overridden.user_ignore = {{0, 3}};
  CHECK(content_key(overridden) != content_key(scene()));
  AutoPairsInput source = scene();
  source.pose_source = "synthetic boxes v2";
  CHECK(content_key(source) != content_key(scene()));
  calls = 0;
  (void)generate_pairs_cached(changed, path, &cached);
  CHECK_FALSE(cached);
  CHECK(calls > 0);

  std::ofstream(path) << "garbage\n";  // unreadable cache: regenerated
  (void)generate_pairs_cached(scene(), path, &cached);
  CHECK_FALSE(cached);
  std::filesystem::remove(path);
}
