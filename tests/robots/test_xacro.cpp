// The in-process xacro expander (robots/src/xacro.hpp, docs/robots.md "xacro"): a ROS-Industrial
// style package (macro file with a prefix parameter, top file including it through $(find))
// expands to the hand-written URDF's arm; expressions, macros, blocks, conditionals, args; the
// hostile cases (cycles, depth, size) and unsupported constructs fail with file:line messages.
#include "asimov/robots/urdf_loader.hpp"
#include "robots/src/xacro.hpp"

#include "support/joints.hpp"

#include "support/run_cli.hpp"
#include "support/result.hpp"

#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <numbers>
#include <unistd.h>

using namespace asimov::robots;
using asimov::test::must;
namespace fs = std::filesystem;

namespace {
const fs::path kWorkspace = fs::path(ASIMOV_SOURCE_DIR) / "programs/cells/ros_ws/src";
const fs::path kPackage = kWorkspace / "demo_support_pkg";

fs::path scratch() { return asimov::test::scratch_dir("xacro"); }

fs::path write(const std::string& name, const std::string& text) {
  const fs::path p = scratch() / name;
  fs::create_directories(p.parent_path());
  std::ofstream(p) << text;
  return p;
}

const char* kNs = "<robot xmlns:xacro=\"http://wiki.ros.org/xacro\" name=\"t\">\n";

std::string expand(const std::string& body, const std::map<std::string, std::string>& args = {}) {
  return expand_xacro(write("t.xacro", std::string(kNs) + body + "</robot>\n").string(), PackagePath{}, args);
}

std::string error_of(const std::string& body, const std::string& name = "t.xacro") {
  try {
    expand_xacro(write(name, std::string(kNs) + body + "</robot>\n").string(), PackagePath{}, {});
  } catch (const UrdfError& e) {
    return e.what();
  }
  return "no error";
}

void has(const std::string& expanded, const std::string& part) {
  std::string what = expanded;  // tinyxml2 writes ' in attributes as &apos;
  for (std::size_t k; (k = what.find("&apos;")) != std::string::npos;) what.replace(k, 6, "'");
  INFO(what);
  INFO("expected: " << part);
  CHECK(what.find(part) != std::string::npos);
}

// A two-link arm whose joint values come from the text given.
std::string joint(const std::string& origin_z, const std::string& lower, const std::string& upper) {
  return "<link name=\"a\"/><link name=\"b\"/><joint name=\"j\" type=\"revolute\"><parent link=\"a\"/><child "
         "link=\"b\"/><origin xyz=\"0 0 " + origin_z + "\"/><axis xyz=\"0 0 1\"/><limit lower=\"" + lower +
         "\" upper=\"" + upper + "\" velocity=\"1\"/></joint>\n";
}
}  // namespace

TEST_CASE("xacro: the ROS-style package expands to the hand-written URDF's arm", "[urdf][xacro]") {
  UrdfOptions o;
  o.packages.add_root(kWorkspace);
  const Robot urdf = must(load_urdf((kPackage / "urdf/demo6.urdf").string(), o));
  const Robot xacro = must(load_urdf((kPackage / "urdf/demo6.xacro").string(), o));
  REQUIRE(xacro.joint_count() == urdf.joint_count());
  for (int i = 0; i < urdf.joint_count(); ++i) {
    CHECK(xacro.chain[i].name == urdf.chain[i].name);
    CHECK(xacro.lower[i] == Approx(urdf.lower[i]).epsilon(1e-12));
    CHECK(xacro.upper[i] == Approx(urdf.upper[i]).epsilon(1e-12));
    CHECK(xacro.max_velocity[i] == Approx(urdf.max_velocity[i]).epsilon(1e-12));
    CHECK((xacro.chain[i].origin.matrix() - urdf.chain[i].origin.matrix()).norm() < 1e-12);
    CHECK((xacro.chain[i].axis - urdf.chain[i].axis).norm() < 1e-15);
  }
  CHECK((xacro.flange_offset.matrix() - urdf.flange_offset.matrix()).norm() < 1e-12);
  for (const auto& q : {asimov::test::jv({0, 0, 0, 0, 0, 0}), asimov::test::jv({10, 20, -30, 40, 50, 60}),
                        asimov::test::jv({-170, 140, -210, 185, -120, 350})})
    CHECK((flange_pose(xacro, q).matrix() - flange_pose(urdf, q).matrix()).norm() < 1e-9);
  // Same bodies (names, links, vertices) including the COLLADA meshes found by package://.
  REQUIRE(xacro.bodies.size() == urdf.bodies.size());
  for (std::size_t i = 0; i < urdf.bodies.size(); ++i) {
    CHECK(xacro.bodies[i].name == urdf.bodies[i].name);
    CHECK(xacro.bodies[i].link == urdf.bodies[i].link);
    REQUIRE(xacro.bodies[i].mesh.vertices.size() == urdf.bodies[i].mesh.vertices.size());
    for (std::size_t v = 0; v < urdf.bodies[i].mesh.vertices.size(); ++v)
      CHECK((xacro.bodies[i].mesh.vertices[v] - urdf.bodies[i].mesh.vertices[v]).norm() < 1e-9);
  }
  // $(arg prefix) from the caller renames every link and joint.
  o.xacro_args["prefix"] = "r1_";
  const Robot prefixed = must(load_urdf((kPackage / "urdf/demo6.xacro").string(), o));
  CHECK(prefixed.chain[0].name == "r1_joint_1");
  CHECK(prefixed.chain[5].name == "r1_joint_6");
}

