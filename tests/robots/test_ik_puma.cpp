// Closed-form PUMA IK (docs/kinematics.md §4-§6): the 8 listed solutions, random round trips,
// configuration selection, singular cases, reach and limit errors.
#include "asimov/robots/cobra_s600.hpp"
#include "asimov/robots/configuration.hpp"
#include "asimov/robots/ik.hpp"
#include "asimov/robots/ik_puma.hpp"
#include "asimov/robots/puma560.hpp"
#include "asimov/robots/viper_s650.hpp"

#include "support/joints.hpp"

#include <catch2/catch.hpp>
#include <Eigen/Geometry>
#include <array>
#include <chrono>
#include <cmath>
#include <numbers>
#include <random>

using namespace asimov::robots;

using asimov::test::jv;

namespace {
constexpr double kDeg = std::numbers::pi / 180;

double angle_diff_deg(double a, double b) { return std::abs(wrap_deg(a - b)); }

bool same_dh(const JointVector& q_rad, const JointVector& deg, double tol) {
  for (int i = 0; i < 6; ++i)
    if (angle_diff_deg(q_rad[i] / kDeg, deg[i]) > tol) return false;
  return true;
}
}  // namespace

TEST_CASE("the 8 IK solutions of the test pose", "[ik]") {
  const Robot r = puma560();
  const Pose t = flange_pose_dh(r, jv({20, 30, -100, 40, 50, 60}) * kDeg);
  CHECK((t.translation() - asimov::collision::Vec3(790.5313, 128.0500, 344.5085)).norm() < 1e-4);
  IkCandidates c;
  REQUIRE(puma_ik_all(r, t, 0.0, c) == IkStatus::ok);
  struct Row {
    bool righty, above;
    JointVector q;
  };
  const Row rows[] = {{true, true, jv({20.0000, 30.0000, -100.0000, 40.0000, 50.0000, 60.0000})},
                      {true, false, jv({20.0000, 17.3013, -74.6167, 48.7810, 40.8910, 47.5484})},
                      {false, true, jv({178.4017, 150.0000, -74.6167, -152.9531, 42.8714, 87.8869})},
                      {false, false, jv({178.4017, 162.6987, -100.0000, -144.2807, 31.9995, 77.0260})}};
  for (const auto& row : rows) {
    const JointVector other = jv({row.q[0], row.q[1], row.q[2], row.q[3] + 180, -row.q[4], row.q[5] + 180});
    int found_main = 0, found_other = 0;
    for (const auto& cand : c) {
      REQUIRE(cand.valid);
      const auto [ep, er] = fk_error(r, cand.dh, t);
      CHECK(ep < 5e-12 * 1000);  // < 5e-9 mm; the table quotes < 5e-13 mm
      CHECK(er < 1e-12);
      if (cand.config.righty != row.righty || cand.config.above != row.above) continue;
      found_main += same_dh(cand.dh, row.q, 1e-4);
      found_other += same_dh(cand.dh, other, 1e-4);
    }
    INFO("branch righty=" << row.righty << " above=" << row.above);
    CHECK(found_main == 1);
    CHECK(found_other == 1);
  }
}

// Declared singular band of the round trip: |J5| < 0.01 deg (wrist), wrist centre within 0.01 mm
// of the shoulder cylinder r = d3, elbow within 1e-6 of full stretch / fold (|cos psi| > 1 - 1e-6).
bool in_singular_band(const Robot& r, const JointVector& display) {
  if (std::abs(display[4]) < 0.01) return true;
  std::vector<Pose> f;
  link_frames(r, display, f);
  const asimov::collision::Vec3 p = f[4].translation();
  const double a2 = r.dh[1].a, d3 = r.dh[2].d, a3 = r.dh[2].a, d4 = r.dh[3].d;
  const double rr = std::hypot(p.x(), p.y());
  if (rr - d3 < 0.01) return true;
  const double rho2 = rr * rr - d3 * d3 + p.z() * p.z();
  const double c = (a2 * a2 - d4 * d4 - a3 * a3 + rho2) / (2 * a2 * std::sqrt(rho2));
  return std::abs(c) > 1 - 1e-6;
}

