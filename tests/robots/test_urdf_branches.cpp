// Side branches of a URDF tree (docs/robots.md "Grippers and side branches"): the arm runs from
// the root to the tip (UrdfOptions::tip, else the one chain of independent joints), fixed
// branches are rigid, prismatic fingers and their <mimic> followers are hand joints moved by
// OPEN/CLOSE, any other movable branch is an error naming it.
#include "asimov/robots/displacement_bound.hpp"
#include "asimov/robots/urdf_loader.hpp"

#include "support/result.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <numbers>
#include <string>

using namespace asimov::robots;
using asimov::test::must;

namespace {
const char* kLink = R"(<link name="%s"><collision><origin xyz="%s"/><geometry><box size="%s"/></geometry></collision></link>
)";

std::string link(const std::string& name, const std::string& at, const std::string& size) {
  std::string s = kLink;
  for (const std::string& v : {name, at, size}) s.replace(s.find("%s"), 2, v);
  return s;
}

std::string joint(const std::string& name, const std::string& type, const std::string& parent, const std::string& child,
                  const std::string& xyz, const std::string& extra = "") {
  return "<joint name=\"" + name + "\" type=\"" + type + "\"><parent link=\"" + parent + "\"/><child link=\"" + child +
         "\"/><origin xyz=\"" + xyz + "\"/>" + extra + "</joint>\n";
}

const std::string kLimitRev = "<axis xyz=\"0 0 1\"/><limit lower=\"-3\" upper=\"3\" velocity=\"1\"/>";
const std::string kLimitFinger = "<axis xyz=\"0 1 0\"/><limit lower=\"0\" upper=\"0.04\" velocity=\"0.1\"/>";

// Two revolute joints, a flange tool0, a hand with a left finger (prismatic, +Y) and a right one
// that mimics it along -Y. `more` adds elements.
std::string gripper_arm(const std::string& more = "", const std::string& right_mimic = "finger_left_joint") {
  return "<robot name=\"g\">\n" + link("base", "0 0 0.05", "0.2 0.2 0.1") + link("link_1", "0 0 0.2", "0.06 0.06 0.4") +
         link("link_2", "0.2 0 0", "0.4 0.05 0.05") + "<link name=\"tool0\"/>\n" + link("hand", "0.02 0 0", "0.04 0.04 0.04") +
         link("finger_left", "0.05 0.015 0", "0.02 0.01 0.02") + link("finger_right", "0.05 -0.015 0", "0.02 0.01 0.02") +
         joint("j1", "revolute", "base", "link_1", "0 0 0.1", kLimitRev) +
         joint("j2", "revolute", "link_1", "link_2", "0 0 0.4", "<axis xyz=\"0 1 0\"/><limit lower=\"-2\" upper=\"2\" velocity=\"1\"/>") +
         joint("flange", "fixed", "link_2", "tool0", "0.4 0 0") + joint("hand_joint", "fixed", "tool0", "hand", "0 0 0") +
         joint("finger_left_joint", "prismatic", "hand", "finger_left", "0 0 0", kLimitFinger) +
         joint("finger_right_joint", "prismatic", "hand", "finger_right", "0 0 0",
               "<axis xyz=\"0 -1 0\"/><limit lower=\"0\" upper=\"0.04\" velocity=\"0.1\"/><mimic joint=\"" + right_mimic +
                   "\" multiplier=\"1\" offset=\"0\"/>") +
         more + "</robot>\n";
}

Robot load(const std::string& xml, const std::string& tip = "") {
  UrdfOptions o;
  o.tip = tip;
  return must(load_urdf_text(xml, "g.urdf", ".", o));
}

std::string error(const std::string& xml, const std::string& tip = "") {
  UrdfOptions o;
  o.tip = tip;
  auto r = load_urdf_text(xml, "g.urdf", ".", o);
  return r ? std::string("loaded") : r.error().message;
}

