// Limits as the description wrote them: a URDF limit rounded to its file's precision
// (IRB 6600's J3 upper 1.04719755 rad = 59.99999996 deg) accepts the value it stands for, in
// limit checks and in IK, and no more than that; degenerate mesh faces are one warning per mesh.
#include "asimov/collision/polyhedron.hpp"
#include "asimov/robots/displacement_bound.hpp"
#include "asimov/robots/ik.hpp"
#include "asimov/robots/urdf_loader.hpp"

#include "support/joints.hpp"
#include "support/result.hpp"
#include "support/scratch.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <filesystem>
#include <numbers>
#include <random>
#include <fstream>
#include <sstream>

using namespace asimov;
using namespace asimov::robots;
using asimov::test::jv;
using asimov::test::must;
namespace fs = std::filesystem;

namespace {
std::string generic6_with(const std::string& from, const std::string& to) {
  std::ifstream in(fs::path(ASIMOV_SOURCE_DIR) / "robots/data/generic6.urdf");
  std::stringstream ss;
  ss << in.rdbuf();
  std::string text = ss.str();
  const std::size_t at = text.find(from);
  REQUIRE(at != std::string::npos);
  return text.replace(at, from.size(), to);
}
}  // namespace

TEST_CASE("URDF limits: compared with the precision the file wrote them with", "[urdf][limits]") {
  const Robot r = must(load_urdf_text(generic6_with("upper=\"1.2217304763960306\"", "upper=\"1.04719755\""), "irb.urdf"));
  REQUIRE(r.upper[2] < 60.0);                      // 59.99999996...
  CHECK(r.upper[2] == Approx(60.0).margin(1e-6));  // but it means 60
  CHECK(r.limit_tolerance[2] == Approx(0.5e-8 * 180 / 3.14159265358979).epsilon(1e-9));
  CHECK(first_limit_violation(r, jv({0, 0, 60, 0, 0, 0})) == -1);
  CHECK(first_limit_violation(r, jv({0, 0, 60.00001, 0, 0, 0})) == 2);  // past the written precision
  CHECK(limit_high(r, 2) > 60.0);
  CHECK(limit_high(r, 2) < 60.000001);
  // IK to the pose at J3 = 60 returns it (the closed form and the numeric solver alike).
  const JointVector q = jv({10, 20, 60, 30, 40, 50});
  const Pose target = flange_pose(r, q);
  const IkResult ik = solve_ik(r, target, jv({9, 19, 58, 29, 39, 49}), configuration_of(r, q), false);
  REQUIRE(ik.status == IkStatus::ok);
  CHECK((ik.joints - q).cwiseAbs().maxCoeff() < 1e-6);
  NumericIkOptions o;
  const NumericIkResult num = solve_numeric(r, target, jv({9, 19, 58, 29, 39, 49}), o);
  REQUIRE(num.success);
  CHECK(num.joints[2] == Approx(60).margin(1e-6));
  // Limits written exactly (many digits, as xacro writes them) keep a tolerance below 1e-9 deg,
  // and a short number is not stretched past 0.001 deg ("3.14" is not pi).
  const Robot g = must(load_urdf_text(generic6_with("upper=\"1.2217304763960306\"", "upper=\"3.14\""), "short.urdf"));
  CHECK(g.limit_tolerance[0] < 1e-9);
  CHECK(g.limit_tolerance[2] == Approx(1e-3));
  CHECK(first_limit_violation(g, jv({0, 0, 180, 0, 0, 0})) == 2);
  CHECK(first_limit_violation(g, jv({0, 0, 3.14 * 180 / 3.14159265358979 + 0.0009, 0, 0, 0})) == -1);
  // Exponents count: 1.5e-1 has its last digit at 1e-2.
  const Robot e = must(load_urdf_text(generic6_with("upper=\"1.2217304763960306\"", "upper=\"1.2217e0\""), "exp.urdf"));
  CHECK(e.limit_tolerance[2] == Approx(1e-3));  // 5e-5 rad = 0.0029 deg, capped
}

