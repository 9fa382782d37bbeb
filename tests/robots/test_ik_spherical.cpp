// Closed form for J1 _|_ J2 || J3 arms with a spherical wrist (Paden-Kahan): detection, round
// trips on generic6 and on the PUMA written as URDF (against the DH closed form), singular wrist.
#include "asimov/robots/ik.hpp"
#include "asimov/robots/ik_spherical.hpp"
#include "asimov/robots/puma560.hpp"
#include "asimov/robots/urdf_loader.hpp"

#include "support/joints.hpp"
#include "support/result.hpp"

#include <catch2/catch.hpp>
#include <Eigen/Geometry>
#include <chrono>
#include <cmath>
#include <random>

using namespace asimov;
using asimov::test::must;
using namespace asimov::robots;

using asimov::test::random_joints;

namespace {
const std::string kData = std::string(ASIMOV_SOURCE_DIR) + "/robots/data/";

double wrapped_distance(const JointVector& a_rad, const JointVector& b_rad) {
  double m = 0;
  for (int i = 0; i < a_rad.size(); ++i) m = std::max(m, std::abs(std::remainder(a_rad[i] - b_rad[i], 2 * std::numbers::pi)));
  return m;
}
}  // namespace

TEST_CASE("spherical wrist: detection", "[ik][spherical]") {
  SphericalWristModel m;
  CHECK(spherical_wrist_model(must(load_urdf(kData + "generic6.urdf")), m));
  CHECK((m.wrist - Vec3(520, 0, 900)).norm() < 1e-9);
  CHECK(spherical_wrist_model(must(load_urdf(kData + "puma560.urdf")), m));
  CHECK_FALSE(spherical_wrist_model(puma560(), m));  // DH robots use solve_puma
  Robot bent = must(load_urdf(kData + "generic6.urdf"));
  bent.chain[5].origin.translation().y() += 5;  // J6 axis no longer through the wrist centre
  CHECK_FALSE(spherical_wrist_model(bent, m));
}

TEST_CASE("spherical wrist: all solutions FK-exact, the original among them", "[ik][spherical][random]") {
  for (const char* file : {"generic6.urdf", "puma560.urdf"}) {
    const Robot r = must(load_urdf(kData + file));
    SphericalWristModel m;
    REQUIRE(spherical_wrist_model(r, m));
    std::mt19937 rng(31);
    double max_p = 0, max_r = 0;
    int tested = 0, recovered = 0, eight = 0;
    for (int n = 0; n < 20000; ++n) {
      const JointVector d = random_joints(r, rng);
      if (std::abs(d[4]) < 0.01) continue;  // wrist band
      const JointVector q = display_to_dh(r, d);
      const Pose t = flange_pose(r, d);
      SphericalIkSolutions s;
      spherical_ik_all(m, t, q[3], s);
      ++tested;
      eight += s.count == 8;
      bool back = false;
      for (int k = 0; k < s.count; ++k) {
        const Pose f = flange_pose_dh(r, s.q[static_cast<std::size_t>(k)]);
        max_p = std::max(max_p, (f.translation() - t.translation()).norm());
        max_r = std::max(max_r, Eigen::AngleAxisd(f.linear() * t.linear().transpose()).angle());
        back |= wrapped_distance(s.q[static_cast<std::size_t>(k)], q) < 1e-7;
      }
      recovered += back;
    }
    WARN(file << ": " << tested << " poses, " << eight << " with 8 solutions, recovered " << recovered
              << ", max FK error " << max_p << " mm / " << max_r << " rad");
    CHECK(recovered == tested);
    CHECK(max_p < 1e-9);
    CHECK(max_r < 1e-12);
  }
}

TEST_CASE("spherical wrist: the PUMA as URDF gets the DH closed-form answers", "[ik][spherical]") {
  const Robot dh = puma560();
  const Robot u = must(load_urdf(kData + "puma560.urdf"));
  std::mt19937 rng(8);
  for (int n = 0; n < 2000; ++n) {
    const JointVector d = random_joints(dh, rng);
    if (std::abs(d[4]) < 0.01) continue;
    const Pose t = flange_pose(dh, d);
    JointVector near = d;  // a little off (two branches can be closer than this near a singularity)
    near[0] += 0.01, near[3] -= 0.01;
    const IkResult a = solve_ik(u, t, near, configuration_of(u, d), false);
    REQUIRE(a.status == IkStatus::ok);
    CHECK((a.joints - d).cwiseAbs().maxCoeff() < 1e-7);  // the nearest solution is the original
  }
}

