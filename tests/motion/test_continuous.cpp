// ContinuousChecker (docs/collision.md §12) on synthetic motions with known contact times: a
// thin blade sweeping through a thinner plate between two checked poses far apart, a near
// miss, a graze-free pass, and the earliest of two pairs.
#include "motion/src/continuous.hpp"

#include "asimov/motion/recorders.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

using namespace asimov;
using namespace asimov::motion;
using collision::Pose;
using collision::Vec3;

namespace {

// One moving body translated along x by q[0] mm (the "joint"), at time t: q[0] = speed * t.
struct Slide {
  collision::Engine engine;
  collision::BodyId moving = 0;
  double speed = 1000;  // mm/s
  Vec3 offset = Vec3::Zero();

  ContinuousPath path() {
    ContinuousPath p;
    p.at = [this](double t, const robots::JointVector&) {
      robots::JointVector q(1);
      q[0] = speed * t;
      return q;
    };
    // A pure translation: every point moves exactly |dx|.
    p.motion = [](std::size_t, double, const robots::JointVector& a, double, const robots::JointVector& b) {
      return std::abs(b[0] - a[0]);
    };
    p.pose = [this](const robots::JointVector& q, double) { engine.set_pose(moving, pose_at(q[0])); };
    return p;
  }
  Pose pose_at(double x) const {
    Pose p = Pose::Identity();
    p.translation() = offset + Vec3(x, 0, 0);
    return p;
  }
  robots::JointVector q(double t) const {
    robots::JointVector v(1);
    v[0] = speed * t;
    return v;
  }
};

// A plate `plate_mm` thick (x) at x = 0 and a blade `blade_mm` thick starting at x = -start.
void build(Slide& s, double plate_mm, double blade_mm, double start_mm) {
  const collision::BodyId plate = s.engine.add_body({.name = "plate", .mesh = collision::make_box(Vec3(plate_mm, 200, 150)), .is_static = true});
  s.moving = s.engine.add_body({.name = "blade", .mesh = collision::make_box(Vec3(blade_mm, 60, 100))});
  s.engine.set_pose(plate, Pose::Identity());
  s.offset = Vec3(-start_mm, 0, 0);
}

}  // namespace

TEST_CASE("continuous: a 0.05 mm blade never passes a 0.01 mm plate unseen, whatever the step", "[continuous]") {
  for (const double step_mm : {0.02, 1.0, 20.0, 500.0}) {
    for (int phase = 0; phase < 12; ++phase) {
      Slide s;
      const double start = 100 + step_mm * phase / 12;  // the contact falls anywhere in a step
      build(s, 0.01, 0.05, start);
      ContinuousChecker checker(s.engine, 0, 1e-6, 10);
      const ContinuousPath path = s.path();
      // Checked poses every step_mm of travel; contact when the blade's face reaches the plate's.
      const double touch_x = start - 0.005 - 0.025;
      const double t_touch = touch_x / s.speed;
      bool found = false;
      for (int k = 0; !found && k * step_mm < start + 50; ++k) {
        const double ta = k * step_mm / s.speed, tb = (k + 1) * step_mm / s.speed;
        path.pose(s.q(tb), tb);
        const bool b_collides = s.engine.check().collided;
        const ContinuousContact c = checker.verify(ta, s.q(ta), tb, s.q(tb), path);
        if (b_collides) REQUIRE(c.found);  // a contact at the checked pose is never lost
        if (!c.found) continue;
        found = true;
        INFO("step " << step_mm << " phase " << phase << ": t_free " << c.t_free << " t_hit " << c.t_hit
                     << " analytic " << t_touch);
        CHECK_FALSE(c.graze);
        CHECK(c.t_hit - c.t_free <= 1e-6);
        CHECK(c.t_free <= t_touch + 1e-12);
        CHECK(c.t_hit >= t_touch - 1e-12);
        // The halting pose is free, the contact pose is not.
        path.pose(c.q_free, c.t_free);
        CHECK_FALSE(s.engine.check().collided);
        path.pose(c.q_hit, c.t_hit);
        CHECK(s.engine.check().collided);
      }
      CHECK(found);
    }
  }
}