TEST_CASE("URDF meshes: zero-area faces are one warning per mesh with the count", "[urdf][mesh]") {
  const fs::path dir = asimov::test::scratch_dir("urdf_limits");
  // A closed tetrahedron plus 150 slivers (three collinear points each).
  std::ofstream obj(dir / "sliver.obj");
  obj << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nv 0.5 0 0\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
  for (int i = 0; i < 150; ++i) obj << "f 1 5 2\n";
  obj.close();
  const std::string urdf =
      "<robot name=\"m\"><link name=\"a\"/><link name=\"b\"><collision><geometry><mesh filename=\"sliver.obj\" "
      "scale=\"0.1 0.1 0.1\"/></geometry></collision></link><joint name=\"j\" type=\"revolute\"><parent link=\"a\"/>"
      "<child link=\"b\"/><axis xyz=\"0 0 1\"/><limit lower=\"-1\" upper=\"1\" velocity=\"1\"/></joint></robot>";
  const Robot r = must(load_urdf_text(urdf, "m.urdf", dir.string()));
  std::size_t zero = 0;
  for (const auto& w : r.warnings) {
    INFO(w);
    if (w.find("zero area") != std::string::npos) {
      ++zero;
      CHECK(w.find("150 faces of zero area dropped (faces 5, 6, 7, 8, 9, ...)") != std::string::npos);
      CHECK(w.rfind("m.urdf:1: ", 0) == 0);
    }
  }
  CHECK(zero == 1);
}

namespace {
// A 4-axis arm whose wrist is split in two: j3b (on the chain, after the link j3 moves) follows
// j3 with multiplier `m` and offset `o`; `expanded` writes the same chain with j3b a free joint.
std::string split_wrist(bool expanded, double m, double o) {
  const std::string mimic = expanded ? "" : "<mimic joint=\"j3\" multiplier=\"" + std::to_string(m) + "\" offset=\"" + std::to_string(o) + "\"/>";
  return "<robot name=\"split\"><link name=\"base\"/><link name=\"l1\"><collision><origin xyz=\"0 0 0.1\"/><geometry><box size=\"0.1 0.1 0.2\"/></geometry></collision></link>"
         "<link name=\"l2\"><collision><origin xyz=\"0.15 0 0\"/><geometry><box size=\"0.3 0.08 0.08\"/></geometry></collision></link>"
         "<link name=\"l3\"/><link name=\"l3b\"><collision><origin xyz=\"0.05 0 0\"/><geometry><box size=\"0.1 0.05 0.05\"/></geometry></collision></link>"
         "<link name=\"l4\"><collision><origin xyz=\"0 0 0.03\"/><geometry><cylinder radius=\"0.03\" length=\"0.06\"/></geometry></collision></link>"
         "<joint name=\"j1\" type=\"revolute\"><parent link=\"base\"/><child link=\"l1\"/><axis xyz=\"0 0 1\"/><limit lower=\"-3\" upper=\"3\" velocity=\"1\"/></joint>"
         "<joint name=\"j2\" type=\"revolute\"><parent link=\"l1\"/><child link=\"l2\"/><origin xyz=\"0 0 0.2\"/><axis xyz=\"0 1 0\"/><limit lower=\"-2\" upper=\"2\" velocity=\"1\"/></joint>"
         "<joint name=\"j3\" type=\"revolute\"><parent link=\"l2\"/><child link=\"l3\"/><origin xyz=\"0.3 0 0\"/><axis xyz=\"0 1 0\"/><limit lower=\"-2\" upper=\"2\" velocity=\"1\"/></joint>"
         "<joint name=\"j3b\" type=\"revolute\"><parent link=\"l3\"/><child link=\"l3b\"/><origin xyz=\"0.05 0 0\" rpy=\"0 0 0.3\"/><axis xyz=\"1 0 0\"/><limit lower=\"-3\" upper=\"3\" velocity=\"1\"/>" +
         mimic + "</joint>"
         "<joint name=\"j4\" type=\"revolute\"><parent link=\"l3b\"/><child link=\"l4\"/><origin xyz=\"0.1 0 0\"/><axis xyz=\"1 0 0\"/><limit lower=\"-3\" upper=\"3\" velocity=\"1\"/></joint>"
         "</robot>";
}
}  // namespace

