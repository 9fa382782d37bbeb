// PUMA 560 model: DH FK oracles (docs/kinematics.md §4), the display convention (§2), limits (§3),
// configuration words (§6) and the displacement bound.
#include "asimov/robots/configuration.hpp"
#include "asimov/robots/displacement_bound.hpp"
#include "asimov/robots/puma560.hpp"

#include "support/joints.hpp"

#include <catch2/catch.hpp>
#include <array>
#include <cmath>
#include <numbers>
#include <random>

using namespace asimov;
using namespace asimov::robots;

using asimov::test::jv;

namespace {
constexpr double kDeg = std::numbers::pi / 180;

Pose fk_dh_deg(const Robot& r, std::initializer_list<double> deg) {
  JointVector q = jv(deg) * kDeg;
  return flange_pose_dh(r, q);
}

void check_pose(const Pose& t, const collision::Mat3& rot, const Vec3& p, double ptol = 1e-4, double rtol = 1e-5) {
  INFO("got p = " << t.translation().transpose() << "\nR =\n" << t.linear());
  CHECK((t.translation() - p).norm() < ptol);
  CHECK((t.linear() - rot).norm() < rtol);
}

// ZYZ O/A/T [deg] of a rotation, general case (dialect §4); the motion layer owns the full rule.
std::array<double, 3> oat_of(const Pose& t) {
  const auto& m = t.linear();
  const double s = std::hypot(m(0, 2), m(1, 2));
  if (s < 1e-10) return {0, m(2, 2) > 0 ? 0.0 : 180.0, std::atan2(m(1, 0), m(2, 2) > 0 ? m(0, 0) : -m(0, 0)) / kDeg};
  return {std::atan2(m(1, 2), m(0, 2)) / kDeg, std::atan2(s, m(2, 2)) / kDeg, std::atan2(m(2, 1), -m(2, 0)) / kDeg};
}

collision::Mat3 mat(double a, double b, double c, double d, double e, double f, double g, double h, double i) {
  collision::Mat3 m;
  m << a, b, c, d, e, f, g, h, i;
  return m;
}
}  // namespace

TEST_CASE("PUMA 560 DH forward kinematics matches the computed table", "[puma560][fk]") {
  const Robot r = puma560();
  REQUIRE(r.joint_count() == 6);
  const collision::Mat3 I = collision::Mat3::Identity();
  const collision::Mat3 down = mat(0, 0, 1, 0, 1, 0, -1, 0, 0);
  check_pose(fk_dh_deg(r, {0, 0, 0, 0, 0, 0}), I, Vec3(452.1, -150.05, 431.8));
  check_pose(fk_dh_deg(r, {0, 90, -90, 0, 0, 0}), I, Vec3(20.3, -150.05, 863.6));
  check_pose(fk_dh_deg(r, {0, 0, -90, 0, 0, 0}), down, Vec3(863.6, -150.05, -20.3));
  check_pose(fk_dh_deg(r, {0, 45, 180, 0, 45, 0}), down, Vec3(596.3031, -150.05, -14.3543));
  check_pose(fk_dh_deg(r, {0, 45, -180, 57.2958, 45, 0}),
             mat(0.22985, 0.59501, 0.77015, 0.59501, 0.54030, -0.59501, -0.77015, 0.59501, -0.22985),
             Vec3(596.3031, -150.05, -14.3543));
  // Python toolbox numerical-IK example (rounded q, ~0.3 mm).
  const Pose t = fk_dh_deg(r, {37.981, -69.328, 14.484, -53.577, -49.887, 131.150});
  CHECK((t.translation() - Vec3(500, 200, -171.83)).norm() < 0.5);
  CHECK((t.linear() - mat(0, 0, 1, 1, 0, 0, 0, 1, 0)).norm() < 2e-3);
}