TEST_CASE("continuous: a blade passing 0.001 mm beside the plate is proven free", "[continuous]") {
  Slide s;
  const collision::BodyId plate = s.engine.add_body({.name = "plate", .mesh = collision::make_box(Vec3(0.01, 200, 150)), .is_static = true});
  s.moving = s.engine.add_body({.name = "blade", .mesh = collision::make_box(Vec3(0.05, 60, 100))});
  s.engine.set_pose(plate, Pose::Identity());
  // The blade slides along x past the plate's edge: its near face 0.001 mm beyond y = 100.
  s.offset = Vec3(-100, 100 + 30 + 0.001, 0);
  ContinuousChecker checker(s.engine, 0, 1e-6, 10);
  collision::DistanceResult least;
  least.distance = std::numeric_limits<double>::infinity();
  checker.on_measure = [&least](const collision::BodyPair&, const collision::DistanceResult& r, double, bool, std::uint64_t) {
    if (r.status != collision::DistanceStatus::beyond && r.distance < least.distance) least = r;
  };
  const ContinuousPath path = s.path();
  for (int k = 0; k < 10; ++k) {
    const double ta = k * 0.02, tb = (k + 1) * 0.02;  // 20 mm steps
    path.pose(s.q(tb), tb);
    REQUIRE_FALSE(s.engine.check().collided);
    CHECK_FALSE(checker.verify(ta, s.q(ta), tb, s.q(tb), path).found);
  }
  // The measurements (what the clearance report records) met the closest approach, 0.001 mm,
  // with its witnesses.
  CHECK(least.distance == Approx(0.001).margin(1e-9));
  CHECK((least.point_a - least.point_b).norm() == Approx(0.001).margin(1e-9));
}

TEST_CASE("continuous: with a clearance the halt comes at distance c, not at touching", "[continuous]") {
  Slide s;
  build(s, 0.1, 0.5, 100);
  ContinuousChecker checker(s.engine, 2.0, 1e-6, 10);
  s.engine.set_default_clearance(2.0);
  const ContinuousPath path = s.path();
  const double t_touch = (100 - 0.05 - 0.25) / s.speed, t_clear = t_touch - 2.0 / s.speed;
  path.pose(s.q(0.2), 0.2);
  const ContinuousContact c = checker.verify(0, s.q(0), 0.2, s.q(0.2), path);
  REQUIRE(c.found);
  CHECK(c.t_free <= t_clear + 1e-12);
  CHECK(c.t_hit >= t_clear - 1e-12);
  CHECK(c.t_hit - c.t_free <= 1e-6);
}

TEST_CASE("clearance recorder: per pair the least distance up to the contact, earliest at ties", "[continuous][clearance]") {
  ClearanceRecorder rec;
  rec.within_mm = 10;
  const auto measure = [&rec](collision::BodyPair p, double d, double t) {
    collision::DistanceResult r;
    r.status = d == 0 ? collision::DistanceStatus::contact : collision::DistanceStatus::exact;
    r.distance = d;
    rec.on_distance(p, r, {.t = t, .probe = true, .step = 3});
  };
  const Trajectory tr;
  measure({0, 1}, 6, 0.5);
  measure({0, 2}, 12, 0.5);  // beyond within_mm: not reported
  rec.on_stretch(tr, {});
  measure({0, 1}, 4, 1.0);
  measure({0, 1}, 0, 1.2);
  measure({0, 1}, 0, 1.1);  // a probe nearer the contact instant, met later
  measure({1, 2}, 2, 1.9);  // measured at the stretch's end, after the contact: never reached
  CollisionReport contact;
  contact.time_s = 1.5;
  contact.id_a = 1, contact.id_b = 0;  // the contact's own pair, in either order
  rec.on_contact(contact, {}, 0);
  rec.on_walk_end();
  REQUIRE(rec.pairs.size() == 1);
  CHECK(rec.pairs[0].distance_mm == 0);
  CHECK(rec.pairs[0].time_s == 1.1);
  CHECK(rec.pairs[0].step == 3);
}

