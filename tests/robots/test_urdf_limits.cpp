// Limits as the description wrote them: a URDF limit rounded to its file's precision
// (IRB 6600's J3 upper 1.04719755 rad = 59.99999996 deg) accepts the value it stands for, in
// limit checks and in IK, and no more than that; degenerate mesh faces are one warning per mesh.
#include "asimov/collision/polyhedron.hpp"
#include "asimov/robots/ik.hpp"
#include "asimov/robots/urdf_loader.hpp"

#include "support/joints.hpp"
#include "support/result.hpp"
#include "support/scratch.hpp"

#include <catch2/catch.hpp>

#include <filesystem>
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
