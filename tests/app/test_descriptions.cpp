// Robot descriptions as shipped, at the cell level (docs/cell-format.md "Pair selection",
// "Robots"): the default pair policy leaves the self-pairs touching at the start joints untested
// (DEFAULT, one warning), `srdf:` imports <disable_collisions> (SRDF) and names the groups and end
// effectors, `tip:` (or the SRDF end effector's parent link) ends the arm chain.
#include "asimov/cell/cell_loader.hpp"
#include "asimov/motion/scene.hpp"

#include "support/cell.hpp"
#include "support/result.hpp"
#include "support/run_cli.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>

using namespace asimov;
namespace fs = std::filesystem;

namespace {
// A cell that must load.
motion::Cell load(const fs::path& p) { return test::load_cell_file(p.string()); }

fs::path dir() { return test::scratch_dir("descriptions"); }

void write(const fs::path& p, const std::string& text) {
  fs::create_directories(p.parent_path());
  std::ofstream(p) << text;
}

// Three revolute joints; link_2's body reaches 0.05 m down into the base's box at the zero pose
// (base and link_2 are not joined), and is clear of it with J2 = 90 deg. A tool0 frame and a
// fixed "camera" side branch on link_1.
const char* kArm = R"(<robot name="touchy">
  <link name="base"><collision><origin xyz="0 0 0.1"/><geometry><box size="0.2 0.2 0.2"/></geometry></collision></link>
  <link name="link_1"><collision><origin xyz="0 0 0.05"/><geometry><cylinder radius="0.04" length="0.1"/></geometry></collision></link>
  <link name="link_2"><collision><origin xyz="0 0 0.025"/><geometry><box size="0.05 0.05 0.55"/></geometry></collision></link>
  <link name="link_3"><collision><origin xyz="0.1 0 0"/><geometry><box size="0.2 0.04 0.04"/></geometry></collision></link>
  <link name="tool0"/>
  <link name="camera"><collision><geometry><box size="0.02 0.02 0.02"/></geometry></collision></link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="link_1"/><origin xyz="0 0 0.2"/><axis xyz="0 0 1"/>
    <limit lower="-3" upper="3" velocity="1"/></joint>
  <joint name="j2" type="revolute"><parent link="link_1"/><child link="link_2"/><origin xyz="0 0 0.1"/><axis xyz="0 1 0"/>
    <limit lower="-2" upper="2" velocity="1"/></joint>
  <joint name="j3" type="revolute"><parent link="link_2"/><child link="link_3"/><origin xyz="0 0 0.3"/><axis xyz="0 1 0"/>
    <limit lower="-2" upper="2" velocity="1"/></joint>
  <joint name="flange" type="fixed"><parent link="link_3"/><child link="tool0"/><origin xyz="0.2 0 0"/></joint>
  <joint name="cam" type="fixed"><parent link="link_1"/><child link="camera"/><origin xyz="0.06 0 0.05"/></joint>
</robot>
)";

const char* kSrdf = R"(<?xml version="1.0"?>
<robot name="touchy">
  <group name="arm"><chain base_link="base" tip_link="tool0"/></group>
  <group name="hand"><link name="link_3"/></group>
  <group_state name="home" group="arm"><joint name="j1" value="0"/></group_state>
  <end_effector name="pointer" parent_link="link_3" group="hand" parent_group="arm"/>
  <disable_collisions link1="camera" link2="link_2" reason="Never"/>
  <disable_collisions link1="base" link2="link_3" reason="Never"/>
</robot>
)";

bool has_pair(const std::vector<std::pair<std::string, std::string>>& ps, const std::string& a, const std::string& b) {
  return std::any_of(ps.begin(), ps.end(), [&](const auto& p) { return (p.first == a && p.second == b) || (p.first == b && p.second == a); });
}

fs::path cell_file(const std::string& name, const std::string& extra) {
  write(dir() / "touchy.urdf", kArm);
  write(dir() / "touchy.srdf", kSrdf);
  write(dir() / name, "robot: touchy.urdf\n" + extra);
  return dir() / name;
}
}  // namespace