TEST_CASE("xacro: expressions", "[urdf][xacro]") {
  const std::string x = expand(
      "<xacro:property name=\"a\" value=\"2\"/><xacro:property name=\"b\" value=\"${a * 3 + 1}\"/>"
      "<xacro:property name=\"s\" value=\"arm\"/>"
      "<e v1=\"${b}\" v2=\"${(a + 1) ** 2 - 10 / 4}\" v3=\"${-2**2}\" v4=\"${radians(180) == pi}\""
      " v5=\"${a &lt; b and not a &gt; 3}\" v7=\"${s}_${a}\" v8=\"${s + '_x'}\""
      " v9=\"${sqrt(16) + abs(-1.5) + cos(0) + sin(0) + tan(0)}\" v10=\"$${literal}\" v11=\"${a % 3 == 2 or 0}\""
      " v12=\"${math.pi / 2}\" v13=\"${a != 2}\"/>\n");
  CHECK(x.find("v1=\"7\"") != std::string::npos);
  CHECK(x.find("v2=\"6.5\"") != std::string::npos);
  CHECK(x.find("v3=\"-4\"") != std::string::npos);  // ** binds tighter than unary minus
  CHECK(x.find("v4=\"True\"") != std::string::npos);
  CHECK(x.find("v5=\"True\"") != std::string::npos);
  CHECK(x.find("v7=\"arm_2\"") != std::string::npos);
  CHECK(x.find("v8=\"arm_x\"") != std::string::npos);
  CHECK(x.find("v9=\"6.5\"") != std::string::npos);
  CHECK(x.find("v10=\"${literal}\"") != std::string::npos);
  CHECK(x.find("v11=\"True\"") != std::string::npos);
  CHECK(x.find("v12=\"1.5707963267948966\"") != std::string::npos);
  CHECK(x.find("v13=\"False\"") != std::string::npos);
}

TEST_CASE("xacro: macros, defaults, blocks, conditionals, args", "[urdf][xacro]") {
  const std::string x = expand(
      "<xacro:arg name=\"side\" default=\"left\"/>"
      "<xacro:property name=\"blk\"><b n=\"1\"/><b n=\"2\"/></xacro:property>"
      "<xacro:macro name=\"m\" params=\"p k:=5 *first **rest\">"
      "<m p=\"${p}\" k=\"${k * 2}\"><xacro:insert_block name=\"first\"/><r><xacro:insert_block name=\"rest\"/></r>"
      "<xacro:if value=\"${k == 5}\"><default/></xacro:if><xacro:unless value=\"${k == 5}\"><given/></xacro:unless>"
      "</m></xacro:macro>"
      "<xacro:m p=\"$(arg side)\"><one/><rest><two/><three/></rest></xacro:m>"
      "<xacro:m p=\"x\" k=\"1\"><one/><w/></xacro:m>"
      "<xacro:insert_block name=\"blk\"/>"
      "<xacro:macro name=\"inner\" params=\"v\"><i v=\"${v}\"/></xacro:macro>"
      "<xacro:macro name=\"outer\" params=\"v\"><xacro:inner v=\"${v + 1}\"/></xacro:macro><xacro:outer v=\"1\"/>\n");
  CHECK(x.find("<m p=\"left\" k=\"10\"><one/><r><two/><three/></r><default/></m>") != std::string::npos);
  CHECK(x.find("<m p=\"x\" k=\"2\"><one/><r/><given/></m>") != std::string::npos);
  CHECK(x.find("<b n=\"1\"/>") != std::string::npos);
  CHECK(x.find("<b n=\"2\"/>") != std::string::npos);
  CHECK(x.find("<i v=\"2\"/>") != std::string::npos);
  CHECK(x.find("xacro") == std::string::npos);
  // A value from the caller replaces the xacro:arg default.
  CHECK(expand("<xacro:arg name=\"side\" default=\"left\"/><s v=\"$(arg side)\"/>", {{"side", "right"}})
            .find("<s v=\"right\"/>") != std::string::npos);
}

