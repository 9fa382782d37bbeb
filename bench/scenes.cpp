#include "bench/scenes.hpp"

#include "asimov/cell/cell_loader.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

namespace asimov::bench {

using collision::Vec3;

Polyhedron make_bumpy_torus(double major, double minor, int nu, int nv, double bump) {
  Polyhedron p;
  const double two_pi = 2 * std::numbers::pi;
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      const double u = two_pi * i / nu, v = two_pi * j / nv;
      const double r = minor * (1 + bump * std::sin(5 * u) * std::sin(3 * v));
      p.vertices.emplace_back((major + r * std::cos(v)) * std::cos(u), (major + r * std::cos(v)) * std::sin(u),
                              r * std::sin(v));
    }
  auto at = [&](int i, int j) { return static_cast<std::uint32_t>((i % nu) * nv + (j % nv)); };
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      const auto a = at(i, j), b = at(i + 1, j), c = at(i + 1, j + 1), d = at(i, j + 1);
      p.triangles.push_back({a, b, c});
      p.triangles.push_back({a, c, d});
    }
  return p;
}

Polyhedron make_torus_with_faces(int faces, double major) {
  const int nv = std::max(3, static_cast<int>(std::lround(std::sqrt(faces / 4.0))));
  const int nu = std::max(3, static_cast<int>(std::lround(faces / (2.0 * nv))));
  return make_bumpy_torus(major, major / 3, nu, nv);
}

Polyhedron make_env_mesh() { return make_bumpy_torus(1000, 300, 50, 20); }  // 2,000 faces
Polyhedron make_rob_mesh() { return make_bumpy_torus(150, 50, 10, 10); }    // 200 faces

std::vector<Pose> random_poses(std::size_t n, double reach, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0, 1);
  std::uniform_real_distribution<double> u(-reach, reach);
  std::vector<Pose> out;
  out.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    Eigen::Quaterniond q(g(rng), g(rng), g(rng), g(rng));
    q.normalize();
    Pose p = Pose::Identity();
    p.linear() = q.toRotationMatrix();
    p.translation() = Vec3(u(rng), u(rng), u(rng));
    out.push_back(p);
  }
  return out;
}

PumaScene make_puma_scene(int moves, int samples, std::uint64_t seed) {
  PumaScene s{cell::default_cell(), {}};
  const auto& robot = s.cell.robot;
  const int n = robot.joint_count();
  std::mt19937_64 rng(seed);
  auto random_q = [&] {
    robots::JointVector q(n);
    for (int j = 0; j < n; ++j) q[j] = std::uniform_real_distribution<double>(robot.lower[j], robot.upper[j])(rng);
    return q;
  };
  robots::JointVector from = robots::ready_joints(robot);
  for (int m = 0; m < moves; ++m) {
    const robots::JointVector to = random_q();
    for (int k = 0; k < samples; ++k) {
      const double t = static_cast<double>(k) / samples;
      s.trajectory.push_back(from + t * (to - from));
    }
    from = to;
  }
  return s;
}

}  // namespace asimov::bench