TEST_CASE("FK(IK(T)) round trips over random poses", "[ik][random]") {
  const Robot r = puma560();
  std::mt19937 rng(20261128);
  std::uniform_real_distribution<double> u(0, 1);
  double max_p = 0, max_r = 0, max_r_angle = 0, max_back = 0;
  int tested = 0, recovered = 0, mislabelled = 0, in_band = 0;
  std::array<int, 8> per_branch{};
  const int n = 110000;  // >= 100,000 poses outside the band, all 8 solutions each
  const auto t0 = std::chrono::steady_clock::now();
  for (int k = 0; k < n; ++k) {
    JointVector d(6);
    for (int i = 0; i < 6; ++i) d[i] = r.lower[i] + u(rng) * (r.upper[i] - r.lower[i]);
    if (in_singular_band(r, d)) {
      ++in_band;
      continue;
    }
    const JointVector q = display_to_dh(r, d);
    const Pose t = flange_pose_dh(r, q);
    IkCandidates c;
    REQUIRE(puma_ik_all(r, t, q[3], c) == IkStatus::ok);
    ++tested;
    bool back = false;
    for (std::size_t b = 0; b < c.size(); ++b) {
      const auto& cand = c[b];
      REQUIRE(cand.valid);
      REQUIRE(cand.dh.allFinite());
      const auto [ep, er] = fk_error(r, cand.dh, t);
      const Pose f = flange_pose_dh(r, cand.dh);
      max_r_angle = std::max(max_r_angle, Eigen::AngleAxisd(f.linear() * t.linear().transpose()).angle());
      max_p = std::max(max_p, ep);
      max_r = std::max(max_r, er);
      per_branch[b] += ep <= 1e-9 && er <= 1e-12;
      if (same_dh(cand.dh, q / kDeg, 1e-6)) back = true;
      if (!(configuration_of(r, dh_to_display(r, cand.dh)) == cand.config)) ++mislabelled;
    }
    recovered += back;
    // The selected solution in the pose's own configuration, near its own joints, is itself.
    const IkResult res = solve_puma(r, t, d, configuration_of(r, d), false);
    REQUIRE(res.status == IkStatus::ok);
    max_back = std::max(max_back, (res.joints - d).cwiseAbs().maxCoeff());
  }
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  WARN("IK round trips: " << tested << " poses x 8 (" << in_band << " in the declared band), max position error "
                          << max_p << " mm, max rotation error " << max_r << " (Frobenius), " << max_r_angle
                          << " rad (angle), max joint recovery error " << max_back << " deg, " << s << " s");
  CHECK(tested >= 100000);
  CHECK(recovered == tested);
  CHECK(mislabelled == 0);  // every branch label agrees with configuration_of (§6)
  for (int b : per_branch) CHECK(b == tested);  // all 8 configurations
  CHECK(max_p <= 1e-9);
  CHECK(max_r <= 1e-12);
  CHECK(max_r_angle <= 1e-12);
  CHECK(max_back < 1e-9);
}

TEST_CASE("IK at the shoulder, elbow and wrist singularities: finite, FK exact, branches merge", "[ik][singular]") {
  const Robot r = puma560();
  const double a2 = r.dh[1].a, d3 = r.dh[2].d, a3 = r.dh[2].a, d4 = r.dh[3].d;
  const double L = std::hypot(a3, d4);
  const auto check_all = [&](const Pose& t, double theta4) {
    IkCandidates c;
    REQUIRE(puma_ik_all(r, t, theta4, c) == IkStatus::ok);
    for (const auto& cand : c) {
      REQUIRE(cand.valid);
      REQUIRE(cand.dh.allFinite());
      const auto [ep, er] = fk_error(r, cand.dh, t);
      CHECK(ep < 1e-6);
      CHECK(er < 1e-9);
    }
    return c;
  };
  SECTION("shoulder: wrist centre on the cylinder r = d3, both shoulders give the same J1") {
    // Wrist centre at (0, d3, 300), tool down: theta1 = phi +- asin(1) meet.
    Pose t = Pose::Identity();
    t.translation() = asimov::collision::Vec3(0, d3, 300);
    const IkCandidates c = check_all(t, 0);
    CHECK(std::abs(wrap_deg((c[0].dh[0] - c[4].dh[0]) / kDeg)) < 1e-6);  // phi + alpha = phi + 180 - alpha
  }
  SECTION("elbow: full stretch, ABOVE and BELOW coincide") {
    const double rho = a2 + L;  // wrist centre at full reach in the J1 = 0 plane
    Pose t = Pose::Identity();
    t.translation() = asimov::collision::Vec3(rho * std::cos(0.3), d3, rho * std::sin(0.3));
    const IkCandidates c = check_all(t, 0);
    CHECK(std::abs(c[0].dh[1] - c[2].dh[1]) < 1e-6);  // theta2 of ABOVE and BELOW
    CHECK(std::abs(c[0].dh[2] - c[2].dh[2]) < 1e-6);
    // Just beyond: out of reach, no NaN anywhere.
    t.translation() *= 1.0001;
    IkCandidates out;
    CHECK(puma_ik_all(r, t, 0, out) == IkStatus::out_of_reach);
    for (const auto& cand : out) CHECK_FALSE(cand.valid);
  }
  SECTION("elbow: folded (rho = |a2 - L|) is reachable and finite") {
    const double rho = std::abs(a2 - L) + 1e-9;
    Pose t = Pose::Identity();
    t.translation() = asimov::collision::Vec3(rho, d3, 0);
    check_all(t, 0);
  }
  SECTION("wrist: theta5 = 0 exactly, theta4 kept, both flips the same") {
    const JointVector q = jv({10, -80, 120, 15, 0, 40});
    const Pose t = flange_pose(r, q);
    const IkCandidates c = check_all(t, 0.5);
    const Configuration own = configuration_of(r, q);
    for (const auto& cand : c) {
      if (cand.config.righty != own.righty || cand.config.above != own.above) continue;  // other arms: regular wrist
      CHECK(cand.wrist_singular);
      CHECK(cand.dh[3] == 0.5);
      CHECK(cand.dh[4] == 0);
    }
  }
}

