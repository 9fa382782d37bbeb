// Built-in Adept Viper s650 (docs/robots.md): FK against ViSP's closed form and against the
// adept_experimental URDF geometry, closed-form IK round trips over the whole joint space for
// all 8 configurations, configuration requests, singularities, limits, link bodies.
#include "asimov/collision/engine.hpp"
#include "asimov/robots/configuration.hpp"
#include "asimov/robots/ik.hpp"
#include "asimov/robots/ik_viper.hpp"
#include "asimov/robots/urdf_loader.hpp"
#include "asimov/robots/puma560.hpp"
#include "asimov/robots/viper_s650.hpp"

#include "support/joints.hpp"
#include "support/link_bodies.hpp"
#include "support/result.hpp"

#include <catch2/catch.hpp>
#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <cstdlib>
#include <numbers>
#include <random>

using namespace asimov::robots;
using asimov::test::must;
using asimov::collision::Vec3;
using asimov::test::jv;
using asimov::test::random_joints;

namespace {
constexpr double kDeg = std::numbers::pi / 180;

// ViSP vpViper::get_fMe (joint values as the controller reports them, radians), written out.
Pose visp_fk(const JointVector& display) {
  using namespace viper;
  const JointVector q = display * kDeg;
  const double c1 = std::cos(q[0]), s1 = std::sin(q[0]), c2 = std::cos(q[1]), s2 = std::sin(q[1]);
  const double c4 = std::cos(q[3]), s4 = std::sin(q[3]), c5 = std::cos(q[4]), s5 = std::sin(q[4]);
  const double c6 = std::cos(q[5]), s6 = std::sin(q[5]), c23 = std::cos(q[1] + q[2]), s23 = std::sin(q[1] + q[2]);
  Pose m = Pose::Identity();
  m.matrix() << c1 * (c23 * (c4 * c5 * c6 - s4 * s6) - s23 * s5 * c6) - s1 * (s4 * c5 * c6 + c4 * s6),
      -c1 * (c23 * (c4 * c5 * s6 + s4 * c6) - s23 * s5 * s6) + s1 * (s4 * c5 * s6 - c4 * c6),
      c1 * (c23 * c4 * s5 + s23 * c5) - s1 * s4 * s5,
      c1 * (c23 * (c4 * s5 * d6 - a3) + s23 * (c5 * d6 + d4) + a1 + a2 * c2) - s1 * s4 * s5 * d6,
      -s1 * (c23 * (-c4 * c5 * c6 + s4 * s6) + s23 * s5 * c6) + c1 * (s4 * c5 * c6 + c4 * s6),
      -s1 * (c23 * (c4 * c5 * s6 + s4 * c6) - s23 * s5 * s6) - c1 * (s4 * c5 * s6 - c4 * c6),
      s1 * (c23 * c4 * s5 + s23 * c5) + c1 * s4 * s5,
      s1 * (c23 * (c4 * s5 * d6 - a3) + s23 * (c5 * d6 + d4) + a1 + a2 * c2) + c1 * s4 * s5 * d6,
      s23 * (s4 * s6 - c4 * c5 * c6) - c23 * s5 * c6, s23 * (c4 * c5 * s6 + s4 * c6) + c23 * s5 * s6,
      -s23 * c4 * s5 + c23 * c5, s23 * (a3 - c4 * s5 * d6) + c23 * (c5 * d6 + d4) - a2 * s2 + d1, 0, 0, 0, 1;
  return m;
}

// The joint origins and axes of adept_experimental's viper_s650.urdf (meshes left out; its
// V+ driver sends V+ degrees as radians unchanged).
const char* const kViperUrdf = R"(<robot name="viper_s650">
  <link name="base_link"/><link name="link_1"/><link name="link_2"/><link name="link_3"/>
  <link name="link_4"/><link name="link_5"/><link name="link_6"/><link name="tool0"/>
  <joint name="joint_1" type="revolute"><origin xyz="0 0 0.203"/><parent link="base_link"/><child link="link_1"/>
    <axis xyz="0 0 1"/><limit lower="-2.9671" upper="2.9671" velocity="5.7247"/></joint>
  <joint name="joint_2" type="revolute"><origin xyz="0.075 0 0.132"/><parent link="link_1"/><child link="link_2"/>
    <axis xyz="0 1 0"/><limit lower="-3.3161" upper="0.7854" velocity="5.2360"/></joint>
  <joint name="joint_3" type="revolute"><origin xyz="0.270 0 0"/><parent link="link_2"/><child link="link_3"/>
    <axis xyz="0 1 0"/><limit lower="-0.5061" upper="4.4680" velocity="6.5450"/></joint>
  <joint name="joint_4" type="revolute"><origin xyz="-0.09 0 0.108"/><parent link="link_3"/><child link="link_4"/>
    <axis xyz="0 0 1"/><limit lower="-3.3161" upper="3.3161" velocity="6.5450"/></joint>
  <joint name="joint_5" type="revolute"><origin xyz="0 0 0.187"/><parent link="link_4"/><child link="link_5"/>
    <axis xyz="0 1 0"/><limit lower="-2.0944" upper="2.0944" velocity="6.54"/></joint>
  <joint name="joint_6" type="revolute"><origin xyz="0 0 0.080"/><parent link="link_5"/><child link="link_6"/>
    <axis xyz="0 0 1"/><limit lower="-6.2832" upper="6.2832" velocity="10.4720"/></joint>
  <joint name="joint_6-tool0" type="fixed"><origin xyz="0 0 0"/><parent link="link_6"/><child link="tool0"/></joint>
</robot>)";

