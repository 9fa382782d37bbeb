// Engine::distance (docs/collision.md §11) against brute force over all face pairs: the same
// distance (1e-9 relative), witness points on the named faces, exact zero at touching, the
// cut-off, containment, degenerate bodies.
#include "asimov/collision/distance.hpp"
#include "asimov/collision/engine.hpp"
#include "collision/src/face_distance.hpp"
#include "scenes.hpp"

#include "support/geometry.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <random>

using namespace asimov::collision;

using asimov::test::box_between;

namespace {


TriangleVerts world_face(const Polyhedron& m, const Pose& p, std::uint32_t f) {
  const Triangle& t = m.triangles[f];
  return {transform_vertex(p, m.vertices[t[0]]), transform_vertex(p, m.vertices[t[1]]),
          transform_vertex(p, m.vertices[t[2]])};
}

bool agrees(double x, double y) { return std::fabs(x - y) <= 1e-9 * std::max(1.0, std::max(x, y)); }

// Engine and brute force on one pose: status, distance, and witnesses on the named faces.
bool same_distance(const DistanceResult& e, const DistanceResult& r, const Polyhedron& ma, const Pose& pa,
                   const Polyhedron& mb, const Pose& pb) {
  if (e.status != r.status) return false;
  if (e.status == DistanceStatus::contact) return e.distance == 0;
  if (!agrees(e.distance, r.distance)) return false;
  const TriangleVerts ta = world_face(ma, pa, e.face_a), tb = world_face(mb, pb, e.face_b);
  const double scale = std::max(1.0, e.distance);
  return (triangle_closest_point(e.point_a, ta) - e.point_a).norm() <= 1e-9 * scale &&
         (triangle_closest_point(e.point_b, tb) - e.point_b).norm() <= 1e-9 * scale &&
         agrees((e.point_a - e.point_b).norm(), e.distance);
}

// `bodies` random pairs of the meshes (a near the origin), each at `poses` random poses of b
// within `reach`: visit(engine, a, b, mesh a, pose a, mesh b, pose b, brute-force answer).
template <class Visit>
void for_random_pairs(const std::vector<Polyhedron>& meshes, std::uint64_t seed, int bodies, int poses, double reach,
                      Visit&& visit) {
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<std::size_t> pick(0, meshes.size() - 1);
  for (int m = 0; m < bodies; ++m) {
    const Polyhedron& ma = meshes[pick(rng)];
    const Polyhedron& mb = meshes[pick(rng)];
    Engine e;
    const BodyId a = e.add_body({.name = "a", .mesh = ma});
    const BodyId b = e.add_body({.name = "b", .mesh = mb});
    const Pose pa = test::random_pose(rng, 5);
    e.set_pose(a, pa);
    for (int k = 0; k < poses; ++k) {
      const Pose pb = test::random_pose(rng, reach);
      e.set_pose(b, pb);
      visit(e, a, b, ma, pa, mb, pb, brute_force_distance(ma, pa, mb, pb));
    }
  }
}

}  // namespace

TEST_CASE("distance equals brute force on random poses of mesh pairs", "[distance][cross_check]") {
  const std::vector<Polyhedron> meshes = {test::make_merged_part(), make_cylinder(10, 40, 16), make_box(Vec3(30, 12, 8)),
                                          test::make_l_prism(40, 10, 20), make_cylinder(15, 10, 24),
                                          make_box(Vec3(60, 60, 60)), make_box(Vec3(4, 4, 4))};
  std::mt19937_64 rng(14);
  std::uniform_int_distribution<std::size_t> pick(0, meshes.size() - 1);
  int cases = 0, contacts = 0, contained = 0, bad = 0;
  for (int m = 0; m < 200; ++m) {
    const Polyhedron& ma = meshes[pick(rng)];
    const Polyhedron& mb = meshes[pick(rng)];
    Engine e;
    const int h = m % 3 == 0 ? kAutoHalvings : m % 3 == 1 ? 3 : 9;
    const BodyId a = e.add_body({.name = "a", .mesh = ma, .halvings = h});
    const BodyId b = e.add_body({.name = "b", .mesh = mb, .halvings = h});
    const Pose pa = test::random_pose(rng, 5);
    e.set_pose(a, pa);
    for (int k = 0; k < 50; ++k) {
      const Pose pb = test::random_pose(rng, 40);
      e.set_pose(b, pb);
      const DistanceResult d = e.distance(a, b);
      const DistanceResult r = brute_force_distance(ma, pa, mb, pb);
      ++cases;
      contacts += d.status == DistanceStatus::contact;
      contained += d.status == DistanceStatus::contact && d.kind == ContactKind::containment;
      // The verdict agrees with check() too.
      if (!same_distance(d, r, ma, pa, mb, pb) || (d.status == DistanceStatus::contact) != e.check().collided) {
        ++bad;
        UNSCOPED_INFO("case " << m << " pose " << k << ": engine " << int(d.status) << " " << d.distance << ", brute "
                              << int(r.status) << " " << r.distance);
      }
    }
  }
  WARN("distance cross-check: " << cases << " cases, " << contacts << " in contact (" << contained
                                << " containment), " << bad << " disagreements");
  CHECK(contacts > cases / 10);
  CHECK(contacts < cases * 9 / 10);
  CHECK(contained > 0);
  REQUIRE(bad == 0);
}