TEST_CASE("xacro: the constructs of the UR and ROS-Industrial packages", "[urdf][xacro]") {
  write("cfg/limits.yaml", "joint_limits:\n  shoulder: {max_position: 3.14, has: true}\n  names: [a, 'b c']\nhash: calib_1\n");
  setenv("ASIMOV_XACRO_TEST_VAR", "from_env", 1);
  const std::string x = expand(
      "<xacro:arg name=\"side_n\" default=\"3\"/><xacro:arg name=\"side\" default=\"left\"/>"
      // lazily evaluated: `late` is defined after `early`, which uses it
      "<xacro:property name=\"early\" value=\"${late * 2}\"/><xacro:property name=\"late\" value=\"21\"/>"
      "<xacro:property name=\"cfg\" value=\"${xacro.load_yaml('cfg/limits.yaml')}\"/>"
      "<xacro:property name=\"lim\" value=\"${cfg['joint_limits']}\"/>"
      "<e a=\"${early}\" b=\"${cfg['joint_limits']['shoulder']['max_position']}\" c=\"${cfg.joint_limits.shoulder.has}\""
      " d=\"${lim['names'][1]}\" e=\"${len(lim['names'])}\" f=\"${cfg.hash}\" g=\"${1 if late > 20 else nope}\""
      " h=\"${'x' if False else 'y'}\" i=\"${[1, 2] + [3]}\" j=\"${{'k': 1}['k']}\" k=\"${'a' in ['a', 'b']}\""
      " l=\"${dict(p=1.5, q='w')['q']}\" m=\"${2 not in [1]}\" n=\"${7 // 2}\" o=\"${float('2.5') + int('3')}\""
      " p=\"$(env ASIMOV_XACRO_TEST_VAR)\" q=\"$(optenv ASIMOV_SURELY_UNSET_VARIABLE fall back)\" r=\"$(eval int(side_n) * 2 + 1)\""
      " s=\"$(eval arg('side') + '_x')\" t=\"${(3 if late else 4) * 2}\" u=\"${None}\" v=\"${str(0.5)}\" w=\"${-lim['names'].__len__ if False else 0}\"/>"
      // ^ defaults and scope="parent" (UR's get_visual_params / read_model_data)
      "<xacro:macro name=\"reader\" params=\"v\"><xacro:property name=\"got\" value=\"${v * 10}\" scope=\"parent\"/>"
      "<xacro:property name=\"glob\" value=\"g${v}\" scope=\"global\"/></xacro:macro>"
      "<xacro:macro name=\"user\" params=\"v\"><xacro:reader v=\"${v}\"/><u got=\"${got}\"/><xacro:inner/></xacro:macro>"
      "<xacro:macro name=\"inner\" params=\"v:=^ w:=^|dflt got:=^\"><in v=\"${v}\" w=\"${w}\" got=\"${got}\"/></xacro:macro>"
      "<xacro:user v=\"4\"/><after glob=\"${glob}\"/>"
      // xacro:element, xacro:attribute, xacro:call
      "<xacro:property name=\"tag\" value=\"made\"/><xacro:element xacro:name=\"${tag}_el\" k=\"1\"><xacro:attribute name=\"extra\" value=\"${late}\"/></xacro:element>"
      "<xacro:macro name=\"named\" params=\"q\"><n q=\"${q}\"/></xacro:macro><xacro:call macro=\"${'na' + 'med'}\" q=\"9\"/>"
      // a macro parameter keeps a dict value
      "<xacro:macro name=\"takes\" params=\"d:=${dict(a=1,b=2)}\"><t b=\"${d['b']}\"/></xacro:macro><xacro:takes/>"
      "<xacro:takes d=\"${dict(b=5)}\"/>"
      // quoted defaults, as ur10_macro.xacro writes prefix:=''
      "<xacro:macro name=\"quoted\" params=\"a:='x y' b:=''\"><q a=\"${a}\" b=\"[${b}]\"/></xacro:macro><xacro:quoted/>\n");
  for (const char* want : {"a=\"42\"", "b=\"3.14\"", "c=\"True\"", "d=\"b c\"", "e=\"2\"", "f=\"calib_1\"", "g=\"1\"",
                           "h=\"y\"", "i=\"[1, 2, 3]\"", "j=\"1\"", "k=\"True\"", "l=\"w\"", "m=\"True\"", "n=\"3\"",
                           "o=\"5.5\"", "p=\"from_env\"", "q=\"fall back\"", "r=\"7\"", "s=\"left_x\"", "t=\"6\"",
                           "u=\"None\"", "v=\"0.5\"", "w=\"0\"", "<u got=\"40\"/>", "<in v=\"4\" w=\"dflt\" got=\"40\"/>",
                           "<after glob=\"g4\"/>", "<q a=\"x y\" b=\"[]\"/>", "<made_el k=\"1\" extra=\"21\"/>", "<n q=\"9\"/>", "<t b=\"2\"/>", "<t b=\"5\"/>"})
    has(x, want);
  // The untaken branch is never evaluated (`nope` is unknown); the root's attributes may use
  // an arg declared inside it.
  write("rootarg.xacro", "<robot xmlns:xacro=\"http://wiki.ros.org/xacro\" name=\"$(arg n)\"><xacro:arg name=\"n\" default=\"named\"/></robot>\n");
  has(expand_xacro((scratch() / "rootarg.xacro").string(), PackagePath{}, {}), "<robot name=\"named\"/>");
  // ns= includes: the file's macros as ns.macro.
  write("nsinc.xacro", std::string(kNs) + "<xacro:macro name=\"part\" params=\"\"><from_ns/></xacro:macro></robot>\n");
  has(expand("<xacro:include filename=\"nsinc.xacro\" ns=\"lib\"/><xacro:lib.part/>"), "<from_ns/>");
}