const LinkBody& body(const Robot& r, const std::string& name) {
  for (const auto& b : r.bodies)
    if (b.name == name) return b;
  FAIL("no body " << name);
  return r.bodies.front();
}

Vec3 centre(const LinkBody& b, const Pose& offset = Pose::Identity()) {
  Vec3 c = Vec3::Zero();
  for (const auto& v : b.mesh.vertices) c += offset * v;
  return c / static_cast<double>(b.mesh.vertices.size());
}
}  // namespace

TEST_CASE("branches: two independent fingers without a tip are ambiguous, the error lists the candidate leaves") {
  // A finger and its follower: the follower is no independent joint, so the finger would be J3
  // and its follower follows an arm joint: an error saying to give the tip.
  const std::string e = error(gripper_arm());
  CHECK(e.find("joint 'finger_right_joint' mimics 'finger_left_joint', the arm's last axis") != std::string::npos);
  CHECK(e.find("name the link the hand hangs on with tip:") != std::string::npos);
  const std::string two = gripper_arm(link("thumb", "0 0 0.01", "0.01 0.01 0.01") +
                                      joint("thumb_joint", "prismatic", "hand", "thumb", "0 0 0", kLimitFinger));
  const std::string e2 = error(two);
  CHECK(e2.find("the arm is ambiguous: at link 'hand' the movable joints 'finger_left_joint', 'thumb_joint' branch off") !=
        std::string::npos);
  CHECK(e2.find("Candidate leaves: finger_left, thumb") != std::string::npos);
  CHECK(e2.find("tip:") != std::string::npos);
  // With the tip both are fingers.
  CHECK(load(two, "tool0").hand.size() == 3);
}

TEST_CASE("branches: with the tip, prismatic fingers and mimic followers are hand joints, not arm joints") {
  const Robot r = load(gripper_arm(), "tool0");
  REQUIRE(r.joint_count() == 2);
  CHECK(r.flange_offset.translation().isApprox(Vec3(400, 0, 0)));
  REQUIRE(r.hand.size() == 2);
  const HandJoint& left = r.hand[0];
  const HandJoint& right = r.hand[1];
  CHECK(left.name == "finger_left_joint");
  CHECK(left.frame == 2);
  CHECK(left.leader == -1);
  CHECK(left.open == Approx(40));  // OPEN = upper limit [mm]
  CHECK(left.closed == Approx(0));
  CHECK(right.name == "finger_right_joint");
  CHECK(right.leader == 0);
  CHECK(right.open == Approx(40));
  // Bodies: the hand rigid in the flange frame, the fingers moved by their joints.
  CHECK(body(r, "hand").hand == -1);
  CHECK(body(r, "hand").link == 2);
  const LinkBody& fl = body(r, "finger_left");
  const LinkBody& fr = body(r, "finger_right");
  CHECK(fl.link == 2);
  CHECK(fl.hand == 0);
  CHECK(fr.hand == 1);
  // At CLOSE (0) the left finger's centre is 15 mm left of the hand's axis, at OPEN 55 mm; the
  // right one mirrors it.
  CHECK((centre(fl, hand_offset(r, 0, true)) - Vec3(50, 15, 0)).norm() < 1e-9);
  CHECK((centre(fl, hand_offset(r, 0, false)) - Vec3(50, 55, 0)).norm() < 1e-9);
  CHECK((centre(fr, hand_offset(r, 1, false)) - Vec3(50, -55, 0)).norm() < 1e-9);
  // A follower with multiplier 0.5 and an offset (metres).
  std::string half = gripper_arm();
  half.replace(half.find("multiplier=\"1\" offset=\"0\""), 25, "multiplier=\"0.5\" offset=\"0.002\"");
  const Robot h = load(half, "tool0");
  CHECK(h.hand[1].open == Approx(22));
  CHECK(h.hand[1].closed == Approx(2));
  Robot changed = h;
  changed.hand[0].open = 20;
  update_hand_followers(changed);
  CHECK(changed.hand[1].open == Approx(12));
}