TEST_CASE("distance cut-off: beyond means at least upper_mm, below it the exact answer", "[distance]") {
  Engine e;
  const Polyhedron m = make_box(Vec3(10, 10, 10));
  const BodyId a = e.add_body({.name = "a", .mesh = m});
  const BodyId b = e.add_body({.name = "b", .mesh = m});
  e.set_pose(a, Pose::Identity());
  Pose p = Pose::Identity();
  p.translation() = Vec3(30, 0, 0);  // faces 20 mm apart
  e.set_pose(b, p);
  const DistanceResult exact = e.distance(a, b);
  REQUIRE(exact.status == DistanceStatus::exact);
  CHECK(exact.distance == 20);
  CHECK(exact.point_a.x() == 5);
  CHECK(exact.point_b.x() == 25);
  for (const double upper : {1.0, 19.0, 20.0}) {
    const DistanceResult r = e.distance(a, b, {.upper_mm = upper});
    CHECK(r.status == DistanceStatus::beyond);
    CHECK(r.distance >= upper);
    CHECK(r.distance <= 20);
  }
  const DistanceResult within = e.distance(a, b, {.upper_mm = 20.5});
  CHECK(within.status == DistanceStatus::exact);
  CHECK(within.distance == 20);
  // Far apart: decided by step 2 alone, no face pair computed, no grid built.
  Engine fresh;
  const BodyId fa = fresh.add_body({.name = "a", .mesh = m});
  const BodyId fb = fresh.add_body({.name = "b", .mesh = m});
  fresh.set_pose(fa, Pose::Identity());
  p.translation() = Vec3(1e4, 0, 0);
  fresh.set_pose(fb, p);
  const DistanceResult far = fresh.distance(fa, fb, {.upper_mm = 10});
  CHECK(far.status == DistanceStatus::beyond);
  CHECK(far.distance >= 10);
  CHECK(far.face_pairs == 0);
  CHECK(!fresh.body_preprocessed(fa));
}

TEST_CASE("distance is exactly zero at touching and positive one ulp away", "[distance][exact]") {
  const Polyhedron table = box_between({400, -600, 360}, {1100, 600, 400});
  const double above = std::nextafter(400.0, 1000.0);
  for (const double bottom : {400.0, above}) {
    Engine e;
    const BodyId a = e.add_body({.name = "table", .mesh = table});
    const BodyId b = e.add_body({.name = "box", .mesh = box_between({600, -50, bottom}, {700, 50, 500})});
    e.set_pose(a, Pose::Identity());
    e.set_pose(b, Pose::Identity());
    const DistanceResult r = e.distance(a, b);
    if (bottom == 400.0) {
      CHECK(r.status == DistanceStatus::contact);
      CHECK(r.distance == 0);
      CHECK(r.point_a.z() == 400);
    } else {
      CHECK(r.status == DistanceStatus::exact);
      CHECK(r.distance == above - 400);
      CHECK(r.point_a.z() == 400);
      CHECK(r.point_b.z() == above);
    }
    CHECK((r.status == DistanceStatus::contact) == e.check().collided);
  }
}