TEST_CASE("xacro: a robot through relative includes loads with the computed values", "[urdf][xacro]") {
  write("inc/part.xacro", std::string(kNs) + "<xacro:property name=\"z\" value=\"${0.1 * 3}\"/></robot>\n");
  const fs::path top = write("rel.xacro", std::string(kNs) + "<xacro:include filename=\"inc/part.xacro\"/>" +
                                              joint("${z}", "${radians(-90)}", "${pi / 2}") + "</robot>\n");
  const Robot r = must(load_urdf(top.string()));
  REQUIRE(r.joint_count() == 1);
  CHECK(r.lower[0] == Approx(-90).epsilon(1e-12));
  CHECK(r.upper[0] == Approx(90).epsilon(1e-12));
  CHECK(r.chain[0].origin.translation().z() == Approx(300).epsilon(1e-12));
}

TEST_CASE("xacro: errors name file, line and construct", "[urdf][xacro]") {
  has(error_of("\n<e v=\"${nope}\"/>"), "t.xacro:3: xacro: unknown property 'nope'");
  has(error_of("<e v=\"${1 / 0}\"/>"), "division by zero");
  has(error_of("<e v=\"${(1 + 2}\"/>"), "missing ')'");
  has(error_of("<e v=\"${1 +}\"/>"), "incomplete expression");
  has(error_of("<e v=\"${'a' * 2}\"/>"), "'a' is not a number");
  has(error_of("<e v=\"${sqrt(-1)}\"/>"), "sqrt() gives no finite number");
  has(error_of("<e v=\"${10 ** 400}\"/>"), "no finite number");
  has(error_of("<e v=\"${xacro.load_yaml('none.yaml')}\"/>"), "load_yaml('none.yaml')");
  write("bad.yaml", "a: [1, 2\n");
  has(error_of("\n<e v=\"${load_yaml('bad.yaml')['a']}\"/>"), "t.xacro:3: xacro: load_yaml('bad.yaml')");
  write("deep.yaml", std::string(500, '[') + std::string(500, ']') + "\n");
  has(error_of("<e v=\"${load_yaml('deep.yaml')}\"/>"), "nested more than 200 levels");
  std::string dashes;
  for (int i = 0; i < 5000; ++i) dashes += "- ";
  write("dashes.yaml", dashes + "x\n");
  has(error_of("<e v=\"${load_yaml('dashes.yaml')}\"/>"), "nested more than 200 levels");
  std::string indented;
  for (int i = 0; i < 3000; ++i) indented += std::string(static_cast<std::size_t>(i), ' ') + "k:\n";
  write("indented.yaml", indented);
  has(error_of("<e v=\"${load_yaml('indented.yaml')}\"/>"), "nested more than 200 levels");
  has(error_of("<e v=\"${1 if True}\"/>"), "'if' without 'else'");
  has(error_of("<e v=\"$(env ASIMOV_SURELY_UNSET_VARIABLE)\"/>"), "the environment variable is not set");
  has(error_of("<e v=\"$(export x)\"/>"), "unsupported substitution $(export x)");
  has(error_of("<e v=\"${[1, 2][5]}\"/>"), "index 5 out of range");
  has(error_of("<e v=\"${dict(a=1)['b']}\"/>"), "no key 'b'");
  has(error_of("<e v=\"${(1).x}\"/>"), "has no attribute 'x'");
  has(error_of("\n<xacro:property name=\"p\" value=\"${p + 1}\"/><e v=\"${p}\"/>"), "t.xacro:3: xacro: property defined by itself");
  has(error_of("<xacro:element/>"), "needs the attribute 'xacro:name'");
  has(error_of("<e><xacro:attribute name=\"a b\" value=\"1\"/></e>"), "bad attribute name 'a b'");
  has(error_of("<xacro:element xacro:name=\"a&lt;b\"/>"), "bad element name 'a<b'");
  has(error_of("<xacro:call macro=\"none\"/>"), "<xacro:call macro=\"none\">: unknown macro");
  has(error_of("<e v=\"$(arg missing)\"/>"), "$(arg missing): no value");
  has(error_of("<e v=\"$(find no_such_pkg)\"/>"), "no package 'no_such_pkg'");
  has(error_of("<e v=\"${1\"/>"), "unterminated ${");
  has(error_of("<xacro:nomacro/>"), "unknown macro");
  has(error_of("<xacro:macro name=\"m\" params=\"a\"/><xacro:m/>"), "missing the parameter 'a'");
  has(error_of("<xacro:macro name=\"m\" params=\"a\"/><xacro:m a=\"1\" b=\"2\"/>"), "no parameter 'b'");
  has(error_of("<xacro:macro name=\"m\" params=\"*o\"/><xacro:m/>"), "missing the block parameter '*o'");
  has(error_of("<xacro:macro name=\"m\" params=\"a:=^\"/><xacro:m/>"), "parameter 'a:=^': no property 'a' in the caller's scope");
  has(error_of("<xacro:insert_block name=\"none\"/>"), "no such block");
  has(error_of("<xacro:if value=\"maybe\"/>"), "a boolean or a number is expected");
  has(error_of("<xacro:arg name=\"q\"/>"), "no default and no value");
  has(error_of("<xacro:include filename=\"missing.xacro\"/>"), "<xacro:include>");
  has(error_of("<e>"), "XML error");
}

