// URDF arms: the PUMA written as URDF reproduces the DH FK, the generic 6-axis arm loads and
// its numeric IK converges, the displacement bound holds for a chain, bad input is reported
// with file and line, STL meshes (collision::read_mesh) and tessellated spheres.
#include "support/scratch.hpp"
#include "asimov/robots/displacement_bound.hpp"
#include "asimov/robots/ik.hpp"
#include "asimov/robots/puma560.hpp"
#include "asimov/robots/urdf_loader.hpp"

#include "support/joints.hpp"
#include "support/result.hpp"

#include <catch2/catch.hpp>
#include <Eigen/Geometry>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <random>
#include <unistd.h>

using namespace asimov;
using asimov::test::must;
using namespace asimov::robots;

using asimov::test::random_joints;

namespace {
const std::string kData = std::string(ASIMOV_SOURCE_DIR) + "/robots/data/";

// Signed volume of a closed triangle mesh (positive when the triangles face outward).
double volume(const collision::Polyhedron& m) {
  double v = 0;
  for (const auto& t : m.triangles) v += m.vertices[t[0]].dot(m.vertices[t[1]].cross(m.vertices[t[2]])) / 6;
  return v;
}

std::string error_of(const std::string& xml) {
  return asimov::test::error_message(load_urdf_text(xml, "bad.urdf"));
}

const char* const kHead = "<?xml version=\"1.0\"?>\n<robot name=\"t\">\n<link name=\"a\"/>\n<link name=\"b\"/>\n";
}  // namespace

TEST_CASE("URDF: the PUMA 560 written from the DH table reproduces the DH FK", "[urdf][puma560]") {
  const Robot dh = puma560();
  const Robot u = must(load_urdf(kData + "puma560.urdf"));
  REQUIRE(u.joint_count() == 6);
  REQUIRE(u.is_chain());
  CHECK_FALSE(is_puma_type(u));
  CHECK(is_puma_type(dh));
  for (int i = 0; i < 6; ++i) {
    CHECK(u.lower[i] == Approx(dh.lower[i]).margin(1e-12));
    CHECK(u.upper[i] == Approx(dh.upper[i]).margin(1e-12));
    CHECK(u.max_velocity[i] == Approx(dh.max_velocity[i]).margin(1e-12));
  }
  std::mt19937 rng(7);
  double max_p = 0, max_r = 0;
  std::vector<Pose> fa, fb;
  for (int n = 0; n < 20000; ++n) {
    const JointVector q = random_joints(dh, rng);
    const Pose a = flange_pose(dh, q), b = flange_pose(u, q);
    max_p = std::max(max_p, (a.translation() - b.translation()).norm());
    max_r = std::max(max_r, (a.linear() - b.linear()).norm());
  }
  WARN("PUMA URDF vs DH over 20000 random poses: max position difference " << max_p << " mm, rotation " << max_r);
  CHECK(max_p <= 1e-9);
  CHECK(max_r <= 1e-12);
}

TEST_CASE("URDF: the generic 6-axis arm loads with its bodies and hand-computed zero pose", "[urdf][generic6]") {
  const Robot r = must(load_urdf(kData + "generic6.urdf"));
  CHECK(r.name == "generic6");
  REQUIRE(r.joint_count() == 6);
  CHECK(r.lower[0] == Approx(-170));
  CHECK(r.upper[2] == Approx(70));
  CHECK(r.max_velocity[5] == Approx(405));
  CHECK(r.max_acceleration[5] == Approx(4 * 405));
  CHECK(ready_joints(r) == JointVector::Zero(6));
  // Zero pose: flange at x = 100 + 100 + 320 + 80, z = 200 + 250 + 450; tool Z along +X, X along -Z.
  const Pose f = flange_pose(r, JointVector::Zero(6));
  CHECK((f.translation() - Vec3(600, 0, 900)).norm() < 1e-9);
  CHECK((f.linear().col(2) - Vec3::UnitX()).norm() < 1e-12);
  CHECK((f.linear().col(0) + Vec3::UnitZ()).norm() < 1e-12);
  // J2 +90 tilts the whole arm forward about the shoulder (100, 0, 450).
  JointVector q = JointVector::Zero(6);
  q[1] = 90;
  CHECK((flange_pose(r, q).translation() - Vec3(100 + 450, 0, 450 - 500)).norm() < 1e-9);
  // Bodies: one per link with geometry, frames 0..6, base static.
  std::vector<std::string> names;
  for (const auto& b : r.bodies) names.push_back(b.name + "@" + std::to_string(b.link));
  CHECK(names == std::vector<std::string>{"base_link@0", "link_1@1", "link_2@2", "link_3@3", "link_4@4", "link_5@5", "link_6@6"});
  // link_6's disc is 60..80 mm past the wrist centre, expressed in the flange frame (Z forward).
  const Pose wrist = f * Pose(Eigen::Translation3d(0, 0, -80));
  std::vector<Pose> frames;
  link_frames(r, JointVector::Zero(6), frames);
  double xmin = 1e9, xmax = -1e9;
  for (const auto& v : r.bodies[6].mesh.vertices) {
    const Vec3 w = frames[6] * v;
    xmin = std::min(xmin, w.x() - wrist.translation().x()), xmax = std::max(xmax, w.x() - wrist.translation().x());
  }
  CHECK(xmin == Approx(60).margin(1e-9));
  CHECK(xmax == Approx(80).margin(1e-9));
}

