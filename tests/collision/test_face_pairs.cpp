// Step 4 list: the stamp-based iteration yields exactly the sorted unique keys of the naive
// "every face of vA times every face of vB" list.
#include "collision/src/face_pairs.hpp"
#include "collision/src/interference.hpp"
#include "scenes.hpp"

#include <catch2/catch.hpp>

#include <algorithm>

using namespace asimov::collision;

TEST_CASE("face pairs are the sorted unique keys of the voxel pairs", "[face_pairs]") {
  std::mt19937_64 rng(64);
  const VoxelGrid ga = build_voxel_grid(test::make_merged_part(), 7);
  const VoxelGrid gb = build_voxel_grid(make_cylinder(10, 40, 16), 6);
  FacePairs iter;
  std::vector<VoxelPair> pairs;
  std::vector<std::uint64_t> naive, got;
  int nonempty = 0;
  for (int n = 0; n < 400; ++n) {
    collect_voxel_pairs(ga, test::random_pose(rng, 25), gb, test::random_pose(rng, 25), 0.0, pairs);
    naive.clear();
    for (const VoxelPair& p : pairs)
      for (const std::uint32_t fa : ga.faces_in(p.a))
        for (const std::uint32_t fb : gb.faces_in(p.b)) naive.push_back(std::uint64_t{fa} << 32 | fb);
    std::sort(naive.begin(), naive.end());
    naive.erase(std::unique(naive.begin(), naive.end()), naive.end());
    got.clear();
    iter.start(ga, gb, pairs);
    std::uint32_t fa = 0, fb = 0;
    while (iter.next(fa, fb)) got.push_back(std::uint64_t{fa} << 32 | fb);
    REQUIRE(got == naive);
    nonempty += !got.empty();
  }
  CHECK(nonempty > 50);
}