TEST_CASE("display convention: READY, safe pose, J1 and J2 facts", "[puma560][display]") {
  const Robot r = puma560();
  // READY: arm straight up, tool frame parallel to the world.
  const Pose ready = flange_pose(r, jv({0, -90, 90, 0, 0, 0}));
  check_pose(ready, collision::Mat3::Identity(), Vec3(20.3, -150.05, 863.6), 1e-9, 1e-12);
  const auto oat = oat_of(ready);
  CHECK(std::abs(oat[0]) < 1e-9);
  CHECK(std::abs(oat[1]) < 1e-9);
  CHECK(std::abs(oat[2]) < 1e-9);
  // Safe pose: upper arm vertical, forearm horizontal forward.
  std::vector<Pose> f;
  link_frames(r, jv({0, -90, 180, 0, 0, 0}), f);
  const Vec3 elbow = f[2].translation(), wrist = f[4].translation();
  CHECK(std::abs(elbow.x()) < 1e-9);
  CHECK(elbow.z() == Approx(431.8));
  CHECK(wrist.x() - elbow.x() == Approx(431.8 - 0.0).margin(1e-9));  // forward along +X
  CHECK(std::abs(wrist.z() - elbow.z() + 20.3) < 1e-9);            // horizontal, a3 below the elbow
  check_pose(f[6], mat(0, 0, 1, 0, 1, 0, -1, 0, 0), Vec3(431.8, -150.05, 431.8 - 20.3), 1e-9, 1e-12);
  // J1 = 0 reaches toward +X with d3 toward -Y; positive J1 is counter-clockwise from above.
  const Vec3 p0 = flange_pose(r, jv({0, -90, 180, 0, 0, 0})).translation();
  const Vec3 p1 = flange_pose(r, jv({30, -90, 180, 0, 0, 0})).translation();
  CHECK(p0.y() < 0);
  CHECK(std::atan2(p1.y(), p1.x()) > std::atan2(p0.y(), p0.x()));
  // J2 increasing from READY tilts the upper arm forward (+X).
  link_frames(r, jv({0, -80, 90, 0, 0, 0}), f);
  CHECK(f[2].translation().x() > 50);
}

TEST_CASE("display convention reproduces the RX90 O/A/T readouts", "[puma560][display]") {
  const Robot r = puma560();
  struct Row {
    JointVector j;
    double o, a, t;
  };
  const Row rows[] = {{jv({0, -74.809, 90, 0, 0, 0}), 0, 15.191, 0},
                      {jv({21.496, -74.809, 125.67, 43.388, 45.408, 0}), 50.81, 87.608, 32.223},
                      {jv({21.496, -74.809, 125.67, 43.388, 45.408, 197.55}), 50.81, 87.608, -130.227}};
  for (const auto& row : rows) {
    const auto oat = oat_of(flange_pose(r, row.j));
    INFO("joints " << row.j.transpose() << " -> " << oat[0] << " " << oat[1] << " " << oat[2]);
    CHECK(std::abs(wrap_deg(oat[0] - row.o)) < 0.005);
    CHECK(std::abs(wrap_deg(oat[1] - row.a)) < 0.005);
    CHECK(std::abs(wrap_deg(oat[2] - row.t)) < 0.005);
  }
}

TEST_CASE("mapping: signs, zero offsets, one conversion", "[puma560][display]") {
  const Robot r = puma560();
  const double signs[6] = {1, -1, -1, 1, -1, 1};
  for (int i = 0; i < 6; ++i) {
    CHECK(r.mapping[static_cast<std::size_t>(i)].sign == signs[i]);
    CHECK(r.mapping[static_cast<std::size_t>(i)].offset == 0);
  }
  const JointVector d = jv({10, -20, 30, -40, 50, -60});
  CHECK((dh_to_display(r, display_to_dh(r, d)) - d).norm() < 1e-12);
  // READY display = qr in DH.
  CHECK((display_to_dh(r, jv({0, -90, 90, 0, 0, 0})) - jv({0, 90, -90, 0, 0, 0}) * kDeg).norm() < 1e-15);
}