TEST_CASE("spherical wrist: singular wrist keeps J4, reach and limits", "[ik][spherical][singular]") {
  const Robot r = must(load_urdf(kData + "generic6.urdf"));
  SphericalWristModel m;
  REQUIRE(spherical_wrist_model(r, m));
  JointVector cur = JointVector::Zero(6);
  cur[3] = 30;
  const Pose t = flange_pose(r, JointVector::Zero(6));  // zero pose: axes 4 and 6 aligned
  const IkResult res = solve_ik(r, t, cur, configuration_of(r, cur), true);
  REQUIRE(res.status == IkStatus::ok);
  CHECK(res.joints[3] == Approx(30).margin(1e-9));
  CHECK(std::abs(res.joints[4]) < 1e-9);
  CHECK(res.joints[5] == Approx(-30).margin(1e-7));
  Pose far = t;
  far.translation() = Vec3(3000, 0, 0);
  CHECK(solve_ik(r, far, cur, configuration_of(r, cur), true).status == IkStatus::out_of_reach);
  Robot narrow = r;
  narrow.lower[0] = -10, narrow.upper[0] = 10;
  JointVector side = JointVector::Zero(6);
  side[0] = 90, side[1] = 30;
  const IkResult lim = solve_ik(narrow, flange_pose(r, side), JointVector::Zero(6), configuration_of(r, side), true);
  CHECK(lim.status == IkStatus::joint_limit);
  CHECK(lim.joint == 0);
}

TEST_CASE("spherical wrist: configuration words agree with the PUMA's and select the branch", "[ik][spherical][configuration]") {
  const Robot dh = puma560();
  const Robot u = must(load_urdf(kData + "puma560.urdf"));
  std::mt19937 rng(77);
  int disagree = 0, tested = 0;
  for (int n = 0; n < 5000; ++n) {
    const JointVector d = random_joints(dh, rng);
    if (std::abs(d[4]) < 0.01) continue;
    ++tested;
    disagree += !(configuration_of(u, d) == configuration_of(dh, d));
  }
  CHECK(disagree == 0);
  CHECK(tested > 4900);
  // Every configuration of a pose of each arm: the solution carries the requested words.
  for (const char* file : {"generic6.urdf", "puma560.urdf"}) {
    const Robot r = must(load_urdf(kData + file));
    JointVector start(6);
    start << 20, 30, -40, 40, -50, 60;
    if (std::string(file) == "puma560.urdf") start << 20, -30, 100, 40, -50, 60;
    const Pose t = flange_pose(r, start);
    int reached = 0;
    for (int mask = 0; mask < 8; ++mask) {
      const Configuration want{(mask & 1) != 0, (mask & 2) != 0, (mask & 4) != 0};
      const IkResult res = solve_ik(r, t, start, want, false);
      INFO(file << " mask " << mask);
      if (res.status != IkStatus::ok) continue;
      ++reached;
      CHECK(configuration_of(r, res.joints) == want);
      double ep, er;
      pose_error(r, res.joints, t, ep, er);
      CHECK(ep < 1e-9);
      CHECK(er < 1e-12);
      if (want == configuration_of(r, start)) CHECK((res.joints - start).cwiseAbs().maxCoeff() < 1e-9);
    }
    WARN(file << ": " << reached << " of 8 configurations reachable within limits");
    CHECK(reached >= 2);
  }
}

TEST_CASE("spherical wrist: branch labels agree with configuration_of", "[ik][spherical][configuration]") {
  for (const char* file : {"generic6.urdf", "puma560.urdf"}) {
    const Robot r = must(load_urdf(kData + file));
    SphericalWristModel m;
    REQUIRE(spherical_wrist_model(r, m));
    std::mt19937 rng(3);
    int mislabelled = 0, labelled = 0;
    for (int n = 0; n < 3000; ++n) {
      const JointVector d = random_joints(r, rng);
      if (std::abs(d[4]) < 0.01) continue;
      SphericalIkSolutions s;
      spherical_ik_all(m, flange_pose(r, d), display_to_dh(r, d)[3], s);
      for (int k = 0; k < s.count; ++k) {
        const auto i = static_cast<std::size_t>(k);
        const Configuration c = configuration_of(r, dh_to_display(r, s.q[i]));
        mislabelled += c.righty != s.righty[i] || c.above != s.above[i];
        ++labelled;
      }
    }
    INFO(file);
    CHECK(mislabelled == 0);
    CHECK(labelled > 10000);
  }
}