TEST_CASE("default pairs: self-pairs touching at the start joints are not tested (DEFAULT), with one warning") {
  const auto cell = load(cell_file("touch.yaml", ""));
  REQUIRE(cell.collision.start_contacts.size() == 1);
  CHECK(has_pair(cell.collision.start_contacts, "base", "link_2"));
  const auto warned = std::count_if(cell.warnings.begin(), cell.warnings.end(),
                                    [](const std::string& w) { return w.find("(DEFAULT): base / link_2") != std::string::npos; });
  CHECK(warned == 1);
  // Clear of each other at the start: nothing disabled, no warning.
  const auto apart = load(cell_file("apart.yaml", "start: [0, 90, 0]\n"));
  CHECK(apart.collision.start_contacts.empty());
  CHECK(apart.warnings.empty());
  // Collision checking off: nothing is looked at.
  CHECK(load(cell_file("off.yaml", "collision: {enabled: false}\n")).collision.start_contacts.empty());
  // A clearance that halts counts, one that only warns does not: at J2 = 90 link_2 lies 75 mm
  // above the base's top.
  const std::string side = "start: [0, 90, 0]\n";
  CHECK(has_pair(load(cell_file("c100.yaml", side + "collision: {clearance_mm: 100}\n")).collision.start_contacts,
                 "base", "link_2"));
  CHECK(load(cell_file("c60.yaml", side + "collision: {clearance_mm: 60}\n")).collision.start_contacts.empty());
  CHECK(load(cell_file("cw.yaml", side + "collision: {clearance_mm: 100, on_clearance: warn}\n"))
            .collision.start_contacts.empty());
}

TEST_CASE("default pairs: the run starts and the pair is DEFAULT in `asimov pairs`, the others still halt") {
  write(dir() / "wave.v2", ".PROGRAM wave()\n    MOVE #PPOINT(30, 0, 20)\n    MOVE #PPOINT(-30, 0, -20)\n    TYPE \"done\"\n.END\n");
  const auto cell = cell_file("run.yaml", "");
  const auto r = test::run_cli("run " + (dir() / "wave.v2").string() + " --cell " + cell.string());
  CHECK(r.exit_code == 0);
  CHECK(r.out.find("done") != std::string::npos);
  CHECK(r.err.find("Warning: the robot touches itself at the start joints; not tested (DEFAULT): base / link_2") != std::string::npos);
  const auto p = test::run_cli("pairs --no-cache " + cell.string());
  CHECK(p.exit_code == 0);
  CHECK(p.out.find("base    link_2  DEFAULT") != std::string::npos);
  // Other pairs are still tested: at J2 = 90 link_3 hangs down at x = 300 mm into a post.
  const auto post = cell_file("post.yaml", "objects: [{name: post, box: [100, 100, 300], at: [300, 0, 0, 0, 0, 0]}]\n");
  write(dir() / "down.v2", ".PROGRAM down()\n    MOVE #PPOINT(0, 90, 0)\n    TYPE \"done\"\n.END\n");
  const auto hit = test::run_cli("run " + (dir() / "down.v2").string() + " --cell " + post.string());
  CHECK(hit.exit_code == 3);
  CHECK(hit.err.find("*Collision*  link_3 / post") != std::string::npos);
}