TEST_CASE("URDF: a coupled (mimic) joint on the arm chain is modelled", "[urdf][mimic]") {
  const double m = -0.5, o = 0.2;
  const Robot r = must(load_urdf_text(split_wrist(false, m, o), "split.urdf"));
  const Robot free = must(load_urdf_text(split_wrist(true, m, o), "free.urdf", ".", UrdfOptions{.tip = "l4"}));
  REQUIRE(r.joint_count() == 4);  // j3b is no joint of its own
  REQUIRE(free.joint_count() == 5);
  REQUIRE(r.chain[2].coupled.size() == 1);
  CHECK(r.chain[2].coupled[0].name == "j3b");
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-100, 100);
  for (int i = 0; i < 200; ++i) {
    const JointVector q = jv({u(rng), u(rng) * 0.9, u(rng) * 0.9, u(rng)});
    JointVector qf(5);
    qf << q[0], q[1], q[2], m * q[2] + o * 180 / std::numbers::pi, q[3];
    std::vector<Pose> a, b;
    link_frames(r, q, a);
    link_frames(free, qf, b);
    CHECK((a.back().matrix() - b.back().matrix()).norm() < 1e-9);  // the flange
    // Bodies: l3b rides with j3 and j3b (frame 3 of the coupled model = after j3b).
    for (const auto& body : r.bodies) {
      const auto other = std::find_if(free.bodies.begin(), free.bodies.end(), [&](const LinkBody& x) { return x.name == body.name; });
      REQUIRE(other != free.bodies.end());
      const Pose pa = a[static_cast<std::size_t>(body.link)], pb = b[static_cast<std::size_t>(other->link)];
      for (std::size_t v = 0; v < body.mesh.vertices.size(); v += 3)
        CHECK((pa * body.mesh.vertices[v] - pb * other->mesh.vertices[v]).norm() < 1e-9);
    }
    // The displacement bound still holds for the coupled motion.
    const JointVector dq = jv({0, 0, u(rng) * 0.01, 0});
    std::vector<Pose> c;
    link_frames(r, q + dq, c);
    for (const auto& body : r.bodies) {
      const BodyReach reach = body_reach(r, body);
      double moved = 0;
      for (const auto& v : body.mesh.vertices)
        moved = std::max(moved, (c[static_cast<std::size_t>(body.link)] * v - a[static_cast<std::size_t>(body.link)] * v).norm());
      CHECK(moved <= max_displacement(reach, dq) + 1e-9);
    }
  }
  // IK (numeric, with the coupled Jacobian columns) reaches poses of the coupled arm.
  const JointVector q = jv({20, 30, -40, 10});
  NumericIkOptions opt;
  const NumericIkResult ik = solve_numeric(r, flange_pose(r, q), jv({15, 25, -30, 0}), opt);
  REQUIRE(ik.success);
  CHECK((flange_pose(r, ik.joints).translation() - flange_pose(r, q).translation()).norm() < 1e-6);
}

TEST_CASE("URDF: coupled joints that cannot be folded are refused naming them", "[urdf][mimic]") {
  // j3b follows j2, not the joint just before it.
  std::string text = split_wrist(false, 1, 0);
  text.replace(text.find("joint=\"j3\""), 10, "joint=\"j2\"");
  const auto bad = load_urdf_text(text, "bad.urdf");
  REQUIRE_FALSE(bad);
  CHECK(bad.error().message.find("'j3b' on the arm chain mimics 'j2', not the movable joint just before it ('j3')") != std::string::npos);
  // Geometry on the link between the joint and its follower.
  std::string geo = split_wrist(false, 1, 0);
  geo.replace(geo.find("<link name=\"l3\"/>"), 17, "<link name=\"l3\"><collision><geometry><box size=\"0.01 0.01 0.01\"/></geometry></collision></link>");
  const auto bad2 = load_urdf_text(geo, "bad2.urdf");
  REQUIRE_FALSE(bad2);
  CHECK(bad2.error().message.find("link 'l3' between them has collision geometry") != std::string::npos);
}