TEST_CASE("xacro: hostile input: cycles, recursion, include depth, size", "[urdf][xacro]") {
  // A file including itself, and two including each other.
  has(error_of("<xacro:include filename=\"self.xacro\"/>", "self.xacro"), "include cycle");
  write("b.xacro", std::string(kNs) + "<xacro:include filename=\"a.xacro\"/></robot>\n");
  has(error_of("<xacro:include filename=\"b.xacro\"/>", "a.xacro"), "include cycle");
  // A chain of 70 distinct files.
  for (int i = 0; i < 70; ++i)
    write("deep/d" + std::to_string(i) + ".xacro",
          std::string(kNs) + "<xacro:include filename=\"d" + std::to_string(i + 1) + ".xacro\"/></robot>\n");
  write("deep/d70.xacro", std::string(kNs) + "</robot>\n");
  try {
    expand_xacro((scratch() / "deep/d0.xacro").string(), PackagePath{}, {});
    FAIL("no error");
  } catch (const UrdfError& e) {
    has(e.what(), "includes nested more than 64 deep");
  }
  // A macro calling itself.
  has(error_of("<xacro:macro name=\"r\" params=\"\"><xacro:r/></xacro:macro><xacro:r/>"), "macros nested more than 64 deep");
  // Expressions nested 100,000 deep (brackets, minus signs, 'not'), properties defined by a
  // 1,000-long chain of properties: bounded, an error each, no stack overflow.
  has(error_of("<e v=\"${" + std::string(100000, '[') + std::string(100000, ']') + "}\"/>"), "nested more than 200 deep");
  has(error_of("<e v=\"${" + std::string(100000, '-') + "1}\"/>"), "nested more than 200 deep");
  std::string nots;
  for (int i = 0; i < 20000; ++i) nots += "not ";
  has(error_of("<e v=\"${" + nots + "1}\"/>"), "nested more than 200 deep");
  has(error_of("<e v=\"${" + std::string(100000, '(') + "1" + std::string(100000, ')') + "}\"/>"), "nested too deeply");
  std::string chain = "<xacro:property name=\"p0\" value=\"1\"/>";
  for (int i = 1; i <= 1000; ++i)
    chain += "<xacro:property name=\"p" + std::to_string(i) + "\" value=\"${p" + std::to_string(i - 1) + " + 1}\"/>";
  has(error_of(chain + "<e v=\"${p1000}\"/>"), "properties nested more than 200 deep");
  // Exponential growth: each level doubles (2^40 elements): stopped at the size bound, quickly.
  std::string body = "<xacro:macro name=\"m0\" params=\"\"><leaf long=\"" + std::string(10000, 'x') + "\"/></xacro:macro>";
  for (int i = 1; i <= 40; ++i)
    body += "<xacro:macro name=\"m" + std::to_string(i) + "\" params=\"\"><xacro:m" + std::to_string(i - 1) +
            "/><xacro:m" + std::to_string(i - 1) + "/></xacro:macro>";
  has(error_of(body + "<xacro:m40/>"), "the expansion exceeds 64 MiB");
}