TEST_CASE("srdf: disable_collisions become SRDF pairs, groups and end effectors are reported, the tip") {
  const auto cell = load(cell_file("srdf.yaml", "srdf: touchy.srdf\n"));
  CHECK(has_pair(cell.collision.srdf_disabled, "camera", "link_2"));
  CHECK(has_pair(cell.collision.srdf_disabled, "base", "link_3"));
  CHECK(cell.collision.srdf_disabled.size() == 2);
  REQUIRE(cell.notes.size() == 1);
  CHECK(cell.notes[0].find("groups: arm (chain base -> tool0), hand (1 links, 0 joints)") != std::string::npos);
  CHECK(cell.notes[0].find("end effectors: pointer (parent link_3, group hand)") != std::string::npos);
  // The end effector's parent link is the tip: the flange is link_3's frame, not tool0's.
  CHECK(cell.robot.flange_offset.translation().norm() < 1e-12);
  const auto no_srdf = load(cell_file("plain.yaml", ""));
  CHECK(no_srdf.robot.flange_offset.translation().x() == Approx(200));
  // `tip:` wins over the SRDF.
  const auto tipped = load(cell_file("tip.yaml", "srdf: touchy.srdf\ntip: tool0\n"));
  CHECK(tipped.robot.flange_offset.translation().x() == Approx(200));
  // disable_default_collisions: every pair of that link, but the enable_collisions ones.
  write(dir() / "defaults.srdf", "<robot name=\"touchy\">\n<disable_default_collisions link=\"base\"/>\n"
                                  "<enable_collisions link1=\"link_3\" link2=\"base\" reason=\"check\"/>\n<bogus/>\n</robot>\n");
  const auto d = load(cell_file("defaults.yaml", "srdf: defaults.srdf\n"));
  for (const char* other : {"link_1", "link_2", "camera"}) CHECK(has_pair(d.collision.srdf_disabled, "base", other));
  CHECK_FALSE(has_pair(d.collision.srdf_disabled, "base", "link_3"));
  CHECK(d.collision.srdf_disabled.size() == 3);
  CHECK(std::count_if(d.warnings.begin(), d.warnings.end(),
                      [](const std::string& w) { return w.find("defaults.srdf:4: <bogus> is not an SRDF element: ignored") != std::string::npos; }) == 1);
  const auto p = test::run_cli("pairs --no-cache " + (dir() / "srdf.yaml").string());
  CHECK(p.out.find("base    link_3  SRDF") != std::string::npos);  // camera / link_2 is ADJACENT first
  CHECK(p.err.find("Note: ") != std::string::npos);
}

TEST_CASE("srdf: hostile files give the SRDF's file:line at the cell's srdf key") {
  auto error_of = [](const std::string& srdf, const std::string& extra = "") {
    write(dir() / "bad.srdf", srdf);
    const auto r = cell::load_cell_file(cell_file("bad.yaml", "srdf: bad.srdf\n" + extra).string());
    return r ? std::string("no error") : cell::format_cell_error(r.error());
  };
  const std::string at = "bad.yaml:2:7: srdf: " + (dir() / "bad.srdf").string();
  std::string e = error_of("<robot name=\"t\">\n<disable_collisions link1=\"base\" link2=\"nope\"/>\n</robot>\n");
  CHECK(e.find(at + ":2: disable_collisions: the robot has no link 'nope'") != std::string::npos);
  e = error_of("<robot name=\"t\">\n\n<disable_collisions link1=\"base\"/>\n</robot>\n");
  CHECK(e.find(":3: <disable_collisions> needs the attribute 'link2'") != std::string::npos);
  e = error_of("<robot>\n<end_effector name=\"e\" parent_link=\"link_3\" group=\"nogroup\"/>\n</robot>\n");
  CHECK(e.find(":2: end_effector 'e': unknown group 'nogroup'") != std::string::npos);
  e = error_of("<robot><group name=\"g\"><chain base_link=\"base\" tip_link=\"ghost\"/></group></robot>\n");
  CHECK(e.find(":1: group 'g' chain: the robot has no link 'ghost'") != std::string::npos);
  e = error_of("<robot>\n<disable_collisions link1=\"base\" link2=\"link_2\"\n</robot>\n");
  CHECK(e.find("XML error") != std::string::npos);
  e = error_of("<nope/>\n");
  CHECK(e.find(":1: the root element must be <robot>") != std::string::npos);
  // An entity "bomb" is not expanded (no DTD processing): the names stay unknown links.
  std::string bomb = "<?xml version=\"1.0\"?>\n<!DOCTYPE r [<!ENTITY a \"aaaaaaaaaa\"><!ENTITY b \"&a;&a;&a;&a;&a;&a;&a;&a;&a;&a;\">"
                     "<!ENTITY c \"&b;&b;&b;&b;&b;&b;&b;&b;&b;&b;\"><!ENTITY d \"&c;&c;&c;&c;&c;&c;&c;&c;&c;&c;\">]>\n"
                     "<robot><disable_collisions link1=\"&d;\" link2=\"base\"/></robot>\n";
  e = error_of(bomb);
  CHECK(e.size() < 2000);
  CHECK(e.find("bad.srdf") != std::string::npos);
  // 100,000 nested elements: tinyxml2's depth limit, an XML error.
  std::string deep = "<robot>";
  for (int i = 0; i < 100000; ++i) deep += "<g>";
  e = error_of(deep);
  CHECK(e.find("XML error") != std::string::npos);
  // A missing file, a bad tip.
  write(dir() / "nosrdf.yaml", "robot: touchy.urdf\nsrdf: missing.srdf\n");
  {
    const auto r = cell::load_cell_file((dir() / "nosrdf.yaml").string());
    REQUIRE_FALSE(r);
    CHECK(r.error().line == 2);
  }
  write(dir() / "badtip.yaml", "robot: touchy.urdf\ntip: wrist\n");
  {
    const auto r = cell::load_cell_file((dir() / "badtip.yaml").string());
    REQUIRE_FALSE(r);
    CHECK(r.error().line == 2);
    CHECK(r.error().message.find("tip: the description has no link 'wrist'") != std::string::npos);
  }
  {
    const auto r = cell::load_cell_text("robot: puma560\ntip: link6\n", "b.yaml");
    REQUIRE_FALSE(r);
    CHECK(r.error().line == 2);
  }
}

