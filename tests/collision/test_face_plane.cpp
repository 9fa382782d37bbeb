// The plane prefilter of step 4 (face_plane.hpp) may only say "separated" when the exact
// orientation signs agree, and the shell samples used by containment stay in their shell.
#include "collision/src/containment.hpp"
#include "collision/src/face_plane.hpp"
#include "collision/src/predicates.hpp"
#include "scenes.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <random>
#include <set>

using namespace asimov::collision;

namespace {

// The exact verdict the prefilter must never contradict: all three vertices of t2 strictly on
// one side of t1's plane.
bool exactly_one_side(const TriangleVerts& t1, const TriangleVerts& t2) {
  const int s0 = orient3d(t1[0], t1[1], t1[2], t2[0]);
  return s0 != 0 && orient3d(t1[0], t1[1], t1[2], t2[1]) == s0 && orient3d(t1[0], t1[1], t1[2], t2[2]) == s0;
}

// The draws are sequenced: the arguments of Vec3(u(rng), u(rng), u(rng)) are evaluated in an
// unspecified order, so gcc and clang built different triangles. z, y, x is the order gcc
// used, which keeps this test's sample the one it was written against.
template <class Dist, class Rng>
Vec3 draw(Dist& u, Rng& rng) {
  const double z = u(rng), y = u(rng), x = u(rng);
  return {x, y, z};
}

template <class Dist, class Rng>
TriangleVerts draw_triangle(Dist& u, Rng& rng) {
  return {draw(u, rng), draw(u, rng), draw(u, rng)};  // braced list: evaluated left to right
}

Vec3 nudge(const Vec3& v, int ulps, int axis) {
  Vec3 w = v;
  for (int i = 0; i < std::abs(ulps); ++i) w[axis] = std::nextafter(w[axis], ulps > 0 ? INFINITY : -INFINITY);
  return w;
}

}  // namespace

TEST_CASE("plane prefilter: clear cases and touching", "[face_plane]") {
  const TriangleVerts floor{Vec3(0, 0, 1), Vec3(8, 0, 1), Vec3(0, 8, 1)};
  const FacePlane f = face_plane(floor);
  CHECK(plane_separates(f, floor, {Vec3(1, 1, 2), Vec3(2, 1, 3), Vec3(1, 2, 3)}));
  CHECK(plane_separates(f, floor, {Vec3(1, 1, -2), Vec3(2, 1, -3), Vec3(1, 2, -3)}));
  CHECK_FALSE(plane_separates(f, floor, {Vec3(1, 1, 1), Vec3(2, 1, 3), Vec3(1, 2, 3)}));  // touches
  CHECK_FALSE(plane_separates(f, floor, {Vec3(1, 1, 0), Vec3(2, 1, 3), Vec3(1, 2, 3)}));  // crosses
  // One ulp above the plane: exactly on one side, and exactly representable, so decided.
  CHECK(plane_separates(f, floor, {Vec3(1, 1, std::nextafter(1.0, 2.0)), Vec3(2, 1, 3), Vec3(1, 2, 3)}));
  // A zero-area triangle has no plane: never separates.
  const TriangleVerts line{Vec3(0, 0, 0), Vec3(1, 1, 1), Vec3(2, 2, 2)};
  CHECK_FALSE(plane_separates(face_plane(line), line, {Vec3(5, 0, 0), Vec3(6, 0, 0), Vec3(5, 1, 0)}));
}

TEST_CASE("plane prefilter never contradicts the exact signs near the plane", "[face_plane]") {
  std::mt19937_64 rng(2026);
  std::uniform_real_distribution<double> u(-100, 100);
  std::uniform_int_distribution<int> ulp(-3, 3), axis(0, 2);
  int separated = 0, checked = 0;
  for (int n = 0; n < 20000; ++n) {
    const TriangleVerts t1 = draw_triangle(u, rng);
    // t2's vertices: points of t1's plane (rounded affine combinations), then a few ulps off.
    TriangleVerts t2;
    for (Vec3& v : t2) {
      const double a = u(rng) / 50, b = u(rng) / 50;
      const int along = axis(rng), ulps = ulp(rng);  // gcc's order, as above
      v = nudge(t1[0] + a * (t1[1] - t1[0]) + b * (t1[2] - t1[0]), ulps, along);
    }
    const bool pre = plane_separates(face_plane(t1), t1, t2);
    ++checked;
    if (!pre) continue;
    ++separated;
    REQUIRE(exactly_one_side(t1, t2));
    REQUIRE_FALSE(triangles_intersect(t1, t2));
  }
  // Random far triangles: decided by the prefilter exactly when the exact signs say so, up to
  // the rare pair within the rounding bound.
  int agree = 0;
  for (int n = 0; n < 20000; ++n) {
    const TriangleVerts t1 = draw_triangle(u, rng);
    const TriangleVerts t2 = draw_triangle(u, rng);
    const bool pre = plane_separates(face_plane(t1), t1, t2), exact = exactly_one_side(t1, t2);
    if (pre) REQUIRE(exact);
    agree += pre == exact;
  }
  CHECK(checked == 20000);
  CHECK(separated > 0);      // near the plane some are still decided (the bound is tight)
  CHECK(agree > 19900);      // and far from it nearly all
}

TEST_CASE("shell samples: per shell, its first vertex first, all of the shell", "[face_plane]") {
  const Polyhedron m = test::make_merged_part();  // an L prism and a cylinder: two shells
  const std::vector<std::uint32_t> roots = shell_vertices(m);
  REQUIRE(roots.size() == 2);
  const auto one = shell_samples(m, 1);
  REQUIRE(one.size() == 2);
  CHECK(one[0] == std::vector<std::uint32_t>{roots[0]});
  CHECK(one[1] == std::vector<std::uint32_t>{roots[1]});
  const auto many = shell_samples(m, 8);
  REQUIRE(many.size() == 2);
  // The prism's vertices come first in the merged mesh: its shell holds the indices below the
  // cylinder's root.
  for (std::size_t s = 0; s < 2; ++s) {
    CHECK(many[s].front() == roots[s]);
    CHECK(many[s].size() == 8);
    CHECK(std::set<std::uint32_t>(many[s].begin(), many[s].end()).size() == many[s].size());
    for (const std::uint32_t v : many[s]) CHECK((s == 0 ? v < roots[1] : v >= roots[1]));
  }
  CHECK(shell_samples(make_box(Vec3(1, 1, 1)), 100).front().size() == 8);  // capped at the shell's size
}