TEST_CASE("xacro: load_yaml angles tagged !degrees / !radians, as ur_description's joint_limits.yaml", "[urdf][xacro]") {
  write("cfg/joint_limits.yaml",
        "joint_limits:\n  shoulder_pan_joint:\n    max_position: !degrees  360.0\n    min_position: !degrees -360.0\n"
        "    max_velocity: !degrees  180.0\n  elbow_joint:\n    max_position: !radians pi / 2\n    min_position: !radians -0.5\n"
        "  list: [!degrees 90, 1]\n");
  const fs::path top = write(
      "urlim.xacro",
      std::string(kNs) +
          "<xacro:property name=\"lim\" value=\"${xacro.load_yaml('cfg/joint_limits.yaml')['joint_limits']}\"/>"
          "<xacro:property name=\"pan\" value=\"${lim['shoulder_pan_joint']}\"/>"
          "<e l=\"${lim.list[0]}\" el=\"${lim.elbow_joint.max_position}\" m=\"${lim.elbow_joint.min_position}\"/>"
          "<link name=\"a\"/><link name=\"b\"/><joint name=\"j\" type=\"revolute\"><parent link=\"a\"/><child link=\"b\"/>"
          "<axis xyz=\"0 0 1\"/><limit lower=\"${pan.min_position}\" upper=\"${pan.max_position}\" velocity=\"${pan.max_velocity}\"/></joint>"
          "</robot>\n");
  const std::string x = expand_xacro(top.string(), PackagePath{}, {});
  has(x, "l=\"1.5707963267948966\"");
  has(x, "el=\"1.5707963267948966\"");
  has(x, "m=\"-0.5\"");
  const Robot r = must(load_urdf(top.string()));
  CHECK(r.upper[0] == Approx(360).epsilon(1e-12));  // not 360 rad = 20626 deg
  CHECK(r.lower[0] == Approx(-360).epsilon(1e-12));
  CHECK(r.max_velocity[0] == Approx(180).epsilon(1e-12));
  // A tag on something that is not a number, and a tagged expression that is not a number.
  write("cfg/bad1.yaml", "a: !degrees [1, 2]\n");
  has(error_of("<e v=\"${xacro.load_yaml('cfg/bad1.yaml')}\"/>"), "!degrees tags a number");
  write("cfg/bad2.yaml", "a: !radians 'text'\n");
  has(error_of("<e v=\"${xacro.load_yaml('cfg/bad2.yaml')}\"/>"), "load_yaml: 'text': unknown property 'text'");
}