namespace {
// Two revolute joints, tool0 400 mm out, a hand with a left finger (prismatic +Y, 0..40 mm) and
// a right one mimicking it along -Y.
const char* kGripperArm = R"(<robot name="grip">
  <link name="base"><collision><origin xyz="0 0 0.05"/><geometry><box size="0.2 0.2 0.1"/></geometry></collision></link>
  <link name="link_1"><collision><origin xyz="0 0 0.2"/><geometry><box size="0.06 0.06 0.4"/></geometry></collision></link>
  <link name="link_2"><collision><origin xyz="0.2 0 0"/><geometry><box size="0.4 0.05 0.05"/></geometry></collision></link>
  <link name="tool0"/>
  <link name="hand"><collision><origin xyz="0.02 0 0"/><geometry><box size="0.04 0.04 0.04"/></geometry></collision></link>
  <link name="finger_left"><collision><origin xyz="0.05 0.015 0"/><geometry><box size="0.02 0.01 0.02"/></geometry></collision></link>
  <link name="finger_right"><collision><origin xyz="0.05 -0.015 0"/><geometry><box size="0.02 0.01 0.02"/></geometry></collision></link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="link_1"/><origin xyz="0 0 0.1"/><axis xyz="0 0 1"/>
    <limit lower="-3" upper="3" velocity="1"/></joint>
  <joint name="j2" type="revolute"><parent link="link_1"/><child link="link_2"/><origin xyz="0 0 0.4"/><axis xyz="0 1 0"/>
    <limit lower="-2" upper="2" velocity="1"/></joint>
  <joint name="flange" type="fixed"><parent link="link_2"/><child link="tool0"/><origin xyz="0.4 0 0"/></joint>
  <joint name="hand_joint" type="fixed"><parent link="tool0"/><child link="hand"/></joint>
  <joint name="finger_left_joint" type="prismatic"><parent link="hand"/><child link="finger_left"/><axis xyz="0 1 0"/>
    <limit lower="0" upper="0.04" velocity="0.1"/></joint>
  <joint name="finger_right_joint" type="prismatic"><parent link="hand"/><child link="finger_right"/><axis xyz="0 -1 0"/>
    <limit lower="0" upper="0.04" velocity="0.1"/><mimic joint="finger_left_joint"/></joint>
</robot>
)";

// A 6 mm cube where the open left finger is (y 50..60 mm), clear of the closed one (y 10..20).
fs::path gripper_cell(const std::string& name, const std::string& extra) {
  write(dir() / "grip.urdf", kGripperArm);
  write(dir() / name, "robot: grip.urdf\ntip: tool0\nobjects: [{name: post, box: [6, 6, 6], at: [450, 55, 500, 0, 0, 0]}]\n" + extra);
  return dir() / name;
}
}  // namespace

