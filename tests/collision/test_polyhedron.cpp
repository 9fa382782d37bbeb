// Primitive builders: closed, outward, consistent.
#include "collision/src/containment.hpp"
#include "asimov/collision/polyhedron.hpp"
#include "scenes.hpp"

#include <catch2/catch.hpp>

using namespace asimov::collision;

namespace {
double signed_volume(const Polyhedron& p) {
  double v = 0;
  for (const Triangle& t : p.triangles)
    v += p.vertices[t[0]].dot(p.vertices[t[1]].cross(p.vertices[t[2]])) / 6;
  return v;
}
}  // namespace

TEST_CASE("primitives are closed with outward triangles", "[polyhedron]") {
  const Polyhedron box = make_box(Vec3(2, 3, 4));
  CHECK(box.triangles.size() == 12);
  CHECK(is_closed(box));
  CHECK(signed_volume(box) == Approx(24));
  const Polyhedron cyl = make_cylinder(2, 5, 32);
  CHECK(cyl.triangles.size() == 4 * 32);
  CHECK(is_closed(cyl));
  CHECK(signed_volume(cyl) == Approx(0.5 * 32 * std::sin(2 * M_PI / 32) * 4 * 5));
  const Polyhedron l = test::make_l_prism(40, 10, 20);
  CHECK(is_closed(l));
  CHECK(signed_volume(l) == Approx((40 * 10 + 30 * 10) * 20));
  const Polyhedron m = test::make_merged_part();
  CHECK(is_closed(m));
  CHECK(shell_vertices(m).size() == 2);
}

TEST_CASE("transformed and merged keep topology and map vertices", "[polyhedron]") {
  Pose pose = Pose::Identity();
  pose.linear() = Eigen::AngleAxisd(0.3, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  pose.translation() = Vec3(10, -5, 2);
  const Polyhedron box = make_box(Vec3(2, 3, 4));
  const Polyhedron moved = transformed(box, pose);
  REQUIRE(moved.triangles == box.triangles);
  for (std::size_t i = 0; i < box.vertices.size(); ++i) CHECK((moved.vertices[i] - pose * box.vertices[i]).norm() == 0);
  CHECK(signed_volume(moved) == Approx(24));
  const Polyhedron both = merged(box, moved);
  CHECK(both.vertices.size() == 16);
  CHECK(both.triangles.size() == 24);
  CHECK(both.triangles[12][0] == box.triangles[0][0] + 8);
  CHECK(is_closed(both));
}