TEST_CASE("every joint at each of its limits: accepted on it, refused past it", "[ik][limits]") {
  const Robot r = puma560();
  const JointVector mid = jv({20, -60, 120, 30, 40, 50});
  for (int j = 0; j < 6; ++j) {
    for (int side = 0; side < 2; ++side) {
      const double limit = side == 0 ? r.lower[j] : r.upper[j];
      JointVector on = mid;
      on[j] = limit;
      INFO("J" << j + 1 << (side == 0 ? " lower " : " upper ") << limit);
      CHECK(first_limit_violation(r, on) == -1);
      // IK of the pose on the limit, from a nearby current pose, returns the limit itself.
      JointVector near = on;
      near[j] += side == 0 ? 2 : -2;
      const Configuration c = configuration_of(r, on);
      const IkResult res = solve_puma(r, flange_pose(r, on), near, c, false);
      if (std::abs(on[4]) > 1e-9) {  // J5 on a limit is never 0 here
        REQUIRE(res.status == IkStatus::ok);
        CHECK(std::abs(res.joints[j] - limit) < 1e-9);
      }
      // One degree past the limit.
      JointVector past = on;
      past[j] += side == 0 ? -1 : 1;
      CHECK(first_limit_violation(r, past) == j);
      const IkResult bad = solve_puma(r, flange_pose(r, past), near, configuration_of(r, past), false);
      if (j == 5) {
        // J6 spans 532 deg: an in-range equivalent always exists (past - 360 or + 360).
        REQUIRE(bad.status == IkStatus::ok);
        CHECK(std::abs(std::abs(bad.joints[5] - past[5]) - 360) < 1e-9);
      } else {
        CHECK(bad.status == IkStatus::joint_limit);
        CHECK(bad.joint == j);
      }
    }
  }
}

TEST_CASE("configuration selection", "[ik][configuration]") {
  const Robot r = puma560();
  const JointVector start = jv({20, -30, 100, 40, -50, 60});  // display
  const Pose t = flange_pose(r, start);
  const Configuration c0 = configuration_of(r, start);
  for (int mask = 0; mask < 8; ++mask) {
    Configuration want{(mask & 1) != 0, (mask & 2) != 0, (mask & 4) != 0};
    const IkResult res = solve_puma(r, t, start, want, true);
    INFO("mask " << mask);
    if (res.status != IkStatus::ok) {
      CHECK(res.status == IkStatus::joint_limit);
      continue;
    }
    CHECK(configuration_of(r, res.joints) == want);
    const auto [ep, er] = fk_error(r, display_to_dh(r, res.joints), t);
    CHECK(ep < 1e-9);
    CHECK(er < 1e-12);
    if (want == c0) CHECK((res.joints - start).norm() < 1e-9);
  }
}

TEST_CASE("wrist singularity keeps the current J4", "[ik][singular]") {
  const Robot r = puma560();
  const JointVector ready = jv({0, -90, 90, 0, 0, 0});
  const JointVector cur = jv({0, -90, 90, 37, 0, 10});
  const Pose t = flange_pose(r, jv({10, -80, 120, 15, 0, 40}));  // J4 + J6 = 55
  const IkResult res = solve_puma(r, t, cur, configuration_of(r, cur), true);
  REQUIRE(res.status == IkStatus::ok);
  CHECK(res.joints[3] == 37);
  CHECK(std::abs(res.joints[4]) < 1e-9);
  CHECK(res.joints[3] + res.joints[5] == Approx(55));
  // READY itself from READY.
  const IkResult rr = solve_puma(r, flange_pose(r, ready), ready, configuration_of(r, ready), true);
  REQUIRE(rr.status == IkStatus::ok);
  CHECK((rr.joints - ready).norm() < 1e-9);
}

