// Step 2: containers and minimax boxes.
#include "collision/src/minimax.hpp"
#include "scenes.hpp"

#include <catch2/catch.hpp>

using namespace asimov::collision;

TEST_CASE("the container bounds every vertex and pads thin sides", "[minimax]") {
  const Polyhedron m = test::make_merged_part();
  const Container c = make_container(m.vertices);
  for (const Vec3& v : m.vertices)
    for (int k = 0; k < 3; ++k) {
      CHECK(v[k] >= c.origin[k]);
      CHECK(v[k] <= c.origin[k] + c.size[k]);
    }
  // A flat plate: the zero side is padded to 1e-6 of the diagonal.
  const Container flat = make_container({Vec3(0, 0, 5), Vec3(10, 0, 5), Vec3(0, 10, 5)});
  CHECK(flat.size.z() > 0);
  CHECK(flat.size.z() < 1e-4);
  CHECK(flat.origin.z() <= 5);
  CHECK(flat.origin.z() + flat.size.z() >= 5);
}

TEST_CASE("minimax boxes contain the transformed vertices, tightly for axis-aligned poses", "[minimax]") {
  std::mt19937_64 rng(2);
  const Polyhedron m = test::make_merged_part();
  const Container c = make_container(m.vertices);
  for (int n = 0; n < 2000; ++n) {
    const Pose pose = test::random_pose(rng, 500);
    const Box b = minimax_box(c, pose);
    const double eps = relative_margin(c, pose, c, pose);
    for (const Vec3& v : m.vertices) {
      const Vec3 w = pose * v;
      for (int k = 0; k < 3; ++k) {
        REQUIRE(w[k] >= b.lo[k] - eps);
        REQUIRE(w[k] <= b.hi[k] + eps);
      }
    }
  }
  Pose shift = Pose::Identity();
  shift.translation() = Vec3(1, 2, 3);
  const Box b = minimax_box(c, shift);
  CHECK((b.lo - (c.origin + shift.translation())).norm() == 0);
  CHECK((b.hi - (c.origin + c.size + shift.translation())).norm() == Approx(0).margin(1e-12));
}

TEST_CASE("the six separation tests and the gap", "[minimax]") {
  const Box a{Vec3(0, 0, 0), Vec3(1, 1, 1)};
  for (int k = 0; k < 3; ++k) {
    Box b{Vec3(0, 0, 0), Vec3(1, 1, 1)};
    b.lo[k] = 3;
    b.hi[k] = 4;
    CHECK(separated(a, b, 0));
    CHECK(separated(b, a, 0));
    CHECK(separated(a, b, 1.9));
    CHECK_FALSE(separated(a, b, 2.0));  // grown by the clearance they touch
    CHECK(box_gap(a, b) == 2);
  }
  CHECK_FALSE(separated(a, Box{Vec3(1, 1, 1), Vec3(2, 2, 2)}, 0));  // touching corners
  CHECK(box_gap(a, Box{Vec3(0.5, 0.5, 0.5), Vec3(2, 2, 2)}) == 0);
}

TEST_CASE("the vertex sphere holds every vertex and rejects discs whose boxes overlap at a corner", "[minimax]") {
  const Polyhedron m = test::make_merged_part();
  const Container c = make_container(m.vertices);
  for (const Vec3& v : m.vertices) CHECK((v - c.centre()).norm() <= c.radius);
  // Two flat discs (radius 10, 2 thick) side by side on a diagonal: their boxes overlap on
  // every axis, their spheres (radius sqrt(101)) do not, and they are 1.2 mm apart.
  const Polyhedron disc = make_cylinder(10, 2, 64);
  const Container d = make_container(disc.vertices);
  CHECK(d.radius >= std::sqrt(101.0));
  CHECK(d.radius < std::sqrt(101.0) * (1 + 1e-12));
  Pose pb = Pose::Identity();
  pb.translation() = Vec3(15, 15, 0);
  CHECK_FALSE(separated(minimax_box(d, Pose::Identity()), minimax_box(d, pb), 0));
  CHECK_FALSE(containers_separated(d, d, relative_pose(Pose::Identity(), pb), 0));
  CHECK(spheres_separated(d.centre(), d.radius, pb * d.centre(), d.radius, 0));
  CHECK_FALSE(spheres_separated(d.centre(), d.radius, pb * d.centre(), d.radius, 1.5));  // grown by a clearance
  pb.translation() = Vec3(14, 14, 0);  // 19.8 apart: the spheres meet
  CHECK_FALSE(spheres_separated(d.centre(), d.radius, pb * d.centre(), d.radius, 0));
}