TEST_CASE("branches: the SRDF-style tip on the hand link, a link past the tip with a finger on a finger") {
  const Robot r = load(gripper_arm(link("pad", "0.06 0 0", "0.005 0.005 0.005") +
                                   joint("pad_joint", "prismatic", "finger_left", "pad", "0 0 0",
                                         "<axis xyz=\"1 0 0\"/><limit lower=\"-0.01\" upper=\"0\" velocity=\"0.1\"/>")),
                       "hand");
  REQUIRE(r.hand.size() == 3);
  // Parents first: the left finger, the pad riding on it, then the right finger.
  CHECK(r.hand[1].name == "pad_joint");
  CHECK(r.hand[1].parent == 0);
  const LinkBody& pad = body(r, "pad");
  CHECK(pad.hand == 1);
  // Open: the finger at +40 mm in Y, the pad at its upper limit 0 in X; closed: finger 0, pad -10.
  CHECK((centre(pad, hand_offset(r, 1, false)) - Vec3(60, 40, 0)).norm() < 1e-9);
  CHECK((centre(pad, hand_offset(r, 1, true)) - Vec3(50, 0, 0)).norm() < 1e-9);
}

TEST_CASE("branches: a movable branch that is no finger is an error naming the joint, never frozen") {
  // A revolute joint off link_1 (a camera pan).
  std::string pan = gripper_arm(link("camera", "0 0 0", "0.02 0.02 0.02") +
                                joint("camera_pan", "revolute", "link_1", "camera", "0.05 0 0.1", kLimitRev));
  std::string e = error(pan, "tool0");
  CHECK(e.find("g.urdf:") == 0);
  CHECK(e.find("joint 'camera_pan' (revolute) branches off the arm chain at link 'link_1'") != std::string::npos);
  // Without the tip the two movable branches are ambiguous first.
  CHECK(error(pan).find("the arm is ambiguous: at link 'link_1'") != std::string::npos);
  // Past the tip: a revolute joint in the hand.
  e = error(gripper_arm(link("wrist_cam", "0 0 0", "0.01 0.01 0.01") +
                        joint("cam_tilt", "continuous", "hand", "wrist_cam", "0 0 0", "<axis xyz=\"1 0 0\"/>")),
            "tool0");
  CHECK(e.find("joint 'cam_tilt' (continuous) branches off the arm chain at link 'hand'") != std::string::npos);
  // A follower of nothing, a follower of an arm joint riding on a finger, a cycle of followers.
  CHECK(error(gripper_arm("", "nothing"), "tool0").find("mimics 'nothing', which is neither an arm joint nor a finger") !=
        std::string::npos);
  const std::string riding = error(gripper_arm(link("pad", "0 0 0", "0.005 0.005 0.005") +
                                               joint("pad_joint", "prismatic", "finger_left", "pad", "0 0 0",
                                                     "<axis xyz=\"1 0 0\"/><limit lower=\"0\" upper=\"0.01\" velocity=\"0.1\"/>"
                                                     "<mimic joint=\"j1\"/>")),
                                   "tool0");
  INFO(riding);
  CHECK(riding.find("joint 'pad_joint' follows the arm joint 'j1' but rides on the finger 'finger_left_joint'") != std::string::npos);
  std::string cycle = gripper_arm("", "finger_right_joint");
  CHECK(error(cycle, "tool0").find("mimics itself") != std::string::npos);
  std::string loop = gripper_arm();
  loop.replace(loop.find(kLimitFinger), kLimitFinger.size(), kLimitFinger + "<mimic joint=\"finger_right_joint\"/>");
  CHECK(error(loop, "tool0").find("form a cycle") != std::string::npos);
  // A mimic joint on the arm chain itself.
  std::string coupled = gripper_arm();
  coupled.replace(coupled.find("<limit lower=\"-2\""), 0, "<mimic joint=\"j1\"/>");
  // (modelled when it follows the joint just before it and the link between carries no
  // geometry: test_urdf_limits.cpp "[mimic]"; here link_1 has a box)
  INFO(error(coupled, "tool0"));
  CHECK(error(coupled, "tool0").find("joint 'j2' follows 'j1', and link 'link_1' between them has collision geometry") != std::string::npos);
  // An unknown tip.
  CHECK(error(gripper_arm(), "palm").find("tip: the description has no link 'palm'") != std::string::npos);
}