TEST_CASE("reach errors: shoulder cylinder and beyond reach", "[ik][reach]") {
  const Robot r = puma560();
  const JointVector cur = jv({0, -90, 180, 0, 0, 0});
  const Configuration c = configuration_of(r, cur);
  Pose t = Pose::Identity();
  t.translation() = asimov::collision::Vec3(50, 50, 300);  // r = 70.7 < d3
  CHECK(solve_puma(r, t, cur, c, true).status == IkStatus::out_of_reach);
  t.translation() = asimov::collision::Vec3(1000, 0, 300);  // rho > a2 + L
  CHECK(solve_puma(r, t, cur, c, true).status == IkStatus::out_of_reach);
  t.translation() = asimov::collision::Vec3(0, 150.0, 0);  // exactly... inside (r < d3)
  CHECK(solve_puma(r, t, cur, c, true).status == IkStatus::out_of_reach);
}

TEST_CASE("joint limits and J6 SINGLE / MULTIPLE", "[ik][limits]") {
  const Robot r = puma560();
  // J1 beyond 160: RIGHTY target behind the robot.
  const JointVector cur = jv({150, -90, 180, 0, 30, 0});
  const Pose t = flange_pose(r, jv({175, -90, 180, 0, 30, 0}));
  JointVector past = jv({175, -90, 180, 0, 30, 0});
  REQUIRE(first_limit_violation(r, past) == 0);
  const IkResult res = solve_puma(r, t, cur, configuration_of(r, cur), true);
  CHECK(res.status == IkStatus::joint_limit);
  CHECK(res.joint == 0);
  // J6: SINGLE keeps (-180, 180]; MULTIPLE goes to the equivalent nearest the current value.
  const JointVector cur6 = jv({0, -90, 180, 0, 30, 200});
  const Pose t6 = flange_pose(r, jv({0, -90, 180, 0, 30, 210}));
  const IkResult single = solve_puma(r, t6, cur6, configuration_of(r, cur6), true);
  REQUIRE(single.status == IkStatus::ok);
  CHECK(single.joints[5] == Approx(-150));
  const IkResult multi = solve_puma(r, t6, cur6, configuration_of(r, cur6), false);
  REQUIRE(multi.status == IkStatus::ok);
  CHECK(multi.joints[5] == Approx(210));
  // J1 nearest equivalent: from J1 = 150 a target at -170 + 360 = 190 is out, the answer is the
  // in-range value, never a jump through the limit.
  const JointVector c1 = jv({-150, -90, 180, 0, 30, 0});
  const IkResult r1 = solve_puma(r, flange_pose(r, jv({-155, -90, 180, 0, 30, 0})), c1, configuration_of(r, c1), true);
  REQUIRE(r1.status == IkStatus::ok);
  CHECK(r1.joints[0] == Approx(-155));
}

TEST_CASE("reach margins: the PUMA family's shoulder and elbow distances, none for other families", "[ik][singular]") {
  // The straight-line sampler stops at these (docs/kinematics.md §7); they come from the arm's
  // IK family, so a PUMA has them and a Viper or SCARA does not (joint jumps only).
  const Robot r = puma560();
  const double a2 = r.dh[1].a, d3 = r.dh[2].d, a3 = r.dh[2].a, d4 = r.dh[3].d;
  const double L = std::hypot(a3, d4);
  // On the J1 axis: r = 0, the shoulder margin is -d3 (inside the singular cylinder).
  const auto on_axis = reach_margins(r, Vec3(0, 0, 300));
  REQUIRE(on_axis);
  CHECK(on_axis->shoulder_mm == Approx(-d3));
  // Stretched out along x at the height of the shoulder, d3 to the side: the elbow margin is 0.
  const double reach = a2 + L;
  const auto stretched = reach_margins(r, Vec3(reach, d3, 0));
  REQUIRE(stretched);
  CHECK(stretched->shoulder_mm == Approx(std::hypot(reach, d3) - d3));
  CHECK(stretched->elbow_mm == Approx(0).margin(1e-9));
  // 10 mm short of full reach: 10 mm of elbow margin.
  const auto short_of = reach_margins(r, Vec3(std::sqrt((reach - 10) * (reach - 10) + d3 * d3), 0, 0));
  REQUIRE(short_of);
  CHECK(short_of->elbow_mm == Approx(10).margin(1e-9));
  CHECK_FALSE(reach_margins(viper_s650(), Vec3(0, 0, 300)));
  CHECK_FALSE(reach_margins(cobra_s600(), Vec3(300, 0, 0)));
}
