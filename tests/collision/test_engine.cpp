// The engine: participation (step 1), per-step counts, contact reports, static bodies,
// clearance, containment and the allocation-free per-pose path.
#include "asimov/collision/engine.hpp"
#include "collision/src/voxel_grid.hpp"
#include "collision/src/face_distance.hpp"
#include "scenes.hpp"

#include <catch2/catch.hpp>

#include <cstdlib>
#include <new>

using namespace asimov::collision;

// Counts heap allocations while `counting` is set (replaces the global operator new of the
// test program; Eigen's fixed-size types never allocate).
namespace {
bool counting = false;
long allocations = 0;
}  // namespace
// Every form is replaced, the nothrow and array ones too: Catch2 allocates with
// new(std::nothrow), and a sanitizer runtime that kept its own nothrow new would see our
// free() release its memory (alloc-dealloc-mismatch).
namespace {
void* counted_alloc(std::size_t n) noexcept {
  if (counting) ++allocations;
  return std::malloc(n ? n : 1);
}
void* counted_alloc_aligned(std::size_t n, std::align_val_t a) noexcept {
  if (counting) ++allocations;
  const auto align = static_cast<std::size_t>(a);
  return std::aligned_alloc(align, (n + align - 1) / align * align + (n ? 0 : align));
}
}  // namespace
void* operator new(std::size_t n) {
  if (void* p = counted_alloc(n)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t n) {
  if (void* p = counted_alloc(n)) return p;
  throw std::bad_alloc();
}
void* operator new(std::size_t n, const std::nothrow_t&) noexcept { return counted_alloc(n); }
void* operator new[](std::size_t n, const std::nothrow_t&) noexcept { return counted_alloc(n); }
void* operator new(std::size_t n, std::align_val_t a) {
  if (void* p = counted_alloc_aligned(n, a)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t n, std::align_val_t a) {
  if (void* p = counted_alloc_aligned(n, a)) return p;
  throw std::bad_alloc();
}
void* operator new(std::size_t n, std::align_val_t a, const std::nothrow_t&) noexcept {
  return counted_alloc_aligned(n, a);
}
void* operator new[](std::size_t n, std::align_val_t a, const std::nothrow_t&) noexcept {
  return counted_alloc_aligned(n, a);
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t, const std::nothrow_t&) noexcept { std::free(p); }

namespace {

Pose at(double x, double y, double z) {
  Pose p = Pose::Identity();
  p.translation() = Vec3(x, y, z);
  return p;
}

TriangleVerts world_triangle(const Polyhedron& m, const Pose& pose, std::uint32_t f) {
  const Triangle& t = m.triangles[f];
  return {pose * m.vertices[t[0]], pose * m.vertices[t[1]], pose * m.vertices[t[2]]};
}

}  // namespace

TEST_CASE("step 1: default pairs, groups, static bodies, toggles", "[engine]") {
  Engine e;
  const BodyId a = e.add_body({.name = "a", .mesh = make_box(Vec3(1, 1, 1)), .group = 1});
  const BodyId b = e.add_body({.name = "b", .mesh = make_box(Vec3(1, 1, 1)), .group = 1});
  const BodyId c = e.add_body({.name = "c", .mesh = make_box(Vec3(1, 1, 1))});
  const BodyId s1 = e.add_body({.name = "table", .mesh = make_box(Vec3(1, 1, 1)), .is_static = true});
  const BodyId s2 = e.add_body({.name = "wall", .mesh = make_box(Vec3(1, 1, 1)), .is_static = true});
  CHECK(e.body_count() == 5);
  CHECK(e.body_name(s1) == "table");
  CHECK(e.body_closed(a));
  Polyhedron open = make_box(Vec3(1, 1, 1));
  open.triangles.pop_back();
  Engine o;
  CHECK_FALSE(o.body_closed(o.add_body({.name = "open", .mesh = open})));
  CHECK_FALSE(e.pair_enabled(a, b));  // one rigid group
  CHECK(e.pair_enabled(a, c));
  CHECK(e.pair_enabled(c, a));
  CHECK(e.pair_enabled(a, s1));
  CHECK_FALSE(e.pair_enabled(s1, s2));  // static-static
  e.set_pair_enabled(s1, s2, true);
  CHECK_FALSE(e.pair_enabled(s1, s2));  // never tested, whatever the user asks
  e.set_pair_enabled(a, b, true);
  CHECK_FALSE(e.pair_enabled(a, b));
  e.set_pair_enabled(c, a, false);
  CHECK_FALSE(e.pair_enabled(a, c));
  CHECK(e.has_enabled_pairs());
  // Everything overlaps at the origin; the disabled pairs are not reported.
  const QueryResult r = e.check();
  REQUIRE(r.collided);
  CHECK(r.contact.body_a == a);
  CHECK(r.contact.body_b == s1);
  CHECK(r.counts.pairs_enabled == 1);

  Engine lonely;
  lonely.add_body({.name = "only", .mesh = make_box(Vec3(1, 1, 1))});
  CHECK_FALSE(lonely.has_enabled_pairs());
  CHECK_FALSE(lonely.check().collided);
}

TEST_CASE("each step filters: far apart, boxes overlap but voxels do not, faces", "[engine]") {
  Engine e;
  const Polyhedron l = test::make_l_prism(40, 10, 20);
  const BodyId a = e.add_body({.name = "L", .mesh = l});
  const BodyId b = e.add_body({.name = "ball", .mesh = make_cylinder(4, 4, 16)});
  e.set_pose(a, at(0, 0, 0));

  e.set_pose(b, at(200, 0, 0));  // step 2 rejects
  QueryResult r = e.check();
  CHECK_FALSE(r.collided);
  CHECK(r.counts.pairs_enabled == 1);
  CHECK(r.counts.pairs_after_minimax == 0);

  e.set_pose(b, at(30, 30, 10));  // in the notch: containers overlap, voxels do not
  r = e.check();
  CHECK_FALSE(r.collided);
  CHECK(r.counts.pairs_after_minimax == 1);
  CHECK(r.counts.pairs_after_voxels == 0);

  // 0.01 mm from the inner wall x = 10, turned 45 deg about its axis (a vertex stays at
  // 180 deg): its voxels' boxes, mapped into L's frame, reach the wall's; face pairs tested.
  e.set_pose(b, at(14.01, 25, 10) * Eigen::AngleAxisd(M_PI / 4, Vec3::UnitZ()));
  r = e.check();
  CHECK_FALSE(r.collided);
  CHECK(r.counts.pairs_after_voxels == 1);
  CHECK(r.counts.face_pairs > 0);

  e.set_pose(b, at(13, 25, 10));  // x in [9, 17]: crosses the wall
  r = e.check();
  CHECK(r.collided);
  CHECK(r.contact.kind == ContactKind::faces);
  CHECK(r.contact.body_a == a);
  CHECK(r.contact.body_b == b);
  const TriangleVerts ta = world_triangle(l, at(0, 0, 0), r.contact.face_a);
  const TriangleVerts tb = world_triangle(make_cylinder(4, 4, 16), at(13, 25, 10), r.contact.face_b);
  CHECK(triangles_intersect(ta, tb));
  CHECK((triangle_closest_point(r.contact.point, ta) - r.contact.point).norm() <= 0.01);
  CHECK((triangle_closest_point(r.contact.point, tb) - r.contact.point).norm() <= 0.01);

  e.set_pose(b, at(14, 25, 10));  // exactly touching the wall x = 10 (radius 4, vertex at angle 180)
  r = e.check();
  CHECK(r.collided);
  e.set_pose(b, at(std::nextafter(14.0, 20.0), 25, 10));  // one ulp away
  CHECK_FALSE(e.check().collided);
}

TEST_CASE("the answer does not depend on which body is A", "[engine]") {
  std::mt19937_64 rng(11);
  const Polyhedron m = test::make_merged_part();
  const Polyhedron c = make_cylinder(8, 30, 12);
  for (int n = 0; n < 500; ++n) {
    const Pose pm = test::random_pose(rng, 30), pc = test::random_pose(rng, 30);
    Engine e1, e2;
    e1.add_body({.name = "m", .mesh = m});
    e1.add_body({.name = "c", .mesh = c});
    e2.add_body({.name = "c", .mesh = c});
    e2.add_body({.name = "m", .mesh = m});
    e1.set_pose(0, pm);
    e1.set_pose(1, pc);
    e2.set_pose(0, pc);
    e2.set_pose(1, pm);
    REQUIRE(e1.check().collided == e2.check().collided);
  }
}

TEST_CASE("clearance: contact when distance <= c, with the distance reported", "[engine]") {
  Engine e;
  const BodyId a = e.add_body({.name = "a", .mesh = make_box(Vec3(10, 10, 10))});
  const BodyId b = e.add_body({.name = "b", .mesh = make_box(Vec3(10, 10, 10))});
  e.set_pose(a, at(0, 0, 0));
  e.set_pose(b, at(12, 3, 1));  // a 2 mm gap
  CHECK_FALSE(e.check().collided);
  e.set_clearance(1.5);
  CHECK_FALSE(e.check().collided);
  e.set_clearance(2.5);
  const QueryResult r = e.check();
  REQUIRE(r.collided);
  CHECK(r.contact.kind == ContactKind::clearance);
  CHECK(r.contact.distance >= 2.0 - 1e-12);  // the first face pair within c, not the closest
  CHECK(r.contact.distance <= 2.5);
  CHECK(brute_force_collides(make_box(Vec3(10, 10, 10)), at(0, 0, 0), make_box(Vec3(10, 10, 10)), at(12, 3, 1), 2.5));
  CHECK_FALSE(brute_force_collides(make_box(Vec3(10, 10, 10)), at(0, 0, 0), make_box(Vec3(10, 10, 10)), at(12, 3, 1), 1.5));
  e.set_clearance(0);
  e.set_pose(b, at(10, 3, 1));
  CHECK(e.check().contact.kind == ContactKind::faces);  // touching: distance 0 counts
}

TEST_CASE("containment: a body inside another collides, a body in a cavity does not", "[engine]") {
  Engine e;
  const BodyId big = e.add_body({.name = "big", .mesh = make_box(Vec3(100, 100, 100))});
  const BodyId small = e.add_body({.name = "small", .mesh = make_cylinder(5, 10, 12)});
  e.set_pose(big, at(0, 0, 0));
  e.set_pose(small, at(10, -20, 5));
  QueryResult r = e.check();
  REQUIRE(r.collided);
  CHECK(r.contact.kind == ContactKind::containment);
  CHECK(r.counts.face_pairs == 0);
  CHECK(brute_force_collides(make_box(Vec3(100, 100, 100)), at(0, 0, 0), make_cylinder(5, 10, 12), at(10, -20, 5)));

  // A hollow shell (outer box with an inward-facing inner box) around the small body.
  Polyhedron inner = make_box(Vec3(60, 60, 60));
  for (Triangle& t : inner.triangles) std::swap(t[1], t[2]);
  Engine h;
  const BodyId shell = h.add_body({.name = "shell", .mesh = merged(make_box(Vec3(100, 100, 100)), inner)});
  const BodyId s2 = h.add_body({.name = "small", .mesh = make_cylinder(5, 10, 12)});
  h.set_pose(shell, at(0, 0, 0));
  h.set_pose(s2, at(10, -20, 5));
  CHECK_FALSE(h.check().collided);
  h.set_pose(s2, at(40, 40, 40));  // inside the wall of the shell
  CHECK(h.check().collided);
  CHECK(h.check().contact.kind == ContactKind::containment);
}

TEST_CASE("static bodies keep their world data and moving the other body works", "[engine]") {
  Engine e;
  const BodyId table = e.add_body({.name = "table", .mesh = make_box(Vec3(100, 100, 10)), .is_static = true});
  const BodyId tool = e.add_body({.name = "tool", .mesh = make_cylinder(5, 20, 12)});
  e.set_pose(table, at(0, 0, -5));
  int hits = 0;
  for (int i = 0; i < 50; ++i) {
    const double zc = 12.0 - 0.1 * i;  // lowered onto the table top (z = 0); bottom at zc - 10
    e.set_pose(tool, at(0, 0, zc));
    CHECK(e.check().collided == (zc <= 10.0));
    hits += zc <= 10.0;
  }
  CHECK(hits > 20);
}

TEST_CASE("identical checks give identical reports (deterministic order)", "[engine]") {
  std::mt19937_64 rng(21);
  Engine e;
  e.add_body({.name = "m", .mesh = test::make_merged_part()});
  e.add_body({.name = "c", .mesh = make_cylinder(8, 30, 12)});
  e.add_body({.name = "b", .mesh = make_box(Vec3(20, 5, 30))});
  for (int n = 0; n < 200; ++n) {
    for (BodyId id = 0; id < 3; ++id) e.set_pose(id, test::random_pose(rng, 25));
    const QueryResult r1 = e.check(), r2 = e.check();
    REQUIRE(r1.collided == r2.collided);
    REQUIRE(r1.contact.body_a == r2.contact.body_a);
    REQUIRE(r1.contact.body_b == r2.contact.body_b);
    REQUIRE(r1.contact.face_a == r2.contact.face_a);
    REQUIRE(r1.contact.face_b == r2.contact.face_b);
    REQUIRE(r1.counts.face_pairs == r2.counts.face_pairs);
  }
}

TEST_CASE("invalid meshes are refused at add_body", "[engine]") {
  Engine e;
  Polyhedron bad = make_box(Vec3(1, 1, 1));
  bad.triangles.push_back({0, 1, 99});
  CHECK_THROWS_AS(e.add_body({.name = "bad", .mesh = bad}), std::invalid_argument);
  Polyhedron nan = make_box(Vec3(1, 1, 1));
  nan.vertices[0].x() = std::nan("");
  CHECK_THROWS_AS(e.add_body({.name = "nan", .mesh = nan}), std::invalid_argument);
}

TEST_CASE("no heap allocation per pose after warm-up", "[engine]") {
  std::mt19937_64 rng(31);
  Engine e;
  e.add_body({.name = "m", .mesh = test::make_merged_part()});
  e.add_body({.name = "c", .mesh = make_cylinder(8, 30, 24)});
  e.add_body({.name = "t", .mesh = make_box(Vec3(200, 200, 4)), .is_static = true});
  e.set_pose(2, at(0, 0, -40));
  std::vector<std::pair<Pose, Pose>> poses;
  for (int n = 0; n < 300; ++n) poses.emplace_back(test::random_pose(rng, 30), test::random_pose(rng, 30));
  e.set_pose(0, at(0, 0, 0));
  e.set_pose(1, at(0, 0, 0));
  (void)e.check();
  Engine hollow;  // containment path too: a body inside a closed box
  hollow.add_body({.name = "big", .mesh = make_box(Vec3(100, 100, 100))});
  hollow.add_body({.name = "small", .mesh = make_cylinder(5, 10, 12)});
  auto run = [&] {
    int hits = 0;
    for (const auto& [p0, p1] : poses) {
      e.set_pose(0, p0);
      e.set_pose(1, p1);
      hits += e.check().collided;
      hollow.set_pose(1, p0);
      hits += hollow.check().collided;
    }
    return hits;
  };
  const int warm = run();  // fills the buffers to their largest size
  counting = true;
  allocations = 0;
  const int again = run();
  counting = false;
  CHECK(again == warm);
  CHECK(allocations == 0);
}

TEST_CASE("halvings: explicit M kept, kAutoHalvings resolved by the cost model", "[engine]") {
  Engine e;
  const Polyhedron small = make_cylinder(10, 20, 12);   // 48 faces
  const Polyhedron large = make_cylinder(100, 300, 500);  // 2,000 faces
  const BodyId nine = e.add_body({.name = "nine", .mesh = large, .halvings = 9});
  const BodyId a = e.add_body({.name = "auto small", .mesh = small, .halvings = kAutoHalvings});
  const BodyId b = e.add_body({.name = "auto large", .mesh = large, .halvings = kAutoHalvings});
  CHECK(e.body_halvings(nine) == 9);
  CHECK(e.body_halvings(a) == auto_halvings(small));
  CHECK(e.body_halvings(b) == auto_halvings(large));
  CHECK(e.body_halvings(a) >= 3);
  CHECK(e.body_halvings(b) <= 18);
  CHECK(e.body_halvings(a) < e.body_halvings(b));  // more faces, finer grid
  // About one face per voxel (2^round(log2 F) cells), but no cell much smaller than a face.
  CHECK(auto_halvings(large) == 11);
  CHECK(auto_halvings(make_box(Vec3(10, 10, 10))) == 3);
}

TEST_CASE("voxel grids are built lazily, only for bodies of an enabled pair that reach step 3", "[engine]") {
  Engine e;
  const BodyId a = e.add_body({.name = "a", .mesh = make_box(Vec3(10, 10, 10))});
  const BodyId b = e.add_body({.name = "b", .mesh = make_box(Vec3(10, 10, 10))});
  const BodyId far = e.add_body({.name = "far", .mesh = make_box(Vec3(10, 10, 10))});
  const BodyId off = e.add_body({.name = "off", .mesh = make_box(Vec3(10, 10, 10))});
  for (const BodyId x : {a, b, far}) e.set_pair_enabled(x, off, false);
  e.set_pose(a, at(0, 0, 0));
  e.set_pose(b, at(5, 5, 5));
  e.set_pose(far, at(500, 0, 0));
  e.set_pose(off, at(0, 0, 0));  // overlaps a and b, but all its pairs are disabled
  for (const BodyId x : {a, b, far, off}) CHECK_FALSE(e.body_preprocessed(x));
  const QueryResult r = e.check();
  CHECK(r.collided);
  CHECK(e.body_preprocessed(a));
  CHECK(e.body_preprocessed(b));
  CHECK_FALSE(e.body_preprocessed(far));  // step 2 rejected every pair it is in
  CHECK_FALSE(e.body_preprocessed(off));  // in no enabled pair
}

TEST_CASE("check_pairs tests only the given enabled pairs, in the order given", "[engine]") {
  Engine e;
  const BodyId a = e.add_body({.name = "a", .mesh = make_box(Vec3(10, 10, 10))});
  const BodyId b = e.add_body({.name = "b", .mesh = make_box(Vec3(10, 10, 10))});
  const BodyId c = e.add_body({.name = "c", .mesh = make_box(Vec3(10, 10, 10))});
  e.set_pose(a, at(0, 0, 0));
  e.set_pose(b, at(8, 0, 0));    // a-b overlap
  e.set_pose(c, at(100, 0, 0));  // c is free
  const BodyPair ac{a, c}, ca{c, a}, ab{a, b};
  CHECK_FALSE(e.check_pairs(std::span(&ac, 1)).collided);
  CHECK_FALSE(e.check_pairs(std::span(&ca, 1)).collided);  // either order
  QueryResult r = e.check_pairs(std::span(&ab, 1));
  CHECK(r.collided);
  CHECK(r.counts.pairs_enabled == 1);
  const std::array<BodyPair, 2> both{ac, BodyPair{b, a}};
  r = e.check_pairs(both);
  CHECK(r.collided);
  CHECK(r.counts.pairs_enabled == 2);
  CHECK((r.contact.body_a == a && r.contact.body_b == b));
  e.set_pair_enabled(a, b, false);
  CHECK_FALSE(e.check_pairs(std::span(&ab, 1)).collided);  // disabled pairs are skipped
  CHECK(e.check_pairs(std::span(&ab, 1)).counts.pairs_enabled == 0);
  CHECK(e.check_pairs({}).counts.pairs_enabled == 0);
}
