// SINGLE / MULTIPLE on URDF arms: the last revolute joint in (-180, 180] (SINGLE) or the
// 2pi-equivalent nearest the current value (MULTIPLE), through the spherical-wrist closed form
// (generic6) and through the numeric solver (generic6 with its wrist made non-spherical).
#include "asimov/robots/configuration.hpp"
#include "asimov/robots/ik.hpp"
#include "asimov/robots/ik_spherical.hpp"
#include "asimov/robots/urdf_loader.hpp"

#include "support/joints.hpp"
#include "support/result.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <random>

using namespace asimov;
using asimov::test::must;
using namespace asimov::robots;

using asimov::test::jv;
using asimov::test::random_joints;

namespace {
const std::string kData = std::string(ASIMOV_SOURCE_DIR) + "/robots/data/";

// generic6 with joint 6's axis moved 5 mm off joint 5's: no spherical wrist, numeric IK.
Robot offset_wrist(const Robot& g) {
  Robot r = g;
  r.chain[5].origin.translation() += Vec3(0, 5, 0);
  return r;
}

// The solution of `target_joints`' pose from `current`, SINGLE or MULTIPLE.
IkResult solve_from(const Robot& r, const JointVector& target_joints, const JointVector& current, bool single) {
  return solve_ik(r, flange_pose(r, target_joints), current, configuration_of(r, target_joints), single);
}
}  // namespace

TEST_CASE("SINGLE and MULTIPLE govern the last revolute joint of a URDF arm", "[ik][urdf][single]") {
  const Robot g = must(load_urdf(kData + "generic6.urdf"));
  REQUIRE(g.upper[5] > 340);  // J6 spans +-350 deg: two equivalents in range
  CHECK(last_revolute_joint(g) == 5);
  SphericalWristModel m;
  REQUIRE(spherical_wrist_model(g, m));
  const Robot n = offset_wrist(g);
  REQUIRE_FALSE(spherical_wrist_model(n, m));
  for (const Robot* r : {&g, &n}) {
    INFO((r == &g ? "closed form" : "numeric"));
    // From J6 = 200 to a pose at J6 = 210: SINGLE -150, MULTIPLE 210.
    const JointVector cur = jv({10, 20, -30, 15, 40, 200});
    const JointVector to = jv({12, 25, -35, 20, 45, 210});
    const IkResult single = solve_from(*r, to, cur, true);
    REQUIRE(single.status == IkStatus::ok);
    CHECK(single.joints[5] == Approx(-150).margin(1e-6));
    CHECK((single.joints.head(5) - to.head(5)).cwiseAbs().maxCoeff() < 1e-6);
    const IkResult multiple = solve_from(*r, to, cur, false);
    REQUIRE(multiple.status == IkStatus::ok);
    CHECK(multiple.joints[5] == Approx(210).margin(1e-6));
    // From J6 = -300 to -310: SINGLE 50, MULTIPLE -310.
    const JointVector cur2 = jv({-20, 10, -20, -10, 30, -300});
    const JointVector to2 = jv({-22, 12, -25, -12, 35, -310});
    CHECK(solve_from(*r, to2, cur2, true).joints[5] == Approx(50).margin(1e-6));
    CHECK(solve_from(*r, to2, cur2, false).joints[5] == Approx(-310).margin(1e-6));
    // SINGLE whose (-180, 180] value is outside the joint's range: a joint limit on J6, while
    // MULTIPLE finds the in-range equivalent.
    Robot narrow = *r;
    narrow.lower[5] = 100, narrow.upper[5] = 350;
    const IkResult bad = solve_from(narrow, to, cur, true);
    CHECK(bad.status == IkStatus::joint_limit);
    CHECK(bad.joint == 5);
    CHECK(bad.value == Approx(-150).margin(1e-6));
    CHECK(solve_from(narrow, to, cur, false).joints[5] == Approx(210).margin(1e-6));
  }
}

TEST_CASE("SINGLE on URDF arms: random poses keep J6 within -180 to 180, the other joints as MULTIPLE", "[ik][urdf][single]") {
  const Robot g = must(load_urdf(kData + "generic6.urdf"));
  std::mt19937 rng(31);
  std::uniform_real_distribution<double> small(-3, 3);
  int wrapped = 0;
  for (int k = 0; k < 300; ++k) {
    const JointVector q = random_joints(g, rng);
    JointVector near = q;
    for (int i = 0; i < 6; ++i) near[i] = std::clamp(q[i] + small(rng), g.lower[i], g.upper[i]);
    const IkResult s = solve_from(g, near, q, true), mu = solve_from(g, near, q, false);
    REQUIRE(s.status == IkStatus::ok);
    REQUIRE(mu.status == IkStatus::ok);
    CHECK(s.joints[5] > -180);
    CHECK(s.joints[5] <= 180);
    CHECK(std::abs(wrap_deg(s.joints[5] - near[5])) < 1e-6);         // the same J6 modulo 360
    CHECK((s.joints.head(5) - mu.joints.head(5)).norm() < 1e-9);     // J1..J5 unaffected
    CHECK((mu.joints - near).cwiseAbs().maxCoeff() < 1e-6);          // MULTIPLE: the nearby solution
    wrapped += std::abs(near[5]) > 180;
  }
  CHECK(wrapped > 50);  // a good share of the poses really needed the wrap
}
