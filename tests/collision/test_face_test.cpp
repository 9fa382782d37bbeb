// The exact face-face test: degenerate catalogue of docs/collision-method.md §5, all 36 vertex orders and
// swapped arguments, exact scalings, a fuzz against an independent edge-by-edge oracle, and
// the contact point.
#include "collision/src/face_distance.hpp"
#include "collision/src/face_test.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>

using namespace asimov::collision;

namespace {

// Independent reference: closed triangles meet iff an edge of one meets the other.
bool oracle(const TriangleVerts& a, const TriangleVerts& b) {
  for (int i = 0; i < 3; ++i) {
    if (segment_intersects_triangle(a[i], a[(i + 1) % 3], b)) return true;
    if (segment_intersects_triangle(b[i], b[(i + 1) % 3], a)) return true;
  }
  return false;
}

TriangleVerts permuted(const TriangleVerts& t, int k) {
  static constexpr int perm[6][3] = {{0, 1, 2}, {1, 2, 0}, {2, 0, 1}, {0, 2, 1}, {2, 1, 0}, {1, 0, 2}};
  return {t[perm[k][0]], t[perm[k][1]], t[perm[k][2]]};
}

TriangleVerts scaled(const TriangleVerts& t, double k) { return {k * t[0], k * t[1], k * t[2]}; }

// The answer for every vertex order of both, both argument orders, and scalings by 2^±10.
bool same_answer_everywhere(const TriangleVerts& a, const TriangleVerts& b, bool& answer) {
  answer = triangles_intersect(a, b);
  for (double k : {1.0, 0x1p10, 0x1p-10})
    for (int i = 0; i < 6; ++i)
      for (int j = 0; j < 6; ++j) {
        const TriangleVerts pa = scaled(permuted(a, i), k), pb = scaled(permuted(b, j), k);
        if (triangles_intersect(pa, pb) != answer || triangles_intersect(pb, pa) != answer) return false;
      }
  return true;
}

void require_case(const TriangleVerts& a, const TriangleVerts& b, bool expected) {
  bool answer = false;
  REQUIRE(same_answer_everywhere(a, b, answer));
  REQUIRE(answer == expected);
  REQUIRE(oracle(a, b) == expected);
  if (expected) {
    const Vec3 p = contact_point(a, b);
    REQUIRE((triangle_closest_point(p, a) - p).norm() <= 0.01);
    REQUIRE((triangle_closest_point(p, b) - p).norm() <= 0.01);
  }
}

double up(double x) { return std::nextafter(x, INFINITY); }
double down(double x) { return std::nextafter(x, -INFINITY); }

}  // namespace

TEST_CASE("general position: crossing, separated, piercing", "[face_test]") {
  const TriangleVerts flat{Vec3(0, 0, 0), Vec3(10, 0, 0), Vec3(0, 10, 0)};
  require_case(flat, {Vec3(1, 1, -1), Vec3(2, 1, 1), Vec3(1, 2, 1)}, true);      // pierces the interior
  require_case(flat, {Vec3(1, 1, 0.5), Vec3(2, 1, 1), Vec3(1, 2, 1)}, false);    // above
  require_case(flat, {Vec3(20, 1, -1), Vec3(21, 1, 1), Vec3(20, 2, 1)}, false);  // beside the plane crossing
  require_case(flat, {Vec3(-5, 3, -1), Vec3(15, 3, -1), Vec3(5, 3, 4)}, true);   // edge through both
  require_case(flat, {Vec3(6, 6, -1), Vec3(6, 6, 1), Vec3(9, 9, 0)}, false);     // crosses the plane outside
}

TEST_CASE("coplanar triangles: overlapping, contained, disjoint, touching", "[face_test]") {
  const TriangleVerts t{Vec3(0, 0, 0), Vec3(4, 0, 0), Vec3(0, 4, 0)};
  require_case(t, {Vec3(1, 1, 0), Vec3(5, 1, 0), Vec3(1, 5, 0)}, true);     // overlap
  require_case(t, {Vec3(0.5, 0.5, 0), Vec3(1, 0.5, 0), Vec3(0.5, 1, 0)}, true);  // contained
  require_case(t, {Vec3(3, 3, 0), Vec3(6, 3, 0), Vec3(3, 6, 0)}, false);    // disjoint
  require_case(t, {Vec3(2, 2, 0), Vec3(6, 2, 0), Vec3(2, 6, 0)}, true);     // vertex on the hypotenuse
  require_case(t, {Vec3(4, 0, 0), Vec3(8, 0, 0), Vec3(4, 4, 0)}, true);     // shared vertex
  require_case(t, {Vec3(4, 0, 0), Vec3(0, 4, 0), Vec3(4, 4, 0)}, true);     // shared edge
  // A tilted plane, so no coordinate plane is the triangles' plane (axom#152 style).
  const Vec3 o(1, 2, 3), u(1, 2, 0.5), v(-0.5, 1, 2);
  auto at = [&](double s, double r) { return Vec3(o + s * u + r * v); };
  require_case({at(0, 0), at(4, 0), at(0, 4)}, {at(1, 1), at(5, 1), at(1, 5)}, true);
  require_case({at(0, 0), at(4, 0), at(0, 4)}, {at(3, 3), at(6, 3), at(3, 6)}, false);
  require_case({at(0, 0), at(4, 0), at(0, 4)}, {at(4, 0), at(8, 0), at(4, 4)}, true);
}

