// Built-in Adept Cobra s600 SCARA (docs/robots.md): FK against the adept_experimental URDF
// geometry with its V+ joint conversion, V+ SCARA location conventions, closed-form IK round
// trips for both elbows, tilted targets, limits, the configuration words, link bodies.
#include "asimov/collision/engine.hpp"
#include "asimov/robots/cobra_s600.hpp"
#include "asimov/robots/configuration.hpp"
#include "asimov/robots/ik.hpp"
#include "asimov/robots/ik_scara.hpp"
#include "asimov/robots/urdf_loader.hpp"

#include "support/joints.hpp"
#include "support/link_bodies.hpp"
#include "support/result.hpp"

#include <catch2/catch.hpp>
#include <Eigen/Geometry>
#include <cmath>
#include <numbers>
#include <random>

using namespace asimov::robots;
using asimov::test::must;
using asimov::collision::Vec3;
using asimov::test::jv;
using asimov::test::random_joints;

namespace {
constexpr double kDeg = std::numbers::pi / 180;

// adept_experimental cobra_s600_macro.xacro, expanded, meshes and the mimic flyover-cable branch
// left out. Its V+ driver: V+ J3 [mm] = -1000 * quill_prismatic_joint [m], the others deg = rad.
const char* const kCobraUrdf = R"(<robot name="cobra_s600">
  <link name="base_link"/><link name="inner_link"/><link name="outer_link"/><link name="quill_prismatic_link"/>
  <link name="quill_rotation_link"/><link name="tool0"/>
  <joint name="inner_joint" type="revolute"><origin xyz="0 0 0.342"/><parent link="base_link"/><child link="inner_link"/>
    <axis xyz="0 0 1"/><limit lower="-1.8326" upper="1.8326" velocity="6.737"/></joint>
  <joint name="outer_joint" type="revolute"><origin xyz="0.325 0 0"/><parent link="inner_link"/><child link="outer_link"/>
    <axis xyz="0 0 1"/><limit lower="-2.618" upper="2.618" velocity="12.5664"/></joint>
  <joint name="quill_prismatic_joint" type="prismatic"><origin xyz="0.275 0 0.045"/><parent link="outer_link"/>
    <child link="quill_prismatic_link"/><axis xyz="0 0 1"/><limit lower="-0.210" upper="0" velocity="1.100"/></joint>
  <joint name="quill_rotation_joint" type="revolute"><origin xyz="0 0 0"/><parent link="quill_prismatic_link"/>
    <child link="quill_rotation_link"/><axis xyz="0 0 -1"/><limit lower="-6.2832" upper="6.2832" velocity="20.944"/></joint>
  <joint name="quill_rotation_link-tool0" type="fixed"><parent link="quill_rotation_link"/><child link="tool0"/>
    <origin xyz="0 0 0" rpy="3.1415926535898 0 0"/></joint>
</robot>)";

double pos_err(const Pose& a, const Pose& b) { return (a.translation() - b.translation()).norm(); }
double rot_err(const Pose& a, const Pose& b) { return (a.linear() - b.linear()).norm(); }

// Declared singular band: elbow within 1e-4 rad of full stretch or fold (the two elbows meet;
// J2 is recovered there only to ~1e-8 deg, the position stays exact).
bool in_singular_band(const JointVector& d) {
  return std::abs(std::sin(d[1] * kDeg)) < 1e-4;
}

struct RoundTrip {
  double max_p = 0, max_r = 0, max_back = 0;
  int tested = 0, in_band = 0, wrong = 0, valid[2] = {0, 0};
};

