// Engine::check() against brute force over all face pairs: a finely tessellated cylinder
// (2,000 faces) and a coarser cylinder (200 faces) under fixed-seed random poses.
// Run: bench_collision [--benchmark_filter=...]. Counters: colliding fraction, mean face pairs.
#include "bench/scenes.hpp"
#include "asimov/collision/engine.hpp"

#include <benchmark/benchmark.h>

#include <vector>

using namespace asimov::collision;

namespace {

const Polyhedron& big_mesh() {
  static const Polyhedron m = make_cylinder(100, 300, 500);  // 4 x 500 = 2,000 triangles
  return m;
}
const Polyhedron& small_mesh() {
  static const Polyhedron m = make_cylinder(30, 120, 50);  // 200 triangles
  return m;
}

// Poses of the small body around the big one (which stays at the origin): translations in
// +-250 mm, so a fair share of the poses touch or cross the big cylinder's surface.
const std::vector<Pose>& poses() {
  static const std::vector<Pose> p = asimov::bench::random_poses(1024, 250, 2180);
  return p;
}

void engine_check(benchmark::State& state) {
  Engine e;
  const BodyId big = e.add_body({.name = "big", .mesh = big_mesh(), .halvings = static_cast<int>(state.range(0))});
  const BodyId small = e.add_body({.name = "small", .mesh = small_mesh(), .halvings = static_cast<int>(state.range(0))});
  e.set_pose(big, Pose::Identity());
  e.set_pose(small, poses()[0]);
  (void)e.check();  // preprocessing (voxel grids) outside the timing
  std::size_t i = 0, queries = 0, hits = 0, face_pairs = 0;
  for (auto _ : state) {
    e.set_pose(small, poses()[i]);
    const QueryResult r = e.check();
    benchmark::DoNotOptimize(r.collided);
    hits += r.collided;
    face_pairs += r.counts.face_pairs;
    ++queries;
    i = (i + 1) % poses().size();
  }
  state.counters["colliding"] = static_cast<double>(hits) / static_cast<double>(queries);
  state.counters["face_pairs"] = static_cast<double>(face_pairs) / static_cast<double>(queries);
}
BENCHMARK(engine_check)->Arg(6)->Arg(9)->Arg(12)->Unit(benchmark::kMicrosecond);

void brute_force(benchmark::State& state) {
  std::size_t i = 0, queries = 0, hits = 0;
  for (auto _ : state) {
    const bool hit = brute_force_collides(big_mesh(), Pose::Identity(), small_mesh(), poses()[i]);
    benchmark::DoNotOptimize(hit);
    hits += hit;
    ++queries;
    i = (i + 1) % poses().size();
  }
  state.counters["colliding"] = static_cast<double>(hits) / static_cast<double>(queries);
}
BENCHMARK(brute_force)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