double pose_distance(const Pose& a, const Pose& b) { return (a.translation() - b.translation()).norm(); }
double rotation_distance(const Pose& a, const Pose& b) { return (a.linear() - b.linear()).norm(); }

// Declared singular band of the round trips: |J5| < 0.01 deg (wrist); wrist centre within 0.01 mm
// of the J1 axis (shoulder) or of the vertical through the J2 axis (R = 0: the elbow words meet);
// elbow within 1e-6 of full stretch / fold (|K| / L > 1 - 1e-6).
bool in_singular_band(const Robot& r, const JointVector& d) {
  using namespace viper;
  if (std::abs(d[4]) < 0.01) return true;
  std::vector<Pose> f;
  link_frames(r, d, f);
  const Vec3 w = f[4].translation();
  const double h = std::hypot(w.x(), w.y());
  if (h < 0.01) return true;
  const double rho = w.x() * std::cos(d[0] * kDeg) + w.y() * std::sin(d[0] * kDeg);
  const double R = rho - a1, Z = w.z() - d1;
  if (std::abs(R) < 0.01) return true;
  const double l = std::hypot(a3, d4), k = (R * R + Z * Z - a2 * a2 - l * l) / (2 * a2);
  return std::abs(k) / l > 1 - 1e-6;
}

struct RoundTrip {
  double max_p = 0, max_r = 0, max_back = 0;
  int tested = 0, in_band = 0, recovered = 0, mislabelled = 0;
  std::array<int, 8> valid{}, exact{};  // per configuration index 4*lefty + 2*below + flip
};