TEST_CASE("clearance recorder: a contact no distance query saw is its pair at 0 mm (clearance 0 only)", "[continuous][clearance]") {
  for (const double clearance : {0.0, 2.0}) {
    ClearanceRecorder rec;
    rec.clearance_mm = clearance;
    CollisionReport contact;
    contact.time_s = 2.25;
    contact.step = 4;
    contact.point = {1, 2, 3};
    contact.id_a = 7, contact.id_b = 5;
    rec.on_contact(contact, {}, 0);
    rec.on_walk_end();
    if (clearance > 0) {  // a contact within a clearance is no distance of 0
      CHECK(rec.pairs.empty());
      continue;
    }
    REQUIRE(rec.pairs.size() == 1);
    CHECK(rec.pairs[0].pair == collision::BodyPair{5, 7});
    CHECK(rec.pairs[0].distance_mm == 0);
    CHECK(rec.pairs[0].time_s == 2.25);
    CHECK(rec.pairs[0].step == 4);
    CHECK(rec.pairs[0].point_a == collision::Vec3(1, 2, 3));
    CHECK(rec.pairs[0].point_b == collision::Vec3(1, 2, 3));
  }
}

TEST_CASE("continuous: the far field costs no distance query, and the walker's bounds lose no contact", "[continuous]") {
  // The container gaps at both ends (what the walker's queries computed) and the window's motion
  // bound given up front: a far blade costs nothing, a thin one is still found at its instant.
  for (const double start : {100.0, 100.37, 119.9}) {
    Slide s;
    build(s, 0.01, 0.05, start);
    ContinuousChecker checker(s.engine, 0, 1e-6, 10);
    ContinuousPath path = s.path();
    path.jump = path.motion;
    const double t_touch = (start - 0.005 - 0.025) / s.speed;
    const auto gaps = [&s] { return s.engine.query({.contact = false, .gaps = true}).gaps; };
    path.pose(s.q(0), 0);
    std::vector<double> ga = gaps();
    bool found = false;
    std::uint64_t far_queries = 0;
    for (int k = 0; !found && k < 20; ++k) {
      const double ta = k * 0.02, tb = (k + 1) * 0.02;  // 20 mm steps
      path.pose(s.q(tb), tb);
      const std::vector<double> gb = gaps();
      const std::vector<double> mu{path.motion(0, ta, s.q(ta), tb, s.q(tb))};
      const std::uint64_t before = checker.distance_queries();
      const ContinuousContact c = checker.verify(ta, s.q(ta), tb, s.q(tb), path, {ga, gb, mu});
      // Both ends farther than the report threshold and than the window's motion allows: no query.
      if (ga[0] > 10 + 20 && gb[0] > 10 + 20) far_queries += checker.distance_queries() - before;
      ga = gb;
      if (!c.found) continue;
      found = true;
      CHECK_FALSE(c.graze);
      CHECK(c.t_free <= t_touch + 1e-12);
      CHECK(c.t_hit >= t_touch - 1e-12);
      CHECK(c.t_hit - c.t_free <= 1e-6);
    }
    CHECK(found);
    CHECK(far_queries == 0);
  }
}