TEST_CASE("distance: a body inside another is in contact, in a cavity it has a distance", "[distance]") {
  Polyhedron cavity = make_box(Vec3(50, 50, 50));
  for (Triangle& tri : cavity.triangles) std::swap(tri[1], tri[2]);
  const Polyhedron hollow = merged(make_box(Vec3(90, 90, 90)), cavity);
  Engine e;
  const BodyId a = e.add_body({.name = "solid", .mesh = make_box(Vec3(90, 90, 90))});
  const BodyId h = e.add_body({.name = "hollow", .mesh = hollow});
  const BodyId b = e.add_body({.name = "small", .mesh = make_box(Vec3(10, 10, 10))});
  for (const BodyId id : {a, h, b}) e.set_pose(id, Pose::Identity());
  const DistanceResult in = e.distance(a, b);
  CHECK(in.status == DistanceStatus::contact);
  CHECK(in.kind == ContactKind::containment);
  const DistanceResult cav = e.distance(h, b);
  CHECK(cav.status == DistanceStatus::exact);
  CHECK(cav.distance == Approx(20).margin(1e-12));  // cavity wall at 25, small box at 5
}

TEST_CASE("distance of a body without faces is beyond any cut-off, bad ids are refused", "[distance]") {
  Engine e;
  Polyhedron empty;
  empty.vertices = {Vec3(0, 0, 0)};
  const BodyId a = e.add_body({.name = "a", .mesh = make_box(Vec3(1, 1, 1))});
  const BodyId b = e.add_body({.name = "b", .mesh = empty});
  e.set_pose(a, Pose::Identity());
  e.set_pose(b, Pose::Identity());
  CHECK(e.distance(a, b).status == DistanceStatus::beyond);
  CHECK_THROWS_AS(e.distance(a, a), std::invalid_argument);
  CHECK_THROWS_AS(e.distance(a, 7), std::invalid_argument);
}

TEST_CASE("distance cut-off on random poses: 'beyond' is a lower bound, at least the cut-off", "[distance][cross_check]") {
  // The bounds tried before any grid (oriented containers, convex hulls) and the descent: a
  // "beyond" answer never exceeds the true distance and is at least the cut-off; below it the
  // answer is the exact one.
  const std::vector<Polyhedron> meshes = {test::make_merged_part(), make_cylinder(10, 40, 16), make_box(Vec3(30, 12, 8)),
                                          test::make_l_prism(40, 10, 20), make_box(Vec3(4, 4, 4))};
  int beyond = 0, exact = 0, bad = 0;
  for_random_pairs(meshes, 1414, 60, 20, 60,
                   [&](Engine& e, BodyId a, BodyId b, const Polyhedron&, const Pose&, const Polyhedron&, const Pose&,
                       const DistanceResult& r) {
                     if (r.status != DistanceStatus::exact) return;
                     for (const double f : {0.3, 0.9, 0.999, 1.001, 1.5, 3.0}) {
                       const double upper = f * r.distance;
                       const DistanceResult d = e.distance(a, b, {.upper_mm = upper});
                       if (d.status == DistanceStatus::beyond) {
                         ++beyond;
                         if (!(d.distance >= upper && d.distance <= r.distance * (1 + 1e-9))) ++bad;
                       } else {
                         ++exact;
                         if (!(d.status == DistanceStatus::exact && agrees(d.distance, r.distance) && f > 1)) ++bad;
                       }
                     }
                   });
  CHECK(beyond > 100);
  CHECK(exact > 100);
  REQUIRE(bad == 0);
}

TEST_CASE("distance equals brute force for many-faced bodies a hair apart, also far from the origin", "[distance][cross_check]") {
  // Leaves of several faces on both sides, each pair first bounded along the line of the
  // leaves' boxes (engine.cpp, distance_leaf_pair): moved to within 1e-2 .. 1e-7 mm of each
  // other at 0, 1e4 and 1e6 mm from the origin (gaps far below the coordinates' size), the
  // answer is brute force's.
  const std::vector<Polyhedron> meshes = {make_cylinder(15, 10, 48), test::make_merged_part(), make_cylinder(10, 40, 32)};
  std::mt19937_64 rng(2026);
  int hair = 0, bad = 0;
  for (const double offset : {0.0, 1e4, 1e6}) {
    for (int k = 0; k < 60; ++k) {
      const Polyhedron& ma = meshes[static_cast<std::size_t>(k) % meshes.size()];
      const Polyhedron& mb = meshes[static_cast<std::size_t>(k / 3) % meshes.size()];
      Pose pa = test::random_pose(rng, 5);
      pa.translation() += Vec3(offset, -offset, 0.5 * offset);
      const Pose pb0 = pa * test::random_pose(rng, 60);
      const DistanceResult r0 = brute_force_distance(ma, pa, mb, pb0);
      if (r0.status != DistanceStatus::exact) continue;
      const Vec3 u = (r0.point_b - r0.point_a) / r0.distance;
      for (const double gap : {1e-2, 1e-5, 1e-7}) {
        Pose pb = pb0;
        pb.translation() -= (r0.distance - gap) * u;
        Engine e;
        const BodyId a = e.add_body({.name = "a", .mesh = ma});
        const BodyId b = e.add_body({.name = "b", .mesh = mb});
        e.set_pose(a, pa);
        e.set_pose(b, pb);
        const DistanceResult d = e.distance(a, b);
        const DistanceResult r = brute_force_distance(ma, pa, mb, pb);
        hair += r.status == DistanceStatus::exact && r.distance < 1e-3;
        if (!same_distance(d, r, ma, pa, mb, pb)) {
          ++bad;
          UNSCOPED_INFO("offset " << offset << " case " << k << " gap " << gap << ": engine " << int(d.status) << " "
                                  << d.distance << ", brute " << int(r.status) << " " << r.distance);
        }
      }
    }
  }
  WARN("hair-gap cases: " << hair);
  CHECK(hair > 200);
  REQUIRE(bad == 0);
}