TEST_CASE("shared edges and vertices out of plane", "[face_test]") {
  const TriangleVerts t{Vec3(0, 0, 0), Vec3(4, 0, 0), Vec3(0, 4, 0)};
  require_case(t, {Vec3(0, 0, 0), Vec3(4, 0, 0), Vec3(0, 0, 4)}, true);   // hinge
  require_case(t, {Vec3(0, 0, 0), Vec3(-1, -1, 3), Vec3(-3, 0, 1)}, true);  // one common vertex
  require_case(t, {Vec3(2, 0, 0), Vec3(3, -1, 2), Vec3(1, -1, 2)}, true);   // vertex on an edge
}

TEST_CASE("touching at distance 0 and separated or crossing by one ulp", "[face_test]") {
  // Non-round coordinates so the plane is not an axis plane.
  const TriangleVerts t{Vec3(0.1, 0.2, 0.3), Vec3(10.7, 0.9, 1.3), Vec3(0.4, 9.1, 2.9)};
  // A point of t's plane: pick x, y and solve z; then sweep z by ulps. The true plane point is
  // generally not a double, so locate the boundary with the exact test itself and check that
  // the answer flips exactly once within a few ulps and is stable under all symmetries.
  const double x = 3.3, y = 2.2;
  const Vec3 n = (t[1] - t[0]).cross(t[2] - t[0]);
  double z = t[0].z() - (n.x() * (x - t[0].x()) + n.y() * (y - t[0].y())) / n.z();
  auto probe = [&](double zz) {
    return TriangleVerts{Vec3(x, y, zz), Vec3(x + 1, y + 0.5, zz + 3), Vec3(x - 0.5, y + 1, zz + 4)};
  };
  for (int k = 0; k < 8; ++k) z = down(z);
  int flips = 0;
  bool previous = triangles_intersect(probe(z), t);
  REQUIRE(previous);  // the probe's apex is below the plane: it pierces
  for (int k = 0; k < 16; ++k) {
    z = up(z);
    bool answer = false;
    REQUIRE(same_answer_everywhere(probe(z), t, answer));
    REQUIRE(answer == oracle(probe(z), t));
    flips += answer != previous;
    previous = answer;
  }
  REQUIRE(flips == 1);
  REQUIRE_FALSE(previous);

  // Exactly representable contact: a vertex on an axis-aligned face, and one ulp off.
  const TriangleVerts floor{Vec3(0, 0, 1), Vec3(8, 0, 1), Vec3(0, 8, 1)};
  require_case(floor, {Vec3(1, 1, 1), Vec3(2, 1, 3), Vec3(1, 2, 3)}, true);
  require_case(floor, {Vec3(1, 1, up(1)), Vec3(2, 1, 3), Vec3(1, 2, 3)}, false);
  require_case(floor, {Vec3(1, 1, down(1)), Vec3(2, 1, 3), Vec3(1, 2, 3)}, true);
  // Edge lying on the face, touching only along a segment.
  require_case(floor, {Vec3(1, 1, 1), Vec3(3, 1, 1), Vec3(2, 1, 5)}, true);
  require_case(floor, {Vec3(1, 1, up(1)), Vec3(3, 1, up(1)), Vec3(2, 1, 5)}, false);
  // Edge-edge touching across the boundary of the face.
  // (Offsets of one ulp next to 1, not 0: a subnormal would not survive the 2^-10 scaling.)
  const TriangleVerts ledge{Vec3(0, 1, 1), Vec3(8, 1, 1), Vec3(0, 9, 1)};
  require_case(ledge, {Vec3(4, -1, 1), Vec3(4, 2, 1), Vec3(4, 0, 5)}, true);
  require_case(ledge, {Vec3(4, -1, 1), Vec3(4, down(1), 1), Vec3(4, -0.5, 5)}, false);
  require_case(ledge, {Vec3(4, -1, 1), Vec3(4, 1, 1), Vec3(4, -0.5, 5)}, true);
}