TEST_CASE("continuous: an anchor keeps an arm going back and forth proven with one distance query", "[continuous]") {
  // The blade oscillates +-2.5 mm about 30 mm from the plate; without container gaps every
  // window would need a distance (the bound carried from a shrinks by each window's motion).
  // The anchor's bound depends on the net motion since it was measured, so one query proves all.
  Slide s;
  build(s, 1, 1, 31);
  const auto x_at = [](int k) { return k % 2 == 0 ? 0.0 : 5.0; };
  for (const bool with_jump : {true, false}) {
    ContinuousChecker checker(s.engine, 0, 1e-6, 10);
    ContinuousPath path = s.path();
    if (with_jump) path.jump = path.motion;
    for (int k = 0; k < 20; ++k) {
      const double ta = k * 0.005, tb = (k + 1) * 0.005;
      robots::JointVector qa(1), qb(1);
      qa[0] = x_at(k);
      qb[0] = x_at(k + 1);
      // The path between the two checked poses is the straight slide: probes land on it.
      path.at = [&](double t, const robots::JointVector&) {
        robots::JointVector q(1);
        q[0] = qa[0] + (qb[0] - qa[0]) * (t - ta) / (tb - ta);
        return q;
      };
      path.pose(qb, tb);
      CHECK_FALSE(checker.verify(ta, qa, tb, qb, path).found);
    }
    if (with_jump) CHECK(checker.distance_queries() == 1);
    else CHECK(checker.distance_queries() > 5);
  }
}

TEST_CASE("continuous: the lazy clearance report finds the same least distance with fewer exact ones", "[continuous][clearance]") {
  // A rod slides past a post (closest approach about 3 mm halfway), checked every 2 mm; then a
  // rod that ends in contact with the post. Eager: every checked pose nearer than the report
  // threshold and the least so far is measured exactly. Lazy: the poses are kept with their
  // bounds and flush() measures nearest bound first: the same least (value, time, witnesses),
  // fewer exact distances; none for the pair that ends in contact.
  struct Least {
    double d = std::numeric_limits<double>::infinity(), t = 0;
    Vec3 a = Vec3::Zero();
    int exact = 0;
  };
  const auto run = [](bool lazy, double post_y, double until_x, bool& contact) {
    Slide s;
    const collision::BodyId post =
        s.engine.add_body({.name = "post", .mesh = collision::make_cylinder(5, 80, 24), .is_static = true});
    s.moving = s.engine.add_body({.name = "rod", .mesh = collision::make_cylinder(10, 60, 24)});
    Pose at = Pose::Identity();
    at.translation() = Vec3(0, post_y, 0);
    s.engine.set_pose(post, at);
    s.offset = Vec3(-100, 0, 0);
    ContinuousChecker checker(s.engine, 0, 1e-6, 10);
    checker.set_lazy_report(lazy);
    Least least;
    checker.on_measure = [&least](const collision::BodyPair&, const collision::DistanceResult& r, double t, bool probe, std::uint64_t) {
      if (r.status == collision::DistanceStatus::beyond || probe) return;
      ++least.exact;
      if (r.distance < least.d) least.d = r.distance, least.t = t, least.a = r.point_a;
    };
    const ContinuousPath path = s.path();
    contact = false;
    for (int k = 0; !contact && 2 * k < until_x; ++k) {
      const double ta = k * 0.002, tb = (k + 1) * 0.002;
      path.pose(s.q(tb), tb);
      contact = checker.verify(ta, s.q(ta), tb, s.q(tb), path).found;
    }
    checker.flush(path);
    return least;
  };
  bool contact = false;
  const Least eager = run(false, 18, 200, contact);
  REQUIRE_FALSE(contact);
  const Least lazy = run(true, 18, 200, contact);
  REQUIRE_FALSE(contact);
  REQUIRE(eager.d < 4);
  CHECK(lazy.d == eager.d);
  CHECK(lazy.t == eager.t);
  CHECK(lazy.a == eager.a);
  CHECK(lazy.exact < eager.exact);
  // Into the post: the contact pair's kept poses are all dropped (its least is the contact).
  const Least eager_hit = run(false, 12, 200, contact);
  REQUIRE(contact);
  const Least lazy_hit = run(true, 12, 200, contact);
  REQUIRE(contact);
  CHECK(eager_hit.exact > 0);
  CHECK(lazy_hit.exact < eager_hit.exact);
  WARN("exact distances at checked poses: pass-by eager " << eager.exact << ", lazy " << lazy.exact
                                                           << "; into the post eager " << eager_hit.exact << ", lazy "
                                                           << lazy_hit.exact);
}