RoundTrip round_trips(int n, std::uint32_t seed) {
  const Robot r = viper_s650();
  std::mt19937 rng(seed);
  RoundTrip rt;
  for (int k = 0; k < n; ++k) {
    const JointVector d = random_joints(r, rng);
    if (in_singular_band(r, d)) {
      ++rt.in_band;
      continue;
    }
    const JointVector q = display_to_dh(r, d);
    const Pose t = flange_pose_dh(r, q);
    IkCandidates c;
    REQUIRE(viper_ik_all(r, t, q[0], q[3], c) == IkStatus::ok);
    ++rt.tested;
    bool back = false;
    for (std::size_t b = 0; b < c.size(); ++b) {
      // With the shoulder offset a1 the arm reaches farther in front than behind: a branch may
      // be out of reach (the other side's distance from the J2 axis differs by 2 a1).
      if (!c[b].valid) continue;
      ++rt.valid[b];
      REQUIRE(c[b].dh.allFinite());
      const Pose f = flange_pose_dh(r, c[b].dh);
      const double ep = pose_distance(f, t), er = rotation_distance(f, t);
      rt.max_p = std::max(rt.max_p, ep);
      rt.max_r = std::max(rt.max_r, er);
      rt.exact[b] += ep <= 1e-9 && er <= 1e-12;
      const JointVector cd = dh_to_display(r, c[b].dh);
      bool same = true;
      for (int i = 0; i < 6; ++i) same = same && std::abs(wrap_deg(cd[i] - d[i])) < 1e-6;
      back = back || same;
      if (!(configuration_of(r, cd) == c[b].config)) ++rt.mislabelled;
    }
    rt.recovered += back;
    const IkResult res = solve_viper(r, t, d, configuration_of(r, d), false);
    REQUIRE(res.status == IkStatus::ok);
    rt.max_back = std::max(rt.max_back, (res.joints - d).cwiseAbs().maxCoeff());
  }
  return rt;
}

void check_round_trips(const RoundTrip& rt) {
  INFO("tested " << rt.tested << " in band " << rt.in_band << " valid " << rt.valid[0] << " " << rt.valid[2] << " "
                 << rt.valid[4] << " " << rt.valid[6] << " max position " << rt.max_p << " mm, rotation "
                 << rt.max_r << ", back " << rt.max_back << " deg");
  CHECK(rt.max_p <= 1e-9);
  CHECK(rt.max_r <= 1e-12);
  for (std::size_t b = 0; b < 8; ++b) {
    CHECK(rt.exact[b] == rt.valid[b]);
    CHECK(rt.valid[b] >= rt.tested / 3);  // every configuration reaches a good part of the space
  }
  CHECK(rt.recovered == rt.tested);
  CHECK(rt.mislabelled == 0);
  // Joints back: 3e-10 deg on 1.2e5 poses; 2e-8 deg at worst on 1.45e6 (next to the elbow band,
  // where J2 / J3 are ill-conditioned and the position is still exact).
  CHECK(rt.max_back < 1e-7);
}
}  // namespace

TEST_CASE("viper_s650 FK is ViSP's closed form and the URDF's chain", "[viper_s650]") {
  const Robot r = viper_s650();
  REQUIRE(is_viper_type(r));
  const Robot urdf = must(load_urdf_text(kViperUrdf, "viper_s650.urdf"));
  std::mt19937 rng(650);
  double ev = 0, eu = 0, rv = 0, ru = 0;
  for (int k = 0; k < 20000; ++k) {
    const JointVector d = random_joints(r, rng);
    const Pose f = flange_pose(r, d);
    ev = std::max(ev, pose_distance(f, visp_fk(d))), rv = std::max(rv, rotation_distance(f, visp_fk(d)));
    eu = std::max(eu, pose_distance(f, flange_pose(urdf, d))), ru = std::max(ru, rotation_distance(f, flange_pose(urdf, d)));
  }
  CHECK(ev < 1e-9);
  CHECK(rv < 1e-12);
  CHECK(eu < 1e-9);
  CHECK(ru < 1e-12);
  // The URDF's limits and speeds are the built-in ones (rounded to 1e-4 rad there).
  for (int i = 0; i < 6; ++i) {
    CHECK(std::abs(urdf.lower[i] - r.lower[i]) < 0.01);
    CHECK(std::abs(urdf.upper[i] - r.upper[i]) < 0.01);
    CHECK(std::abs(urdf.max_velocity[i] - r.max_velocity[i]) < 0.5);  // 6.54 rad/s = 374.7 deg/s
  }
  // All joints 0: upper arm horizontal, forearm up, flange frame = world axes.
  const Pose z = flange_pose(r, jv({0, 0, 0, 0, 0, 0}));
  CHECK((z.translation() - Vec3(75 + 270 - 90, 0, 335 + 295 + 80)).norm() < 1e-12);
  CHECK((z.linear() - asimov::collision::Mat3::Identity()).norm() < 1e-15);
  // READY (0, -90, 180, 0, 0, 0): upper arm vertical, forearm horizontal, approach forward.
  const Pose ready = flange_pose(r, ready_joints(r));
  CHECK((ready.translation() - Vec3(75 + 295 + 80, 0, 335 + 270 + 90)).norm() < 1e-9);
  CHECK((ready.linear().col(2) - Vec3::UnitX()).norm() < 1e-12);
}