TEST_CASE("branches: a follower of an arm joint moves with that joint (a parallel-link lever)") {
  // The right finger made a follower of J2 (1 rad -> 1 m, display: 1000 mm per 180/pi deg).
  const Robot r = load(gripper_arm("", "j2"), "tool0");
  REQUIRE(r.hand.size() == 2);
  const HandJoint& f = r.hand[1];
  CHECK(f.arm_joint == 1);
  CHECK(f.leader == -1);
  CHECK(f.multiplier == Approx(1000 * std::numbers::pi / 180));
  CHECK(hand_follows_arm(r, 1));
  CHECK_FALSE(hand_follows_arm(r, 0));
  JointVector q(2);
  q << 0, 10;
  // Along -Y by 10 deg worth of the multiplier, whatever the hand does.
  for (const bool closed : {false, true}) {
    const Pose o = hand_offset(r, 1, closed, q);
    CHECK((o.translation() - Vec3(0, -10 * f.multiplier, 0)).norm() < 1e-9);
  }
  // Its reach: J2 moves it by |multiplier| per degree of J2 on its own (180/pi per rad).
  const LinkBody& body_r = body(r, "finger_right");
  const BodyReach reach = body_reach(r, body_r);
  CHECK(reach.radius[1] >= 1000.0 - 1e-9);
  // A lever that turns against J2 (multiplier -1), hanging on link_1.
  const Robot lever = load(gripper_arm(link("lever", "0.15 0 0", "0.3 0.02 0.02") +
                                       joint("lever_joint", "continuous", "link_1", "lever", "0 0 0.2",
                                             "<axis xyz=\"0 1 0\"/><mimic joint=\"j2\" multiplier=\"-1\"/>")),
                           "tool0");
  const auto it = std::find_if(lever.hand.begin(), lever.hand.end(), [](const HandJoint& h) { return h.name == "lever_joint"; });
  REQUIRE(it != lever.hand.end());
  const HandJoint& l = *it;
  CHECK(l.frame == 1);
  CHECK(l.arm_joint == 1);
  CHECK(l.multiplier == Approx(-1));
  q << 0, 90;
  const Vec3 tip = hand_offset(lever, static_cast<int>(it - lever.hand.begin()), false, q) * Vec3(300, 0, 200);
  CHECK((tip - Vec3(0, 0, 500)).norm() < 1e-9);  // turned -90 deg about Y: straight up from (0, 0, 200)
}

TEST_CASE("branches: one finger without a tip stays the last axis, with a warning saying so, fixed branches are rigid") {
  std::string one = gripper_arm();
  one.replace(one.find("<joint name=\"finger_right_joint\""), std::string::npos, "</robot>\n");
  one.replace(one.find(link("finger_right", "0.05 -0.015 0", "0.02 0.01 0.02")), link("finger_right", "0.05 -0.015 0", "0.02 0.01 0.02").size(), "");
  const Robot r = load(one);
  CHECK(r.joint_count() == 3);
  REQUIRE(r.warnings.size() == 1);
  CHECK(r.warnings[0].find("joint 'finger_left_joint' (prismatic) is the arm's last axis, J3") != std::string::npos);
  // With the tip it is the hand's.
  const Robot t = load(one, "tool0");
  CHECK(t.joint_count() == 2);
  CHECK(t.hand.size() == 1);
  CHECK(t.warnings.empty());
}