TEST_CASE("zero-area triangles act as the segment or point they are", "[face_test]") {
  const TriangleVerts t{Vec3(0, 0, 0), Vec3(4, 0, 0), Vec3(0, 4, 0)};
  // Repeated vertex: a segment.
  require_case(t, {Vec3(1, 1, -1), Vec3(1, 1, -1), Vec3(1, 1, 1)}, true);
  require_case(t, {Vec3(1, 1, 0.5), Vec3(1, 1, 0.5), Vec3(1, 1, 1)}, false);
  require_case(t, {Vec3(3, 3, -1), Vec3(3, 3, -1), Vec3(3, 3, 1)}, false);  // misses: outside
  // Collinear vertices: a segment, lying in the plane.
  require_case(t, {Vec3(-1, 1, 0), Vec3(0.5, 1, 0), Vec3(2, 1, 0)}, true);
  require_case(t, {Vec3(3, 3, 0), Vec3(4, 4, 0), Vec3(5, 5, 0)}, false);    // geometry3Sharp#85
  require_case(t, {Vec3(-1, -1, 0), Vec3(-2, -2, 0), Vec3(-3, -3, 0)}, false);
  require_case(t, {Vec3(2, 2, 0), Vec3(3, 3, 0), Vec3(4, 4, 0)}, true);     // touches the hypotenuse
  // A single point.
  require_case(t, {Vec3(1, 1, 0), Vec3(1, 1, 0), Vec3(1, 1, 0)}, true);
  require_case(t, {Vec3(1, 1, 1e-9), Vec3(1, 1, 1e-9), Vec3(1, 1, 1e-9)}, false);
  // Both degenerate: crossing segments, skew segments, a point on a segment.
  require_case({Vec3(0, 0, 0), Vec3(1, 1, 1), Vec3(2, 2, 2)}, {Vec3(0, 2, 0), Vec3(2, 0, 2), Vec3(2, 0, 2)}, true);
  require_case({Vec3(0, 0, 0), Vec3(1, 1, 1), Vec3(2, 2, 2)}, {Vec3(0, 2, 0), Vec3(2, 0, 0), Vec3(2, 0, 0)}, false);
  require_case({Vec3(0, 0, 0), Vec3(2, 2, 2), Vec3(0, 0, 0)}, {Vec3(1, 1, 1), Vec3(1, 1, 1), Vec3(1, 1, 1)}, true);
  require_case({Vec3(0, 0, 0), Vec3(2, 2, 2), Vec3(0, 0, 0)}, {Vec3(3, 3, 3), Vec3(3, 3, 3), Vec3(3, 3, 3)}, false);
}

TEST_CASE("fuzz on a small integer grid agrees with the edge oracle under all symmetries", "[face_test]") {
  // Coordinates in {0..3}: coplanar pairs, shared vertices and zero-area triangles abound.
  std::mt19937 rng(1998);
  std::uniform_int_distribution<int> c(0, 3);
  auto point = [&] { return Vec3(c(rng), c(rng), c(rng)); };
  int hits = 0;
  for (int n = 0; n < 6000; ++n) {
    const TriangleVerts a{point(), point(), point()}, b{point(), point(), point()};
    bool answer = false;
    REQUIRE(same_answer_everywhere(a, b, answer));
    INFO("a = " << a[0].transpose() << " | " << a[1].transpose() << " | " << a[2].transpose());
    INFO("b = " << b[0].transpose() << " | " << b[1].transpose() << " | " << b[2].transpose());
    REQUIRE(answer == oracle(a, b));
    if (answer) {
      ++hits;
      const Vec3 p = contact_point(a, b);
      REQUIRE((triangle_closest_point(p, a) - p).norm() <= 0.01);
      REQUIRE((triangle_closest_point(p, b) - p).norm() <= 0.01);
    }
  }
  CHECK(hits > 1000);
}

TEST_CASE("fuzz in general position agrees with the oracle and contact points lie on both", "[face_test]") {
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> u(-50, 50);
  auto point = [&] { return Vec3(u(rng), u(rng), u(rng)); };
  int hits = 0;
  for (int n = 0; n < 200000; ++n) {
    TriangleVerts a{point(), point(), point()}, b{point(), point(), point()};
    if (n % 4 == 1) b[0] = a[1];  // shared vertex
    if (n % 4 == 2) {             // shared edge
      b[0] = a[0];
      b[1] = a[2];
    }
    const bool answer = triangles_intersect(a, b);
    REQUIRE(answer == oracle(a, b));
    REQUIRE(answer == triangles_intersect(b, a));
    if (answer) {
      ++hits;
      const Vec3 p = contact_point(a, b);
      REQUIRE((triangle_closest_point(p, a) - p).norm() <= 0.01);
      REQUIRE((triangle_closest_point(p, b) - p).norm() <= 0.01);
    }
  }
  CHECK(hits > 10000);
}

TEST_CASE("nearly coplanar pairs (three-mesh-bvh#384) are decided exactly", "[face_test]") {
  // b is a copy of a, rotated by a tiny angle about an in-plane axis through its centroid:
  // always intersecting along that axis.
  std::mt19937_64 rng(384);
  std::uniform_real_distribution<double> u(-10, 10);
  for (int n = 0; n < 2000; ++n) {
    const TriangleVerts a{Vec3(u(rng), u(rng), u(rng)), Vec3(u(rng), u(rng), u(rng)), Vec3(u(rng), u(rng), u(rng))};
    const Vec3 g = (a[0] + a[1] + a[2]) / 3;
    const Vec3 axis = (a[1] - a[0]).normalized();
    const Eigen::AngleAxisd rot(1e-9 * (1 + n % 7), axis);
    TriangleVerts b;
    for (int i = 0; i < 3; ++i) b[i] = g + rot * (a[i] - g);
    REQUIRE(triangles_intersect(a, b));
    REQUIRE(oracle(a, b));
  }
}