RoundTrip round_trips(int n, std::uint32_t seed) {
  const Robot r = cobra_s600();
  ScaraModel m;
  REQUIRE(scara_model(r, m));
  std::mt19937 rng(seed);
  RoundTrip rt;
  for (int k = 0; k < n; ++k) {
    const JointVector d = random_joints(r, rng);
    if (in_singular_band(d)) {
      ++rt.in_band;
      continue;
    }
    ++rt.tested;
    const Pose t = flange_pose(r, d);
    const Configuration own = configuration_of(r, d);
    for (const bool righty : {true, false}) {
      Configuration want;
      want.righty = righty;
      const IkResult res = solve_scara(r, m, t, d, want, false);
      if (res.status == IkStatus::joint_limit) continue;  // the other elbow past J1 / J2 limits
      REQUIRE(res.status == IkStatus::ok);
      ++rt.valid[righty ? 0 : 1];
      const Pose f = flange_pose(r, res.joints);
      rt.max_p = std::max(rt.max_p, pos_err(f, t));
      rt.max_r = std::max(rt.max_r, rot_err(f, t));
      rt.wrong += configuration_of(r, res.joints).righty != righty;
      if (righty == own.righty) rt.max_back = std::max(rt.max_back, (res.joints - d).cwiseAbs().maxCoeff());
    }
  }
  return rt;
}

void check_round_trips(const RoundTrip& rt) {
  INFO("tested " << rt.tested << " in band " << rt.in_band << " righty " << rt.valid[0] << " lefty " << rt.valid[1]
                 << " max position " << rt.max_p << " mm, rotation " << rt.max_r << ", back " << rt.max_back);
  CHECK(rt.max_p <= 1e-9);
  CHECK(rt.max_r <= 1e-12);
  CHECK(rt.wrong == 0);
  CHECK(rt.max_back < 1e-9);
  CHECK(rt.valid[0] >= rt.tested / 2);
  CHECK(rt.valid[1] >= rt.tested / 2);
}
}  // namespace

TEST_CASE("cobra_s600 FK is the URDF's chain with V+ J3 = -1000 x its quill joint", "[cobra_s600]") {
  const Robot r = cobra_s600();
  const Robot urdf = must(load_urdf_text(kCobraUrdf, "cobra_s600.urdf"));
  std::mt19937 rng(600);
  double ep = 0, er = 0;
  for (int k = 0; k < 20000; ++k) {
    const JointVector d = random_joints(r, rng);
    JointVector u = d;
    u[2] = -d[2];  // URDF value in mm (the loader's display unit)
    ep = std::max(ep, pos_err(flange_pose(r, d), flange_pose(urdf, u)));
    er = std::max(er, rot_err(flange_pose(r, d), flange_pose(urdf, u)));
  }
  CHECK(ep < 1e-9);
  CHECK(er < 1e-12);
  for (int i : {0, 1, 3}) CHECK(std::abs(urdf.upper[i] - r.upper[i]) < 0.01);
  CHECK(urdf.lower[2] == Approx(-r.upper[2]));
  // All joints 0: arm stretched along +X, flange 387 mm up, its Z down (V+: pitch 180).
  const Pose z = flange_pose(r, jv({0, 0, 0, 0}));
  CHECK((z.translation() - Vec3(600, 0, 387)).norm() < 1e-12);
  CHECK((z.linear().col(2) + Vec3::UnitZ()).norm() < 1e-15);
  // J3 = 210 lowers the flange by 210 mm; J4 turns it about the downward axis.
  CHECK((flange_pose(r, jv({0, 0, 210, 0})).translation() - Vec3(600, 0, 177)).norm() < 1e-12);
  const Pose t4 = flange_pose(r, jv({0, 0, 0, 90}));
  CHECK((t4.linear().col(0) - Vec3(0, -1, 0)).norm() < 1e-12);  // x: +X turned clockwise seen from above
}

TEST_CASE("cobra_s600 IK round trips for both elbows", "[cobra_s600][ik]") {
  check_round_trips(round_trips(200000, 20261201));
}