TEST_CASE("fingers: OPEN / CLOSE drive the prismatic fingers and their follower, the cell can set the travel") {
  write(dir() / "closed.v2", ".PROGRAM closed()\n    CLOSE\n    MOVE #PPOINT(0, -5)\n    TYPE \"done\"\n.END\n");
  write(dir() / "open.v2", ".PROGRAM open()\n    MOVE #PPOINT(0, -5)\n    TYPE \"done\"\n.END\n");
  const auto cell = gripper_cell("grip.yaml", "");
  const auto loaded = load(cell);
  CHECK(loaded.robot.joint_count() == 2);
  REQUIRE(loaded.robot.hand.size() == 2);
  auto closed = test::run_cli("run " + (dir() / "closed.v2").string() + " --cell " + cell.string());
  CHECK(closed.exit_code == 0);
  CHECK(closed.out.find("done") != std::string::npos);
  // The hand starts open: the left finger is in the cube as the motion starts.
  auto open = test::run_cli("run " + (dir() / "open.v2").string() + " --cell " + cell.string());
  CHECK(open.exit_code == 3);
  CHECK(open.err.find("*Collision*  finger_left / post") != std::string::npos);
  CHECK(open.err.find("at t = 0.000000 s") != std::string::npos);
  // Travel from the cell: open at 20 mm (y 30..40), clear of the cube; the follower follows.
  const auto short_travel = gripper_cell("short.yaml", "gripper: {fingers: {finger_left_joint: [10, 20]}}\n");
  const auto s = load(short_travel);
  CHECK(s.robot.hand[0].open == Approx(20));
  CHECK(s.robot.hand[1].open == Approx(20));
  CHECK(s.robot.hand[1].closed == Approx(10));
  CHECK(s.workcell.empty());
  open = test::run_cli("run " + (dir() / "open.v2").string() + " --cell " + short_travel.string());
  CHECK(open.exit_code == 0);
  // Bad travel: no such finger, a follower, outside the limits.
  auto fails = [&](const std::string& extra, const std::string& what) {
    const auto r = cell::load_cell_file(gripper_cell("badgrip.yaml", extra).string());
    INFO(extra);
    REQUIRE_FALSE(r);
    CHECK(r.error().message.find(what) != std::string::npos);
  };
  fails("gripper: {fingers: {thumb: [0, 1]}}\n", "'thumb' is no finger of the robot (fingers: finger_left_joint)");
  fails("gripper: {fingers: {finger_right_joint: [0, 1]}}\n", "'finger_right_joint' is no finger");
  fails("gripper: {fingers: {finger_left_joint: [0, 50]}}\n", "50 is outside the joint's limits [0, 40]");
  // Without the tip the left finger would be J3 and the right one follows an arm joint: a cell
  // error saying to give the tip.
  write(dir() / "notip.yaml", "robot: grip.urdf\n");
  {
    const auto r = cell::load_cell_file((dir() / "notip.yaml").string());
    REQUIRE_FALSE(r);
    CHECK(r.error().message.find("mimics 'finger_left_joint', the arm's last axis") != std::string::npos);
  }
}