TEST_CASE("distance warm start: a chained, stale or garbage guess changes no answer", "[distance]") {
  // A body sliding past another in small steps, each query given the last answer's guess (the
  // continuous checker's use), then a guess from far back, then NaN, huge and tiny ones: every
  // answer is the one without a guess (status; exact distances to the last digit, as the descent
  // is the same; "beyond" bounds valid against brute force).
  const Polyhedron ma = test::make_l_prism(40, 10, 20), mb = make_cylinder(10, 40, 16);
  Engine e;
  const BodyId a = e.add_body({.name = "a", .mesh = ma});
  const BodyId b = e.add_body({.name = "b", .mesh = mb});
  e.set_pose(a, Pose::Identity());
  Vec3 chained = Vec3::Zero(), first = Vec3::Zero();
  int beyond = 0, exact = 0;
  for (int k = 0; k <= 200; ++k) {
    Pose pb(Eigen::AngleAxisd(0.01 * k, Vec3(0.3, 0.2, 1).normalized()));
    pb.translation() = Vec3(-120 + 1.2 * k, 35, 8);
    e.set_pose(b, pb);
    const DistanceResult truth = brute_force_distance(ma, Pose::Identity(), mb, pb);
    for (const double upper : {5.0, 15.0, 40.0}) {
      const DistanceResult plain = e.distance(a, b, {.upper_mm = upper});
      for (const Vec3& g : {chained, first, Vec3(NAN, 0, 0), Vec3(1e300, 1e300, 0), Vec3(1e-300, 0, 0), Vec3(0, 0, -1)}) {
        const DistanceResult warm = e.distance(a, b, {.upper_mm = upper, .guess = g});
        REQUIRE(warm.status == plain.status);
        if (plain.status == DistanceStatus::exact) {
          CHECK(warm.distance == plain.distance);
          CHECK(agrees(warm.distance, truth.distance));
        } else if (plain.status == DistanceStatus::beyond) {
          CHECK(warm.distance >= upper);
          CHECK(warm.distance <= truth.distance * (1 + 1e-9));
        }
      }
      const DistanceResult next = e.distance(a, b, {.upper_mm = upper, .guess = chained});
      if (upper == 15.0) chained = next.guess;
      if (k == 0 && upper == 15.0) first = next.guess;
      beyond += plain.status == DistanceStatus::beyond;
      exact += plain.status == DistanceStatus::exact;
    }
  }
  CHECK(beyond > 50);
  CHECK(exact > 50);
}

namespace {
// A fork: a base and two prongs, three boxes side by side (three shells, as the built-in links).
Polyhedron make_fork() {
  return merged(merged(box_between(Vec3(0, -30, 0), Vec3(10, 30, 10)), box_between(Vec3(10, -30, 0), Vec3(60, -20, 10))),
                box_between(Vec3(10, 20, 0), Vec3(60, 30, 10)));
}
}  // namespace