TEST_CASE("limits set A in DH and display angles", "[puma560][limits]") {
  const Robot r = puma560();
  const JointVector lo = jv({-160, -225, -45, -110, -100, -266});
  const JointVector hi = jv({160, 45, 225, 170, 100, 266});
  CHECK((r.lower - lo).norm() == 0);
  CHECK((r.upper - hi).norm() == 0);
  // The same limits in DH: [-160,160], [-45,225], [-225,45], [-110,170], [-100,100], [-266,266].
  const JointVector dl = display_to_dh(r, r.lower) / kDeg, du = display_to_dh(r, r.upper) / kDeg;
  const double dh_lo[6] = {-160, -45, -225, -110, -100, -266}, dh_hi[6] = {160, 225, 45, 170, 100, 266};
  for (int i = 0; i < 6; ++i) {
    CHECK(std::min(dl[i], du[i]) == Approx(dh_lo[i]));
    CHECK(std::max(dl[i], du[i]) == Approx(dh_hi[i]));
  }
  CHECK(first_limit_violation(r, jv({0, -90, 90, 0, 0, 0})) == -1);   // READY
  CHECK(first_limit_violation(r, jv({0, -90, 180, 0, 0, 0})) == -1);  // safe pose
  CHECK(first_limit_violation(r, jv({0, -90, 226, 0, 0, 0})) == 2);
  CHECK(first_limit_violation(r, jv({161, 0, 0, 0, 0, 0})) == 0);
  CHECK(first_limit_violation(r, jv({0, 0, 0, 0, 0, -267})) == 5);
  CHECK(r.max_velocity[0] == 90);
  CHECK(r.max_velocity[5] == 180);
  CHECK(r.max_acceleration[2] == 360);
  CHECK(r.max_acceleration[3] == 720);
}

TEST_CASE("configuration words of the named poses", "[puma560][configuration]") {
  const Robot r = puma560();
  auto disp = [&](std::initializer_list<double> dh_deg) { return dh_to_display(r, jv(dh_deg) * kDeg); };
  const Configuration qz = configuration_of(r, disp({0, 0, 0, 0, 0, 0}));
  CHECK(qz.righty);
  CHECK_FALSE(qz.above);
  for (auto q : {disp({0, 90, -90, 0, 0, 0}), disp({0, 0, -90, 0, 0, 0}), disp({0, 45, 180, 0, 45, 0}),
                 jv({0, -90, 180, 0, 0, 0})}) {
    const Configuration c = configuration_of(r, q);
    INFO(q.transpose());
    CHECK(c.righty);
    CHECK(c.above);
  }
  CHECK(configuration_of(r, jv({0, -90, 90, 0, 10, 0})).noflip);
  CHECK_FALSE(configuration_of(r, jv({0, -90, 90, 0, -10, 0})).noflip);
  ConfigurationRequest req;
  req.above = 0;
  const Configuration c = requested_configuration(Configuration{}, req);
  CHECK(c.righty);
  CHECK_FALSE(c.above);
  CHECK(c.noflip);
}

TEST_CASE("link bodies: named link0..link6, column reaches the floor", "[puma560][bodies]") {
  const Robot r = puma560();
  REQUIRE(r.bodies.size() == 7);
  for (int k = 0; k < 7; ++k) {
    CHECK(r.bodies[static_cast<std::size_t>(k)].link == k);
    CHECK(r.bodies[static_cast<std::size_t>(k)].name == "link" + std::to_string(k));
    CHECK_FALSE(r.bodies[static_cast<std::size_t>(k)].mesh.triangles.empty());
  }
  double zmin = 0;
  for (const auto& v : r.bodies[0].mesh.vertices) zmin = std::min(zmin, v.z());
  CHECK(zmin == Approx(-670));
}

TEST_CASE("displacement bound holds for random joint steps", "[puma560][bound]") {
  const Robot r = puma560();
  std::vector<BodyReach> reach;
  for (const auto& b : r.bodies) reach.push_back(body_reach(r, b.mesh, b.link));
  std::mt19937 rng(12345);
  std::uniform_real_distribution<double> u(0, 1), step(-3, 3);
  std::vector<Pose> fa, fb;
  double worst_ratio = 0;
  for (int n = 0; n < 300; ++n) {
    JointVector a(6), d(6);
    for (int i = 0; i < 6; ++i) a[i] = r.lower[i] + u(rng) * (r.upper[i] - r.lower[i]), d[i] = step(rng);
    link_frames(r, a, fa);
    link_frames(r, a + d, fb);
    for (std::size_t k = 0; k < r.bodies.size(); ++k) {
      const auto& b = r.bodies[k];
      double moved = 0;
      for (const auto& v : b.mesh.vertices)
        moved = std::max(moved, (fa[static_cast<std::size_t>(b.link)] * v - fb[static_cast<std::size_t>(b.link)] * v).norm());
      const double bound = max_displacement(reach[k], d);
      CHECK(moved <= bound + 1e-9);
      if (bound > 0) worst_ratio = std::max(worst_ratio, moved / bound);
    }
  }
  WARN("worst measured/bound ratio " << worst_ratio);
}
