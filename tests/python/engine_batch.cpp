// The C++ peer of the Python engine tests and bench (tests/python/test_engine.py,
// bench/bench_python.py): the scene of docs/python.md's engine example, N seeded random poses of
// its moving body, the engine queried at each. Writes the poses (N x 16 doubles, row-major 4x4)
// and the answers (N bytes, 1 = contact) to OUT, and prints the median wall time of `repeats`
// passes over the N poses as JSON.
// usage: asimov_engine_batch N SEED REPEATS OUT
#include "asimov/collision/engine.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <random>
#include <vector>

using namespace asimov::collision;

int main(int argc, char** argv) {
  if (argc != 5) {
    std::fprintf(stderr, "usage: asimov_engine_batch N SEED REPEATS OUT\n");
    return 1;
  }
  const long n = std::atol(argv[1]);
  const unsigned seed = static_cast<unsigned>(std::atol(argv[2]));
  const int repeats = std::max(1, std::atoi(argv[3]));
  if (n <= 0) {
    std::fprintf(stderr, "asimov_engine_batch: N > 0\n");
    return 1;
  }

  // The scene (same as the Python side builds): a cylinder moving about a static box.
  Engine engine;
  const BodyId part = engine.add_body({.name = "part", .mesh = make_cylinder(50, 300, 24)});
  const BodyId box = engine.add_body({.name = "box", .mesh = make_box(Vec3(400, 300, 200)), .is_static = true});
  engine.set_pose(box, Pose::Identity());

  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> offset(-450, 450);
  std::normal_distribution<double> gauss;
  std::vector<Pose> poses(static_cast<std::size_t>(n));
  for (auto& p : poses) {
    Eigen::Quaterniond q(gauss(rng), gauss(rng), gauss(rng), gauss(rng));
    q.normalize();
    p = Pose::Identity();
    p.linear() = q.toRotationMatrix();
    p.translation() = Vec3(offset(rng), offset(rng), offset(rng));
  }

  std::vector<unsigned char> hit(poses.size());
  const auto pass = [&] {
    for (std::size_t i = 0; i < poses.size(); ++i) {
      engine.set_pose(part, poses[i]);
      hit[i] = engine.check().collided ? 1 : 0;
    }
  };
  pass();  // warm-up: the lazy voxel grids are built in the first queries
  std::vector<double> times;
  for (int r = 0; r < repeats; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    pass();
    times.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  std::sort(times.begin(), times.end());

  std::ofstream out(argv[4], std::ios::binary);
  for (const auto& p : poses) {
    double m[16];
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) m[r * 4 + c] = p.matrix()(r, c);
    out.write(reinterpret_cast<const char*>(m), sizeof m);
  }
  out.write(reinterpret_cast<const char*>(hit.data()), static_cast<std::streamsize>(hit.size()));
  if (!out) {
    std::fprintf(stderr, "asimov_engine_batch: cannot write %s\n", argv[4]);
    return 1;
  }
  long contacts = 0;
  for (auto h : hit) contacts += h;
  std::printf("{\"n\": %ld, \"contacts\": %ld, \"repeats\": %d, \"median_s\": %.9f}\n", n, contacts, repeats,
              times[times.size() / 2]);
  return 0;
}