TEST_CASE("distance exact_below: a body of separate pieces is bounded piece by piece", "[distance]") {
  // A bar between the fork's prongs, 4 mm from the base and 6 mm from each prong: it lies in the
  // hull of the whole fork, not in any piece's. Asked for the distance exactly only below 3 mm
  // (cut-off 20), the pieces' hulls answer "beyond" with a bound of at least 3 and at most the
  // distance, without the exact search; without exact_below the same query is exact.
  const Polyhedron fork = make_fork(), bar = box_between(Vec3(14, -14, 2), Vec3(70, 14, 8));
  Engine e;
  const BodyId a = e.add_body({.name = "fork", .mesh = fork});
  const BodyId b = e.add_body({.name = "bar", .mesh = bar});
  e.set_pose(a, Pose::Identity());
  e.set_pose(b, Pose::Identity());
  const DistanceResult exact = e.distance(a, b, {.upper_mm = 20});
  REQUIRE(exact.status == DistanceStatus::exact);
  CHECK(exact.distance == 4);
  CHECK(agrees(exact.distance, brute_force_distance(fork, Pose::Identity(), bar, Pose::Identity()).distance));
  const DistanceResult bound = e.distance(a, b, {.upper_mm = 20, .exact_below_mm = 3});
  CHECK(bound.status == DistanceStatus::beyond);
  CHECK(bound.distance >= 3);
  CHECK(bound.distance <= 4 * (1 + 1e-9));
  CHECK(bound.distance > 3.9);  // the pieces' hulls: nearly the distance
  CHECK(bound.face_pairs == 0);
  CHECK(bound.node_pairs == 0);
  // Below the bound the caller asked for, the exact answer again.
  const DistanceResult near = e.distance(a, b, {.upper_mm = 20, .exact_below_mm = 4.5});
  CHECK(near.status == DistanceStatus::exact);
  CHECK(near.distance == 4);
  // One piece holding the other body: contact (containment), whatever exact_below says.
  Engine inside;
  const BodyId f = inside.add_body({.name = "fork", .mesh = fork});
  const BodyId s = inside.add_body({.name = "speck", .mesh = box_between(Vec3(30, 22, 2), Vec3(32, 24, 4))});
  inside.set_pose(f, Pose::Identity());
  inside.set_pose(s, Pose::Identity());
  for (const double below : {0.0, 1.0, 1e9}) {
    const DistanceResult r = inside.distance(f, s, {.upper_mm = 20, .exact_below_mm = below});
    CHECK(r.status == DistanceStatus::contact);
    CHECK(r.kind == ContactKind::containment);
  }
}

TEST_CASE("distance exact_below on random poses: 'beyond' bounds the distance, below it the exact one", "[distance][cross_check]") {
  // Bodies of one and of several pieces: for cut-offs and exact_below thresholds around the true
  // distance, "beyond" is at least the smaller of the two and never above the distance; an exact
  // answer is the brute-force one; contact is contact whatever is asked.
  const std::vector<Polyhedron> meshes = {make_fork(), test::make_merged_part(), make_cylinder(10, 40, 16),
                                          merged(make_cylinder(8, 20, 16), box_between(Vec3(-5, -5, 12), Vec3(5, 5, 30))),
                                          test::make_l_prism(40, 10, 20), make_box(Vec3(4, 4, 4))};
  int bounded = 0, exact = 0, contacts = 0, bad = 0;
  for_random_pairs(meshes, 2026, 80, 20, 50,
                   [&](Engine& e, BodyId a, BodyId b, const Polyhedron&, const Pose&, const Polyhedron&, const Pose&,
                       const DistanceResult& r) {
                     Vec3 guess = Vec3::Zero();
                     for (const double fu : {1.2, 3.0})
                       for (const double fe : {0.3, 0.9, 0.999, 1.001, 1.5}) {
                         const double d0 = r.status == DistanceStatus::exact ? r.distance : 10.0;
                         const double upper = fu * d0, below = fe * d0;
                         const DistanceResult d = e.distance(a, b, {.upper_mm = upper, .guess = guess, .exact_below_mm = below});
                         guess = d.guess;
                         if (r.status == DistanceStatus::contact) {
                           ++contacts;
                           if (d.status != DistanceStatus::contact) ++bad;
                         } else if (d.status == DistanceStatus::beyond) {
                           bounded += below < r.distance && r.distance < upper;
                           if (!(d.distance >= std::min(upper, below) && d.distance <= r.distance * (1 + 1e-9))) ++bad;
                         } else {
                           ++exact;
                           if (!(d.status == DistanceStatus::exact && agrees(d.distance, r.distance))) ++bad;
                         }
                       }
                   });
  WARN("exact_below: " << bounded << " bounded below the cut-off, " << exact << " exact, " << contacts << " contact");
  CHECK(bounded > 100);
  CHECK(exact > 100);
  CHECK(contacts > 50);
  REQUIRE(bad == 0);
}
