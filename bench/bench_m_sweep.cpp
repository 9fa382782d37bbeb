// The thesis' M = 9 claim (docs/collision-method.md §3, §8): M = 3..14 halvings over pairs of bodies of
// 50 to 1,400 faces (the thesis' range), plus larger bodies (5,000 - 50,000 faces, M up to 18)
// for the per-body cost model. Per (faces, M): us per query (median, mean over fixed-seed
// random poses; best of three runs), preprocessing time and memory of one grid. Writes bench/results/m_sweep.json
// as rows {name, ours_us, peer, peer_us, ratio, agreement} where the peer is M = 9 (ratio < 1:
// this M beats the thesis' choice) plus the measured details.
// Run: bench_m_sweep [--quick] [--out FILE].
#include "bench/scenes.hpp"
#include "asimov/collision/engine.hpp"
#include "collision/src/voxel_grid.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <fstream>
#include <numeric>
#include <string>
#include <vector>

using namespace asimov;
using namespace asimov::collision;
using Clock = std::chrono::steady_clock;

namespace {

struct Cell {
  int faces = 0, m = 0;
  double median = 0, mean = 0, prep_ms = 0;
  std::size_t bytes = 0;
  double colliding = 0;
};

double thread_cpu_us() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) * 1e6 + static_cast<double>(ts.tv_nsec) * 1e-3;
}

// Everything a body's step 3 keeps: face lists both ways, per-incidence face parts, content
// boxes, the summed-volume table, voxel classes and the halvings tree.
std::size_t grid_bytes(const VoxelGrid& g) {
  return sizeof(std::uint32_t) * (g.offsets.size() + g.faces.size() + g.face_offsets.size() + g.face_voxels.size() +
                                  g.occupied.size()) +
         sizeof(FloatBox) * g.face_parts.size() + sizeof(Box) * g.content.size() + sizeof(TreeNode) * g.tree.size() + sizeof(TreeSlabs) * g.slabs.size() + g.classes.size();
}

Cell measure_once(const Polyhedron& mesh, int m, const std::vector<Pose>& poses) {
  Cell c{.faces = static_cast<int>(mesh.triangles.size()), .m = m};
  auto t0 = Clock::now();
  const VoxelGrid g = build_voxel_grid(mesh, m);
  c.prep_ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
  c.bytes = grid_bytes(g);
  Engine e;
  const BodyId a = e.add_body({.name = "a", .mesh = mesh, .is_static = true, .halvings = m});
  const BodyId b = e.add_body({.name = "b", .mesh = mesh, .halvings = m});
  e.set_pose(a, Pose::Identity());
  std::vector<double> t(poses.size());
  double cpu_us = 0;
  for (int pass = 0; pass < 2; ++pass) {
    const double cpu0 = thread_cpu_us();
    for (std::size_t i = 0; i < poses.size(); ++i) {
      const auto s = Clock::now();
      e.set_pose(b, poses[i]);
      const bool hit = e.check().collided;
      t[i] = std::chrono::duration<double, std::micro>(Clock::now() - s).count();
      if (pass == 1) c.colliding += hit;
    }
    cpu_us = thread_cpu_us() - cpu0;
  }
  c.colliding /= static_cast<double>(poses.size());
  // Mean from the thread's CPU time over the timed pass: time the scheduler gave to other
  // programs on this shared machine is not counted (the per-query clock reads are, ~40 ns).
  c.mean = cpu_us / static_cast<double>(poses.size());
  std::nth_element(t.begin(), t.begin() + static_cast<std::ptrdiff_t>(t.size() / 2), t.end());
  c.median = t[t.size() / 2];
  return c;
}

// The machine is shared and noisy: three runs, keeping the fastest (mean and median) and
// the fastest preprocessing.
Cell measure(const Polyhedron& mesh, int m, const std::vector<Pose>& poses) {
  Cell best = measure_once(mesh, m, poses);
  for (int rep = 1; rep < 3; ++rep) {
    const Cell c = measure_once(mesh, m, poses);
    best.mean = std::min(best.mean, c.mean);
    best.median = std::min(best.median, c.median);
    best.prep_ms = std::min(best.prep_ms, c.prep_ms);
  }
  return best;
}

}  // namespace

int main(int argc, char** argv) {
  bool quick = false;
  std::string out = std::string(ASIMOV_SOURCE_DIR) + "/bench/results/m_sweep.json";
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--quick")) quick = true;
    else if (!std::strcmp(argv[i], "--out") && i + 1 < argc) out = argv[++i];
  }
  struct Range {
    int faces, m_lo, m_hi;
    std::size_t poses;
  };
  const std::vector<Range> ranges = {{50, 3, 14, 4000},    {100, 3, 14, 4000},   {200, 3, 14, 4000},
                                     {400, 3, 14, 4000},   {800, 3, 14, 4000},   {1400, 3, 15, 4000},
                                     {5000, 6, 17, 1000},  {20000, 8, 18, 400},  {50000, 9, 18, 300}};
  nlohmann::json rows = nlohmann::json::array();
  std::printf("%7s %3s %10s %10s %9s %10s %6s\n", "faces", "M", "median us", "mean us", "prep ms", "grid KiB", "coll");
  for (const Range& r : ranges) {
    const Polyhedron mesh = bench::make_torus_with_faces(r.faces, 100);
    const auto poses = bench::random_poses(quick ? r.poses / 4 : r.poses, 250, 9000 + static_cast<std::uint64_t>(r.faces));
    std::vector<Cell> cells;
    for (int m = r.m_lo; m <= r.m_hi; ++m) {
      cells.push_back(measure(mesh, m, poses));
      const Cell& c = cells.back();
      std::printf("%7d %3d %10.2f %10.2f %9.2f %10.1f %5.1f%%\n", c.faces, c.m, c.median, c.mean, c.prep_ms,
                  static_cast<double>(c.bytes) / 1024, 100 * c.colliding);
      std::fflush(stdout);
    }
    const auto best = std::min_element(cells.begin(), cells.end(), [](const Cell& x, const Cell& y) { return x.mean < y.mean; });
    const auto nine = std::find_if(cells.begin(), cells.end(), [](const Cell& x) { return x.m == 9; });
    std::printf("  fastest mean: M = %d (%.2f us)%s\n", best->m, best->mean,
                nine != cells.end() ? (" vs M = 9: " + std::to_string(nine->mean) + " us").c_str() : "");
    for (const Cell& c : cells) {
      const double ref = nine != cells.end() ? nine->mean : c.mean;
      rows.push_back({{"name", std::to_string(c.faces) + " faces, M = " + std::to_string(c.m)},
                      {"ours_us", c.mean},
                      {"peer", "M=9"},
                      {"peer_us", ref},
                      {"ratio", c.mean / ref},
                      {"agreement", 1.0},
                      {"faces", c.faces},
                      {"m", c.m},
                      {"median_us", c.median},
                      {"prep_ms", c.prep_ms},
                      {"grid_bytes", c.bytes},
                      {"colliding", c.colliding},
                      {"fastest", c.m == best->m}});
    }
  }
  std::ofstream(out) << rows.dump(2) << "\n";
  std::printf("wrote %s\n", out.c_str());
  return 0;
}
