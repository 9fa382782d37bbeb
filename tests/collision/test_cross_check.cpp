// The whole-engine check (docs/collision-method.md §5): over random poses, Engine::check() must give the
// same answer as brute force over all face pairs with the same exact predicate, including
// poses within an ulp of touching. Zero disagreements are allowed.
#include "asimov/collision/engine.hpp"
#include "collision/src/face_distance.hpp"
#include "scenes.hpp"

#include <catch2/catch.hpp>

#include <cmath>

using namespace asimov::collision;

namespace {

struct Scene {
  std::vector<Polyhedron> meshes;
  std::vector<Pose> poses;
  Engine engine;

  explicit Scene(std::vector<std::pair<Polyhedron, int>> bodies) {
    for (auto& [mesh, halvings] : bodies) {
      meshes.push_back(mesh);
      std::string name = "body";  // (not "b" + to_string: GCC 12 warns falsely on that)
      name += std::to_string(meshes.size());
      engine.add_body({.name = name, .mesh = mesh, .halvings = halvings});
      poses.push_back(Pose::Identity());
    }
  }
  void set(std::size_t i, const Pose& p) {
    poses[i] = p;
    engine.set_pose(static_cast<BodyId>(i), p);
  }
  bool brute(std::size_t i, std::size_t j, double c) const {
    return brute_force_collides(meshes[i], poses[i], meshes[j], poses[j], c);
  }
};

struct Tally {
  int poses = 0, collisions = 0, disagreements = 0, contained = 0;
};

// Engine vs brute force over every pair in the engine's order: the same verdict and the same
// first colliding pair; a face contact must name intersecting faces and a point on both.
void compare(Scene& s, double c, Tally& t) {
  const QueryResult r = s.engine.check();
  bool any = false;
  std::size_t first_i = 0, first_j = 0;
  for (std::size_t i = 0; i < s.meshes.size() && !any; ++i)
    for (std::size_t j = i + 1; j < s.meshes.size() && !any; ++j)
      if (s.engine.pair_enabled(static_cast<BodyId>(i), static_cast<BodyId>(j)) && s.brute(i, j, c)) {
        any = true;
        first_i = i;
        first_j = j;
      }
  ++t.poses;
  t.collisions += any;
  t.contained += r.collided && r.contact.kind == ContactKind::containment;
  bool ok = r.collided == any;
  if (ok && any) {
    ok = r.contact.body_a == first_i && r.contact.body_b == first_j;
    if (ok && r.contact.kind == ContactKind::faces) {
      const Triangle& fa = s.meshes[first_i].triangles[r.contact.face_a];
      const Triangle& fb = s.meshes[first_j].triangles[r.contact.face_b];
      const Pose& pa = s.poses[first_i];
      const Pose& pb = s.poses[first_j];
      const auto& va = s.meshes[first_i].vertices;
      const auto& vb = s.meshes[first_j].vertices;
      const TriangleVerts ta{pa * va[fa[0]], pa * va[fa[1]], pa * va[fa[2]]};
      const TriangleVerts tb{pb * vb[fb[0]], pb * vb[fb[1]], pb * vb[fb[2]]};
      const Vec3& p = r.contact.point;
      ok = triangles_intersect(ta, tb) && (triangle_closest_point(p, ta) - p).norm() <= 0.01 &&
           (triangle_closest_point(p, tb) - p).norm() <= 0.01;
    }
  }
  if (!ok) {
    ++t.disagreements;
    UNSCOPED_INFO("disagreement at pose " << t.poses << ": engine " << r.collided << " brute " << any);
  }
}

// Slides body j along `dir` from a colliding offset to a free one and bisects (with brute
// force) down to adjacent doubles; both sides of the boundary are then compared.
void near_touching(Scene& s, std::size_t i, std::size_t j, const Pose& base, const Vec3& dir, double c, Tally& t) {
  auto placed = [&](double u) {
    Pose p = base;
    p.translation() += u * dir;
    return p;
  };
  double lo = 0, hi = 200;  // at lo the bodies overlap (centres together), at hi they are apart
  s.set(j, placed(lo));
  if (!s.brute(i, j, c)) return;
  s.set(j, placed(hi));
  if (s.brute(i, j, c)) return;
  while (true) {
    const double mid = 0.5 * (lo + hi);
    if (mid <= lo || mid >= hi) break;
    s.set(j, placed(mid));
    (s.brute(i, j, c) ? lo : hi) = mid;
  }
  for (const double u : {lo, hi}) {
    s.set(j, placed(u));
    compare(s, c, t);
  }
}

}  // namespace