TEST_CASE("URDF: displacement bound holds for a chain arm", "[urdf][bound]") {
  const Robot r = must(load_urdf(kData + "generic6.urdf"));
  std::vector<BodyReach> reach;
  for (const auto& b : r.bodies) reach.push_back(body_reach(r, b.mesh, b.link));
  std::mt19937 rng(99);
  std::uniform_real_distribution<double> step(-3, 3);
  std::vector<Pose> fa, fb;
  double worst = 0;
  for (int n = 0; n < 500; ++n) {
    const JointVector a = random_joints(r, rng);
    JointVector d(6);
    for (int i = 0; i < 6; ++i) d[i] = step(rng);
    link_frames(r, a, fa);
    link_frames(r, a + d, fb);
    for (std::size_t k = 0; k < r.bodies.size(); ++k) {
      const auto& b = r.bodies[k];
      const auto l = static_cast<std::size_t>(b.link);
      double moved = 0;
      for (const auto& v : b.mesh.vertices) moved = std::max(moved, (fa[l] * v - fb[l] * v).norm());
      const double bound = max_displacement(reach[k], d);
      CHECK(moved <= bound + 1e-9);
      if (bound > 0) worst = std::max(worst, moved / bound);
    }
  }
  WARN("generic6: worst measured/bound ratio " << worst);
}

TEST_CASE("URDF: prismatic joints move in mm, bound equals the travel", "[urdf][prismatic]") {
  const std::string xml = std::string(kHead) +
                          "<link name=\"c\"><collision><geometry><box size=\"0.1 0.1 0.1\"/></geometry></collision></link>\n"
                          "<joint name=\"slide\" type=\"prismatic\"><parent link=\"a\"/><child link=\"b\"/>"
                          "<axis xyz=\"0 0 2\"/><limit lower=\"-0.5\" upper=\"0.5\" velocity=\"0.25\"/></joint>\n"
                          "<joint name=\"turn\" type=\"continuous\"><parent link=\"b\"/><child link=\"c\"/>"
                          "<origin xyz=\"0.3 0 0\"/><axis xyz=\"0 0 1\"/></joint>\n</robot>\n";
  const Robot r = must(load_urdf_text(xml, "slide.urdf"));
  REQUIRE(r.joint_count() == 2);
  CHECK(r.prismatic(0));
  CHECK(r.lower[0] == Approx(-500));
  CHECK(r.max_velocity[0] == Approx(250));
  CHECK(r.lower[1] == -360);
  JointVector q(2);
  q << 120, 90;
  const Pose f = flange_pose(r, q);
  CHECK((f.translation() - Vec3(300, 0, 120)).norm() < 1e-9);
  const BodyReach reach = body_reach(r, r.bodies[0].mesh, r.bodies[0].link);
  JointVector d(2);
  d << 7, 0;
  CHECK(max_displacement(reach, d) == Approx(7));
  const NumericIkResult ik = solve_numeric(r, f, JointVector::Zero(2));
  CHECK(ik.success);
  CHECK(ik.joints[0] == Approx(120).margin(1e-6));
}

TEST_CASE("URDF: numeric IK converges on the generic arm", "[urdf][ik]") {
  const Robot r = must(load_urdf(kData + "generic6.urdf"));
  std::mt19937 rng(2026);
  const int n = 2000;
  int ok = 0, from_seed = 0;
  double max_p = 0, max_r = 0;
  long iterations = 0;
  const auto t0 = std::chrono::steady_clock::now();
  for (int k = 0; k < n; ++k) {
    const JointVector q = random_joints(r, rng);
    const Pose target = flange_pose(r, q);
    const NumericIkResult res = solve_numeric(r, target, ready_joints(r));
    iterations += res.iterations;
    if (!res.success) continue;
    ++ok;
    from_seed += res.attempts == 1;
    max_p = std::max(max_p, res.position_error_mm);
    max_r = std::max(max_r, res.rotation_error_rad);
    CHECK(first_limit_violation(r, res.joints) < 0);
  }
  const double us = std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count() / n;
  WARN("generic6 numeric IK from READY: " << ok << "/" << n << " solved (" << from_seed << " from the seed), "
                                          << double(iterations) / n << " iterations, " << us
                                          << " us per solve, max residual " << max_p << " mm / " << max_r << " rad");
  CHECK(ok >= n * 99 / 100);
  CHECK(max_p <= 1e-6);
  CHECK(max_r <= 1e-9);
}

