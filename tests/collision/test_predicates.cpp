// Exact orientation signs: near-degenerate grids where naive doubles fail, exact zeros,
// scaling invariance and agreement between the filter and the exact fallback.
#include "collision/src/predicates.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <random>

using namespace asimov::collision;

namespace {
int sgn(double v) { return (v > 0) - (v < 0); }
double ulps(double x, int n) {
  for (; n > 0; --n) x = std::nextafter(x, 2 * x + 1);
  for (; n < 0; ++n) x = std::nextafter(x, -1.0);
  return x;
}
}  // namespace

TEST_CASE("orient2d is exact on points a few ulps from a line", "[predicates]") {
  // b and c lie on y = x; a = (0.5 + i ulp, 0.5 + j ulp) is left of b->c iff j > i.
  int naive_wrong = 0;
  for (int i = 0; i < 48; ++i)
    for (int j = 0; j < 48; ++j) {
      const double ax = ulps(0.5, i), ay = ulps(0.5, j);
      const int expected = sgn(j - i);
      REQUIRE(orient2d(ax, ay, 12, 12, 24, 24) == expected);
      REQUIRE(orient2d_exact(ax, ay, 12, 12, 24, 24) == expected);
      REQUIRE(orient2d(12, 12, 24, 24, ax, ay) == expected);  // cyclic order keeps the sign
      REQUIRE(orient2d(12, 12, ax, ay, 24, 24) == -expected);
      const double naive = (12 - ax) * (24 - ay) - (12 - ay) * (24 - ax);
      naive_wrong += sgn(naive) != expected;
    }
  CHECK(naive_wrong > 0);  // the grid really exercises the exact fallback
}

TEST_CASE("orient3d is exact on points a few ulps from a plane", "[predicates]") {
  // b, c, d span the plane x = y; a = (0.5 + i ulp, 0.5 + j ulp, 0.3).
  const Vec3 b(12, 12, 0), c(24, 24, 0), d(0, 0, 1);
  const int side = orient3d(b, c, d, Vec3(0, 1, 0));  // sign for a point with y > x
  REQUIRE(side != 0);
  for (int i = 0; i < 32; ++i)
    for (int j = 0; j < 32; ++j) {
      const Vec3 a(ulps(0.5, i), ulps(0.5, j), 0.3);
      const int expected = side * sgn(j - i);
      REQUIRE(orient3d(b, c, d, a) == expected);
      REQUIRE(orient3d_exact(b, c, d, a) == expected);
      REQUIRE(orient3d(a, b, c, d) == -expected);  // odd permutation of four points
      REQUIRE(orient3d(c, d, b, a) == expected);   // cyclic order of the first three
    }
}

TEST_CASE("orientation signs of degenerate inputs are zero", "[predicates]") {
  const Vec3 a(1.1, 2.3, -0.7), b(-4.1, 0.3, 9.9), c(0.37, 0.11, 5.5);
  CHECK(orient3d(a, a, b, c) == 0);
  CHECK(orient3d(a, b, c, a) == 0);
  CHECK(orient3d(a, b, a, b) == 0);
  CHECK(orient3d(a, a, a, a) == 0);
  CHECK(orient2d(1.1, 2.3, 1.1, 2.3, 5, 7) == 0);
  CHECK(orient2d(0.1, 0.1, 0.2, 0.2, 0.3, 0.3) == 0);  // the rounded values are still on y = x
  // Exactly coplanar: d = a + 2(b - a) - 3(c - a) with all values small integers.
  const Vec3 p(1, 2, 3), q(4, -1, 7), r(-2, 5, 1);
  CHECK(orient3d(p, q, r, p + 2 * (q - p) - 3 * (r - p)) == 0);
  // Orientation of the unit tetrahedron fixes the convention.
  CHECK(orient3d(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)) == 1);
  CHECK(orient2d(0, 0, 1, 0, 0, 1) == 1);
}

TEST_CASE("orientation signs are invariant under scaling by 2^k and agree with the exact path",
          "[predicates]") {
  std::mt19937_64 rng(20260);
  std::uniform_real_distribution<double> u(-100, 100);
  std::uniform_int_distribution<int> small(-3, 3);
  for (int n = 0; n < 20000; ++n) {
    Vec3 v[4];
    for (auto& p : v) p = Vec3(u(rng), u(rng), u(rng));
    if (n % 2) v[3] = v[0] + small(rng) * (v[1] - v[0]) + small(rng) * (v[2] - v[0]);  // near-coplanar
    const int s = orient3d(v[0], v[1], v[2], v[3]);
    REQUIRE(s == orient3d_exact(v[0], v[1], v[2], v[3]));
    for (double k : {0x1p10, 0x1p-10})
      REQUIRE(orient3d(k * v[0], k * v[1], k * v[2], k * v[3]) == s);
    const int t = orient2d(v[0].x(), v[0].y(), v[1].x(), v[1].y(), v[3].x(), v[3].y());
    REQUIRE(t == orient2d_exact(v[0].x(), v[0].y(), v[1].x(), v[1].y(), v[3].x(), v[3].y()));
  }
}