TEST_CASE("four steps equal brute force on 20,000 random poses of three bodies", "[cross_check]") {
  Scene s({{test::make_merged_part(), 9}, {make_cylinder(10, 40, 16), 6}, {make_box(Vec3(30, 12, 8)), 4}});
  std::mt19937_64 rng(19980);
  Tally t;
  for (int n = 0; n < 20000; ++n) {
    for (std::size_t i = 0; i < 3; ++i) s.set(i, test::random_pose(rng, 35));
    compare(s, 0.0, t);
  }
  INFO("poses " << t.poses << ", colliding " << t.collisions << ", disagreements " << t.disagreements);
  CHECK(t.collisions > 4000);
  CHECK(t.collisions < 18000);
  REQUIRE(t.disagreements == 0);
  WARN("cross-check random: " << t.poses << " poses, " << t.collisions << " colliding (" << t.contained
                               << " by containment), " << t.disagreements << " disagreements");
}

TEST_CASE("four steps equal brute force within one ulp of touching", "[cross_check]") {
  Scene s({{test::make_merged_part(), 9}, {make_cylinder(10, 40, 16), 7}});
  std::mt19937_64 rng(2003);
  std::normal_distribution<double> n(0, 1);
  Tally t;
  for (int k = 0; k < 1500; ++k) {
    s.set(0, test::random_pose(rng, 10));
    const Vec3 dir = Vec3(n(rng), n(rng), n(rng)).normalized();
    Pose base = test::random_pose(rng, 0);
    base.translation() = s.poses[0].translation();
    near_touching(s, 0, 1, base, dir, 0.0, t);
  }
  INFO("poses " << t.poses << ", colliding " << t.collisions << ", disagreements " << t.disagreements);
  CHECK(t.poses > 2500);
  REQUIRE(t.disagreements == 0);
  WARN("cross-check near touching: " << t.poses << " poses, " << t.collisions << " colliding, " << t.disagreements << " disagreements");
}

TEST_CASE("four steps equal brute force on exact face-to-face contacts and one ulp off", "[cross_check]") {
  // Boxes stacked with rotations about z only: the z coordinates stay exact, so the faces are
  // exactly coplanar at contact, and one ulp up or down separates or overlaps them.
  Scene s({{make_box(Vec3(40, 30, 10)), 9}, {make_box(Vec3(20, 20, 6)), 9}, {make_cylinder(7, 6, 12), 5}});
  std::mt19937_64 rng(85);
  std::uniform_real_distribution<double> u(-25, 25), ang(-M_PI, M_PI);
  Tally t;
  for (int k = 0; k < 1500; ++k) {
    Pose p0 = Pose::Identity();
    p0.linear() = Eigen::AngleAxisd(ang(rng), Vec3::UnitZ()).toRotationMatrix();
    p0.translation() = Vec3(u(rng), u(rng), 0);
    s.set(0, p0);
    for (std::size_t j = 1; j < 3; ++j) {
      Pose p = Pose::Identity();
      p.linear() = Eigen::AngleAxisd(ang(rng), Vec3::UnitZ()).toRotationMatrix();
      p.translation() = Vec3(u(rng), u(rng), j == 1 ? 8.0 : -8.0);  // top face of 0 is z = 5
      s.set(j, p);
    }
    for (const int ulps : {0, 1, -1}) {
      Pose p1 = s.poses[1];
      if (ulps) p1.translation().z() = std::nextafter(8.0, ulps * 100.0);
      s.set(1, p1);
      compare(s, 0.0, t);
    }
  }
  INFO("poses " << t.poses << ", colliding " << t.collisions << ", disagreements " << t.disagreements);
  CHECK(t.collisions > 500);
  REQUIRE(t.disagreements == 0);
  WARN("cross-check face to face: " << t.poses << " poses, " << t.collisions << " colliding, " << t.disagreements << " disagreements");
}

