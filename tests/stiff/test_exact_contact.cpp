// Exact contact (docs/collision-method.md §6.2, docs/stiff-cases.md "Exact contact"): at clearance 0,
// touching is a contact and one ulp of separation is not. The meshes are built from exactly
// representable coordinates (no rotation rounding), so "touching" is exact.
#include "asimov/collision/engine.hpp"

#include "support/geometry.hpp"

#include <catch2/catch.hpp>

#include <cmath>

using namespace asimov::collision;

using asimov::test::box_between;

namespace {


// A roof prism, ridge along x at height `ridge` over the base z = 0, |x|, |y| <= 5.
Polyhedron roof_x(double ridge) {
  Polyhedron p;
  p.vertices = {{-5, -5, 0}, {5, -5, 0}, {5, 5, 0}, {-5, 5, 0}, {-5, 0, ridge}, {5, 0, ridge}};
  p.triangles = {{0, 2, 1}, {0, 3, 2}, {0, 1, 5}, {0, 5, 4}, {2, 3, 4}, {2, 4, 5}, {3, 0, 4}, {1, 2, 5}};
  return p;
}

// The same roof upside down with its ridge along y at height `ridge` and its base at z = 10:
// (x, y, z) -> (y, x, 10 - z) is a proper rotation, so the triangles stay outward.
Polyhedron roof_y_down(double ridge) {
  Polyhedron p = roof_x(5);
  for (auto& v : p.vertices) v = Vec3(v.y(), v.x(), v.z() == 5 ? ridge : 10 - v.z());
  return p;
}

struct Scene {
  Engine engine;
  BodyId a = 0, b = 0;
  Scene(const Polyhedron& ma, const Polyhedron& mb) {
    a = engine.add_body({.name = "a", .mesh = ma});
    b = engine.add_body({.name = "b", .mesh = mb});
    engine.set_pose(a, Pose::Identity());
    engine.set_pose(b, Pose::Identity());
  }
};

Pose shifted_x(double x) {
  Pose p = Pose::Identity();
  p.translation() = Vec3(x, 0, 0);
  return p;
}

const double kAbove400 = std::nextafter(400.0, 1000.0);  // one ulp above the table top

}  // namespace

TEST_CASE("a box resting exactly on the table touches, one ulp above it does not", "[stiff][exact]") {
  const Polyhedron table = box_between({400, -600, 360}, {1100, 600, 400});
  {
    Scene s(table, box_between({600, -50, 400}, {700, 50, 500}));
    const QueryResult r = s.engine.check();
    REQUIRE(r.collided);
    CHECK(r.contact.kind == ContactKind::faces);
    CHECK(r.contact.point.z() == 400);
  }
  {
    Scene s(table, box_between({600, -50, kAbove400}, {700, 50, 500}));
    CHECK_FALSE(s.engine.check().collided);
    // Any clearance >= the gap turns it into a clearance contact.
    s.engine.set_default_clearance(1e-12);
    const QueryResult r = s.engine.check();
    REQUIRE(r.collided);
    CHECK(r.contact.kind == ContactKind::clearance);
    CHECK(r.contact.distance == Approx(kAbove400 - 400).margin(1e-15));
  }
}

TEST_CASE("coplanar sliding: a box sliding on the table touches at every pose, one ulp above at none",
          "[stiff][exact]") {
  const Polyhedron table = box_between({400, -600, 360}, {1100, 600, 400});
  for (const double bottom : {400.0, kAbove400}) {
    Scene s(table, box_between({500, -50, bottom}, {600, 50, 500}));
    int contacts = 0;
    constexpr int kPoses = 200;
    for (int i = 0; i < kPoses; ++i) {
      s.engine.set_pose(s.b, shifted_x(i * 2.5));  // x only: z stays exact
      contacts += s.engine.check().collided ? 1 : 0;
    }
    INFO("bottom at " << bottom);
    CHECK(contacts == (bottom == 400.0 ? kPoses : 0));
  }
}

TEST_CASE("edge on edge: crossing ridges touch at one point, one ulp apart they do not", "[stiff][exact]") {
  {
    Scene s(roof_x(5), roof_y_down(5));
    const QueryResult r = s.engine.check();
    REQUIRE(r.collided);
    CHECK(r.contact.kind == ContactKind::faces);
    CHECK((r.contact.point - Vec3(0, 0, 5)).norm() <= 1e-12);
  }
  {
    Scene s(roof_x(5), roof_y_down(std::nextafter(5.0, 10.0)));
    CHECK_FALSE(s.engine.check().collided);
  }
  {
    // Ridges crossing the other way round (A's ridge one ulp high reaches into B's).
    Scene s(roof_x(std::nextafter(5.0, 10.0)), roof_y_down(5));
    CHECK(s.engine.check().collided);
  }
}

TEST_CASE("exact contact far from the origin: the same verdicts 1e6 mm away", "[stiff][exact][scale]") {
  // Shifted by 2^20 mm (about 1.05e6), an exact translation of these coordinates.
  const double d = 1048576;
  auto lift = [&](Polyhedron p) {
    for (auto& v : p.vertices) v += Vec3(d, d, d);
    return p;
  };
  Scene touching(lift(roof_x(5)), lift(roof_y_down(5)));
  CHECK(touching.engine.check().collided);
  // One ulp at 1e6 is 2.3e-10 mm.
  Polyhedron up = lift(roof_y_down(5));
  for (auto& v : up.vertices)
    if (v.z() == d + 5) v.z() = std::nextafter(v.z(), 2 * d);
  Scene apart(lift(roof_x(5)), up);
  CHECK_FALSE(apart.engine.check().collided);
}