TEST_CASE("viper_s650 IK round trips for all 8 configurations", "[viper_s650][ik]") {
  check_round_trips(round_trips(120000, 20261201));
}

// >= 10^6 poses per configuration (1.45e6 random poses; lefty reaches ~71 % of them), ~25 s
// in Release, run on demand:
// test_robots "[.viper_million]"
TEST_CASE("viper_s650 IK round trips, 10^6 poses", "[.viper_million]") {
  const RoundTrip rt = round_trips(1450000, 1);
  check_round_trips(rt);
  for (std::size_t b = 0; b < 8; ++b) CHECK(rt.valid[b] >= 1000000);
  WARN("viper 10^6: tested " << rt.tested << ", per configuration " << rt.valid[0] << " " << rt.valid[1] << " "
       << rt.valid[2] << " " << rt.valid[3] << " " << rt.valid[4] << " " << rt.valid[5] << " " << rt.valid[6]
       << " " << rt.valid[7] << ", max position " << rt.max_p << " mm, rotation " << rt.max_r);
}

TEST_CASE("viper_s650 configuration requests", "[viper_s650][ik]") {
  const Robot r = viper_s650();
  const JointVector start = jv({10, -60, 150, 20, 40, 30});
  const Pose t = flange_pose(r, start);
  int reached = 0;
  for (int k = 0; k < 8; ++k) {
    const Configuration want{(k & 4) == 0, (k & 2) == 0, (k & 1) == 0};
    const IkResult res = solve_ik(r, t, start, want, true);
    INFO("request " << k);
    if (res.status != IkStatus::ok) continue;
    ++reached;
    CHECK(configuration_of(r, res.joints) == want);
    CHECK(pose_distance(flange_pose(r, res.joints), t) < 1e-6);
  }
  CHECK(reached >= 4);
  // The pose's own configuration gives its own joints back.
  const IkResult own = solve_ik(r, t, start, configuration_of(r, start), true);
  REQUIRE(own.status == IkStatus::ok);
  CHECK((own.joints - start).cwiseAbs().maxCoeff() < 1e-9);
}

TEST_CASE("viper_s650 singular poses are finite and FK-exact", "[viper_s650][ik]") {
  const Robot r = viper_s650();
  // Wrist: J5 = 0, J4 kept from the current joints.
  const JointVector w = jv({15, -70, 160, 33, 0, 20});
  const IkResult rw = solve_ik(r, flange_pose(r, w), w, configuration_of(r, w), true);
  REQUIRE(rw.status == IkStatus::ok);
  CHECK(rw.joints[3] == 33);
  CHECK(pose_distance(flange_pose(r, rw.joints), flange_pose(r, w)) < 1e-9);
  // Shoulder: wrist centre on the J1 axis, J1 kept.
  Pose above = Pose::Identity();
  above.translation() = Vec3(0, 0, 650 + viper::d6);
  const JointVector cur = jv({25, -90, 180, 0, 0, 0});
  const IkResult rs = solve_ik(r, above, cur, Configuration{}, true);
  REQUIRE(rs.status == IkStatus::ok);
  CHECK(rs.joints[0] == Approx(25).margin(1e-9));
  CHECK(pose_distance(flange_pose(r, rs.joints), above) < 1e-9);
  // Elbow at full stretch: the arm straight up.
  const double phi = std::atan2(viper::a3, viper::d4) / kDeg;
  const JointVector s = jv({0, -90, 90 + phi, 0, 30, 0});
  const IkResult rst = solve_ik(r, flange_pose(r, s), s, configuration_of(r, s), true);
  REQUIRE(rst.status == IkStatus::ok);
  CHECK(pose_distance(flange_pose(r, rst.joints), flange_pose(r, s)) < 1e-9);
  // Out of reach past full stretch.
  Pose far = Pose::Identity();
  far.translation() = Vec3(900, 0, 335);
  CHECK(solve_ik(r, far, cur, Configuration{}, true).status == IkStatus::out_of_reach);
}