TEST_CASE("four steps equal brute force when bodies nest (containment, cavities)", "[cross_check]") {
  // A box with a cavity (inner box turned inside out), a solid box and two small bodies that
  // often end up wholly inside one of them, in its wall, or in the cavity.
  Polyhedron cavity = make_box(Vec3(50, 50, 50));
  for (Triangle& tri : cavity.triangles) std::swap(tri[1], tri[2]);
  Scene s({{merged(make_box(Vec3(90, 90, 90)), cavity), 9},
           {make_box(Vec3(70, 40, 60)), 6},
           {make_cylinder(4, 9, 10), 4},
           {test::make_l_prism(8, 3, 5), 3}});
  s.engine.set_pair_enabled(0, 1, false);  // the two big ones always overlap
  std::mt19937_64 rng(492);
  Tally t;
  for (int n = 0; n < 5000; ++n) {
    for (std::size_t i = 0; i < 4; ++i) s.set(i, test::random_pose(rng, i < 2 ? 10 : 45));
    compare(s, 0.0, t);
  }
  INFO("poses " << t.poses << ", colliding " << t.collisions << ", containment " << t.contained);
  CHECK(t.contained > 400);
  REQUIRE(t.disagreements == 0);
  WARN("cross-check nesting: " << t.poses << " poses, " << t.collisions << " colliding (" << t.contained
                               << " by containment), " << t.disagreements << " disagreements");
}

TEST_CASE("four steps equal brute force with a clearance", "[cross_check]") {
  Scene s({{test::make_merged_part(), 8}, {make_cylinder(10, 40, 16), 6}, {make_box(Vec3(30, 12, 8)), 5}});
  s.engine.set_clearance(2.0);
  std::mt19937_64 rng(62);
  Tally t;
  for (int n = 0; n < 4000; ++n) {
    for (std::size_t i = 0; i < 3; ++i) s.set(i, test::random_pose(rng, 40));
    compare(s, 2.0, t);
  }
  INFO("poses " << t.poses << ", colliding " << t.collisions << ", disagreements " << t.disagreements);
  CHECK(t.collisions > 600);
  REQUIRE(t.disagreements == 0);
  WARN("cross-check clearance 2 mm: " << t.poses << " poses, " << t.collisions << " colliding, " << t.disagreements << " disagreements");
}

TEST_CASE("four steps equal brute force at other scales and far from the origin", "[cross_check]") {
  // The margins are relative: millimetre parts scaled to micrometres or to metres-as-mm, and
  // parts placed 1e5 mm from the origin, must still agree with brute force exactly.
  for (const auto& [scale, offset] : {std::pair{1e-3, 0.0}, std::pair{1e3, 0.0}, std::pair{1.0, 1e5}}) {
    Pose s = Pose::Identity();
    s.linear() *= scale;  // scaling the meshes once; poses below are rigid
    auto scaled = [&](const Polyhedron& m) { return transformed(m, s); };
    Scene sc({{scaled(test::make_merged_part()), 9}, {scaled(make_cylinder(10, 40, 16)), 6}, {scaled(make_box(Vec3(30, 12, 8))), 5}});
    const double c = 0.5 * scale;
    sc.engine.set_clearance(c);
    std::mt19937_64 rng(1000);
    Tally t;
    for (int n = 0; n < 2000; ++n) {
      for (std::size_t i = 0; i < 3; ++i) {
        Pose p = test::random_pose(rng, 35);
        p.translation() = scale * p.translation() + Vec3::Constant(offset);
        sc.set(i, p);
      }
      compare(sc, c, t);
    }
    INFO("scale " << scale << " offset " << offset << ": poses " << t.poses << ", colliding " << t.collisions);
    CHECK(t.collisions > 400);
    REQUIRE(t.disagreements == 0);
    WARN("cross-check scale " << scale << " offset " << offset << ": " << t.poses << " poses, " << t.collisions
                              << " colliding, " << t.disagreements << " disagreements");
  }
}