TEST_CASE("URDF: numeric IK near the seed keeps the nearby solution", "[urdf][ik]") {
  const Robot r = must(load_urdf(kData + "generic6.urdf"));
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> small(-2, 2);
  for (int k = 0; k < 200; ++k) {
    const JointVector q = random_joints(r, rng);
    JointVector near = q;
    for (int i = 0; i < 6; ++i) near[i] = std::clamp(q[i] + small(rng), r.lower[i], r.upper[i]);
    // MULTIPLE: SINGLE would take J6 (+-350 deg here) in (-180, 180] (tests/robots/test_ik_single.cpp).
    const IkResult res = solve_ik(r, flange_pose(r, near), q, configuration_of(r, near), false);
    REQUIRE(res.status == IkStatus::ok);
    CHECK((res.joints - near).cwiseAbs().maxCoeff() < 1e-5);
  }
}

TEST_CASE("URDF: numeric IK tells out of reach from a joint limit", "[urdf][ik]") {
  const Robot r = must(load_urdf(kData + "generic6.urdf"));
  const JointVector ready = ready_joints(r);
  Pose far = flange_pose(r, ready);
  far.translation() = Vec3(3000, 0, 900);
  CHECK(solve_ik(r, far, ready, configuration_of(r, ready), true).status == IkStatus::out_of_reach);
  // J1 held to [-10, 10]: a pose beside the arm (J1 = 90, or -90 reaching over backwards) is
  // reachable only outside the J1 range.
  Robot narrow = r;
  narrow.lower[0] = -10, narrow.upper[0] = 10;
  JointVector q = ready;
  q[0] = 90;
  q[1] = 30;
  const IkResult res = solve_ik(narrow, flange_pose(r, q), ready, configuration_of(r, q), true);
  CHECK(res.status == IkStatus::joint_limit);
  CHECK(res.joint == 0);
  CHECK(std::abs(res.value) > 10);
}

TEST_CASE("URDF: bad input is reported with file and line", "[urdf][errors]") {
  CHECK_THAT(asimov::test::error_message(load_urdf("/nonexistent/arm.urdf")), Catch::Contains("/nonexistent/arm.urdf:0: cannot open"));
  CHECK_THAT(error_of("<robot name=\"t\">\n<link name=\"a\">\n</robot>\n"), Catch::StartsWith("bad.urdf:2: XML error"));
  CHECK_THAT(error_of(std::string(kHead) + "<joint name=\"j\" type=\"floating\"><parent link=\"a\"/><child link=\"b\"/></joint>\n</robot>"),
             Catch::StartsWith("bad.urdf:5: joint 'j': unsupported joint type 'floating'"));
  CHECK_THAT(error_of(std::string(kHead) + "<joint name=\"j\" type=\"revolute\"><parent link=\"a\"/><child link=\"b\"/></joint>\n</robot>"),
             Catch::StartsWith("bad.urdf:5: joint 'j' (revolute) needs <limit"));
  CHECK_THAT(error_of(std::string(kHead) + "<joint name=\"j\" type=\"revolute\"><parent link=\"a\"/><child link=\"b\"/>\n"
                                           "<limit lower=\"-1\" velocity=\"1\"/></joint>\n</robot>"),
             Catch::StartsWith("bad.urdf:6: <limit> needs the attribute 'upper'"));
  CHECK_THAT(error_of(std::string(kHead) + "<joint name=\"j\" type=\"revolute\"><parent link=\"a\"/><child link=\"b\"/>\n"
                                           "<origin xyz=\"0 nan 0\"/>\n<limit lower=\"-1\" upper=\"1\" velocity=\"1\"/></joint>\n</robot>"),
             Catch::StartsWith("bad.urdf:6: <origin xyz=\"nan\">: a finite number"));
  CHECK_THAT(error_of(std::string(kHead) + "<joint name=\"j\" type=\"revolute\"><parent link=\"a\"/><child link=\"zz\"/>\n"
                                           "<limit lower=\"-1\" upper=\"1\" velocity=\"1\"/></joint>\n</robot>"),
             Catch::StartsWith("bad.urdf:5: joint 'j': unknown link 'zz'"));
  CHECK_THAT(error_of("<?xml version=\"1.0\"?>\n<robot name=\"t\">\n<link name=\"a\">\n<collision><geometry>"
                      "<mesh filename=\"missing.stl\"/></geometry></collision>\n</link>\n</robot>"),
             Catch::StartsWith("bad.urdf:4: ") && Catch::Contains("no such file: missing.stl"));
  CHECK_THAT(error_of("<?xml version=\"1.0\"?>\n<robot name=\"t\">\n<link name=\"a\"/>\n</robot>"),
             Catch::Contains("no movable joint"));
  CHECK_THAT(error_of(std::string(kHead) + "<joint name=\"j\" type=\"revolute\"><parent link=\"a\"/><child link=\"b\"/>\n"
                                           "<limit lower=\"2\" upper=\"1\" velocity=\"1\"/></joint>\n</robot>"),
             Catch::StartsWith("bad.urdf:6: joint 'j': lower limit above"));
}