TEST_CASE("configuration words: honoured on a spherical-wrist URDF arm, said once where they mean nothing (UR-like)") {
  // A UR-like 6R chain: J2, J3, J4 parallel, J5 and J6 offset (d4, d5, d6): no spherical wrist.
  std::string ur = "<robot name=\"urlike\">\n<link name=\"base\"><collision><geometry><box size=\"0.1 0.1 0.1\"/></geometry></collision></link>\n";
  const char* axes[] = {"0 0 1", "0 1 0", "0 1 0", "0 1 0", "0 0 -1", "0 1 0"};
  const char* origins[] = {"0 0 0.089", "0 0.136 0", "0 -0.12 0.425", "0 0 0.392", "0 0.093 0", "0 0 0.095"};
  for (int i = 1; i <= 6; ++i) {
    ur += "<link name=\"l" + std::to_string(i) + "\"/>\n<joint name=\"j" + std::to_string(i) + "\" type=\"revolute\"><parent link=\"" +
          (i == 1 ? std::string("base") : "l" + std::to_string(i - 1)) + "\"/><child link=\"l" + std::to_string(i) +
          "\"/><origin xyz=\"" + origins[i - 1] + "\"/><axis xyz=\"" + axes[i - 1] +
          "\"/><limit lower=\"-6.28\" upper=\"6.28\" velocity=\"3\"/></joint>\n";
  }
  ur += "<link name=\"tool0\"/><joint name=\"f\" type=\"fixed\"><parent link=\"l6\"/><child link=\"tool0\"/><origin xyz=\"0 0.082 0\"/></joint>\n</robot>\n";
  write(dir() / "urlike.urdf", ur);
  write(dir() / "urlike.yaml", "robot: urlike.urdf\n");
  write(dir() / "words.v2", ".PROGRAM words()\n    LEFTY\n    ABOVE\n    LEFTY\n    MOVE #PPOINT(10, 10, 10, 0, 30, 0)\n    TYPE \"done\"\n.END\n");
  auto r = test::run_cli("run " + (dir() / "words.v2").string() + " --cell " + (dir() / "urlike.yaml").string());
  CHECK(r.exit_code == 0);
  const auto count = [](const std::string& s, const std::string& part) {
    std::size_t n = 0;
    for (std::size_t at = s.find(part); at != std::string::npos; at = s.find(part, at + 1)) ++n;
    return n;
  };
  CHECK(count(r.err, "LEFTY (no meaning for this arm: ignored)") == 1);
  CHECK(count(r.err, "ABOVE (no meaning for this arm: ignored)") == 1);
  // generic6 has a spherical wrist: the words select the closed-form branch, no warning.
  const std::string generic6 = test::source_path("programs/cells/generic6_cell.yaml");
  r = test::run_cli("run " + (dir() / "words.v2").string() + " --cell " + generic6);
  CHECK(r.exit_code == 0);
  CHECK(r.err.find("no meaning for this arm") == std::string::npos);
}

TEST_CASE("levers: a body following an arm joint is posed and checked as that joint moves") {
  // J1 about Z, J2 about Y; a lever on link_1 turning against J2 (as the IRB 2400's parallel
  // links follow J3). J2 = +60 turns it up into a post, J2 = -60 down beside the base.
  write(dir() / "lever.urdf", R"(<robot name="lever">
  <link name="base"><collision><origin xyz="0 0 0.05"/><geometry><box size="0.2 0.2 0.1"/></geometry></collision></link>
  <link name="link_1"><collision><origin xyz="0 0 0.1"/><geometry><cylinder radius="0.03" length="0.2"/></geometry></collision></link>
  <link name="link_2"/>
  <link name="lever"><collision><origin xyz="0.15 0 0"/><geometry><box size="0.3 0.02 0.02"/></geometry></collision></link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="link_1"/><origin xyz="0 0 0.1"/><axis xyz="0 0 1"/>
    <limit lower="-3" upper="3" velocity="1"/></joint>
  <joint name="j2" type="revolute"><parent link="link_1"/><child link="link_2"/><origin xyz="0 0 0.3"/><axis xyz="0 1 0"/>
    <limit lower="-2" upper="2" velocity="1"/></joint>
  <joint name="lever_joint" type="continuous"><parent link="link_1"/><child link="lever"/><origin xyz="0 0 0.2"/>
    <axis xyz="0 1 0"/><mimic joint="j2" multiplier="-1"/></joint>
</robot>
)");
  write(dir() / "lever.yaml", "robot: lever.urdf\nobjects: [{name: post, box: [40, 40, 40], at: [120, 0, 510, 0, 0, 0]}]\n");
  write(dir() / "up.v2", ".PROGRAM up()\n    MOVE #PPOINT(0, 60)\n.END\n");
  write(dir() / "downward.v2", ".PROGRAM downward()\n    MOVE #PPOINT(0, -60)\n    TYPE \"clear\"\n.END\n");
  auto r = test::run_cli("run " + (dir() / "up.v2").string() + " --cell " + (dir() / "lever.yaml").string());
  CHECK(r.exit_code == 3);
  CHECK(r.err.find("*Collision*  lever / post") != std::string::npos);
  r = test::run_cli("run " + (dir() / "downward.v2").string() + " --cell " + (dir() / "lever.yaml").string());
  CHECK(r.exit_code == 0);
  CHECK(r.out.find("clear") != std::string::npos);
}