// The completion criterion (>= 100,000 pose and mesh cases; 200,000 here), zero disagreements. Each case
// draws a mesh pair (tori from 18 to 200 faces, L prisms, the two-shell part, boxes,
// cylinders), a scale (1, 1e-3, 1e3), an M (the cost model, 3 or 9), a clearance (mostly 0)
// and a pose, then compares Engine::check() with brute force on the same world vertices.
TEST_CASE("four steps equal brute force on 200000 pose and mesh cases", "[cross_check][slow]") {
  auto torus = [](double major, double minor, int nu, int nv) {
    Polyhedron p;
    for (int i = 0; i < nu; ++i)
      for (int j = 0; j < nv; ++j) {
        const double u = 2 * M_PI * i / nu, v = 2 * M_PI * j / nv;
        const double r = minor * (1 + 0.15 * std::sin(5 * u) * std::sin(3 * v));
        p.vertices.emplace_back((major + r * std::cos(v)) * std::cos(u), (major + r * std::cos(v)) * std::sin(u),
                                r * std::sin(v));
      }
    auto at = [&](int i, int j) { return static_cast<std::uint32_t>((i % nu) * nv + (j % nv)); };
    for (int i = 0; i < nu; ++i)
      for (int j = 0; j < nv; ++j) {
        p.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
        p.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
      }
    return p;
  };
  const std::vector<Polyhedron> meshes = {
      torus(20, 7, 3, 3),       torus(20, 7, 6, 4),  torus(25, 8, 10, 10), make_box(Vec3(30, 20, 10)),
      make_box(Vec3(60, 60, 60)), make_cylinder(6, 30, 8), make_cylinder(15, 10, 24),
      test::make_l_prism(40, 10, 20), test::make_merged_part(), make_box(Vec3(4, 4, 4))};
  const std::array<double, 3> scales{1.0, 1e-3, 1e3};
  std::mt19937_64 rng(100000);
  std::uniform_int_distribution<std::size_t> pick(0, meshes.size() - 1);
  std::uniform_int_distribution<int> pick3(0, 2);
  std::uniform_real_distribution<double> unit(0, 1);
  constexpr int kMeshCases = 2000, kPosesPerCase = 100;
  long cases = 0, hits = 0, contained = 0, disagreements = 0, distance_cases = 0, distance_disagreements = 0;
  for (int m = 0; m < kMeshCases; ++m) {
    const double s = scales[static_cast<std::size_t>(pick3(rng))];
    Pose scale = Pose::Identity();
    scale.linear() *= s;
    const Polyhedron ma = transformed(meshes[pick(rng)], scale), mb = transformed(meshes[pick(rng)], scale);
    const int mode = pick3(rng);
    const int h = mode == 0 ? kAutoHalvings : mode == 1 ? 3 : 9;
    const double c = unit(rng) < 0.2 ? s * 2 * unit(rng) : 0.0;
    Engine e;
    const BodyId a = e.add_body({.name = "a", .mesh = ma, .halvings = h});
    const BodyId b = e.add_body({.name = "b", .mesh = mb, .halvings = h});
    e.set_clearance(c);
    const Pose pa = test::random_pose(rng, 5 * s);
    e.set_pose(a, pa);
    for (int k = 0; k < kPosesPerCase; ++k) {
      const Pose pb = test::random_pose(rng, 45 * s);
      e.set_pose(b, pb);
      const QueryResult r = e.check();
      const bool brute = brute_force_collides(ma, pa, mb, pb, c);
      ++cases;
      hits += brute;
      contained += r.collided && r.contact.kind == ContactKind::containment;
      if (r.collided != brute) {
        ++disagreements;
        UNSCOPED_INFO("mesh case " << m << " pose " << k << " scale " << s << " M " << h << " c " << c);
      }
      if (k % 2 == 0) {  // distances on every other pose: 100,000 cases (docs/collision.md §11)
        const DistanceResult de = e.distance(a, b), db = brute_force_distance(ma, pa, mb, pb);
        ++distance_cases;
        const bool same = de.status == db.status &&
                          (de.status == DistanceStatus::contact
                               ? de.distance == 0
                               : std::fabs(de.distance - db.distance) <= 1e-9 * std::max(s, db.distance));
        // The distance query's zero is check()'s contact at clearance 0.
        const bool consistent = c > 0 || (de.status == DistanceStatus::contact) == brute;
        if (!same || !consistent) {
          ++distance_disagreements;
          UNSCOPED_INFO("distance: mesh case " << m << " pose " << k << " engine " << de.distance << " brute " << db.distance);
        }
      }
    }
  }
  WARN(distance_cases << " distance cases, " << distance_disagreements << " disagreements (1e-9 relative)");
  CHECK(distance_cases >= 100000);
  CHECK(distance_disagreements == 0);
  WARN(cases << " cases, " << hits << " colliding, " << contained << " by containment, " << disagreements
             << " disagreements");
  CHECK(cases >= 200000);
  CHECK(disagreements == 0);
  CHECK(hits > cases / 10);
  CHECK(contained > 0);
}