// >= 10^6 poses per elbow, run on demand: test_robots "[.cobra_million]"
TEST_CASE("cobra_s600 IK round trips, 10^6 poses per elbow", "[.cobra_million]") {
  const RoundTrip rt = round_trips(1600000, 1);
  check_round_trips(rt);
  CHECK(rt.valid[0] >= 1000000);
  CHECK(rt.valid[1] >= 1000000);
  WARN("cobra 10^6: tested " << rt.tested << ", righty " << rt.valid[0] << ", lefty " << rt.valid[1]
                             << ", max position " << rt.max_p << " mm, rotation " << rt.max_r);
}

TEST_CASE("cobra_s600 configuration: RIGHTY iff J2 >= 0, the words that do not apply change nothing", "[cobra_s600]") {
  const Robot r = cobra_s600();
  CHECK(configuration_of(r, jv({0, 30, 0, 0})).righty);
  CHECK_FALSE(configuration_of(r, jv({0, -30, 0, 0})).righty);
  const JointVector start = jv({20, 60, 50, 10});
  const Pose t = flange_pose(r, start);
  for (const bool above : {true, false})
    for (const bool noflip : {true, false}) {
      const IkResult res = solve_ik(r, t, start, Configuration{true, above, noflip}, true);
      REQUIRE(res.status == IkStatus::ok);
      CHECK((res.joints - start).cwiseAbs().maxCoeff() < 1e-9);
    }
  const IkResult lefty = solve_ik(r, t, start, Configuration{false, true, true}, true);
  REQUIRE(lefty.status == IkStatus::ok);
  CHECK(lefty.joints[1] == Approx(-60).margin(1e-9));
  CHECK(pos_err(flange_pose(r, lefty.joints), t) < 1e-9);
}

TEST_CASE("cobra_s600 IK: tilted targets, reach and limits", "[cobra_s600][ik]") {
  const Robot r = cobra_s600();
  const JointVector start = jv({20, 60, 50, 10});
  Pose t = flange_pose(r, start);
  Pose tilted = t;
  tilted.linear() = t.linear() * Eigen::AngleAxisd(1e-3, Vec3::UnitX()).toRotationMatrix();
  CHECK(solve_ik(r, tilted, start, Configuration{}, true).status == IkStatus::out_of_reach);
  Pose far = t;
  far.translation() = Vec3(700, 0, 300);
  CHECK(solve_ik(r, far, start, Configuration{}, true).status == IkStatus::out_of_reach);
  Pose near = t;
  near.translation() = Vec3(40, 0, 300);  // inside the inner circle |325 - 275|
  CHECK(solve_ik(r, near, start, Configuration{}, true).status == IkStatus::out_of_reach);
  // Quill: on its limits accepted, 1 mm past named.
  for (const double j3 : {0.0, 210.0}) {
    JointVector on = start;
    on[2] = j3;
    const IkResult ok = solve_ik(r, flange_pose(r, on), start, Configuration{}, true);
    REQUIRE(ok.status == IkStatus::ok);
    CHECK(ok.joints[2] == Approx(j3).margin(1e-9));
    JointVector past = on;
    past[2] = j3 == 0 ? -1 : 211;
    const IkResult bad = solve_ik(r, flange_pose(r, past), start, Configuration{}, true);
    CHECK(bad.status == IkStatus::joint_limit);
    CHECK(bad.joint == 2);
    CHECK(bad.value == Approx(past[2]).margin(1e-9));
  }
  // J2 past its limit in the requested elbow.
  JointVector j2 = start;
  j2[1] = 155;
  const IkResult bad2 = solve_ik(r, flange_pose(r, j2), start, Configuration{}, true);
  CHECK(bad2.status == IkStatus::joint_limit);
  CHECK(bad2.joint == 1);
}

TEST_CASE("cobra_s600 link bodies: adjacent joined, others apart", "[cobra_s600][bodies]") {
  const Robot r = cobra_s600();
  REQUIRE(r.bodies.size() == 5);
  asimov::test::check_adjacent_joined_others_apart(
      r, {ready_joints(r), jv({0, 90, 0, 0}), jv({50, -120, 210, 200}), jv({-105, 150, 100, -300})});
}