TEST_CASE("xacro: Python slices, comprehensions, tuples, builtins and string methods", "[urdf][xacro]") {
  const std::string x = expand(
      "<xacro:property name=\"l\" value=\"${[1, 2, 3, 4, 5]}\"/><xacro:property name=\"s\" value=\"Arm_Link\"/>"
      "<xacro:property name=\"d\" value=\"${dict(a=1, b=2)}\"/>"
      "<e a=\"${l[1:3]}\" b=\"${l[::-1]}\" c=\"${l[-2:]}\" d=\"${s[:3]}\" e=\"${l[::2]}\" f=\"${l[1:-1:2]}\" g=\"${l[10:]}\""
      " h=\"${[x * 2 for x in l if x % 2]}\" i=\"${[k + '=' + str(v) for k, v in d.items()]}\" j=\"${sum(x for x in l)}\""
      " k=\"${{k: v * 10 for k, v in d.items()}}\" m=\"${(1, 'a')}\" n=\"${(7,)}\" o=\"${s.upper()} ${s.lower()}\""
      " p=\"${'-'.join(s.split('_'))}\" q=\"${s.replace('_', ' ').strip()}\" r=\"${s.startswith('Arm')} ${s.endswith('x')}\""
      " t=\"${'{}_{:.2f}_{n}'.format('j', 1.5, n=3)}\" u=\"${sorted([3, 1, 2])} ${list(range(3))} ${max(l)} ${min([4, 2])}\""
      " v=\"${[i for i, x in enumerate(['a', 'b'])]} ${list(zip([1, 2], 'ab'))}\" w=\"${any([0, 1])} ${all([])} ${len(l[1:])}\""
      " y=\"${d.get('z', 'none')} ${d.get('a')} ${list(d.keys())} ${l.index(3)} ${'  x '.strip()} ${' a  b '.split()}\""
      " z=\"${python.sorted('cba')} ${'arm'.capitalize()} ${'a b'.title()} ${'7'.zfill(3)} ${s.find('L')} ${s.count('a')}\"/>\n");
  for (const char* want : {"a=\"[2, 3]\"", "b=\"[5, 4, 3, 2, 1]\"", "c=\"[4, 5]\"", "d=\"Arm\"", "e=\"[1, 3, 5]\"", "f=\"[2, 4]\"",
                           "g=\"[]\"", "h=\"[2, 6, 10]\"", "i=\"['a=1', 'b=2']\"", "j=\"15\"", "k=\"{'a': 10, 'b': 20}\"",
                           "m=\"(1, 'a')\"", "n=\"(7,)\"", "o=\"ARM_LINK arm_link\"", "p=\"Arm-Link\"", "q=\"Arm Link\"",
                           "r=\"True False\"", "t=\"j_1.50_3\"", "u=\"[1, 2, 3] [0, 1, 2] 5 2\"", "v=\"[0, 1] [(1, 'a'), (2, 'b')]\"",
                           "w=\"True True 4\"", "y=\"none 1 ['a', 'b'] 2 x ['a', 'b']\"", "z=\"['a', 'b', 'c'] Arm A B 007 4 0\""})
    has(x, want);
  // Errors: file, line and construct; the bounds hold.
  has(error_of("<e v=\"${[x for x in range(10**8)]}\"/>"), "range() of more than");
  has(error_of("<e v=\"${[1, 2][::0]}\"/>"), "slice step cannot be zero");
  has(error_of("<e v=\"${[x for x in 5]}\"/>"), "not iterable");
  has(error_of("<e v=\"${[x for x in [1] for y in [2]]}\"/>"), "nested 'for'");
  has(error_of("<e v=\"${[a for a, b in [1, 2]]}\"/>"), "cannot unpack");
  has(error_of("\n<e v=\"${'a'.format(x=1) + '{}'.format()}\"/>"), "t.xacro:3");
}

TEST_CASE("xacro: $(anon), namespaced include properties, arg defaults, nested load_yaml keys", "[urdf][xacro]") {
  write("nsprops.xacro", std::string(kNs) + "<xacro:property name=\"width\" value=\"${base * 2}\"/>"
                                            "<xacro:macro name=\"m\" params=\"\"><m/></xacro:macro></robot>\n");
  write("cfg/nested.yaml", "arm:\n  joints:\n    - name: j1\n      limits: {max: 2.5, min: -2.5}\n    - name: j2\n      limits: {max: 1, min: 0}\n");
  const std::string x = expand(
      "<xacro:property name=\"base\" value=\"21\"/><xacro:include filename=\"nsprops.xacro\" ns=\"lib\"/>"
      "<xacro:arg name=\"robot\" default=\"ur5\"/><xacro:arg name=\"prefix\" default=\"$(arg robot)_\"/>"
      "<xacro:arg name=\"flag\" default=\"false\"/>"
      "<xacro:property name=\"cfg\" value=\"${load_yaml('cfg/nested.yaml')}\"/>"
      "<e ns=\"${lib.width}\" a1=\"$(anon node)\" a2=\"$(anon node)\" a3=\"$(anon other)\" p=\"$(arg prefix)\""
      " f=\"${'on' if $(arg flag) else 'off'}\" y=\"${cfg['arm']['joints'][1]['limits']['max']} ${cfg.arm.joints[0].limits.min}\""
      " n=\"${[j.name for j in cfg.arm.joints]}\"/><xacro:lib.m/>\n",
      {{"flag", "true"}});
  has(x, "ns=\"42\"");
  has(x, "p=\"ur5_\"");
  has(x, "f=\"on\"");
  has(x, "y=\"1 -2.5\"");
  has(x, "n=\"['j1', 'j2']\"");
  has(x, "<m/>");
  // $(anon NAME): one value per name within an expansion, different names differ, and the same
  // file expands the same way twice (reproducible cells).
  const auto attr = [&](const std::string& text, const std::string& name) {
    const std::size_t b = text.find(name + "=\"") + name.size() + 2;
    return text.substr(b, text.find('"', b) - b);
  };
  CHECK(attr(x, "a1").rfind("node_", 0) == 0);
  CHECK(attr(x, "a1") == attr(x, "a2"));
  CHECK(attr(x, "a1") != attr(x, "a3"));
  CHECK(attr(x, "a3").rfind("other_", 0) == 0);
  // A namespace's properties are its own: an unknown one is an error naming it.
  has(error_of("<xacro:property name=\"base\" value=\"1\"/><xacro:include filename=\"nsprops.xacro\" ns=\"lib\"/><e v=\"${lib.nope}\"/>"),
      "no property 'nope' in the namespace");
}

