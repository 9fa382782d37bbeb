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

// Set-up of a cell of N static boxes and 8 moving bodies (issue 17): add_body, then the enabled
// pair list read once. No static-static work (a static body pairs only with the moving ones): the
// counter us_per_object (microseconds per static object, shown with unit "s") grows only with the
// pair set's size and cache misses, not with N (3.1 at 10^4, 7.0 at 10^5, 2 December 2026).
void static_setup(benchmark::State& state) {
  const Polyhedron box = make_box({10, 10, 10});
  const auto n = static_cast<int>(state.range(0));
  std::size_t pairs = 0;
  for (auto _ : state) {
    Engine e;
    for (int k = 0; k < 8; ++k) e.add_body({.name = "link", .mesh = box, .group = 0});
    for (int k = 0; k < n; ++k) e.add_body({.name = "object", .mesh = box, .is_static = true});
    pairs = e.enabled_pairs().size();
    benchmark::DoNotOptimize(pairs);
  }
  state.counters["pairs"] = static_cast<double>(pairs);
  state.counters["us_per_object"] = benchmark::Counter(static_cast<double>(n) * 1e-6,
                                                       benchmark::Counter::kIsIterationInvariantRate |
                                                           benchmark::Counter::kInvert);
}
BENCHMARK(static_setup)->Arg(10000)->Arg(100000)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
