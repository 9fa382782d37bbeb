// container_gap (gap stepping, docs/collision-method.md §6.3): a lower bound on the distance of two bodies.
#include "collision/src/container_gap.hpp"
#include "collision/src/face_distance.hpp"
#include "asimov/collision/polyhedron.hpp"

#include <catch2/catch.hpp>
#include <random>

using namespace asimov::collision;

TEST_CASE("box_distance: apart along one axis, along a diagonal, overlapping") {
  const Box a{Vec3(0, 0, 0), Vec3(1, 1, 1)};
  CHECK(box_distance(a, Box{Vec3(3, 0, 0), Vec3(4, 1, 1)}) == 2);
  CHECK(box_distance(a, Box{Vec3(4, 5, 0), Vec3(6, 7, 1)}) == Approx(5));  // 3-4-5 between corners
  CHECK(box_distance(a, Box{Vec3(0.5, 0.5, 0.5), Vec3(2, 2, 2)}) == 0);
  CHECK(box_distance(a, Box{Vec3(1, 0, 0), Vec3(2, 1, 1)}) == 0);  // touching
}

TEST_CASE("container_gap never exceeds the distance between the two meshes' vertices") {
  const Polyhedron box = make_box({40, 60, 100});
  const Container c = make_container(box.vertices);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  int apart = 0;
  for (int i = 0; i < 200; ++i) {
    const Pose pa = Pose(Eigen::AngleAxisd(u(rng) * 3, Vec3(u(rng), u(rng), u(rng)).normalized()));
    Pose pb = Pose(Eigen::AngleAxisd(u(rng) * 3, Vec3(u(rng), u(rng), u(rng)).normalized()));
    pb.translation() = Vec3(u(rng), u(rng), u(rng)) * 300;
    const double g = container_gap(c, pa, c, pb);
    // Boxes are convex: the closest points are no farther than the closest vertex pair.
    double closest = 1e300;
    for (const Vec3& va : box.vertices)
      for (const Vec3& vb : box.vertices) closest = std::min(closest, (pa * va - pb * vb).norm());
    CHECK(g >= 0);
    CHECK(g <= closest);
    apart += g > 0;
  }
  CHECK(apart > 50);  // the bound is not always 0
}

namespace {

// Distance between two meshes over all face pairs (0 when some pair intersects).
double mesh_distance(const Polyhedron& m, const Pose& pa, const Pose& pb) {
  double best = 1e300;
  for (const Triangle& ta : m.triangles)
    for (const Triangle& tb : m.triangles) {
      const TriangleVerts a{pa * m.vertices[ta[0]], pa * m.vertices[ta[1]], pa * m.vertices[ta[2]]};
      const TriangleVerts b{pb * m.vertices[tb[0]], pb * m.vertices[tb[1]], pb * m.vertices[tb[2]]};
      if (triangles_intersect(a, b)) return 0;
      Vec3 on_a, on_b;
      best = std::min(best, std::sqrt(triangle_closest_points(a, b, on_a, on_b)));
    }
  return best;
}

}  // namespace

TEST_CASE("container_gap of long rods: the vertex spheres tighten the box bound, never past the distance") {
  // A 400 mm rod turned diagonally has a world box ~280 mm wide that is mostly empty; the
  // spheres about the rods' centres then bound the distance better.
  const Polyhedron rod = make_box({400, 10, 10});
  const Container c = make_container(rod.vertices);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  int sphere_wins = 0, apart = 0;
  for (int i = 0; i < 300; ++i) {
    const Pose pa = Pose(Eigen::AngleAxisd(u(rng) * 3, Vec3(u(rng), u(rng), u(rng)).normalized()));
    Pose pb = Pose(Eigen::AngleAxisd(u(rng) * 3, Vec3(u(rng), u(rng), u(rng)).normalized()));
    pb.translation() = Vec3(u(rng), u(rng), u(rng)) * 900;
    const PlacedContainer a = place(c, pa), b = place(c, pb);
    const double margin = relative_margin(c, pa, c, pb);
    const double g = container_gap(a, b, margin);
    CHECK(g == container_gap(c, pa, c, pb));
    const double d = mesh_distance(rod, pa, pb);
    INFO("pose " << i << ": gap " << g << ", distance " << d);
    CHECK(g >= 0);
    CHECK(g <= d);
    sphere_wins += g > std::max(0.0, box_distance(a.box, b.box) - margin);
    apart += g > 0;
  }
  CHECK(apart > 100);
  CHECK(sphere_wins > 0);  // the sphere bound is the tighter one on some poses (4 of 300 here)
}

TEST_CASE("hull_gap warm start: the last direction proves a far pair in one pass, any guess gives a bound") {
  // Two boxes 30 mm apart across a diagonal: one pass from the first vertex pair bounds little,
  // one pass along the last best direction gives (nearly) the hull distance.
  const Polyhedron box = make_box({40, 60, 100});
  Pose b_pose(Eigen::AngleAxisd(0.7, Vec3(1, 1, 0).normalized()));
  b_pose.translation() = Vec3(100, 90, 40);
  const Pose a_from_b = b_pose;  // A at the origin
  const double truth = mesh_distance(box, Pose::Identity(), b_pose);
  REQUIRE(truth > 10);
  Vec3 dir = Vec3::Zero();
  const double full = hull_gap(box.vertices, box.vertices, a_from_b, 0, 1e300, 200, 0, &dir);
  CHECK(full <= truth);
  CHECK(full >= truth * (1 - 2e-3));
  REQUIRE(dir.squaredNorm() > 0);
  // One iteration: cold, from a[0] - b[0], it stays below 90 % of the distance; warm it is there.
  const double cold = hull_gap(box.vertices, box.vertices, a_from_b, 0, 1e300, 1);
  CHECK(cold < 0.9 * truth);
  Vec3 warm_dir = dir;
  const double warm = hull_gap(box.vertices, box.vertices, a_from_b, 0, 1e300, 1, 0, &warm_dir);
  CHECK(warm >= full * (1 - 1e-12));
  CHECK(warm <= truth);
  // Any direction, however stale or odd, gives a valid bound and a unit direction back.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int i = 0; i < 100; ++i) {
    Vec3 g(u(rng), u(rng), u(rng));
    g *= i % 3 == 0 ? 1e-200 : i % 3 == 1 ? 1e200 : 1.0;
    const double lb = hull_gap(box.vertices, box.vertices, a_from_b, 0, 1e300, 24, 0, &g);
    CHECK(lb <= truth);
    CHECK(std::abs(g.norm() - 1) < 1e-12);
  }
  Vec3 nan_guess(NAN, 0, 0);
  CHECK(hull_gap(box.vertices, box.vertices, a_from_b, 0, 1e300, 24, 0, &nan_guess) <= truth);
}