TEST_CASE("viper_s650 joint limits: on the limit accepted, past it named", "[viper_s650][ik]") {
  const Robot r = viper_s650();
  const JointVector base = jv({10, -80, 120, 10, 40, 10});
  for (int j : {0, 1, 2, 4}) {
    for (const double lim : {r.lower[j], r.upper[j]}) {
      JointVector on = base;
      on[j] = lim;
      INFO("J" << j + 1 << " = " << lim);
      const IkResult res = solve_ik(r, flange_pose(r, on), on, configuration_of(r, on), true);
      REQUIRE(res.status == IkStatus::ok);
      CHECK(res.joints[j] == Approx(lim).margin(1e-9));
      // 1 deg past the limit: the same pose is out of the range, the joint is named.
      JointVector past = on;
      past[j] = lim + (lim == r.lower[j] ? -1 : 1);
      const IkResult bad = solve_ik(r, flange_pose(r, past), on, configuration_of(r, past), true);
      if (bad.status == IkStatus::ok) continue;  // another configuration word set differs
      CHECK(bad.status == IkStatus::joint_limit);
      CHECK(bad.joint == j);
    }
  }
}

TEST_CASE("viper_s650 link bodies: adjacent joined, others apart", "[viper_s650][bodies]") {
  const Robot r = viper_s650();
  REQUIRE(r.bodies.size() == 7);
  asimov::test::check_adjacent_joined_others_apart(r, {ready_joints(r), jv({0, 0, 0, 0, 0, 0}), jv({0, -90, 180, 0, 90, 0}),
                                                       jv({30, -60, 150, 45, 60, -30}), jv({-40, -120, 200, -90, -100, 0})});
}

TEST_CASE("viper_pick's picks: the Viper reaches them tool down, no PUMA configuration does", "[viper_s650]") {
  // programs/cells/viper_pick.v2 in viper_cell.yaml / puma_floor_cell.yaml: parts at
  // (250, -100 + 100 k, 450), their approaches 60 mm above, the drop (200, 220, 500) and its
  // approach 50 mm above, tool (120 mm along flange Z) pointing down; the PUMA's base 672 mm up.
  // Tool down = TRANS(0, 0, 0, 0, 180, 0) = Ry(180).
  const Robot viper = viper_s650();
  const Robot puma = asimov::robots::puma560();
  Pose tool = Pose::Identity();
  tool.translation() = Vec3(0, 0, 120);
  Pose puma_base = Pose::Identity();
  puma_base.translation() = Vec3(0, 0, 672);
  const Vec3 places[] = {{250, -100, 450}, {250, 0, 450}, {250, 100, 450}, {250, -100, 510}, {250, 0, 510},
                         {250, 100, 510}, {200, 220, 500}, {200, 220, 550}};
  for (int k = 0; k < 8; ++k) {
    Pose part = Pose::Identity();
    part.linear() = Eigen::AngleAxisd(std::numbers::pi, Vec3::UnitY()).toRotationMatrix();
    part.translation() = places[k];
    const Pose flange = part * tool.inverse();
    const JointVector vstart = jv({0, -90, 180, 0, 90, 0});
    const IkResult v = solve_ik(viper, flange, vstart, configuration_of(viper, vstart), true);
    INFO("place " << k);
    CHECK(v.status == IkStatus::ok);
    const Pose pf = puma_base.inverse() * flange;
    for (int c = 0; c < 8; ++c) {
      const Configuration want{(c & 4) == 0, (c & 2) == 0, (c & 1) == 0};
      for (const bool single : {true, false}) {
        const IkResult p = solve_ik(puma, pf, ready_joints(puma), want, single);
        INFO("PUMA configuration " << c);
        CHECK(p.status != IkStatus::ok);
      }
    }
  }
}