TEST_CASE("STL: ASCII and binary cubes, sphere tessellation", "[urdf][mesh]") {
  // Meshes go through collision::read_mesh; its Error becomes the URDF error at the <mesh> line.
  const auto dir = asimov::test::scratch_dir("urdf_stl");
  const collision::Polyhedron box = collision::make_box(Vec3(1, 2, 3));
  const std::string ascii = (dir / "cube_ascii.stl").string();
  const std::string binary = (dir / "cube_binary.STL").string();
  {
    std::ofstream a(ascii);
    a << "solid cube\n";
    for (const auto& t : box.triangles) {
      a << " facet normal 0 0 0\n  outer loop\n";
      for (auto i : t) a << "   vertex " << box.vertices[i].x() << " " << box.vertices[i].y() << " " << box.vertices[i].z() << "\n";
      a << "  endloop\n endfacet\n";
    }
    a << "endsolid cube\n";
    std::ofstream b(binary, std::ios::binary);
    char header[80] = {};
    b.write(header, 80);
    const auto n = static_cast<std::uint32_t>(box.triangles.size());
    b.write(reinterpret_cast<const char*>(&n), 4);
    for (const auto& t : box.triangles) {
      float f[12] = {};
      for (int k = 0; k < 3; ++k)
        for (int c = 0; c < 3; ++c) f[3 + 3 * k + c] = static_cast<float>(box.vertices[t[static_cast<std::size_t>(k)]][c]);
      b.write(reinterpret_cast<const char*>(f), sizeof f);
      const std::uint16_t attr = 0;
      b.write(reinterpret_cast<const char*>(&attr), 2);
    }
  }
  // One revolute joint; link b carries `geometry` (the file names are relative to `dir`).
  const auto urdf = [](const std::string& geometry) {
    return "<?xml version=\"1.0\"?>\n<robot name=\"t\">\n<link name=\"a\"/>\n<link name=\"b\">\n"
           "<collision><geometry>" + geometry + "</geometry></collision>\n</link>\n"
           "<joint name=\"j\" type=\"revolute\"><parent link=\"a\"/><child link=\"b\"/>"
           "<limit lower=\"-1\" upper=\"1\" velocity=\"1\"/></joint>\n</robot>\n";
  };
  for (const auto& name : {"cube_ascii.stl", "cube_binary.STL"}) {
    const Robot r = must(load_urdf_text(urdf(std::string("<mesh filename=\"") + name + "\"/>"), "m.urdf", dir.string()));
    REQUIRE(r.bodies.size() == 1);
    const collision::Polyhedron& m = r.bodies[0].mesh;
    CHECK(m.vertices.size() == 8);  // welded
    CHECK(m.triangles.size() == 12);
    CHECK(volume(m) == Approx(6e9));  // metres -> mm
    CHECK(r.warnings.empty());
  }
  {
    std::ofstream bad(ascii);
    bad << "solid x\n facet normal 0 0 0\n  outer loop\n   vertex 0 0 0\n   vertex 1 nan 0\n   vertex 0 1 0\n"
           "  endloop\n endfacet\nendsolid x\n";
  }
  const auto bad = load_urdf_text(urdf("<mesh filename=\"cube_ascii.stl\"/>"), "bad.urdf", dir.string());
  const std::string what = asimov::test::error_message(bad);
  CHECK((!bad.ok() && bad.error().line == 5));
  CHECK_THAT(what, Catch::StartsWith("bad.urdf:5: ") && Catch::Contains("cube_ascii.stl: face 1: non-finite"));
  CHECK_THAT(error_of(urdf("<mesh filename=\"arm.dae\"/>")), Catch::StartsWith("bad.urdf:5: ") && Catch::Contains("no such file: arm.dae"));
  std::filesystem::remove_all(dir);
  const Robot sphere = must(load_urdf_text(urdf("<sphere radius=\"0.05\"/>"), "s.urdf"));
  REQUIRE(sphere.bodies.size() == 1);
  const double v = volume(sphere.bodies[0].mesh);
  CHECK(v > 4.0 / 3 * std::numbers::pi * std::pow(50 - 0.5, 3));  // every face within 0.5 mm of the sphere
  CHECK(v < 4.0 / 3 * std::numbers::pi * 125000);
}