TEST_CASE("xacro: the xacro namespace's helpers: arg, abs_filename, dotify, error", "[urdf][xacro]") {
  // Exported and generated descriptions test arguments inside expressions:
  // ${xacro.arg('ros_profile') == 'ros1' and ...}; arguments are strings there.
  write("sub/part.yaml", "size: 3\n");
  const std::string x = expand(
      "<xacro:arg name=\"ros_profile\" default=\"ros2\"/><xacro:arg name=\"n\" default=\"4\"/>"
      "<xacro:if value=\"${xacro.arg('ros_profile') == 'ros1'}\"><ros1/></xacro:if>"
      "<xacro:if value=\"${xacro.arg('ros_profile') == 'ros2' and int(xacro.arg('n')) > 3}\"><ros2/></xacro:if>"
      "<xacro:property name=\"arg\" value=\"7\"/>"  // a property may be called arg
      "<xacro:property name=\"d\" value=\"${xacro.dotify(xacro.load_yaml(xacro.abs_filename('sub/part.yaml')))}\"/>"
      "<e a=\"${arg}\" s=\"${d.size}\" f=\"${xacro.abs_filename('sub/part.yaml')}\"/>\n",
      {{"n", "5"}});
  has(x, "<ros2/>");
  CHECK(x.find("<ros1/>") == std::string::npos);
  has(x, "a=\"7\"");
  has(x, "s=\"3\"");
  has(x, "f=\"" + (scratch() / "sub/part.yaml").lexically_normal().string() + "\"");
  // abs_filename of a package:// URI is the file in the package.
  PackagePath packages;
  packages.add_root(kWorkspace);
  const std::string pkg = expand_xacro(
      write("p.xacro", std::string(kNs) + "<e f=\"${xacro.abs_filename('package://asimov_demo_support/package.xml')}\"/></robot>\n").string(),
      packages, {});
  has(pkg, "f=\"" + fs::absolute(kPackage / "package.xml").lexically_normal().string() + "\"");
  has(error_of("<e v=\"${xacro.arg('missing')}\"/>"), "xacro.arg('missing'): no such argument");
  has(error_of("<xacro:if value=\"${True}\">\n<e v=\"${xacro.error('this arm needs a tip')}\"/></xacro:if>"),
      "t.xacro:3: xacro: xacro.error: this arm needs a tip");
  has(error_of("<e v=\"${xacro.dotify(1)}\"/>"), "xacro.dotify() takes a dict");
}

TEST_CASE("xacro: properties with lazy_eval=\"false\" and remove=\"true\"", "[urdf][xacro]") {
  // lazy_eval="false": evaluated where it is defined, so it may build on the property of the same
  // name already visible (lazily that is a cycle) and keeps the value of that moment.
  const std::string x = expand(
      "<xacro:arg name=\"use_ir\" default=\"true\"/>"
      "<xacro:property name=\"use_ir\" value=\"$(arg use_ir)\" lazy_eval=\"false\"/>"
      "<xacro:property name=\"n\" value=\"1\"/>"
      "<xacro:property name=\"m\" value=\"${n * 10}\" lazy_eval=\"false\"/>"
      "<xacro:property name=\"l\" value=\"${n * 10}\"/>"
      "<xacro:macro name=\"grow\" params=\"\"><xacro:property name=\"n\" value=\"${n + 1}\" lazy_eval=\"false\" scope=\"parent\"/></xacro:macro>"
      "<xacro:grow/><xacro:grow/>"
      "<xacro:property name=\"gone\" value=\"1\"/><xacro:property name=\"gone\" remove=\"true\"/>"
      "<xacro:property name=\"kept\" value=\"2\"/><xacro:property name=\"kept\" remove=\"false\"/>"
      "<e ir=\"${use_ir}\" n=\"${n}\" m=\"${m}\" l=\"${l}\" k=\"${kept}\"/>\n",
      {{"use_ir", "false"}});
  has(x, "ir=\"False\"");
  has(x, "n=\"3\"");
  has(x, "m=\"10\"");  // eager: n was 1
  has(x, "l=\"30\"");  // lazy: n is 3 when used
  has(x, "k=\"2\"");
  has(error_of("<xacro:property name=\"gone\" value=\"1\"/><xacro:property name=\"gone\" remove=\"true\"/>\n<e v=\"${gone}\"/>"),
      "unknown property 'gone'");
  has(error_of("<xacro:property name=\"p\" value=\"${p + 1}\"/>\n<e v=\"${p}\"/>"), "cycle");
  has(error_of("<xacro:property name=\"p\" remove=\"maybe\"/>"), "remove=\"maybe\"");
}
