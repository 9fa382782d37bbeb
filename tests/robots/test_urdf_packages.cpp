// URDF as shipped (robots/README.md "Descriptions as shipped"): package:// through a package
// search path (found by package.xml), file://, COLLADA and other assimp meshes with the units and
// up axis they declare, and the messages for what is missing.
#include "asimov/robots/package_path.hpp"
#include "asimov/robots/urdf_loader.hpp"

#include "support/joints.hpp"

#include "support/run_cli.hpp"
#include "support/result.hpp"

#include <catch2/catch.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <unistd.h>

using namespace asimov::robots;
using asimov::test::must;
namespace fs = std::filesystem;

namespace {
const fs::path kWorkspace = fs::path(ASIMOV_SOURCE_DIR) / "programs/cells/ros_ws/src";
const fs::path kPackage = kWorkspace / "demo_support_pkg";

fs::path scratch() { return asimov::test::scratch_dir("urdf-packages"); }

void write(const fs::path& p, const std::string& text) {
  fs::create_directories(p.parent_path());
  std::ofstream(p) << text;
}

void package_xml(const fs::path& dir, const std::string& name) {
  write(dir / "package.xml", "<package format=\"2\">\n  <name> " + name + " </name>\n</package>\n");
}

// Axis-aligned bounds of a body's vertices in its frame.
std::pair<Vec3, Vec3> bounds(const asimov::collision::Polyhedron& m) {
  Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
  for (const auto& v : m.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
  return {lo, hi};
}

const LinkBody& body(const Robot& r, const std::string& name) {
  for (const auto& b : r.bodies)
    if (b.name == name) return b;
  FAIL("no body " << name);
  return r.bodies.front();
}

// A one-link arm whose base collision is the mesh `uri`.
std::string one_link(const std::string& uri, const std::string& extra = "") {
  return "<robot name=\"t\">\n<link name=\"base\"><collision><geometry><mesh filename=\"" + uri + "\"" + extra +
         "/></geometry></collision></link>\n<link name=\"l1\"/>\n<joint name=\"j1\" type=\"continuous\"><parent "
         "link=\"base\"/><child link=\"l1\"/></joint>\n</robot>\n";
}

// A COLLADA box of the given size and centre in file units.
std::string dae_box(double sx, double sy, double sz, double cx, double cy, double cz, double metres, const char* up) {
  std::string pos;
  for (int k = 0; k < 8; ++k) {
    const double x = cx + ((k & 1) ? sx : -sx) / 2, y = cy + ((k & 2) ? sy : -sy) / 2, z = cz + ((k & 4) ? sz : -sz) / 2;
    pos += std::to_string(x) + " " + std::to_string(y) + " " + std::to_string(z) + " ";
  }
  // Vertex k: bit 0 = +x, bit 1 = +y, bit 2 = +z; outward triangles.
  const char* tris = "0 2 1 1 2 3 4 5 6 5 7 6 0 1 4 1 5 4 2 6 3 3 6 7 0 4 2 2 4 6 1 3 5 3 7 5";
  return std::string("<?xml version=\"1.0\"?>\n<COLLADA xmlns=\"http://www.collada.org/2005/11/COLLADASchema\" "
                     "version=\"1.4.1\"><asset><unit meter=\"") +
         std::to_string(metres) + "\"/><up_axis>" + up +
         "</up_axis></asset><library_geometries><geometry id=\"g\"><mesh><source id=\"p\"><float_array id=\"pa\" "
         "count=\"24\">" + pos +
         "</float_array><technique_common><accessor source=\"#pa\" count=\"8\" stride=\"3\"><param name=\"X\" "
         "type=\"float\"/><param name=\"Y\" type=\"float\"/><param name=\"Z\" type=\"float\"/></accessor>"
         "</technique_common></source><vertices id=\"v\"><input semantic=\"POSITION\" source=\"#p\"/></vertices>"
         "<triangles count=\"12\"><input semantic=\"VERTEX\" source=\"#v\" offset=\"0\"/><p>" + tris +
         "</p></triangles></mesh></geometry></library_geometries><library_visual_scenes><visual_scene id=\"s\">"
         "<node id=\"n\"><instance_geometry url=\"#g\"/></node></visual_scene></library_visual_scenes><scene>"
         "<instance_visual_scene url=\"#s\"/></scene></COLLADA>\n";
}
}  // namespace

TEST_CASE("packages are found by the name in their package.xml, not by their folder", "[urdf][packages]") {
  PackagePath p;
  p.add_root(kWorkspace);
  const auto found = p.find("asimov_demo_support");
  REQUIRE(found);
  CHECK(fs::equivalent(*found, kPackage));
  CHECK_FALSE(p.find("demo_support_pkg"));  // the folder name is no package name
  CHECK_FALSE(p.find("no_such_package"));
  CHECK(package_name(kPackage) == "asimov_demo_support");
  // A package's own folders are not searched; ignored folders are skipped.
  const fs::path root = scratch() / "ws";
  package_xml(root / "outer", "outer_pkg");
  package_xml(root / "outer" / "inner", "inner_pkg");
  package_xml(root / "skipped" / "pkg", "skipped_pkg");
  write(root / "skipped" / "COLCON_IGNORE", "");
  package_xml(root / "a" / "b" / "c", "deep_pkg");
  PackagePath q;
  q.add_root(root);
  CHECK(q.find("outer_pkg"));
  CHECK_FALSE(q.find("inner_pkg"));
  CHECK_FALSE(q.find("skipped_pkg"));
  CHECK(q.find("deep_pkg"));
}

TEST_CASE("resolve_uri: package://, file://, relative, the errors name what is missing", "[urdf][packages]") {
  PackagePath p;
  p.add_root(kWorkspace);
  std::string err;
  CHECK(resolve_uri("package://asimov_demo_support/urdf/demo6.urdf", "/x", p, err) == kPackage / "urdf/demo6.urdf");
  CHECK(err.empty());
  CHECK(resolve_uri("file:///opt/m.stl", "/x", p, err) == fs::path("/opt/m.stl"));
  CHECK(resolve_uri("m.stl", "/x/y", p, err) == fs::path("/x/y/m.stl"));
  CHECK(resolve_uri("package://nowhere/m.stl", "/x", p, err).empty());
  CHECK(err.find("package 'nowhere' not found") != std::string::npos);
  CHECK(err.find(kWorkspace.string()) != std::string::npos);
  CHECK(resolve_uri("package://nowhere/m.stl", "/x", PackagePath(), err).empty());
  CHECK(err.find("ROS_PACKAGE_PATH") != std::string::npos);
  CHECK(resolve_uri("http://example.com/m.stl", "/x", p, err).empty());
  CHECK(err.find("only package:// and file://") != std::string::npos);
  CHECK(resolve_uri("package:///m.stl", "/x", p, err).empty());
}

TEST_CASE("ROS_PACKAGE_PATH is searched after the given roots", "[urdf][packages]") {
  const char* old = std::getenv("ROS_PACKAGE_PATH");
  const std::string saved = old ? old : "";
  ::setenv("ROS_PACKAGE_PATH", ("/nonexistent:" + kWorkspace.string()).c_str(), 1);
  const PackagePath p = PackagePath::with_environment({scratch() / "empty"});
  if (old) ::setenv("ROS_PACKAGE_PATH", saved.c_str(), 1); else ::unsetenv("ROS_PACKAGE_PATH");
  REQUIRE(p.roots().size() == 3);
  CHECK(p.find("asimov_demo_support"));
}

TEST_CASE("a ROS-style package: package:// COLLADA meshes in mm Z_UP and m Y_UP match the primitives", "[urdf][packages]") {
  UrdfOptions o;
  o.packages.add_root(kWorkspace);
  const Robot demo = must(load_urdf((kPackage / "urdf/demo6.urdf").string(), o));
  const Robot generic = must(load_urdf(std::string(ASIMOV_SOURCE_DIR) + "/robots/data/generic6.urdf"));
  // base_link.dae: the box 280 x 280 x 180 mm standing on the floor.
  const auto [blo, bhi] = bounds(body(demo, "base_link").mesh);
  CHECK((blo - Vec3(-140, -140, 0)).norm() < 1e-6);
  CHECK((bhi - Vec3(140, 140, 180)).norm() < 1e-6);
  // turret.dae (metres, Y_UP) is generic6's turret box: the link bodies have the same bounds,
  // to assimp's single precision (0.17 m as a float is 1e-5 mm off).
  const auto [dlo, dhi] = bounds(body(demo, "link_1").mesh);
  const auto [glo, ghi] = bounds(body(generic, "link_1").mesh);
  CHECK((dlo - glo).norm() < 1e-4);
  CHECK((dhi - ghi).norm() < 1e-4);
  CHECK(body(demo, "link_1").mesh.triangles.size() == body(generic, "link_1").mesh.triangles.size());
  // Same kinematics as generic6.
  const JointVector q = asimov::test::jv({10, 20, -30, 40, 50, 60});
  CHECK((flange_pose(demo, q).matrix() - flange_pose(generic, q).matrix()).norm() < 1e-12);
}

TEST_CASE("COLLADA X_UP, other assimp formats, and bad or missing meshes", "[urdf][packages]") {
  const fs::path d = scratch();
  // X_UP: file X is up, file -Y is world X.
  write(d / "x.dae", dae_box(300, 100, 200, 150, 0, 0, 0.001, "X_UP"));
  const Robot rx = must(load_urdf_text(one_link("x.dae"), "x.urdf", d.string()));
  const auto [xlo, xhi] = bounds(rx.bodies[0].mesh);
  CHECK((xlo - Vec3(-50, -100, 0)).norm() < 1e-6);
  CHECK((xhi - Vec3(50, 100, 300)).norm() < 1e-6);
  // The URDF scale applies after the file's units.
  const Robot rs = must(load_urdf_text(one_link("x.dae", " scale=\"2 2 2\""), "x.urdf", d.string()));
  CHECK((bounds(rs.bodies[0].mesh).second - Vec3(100, 200, 600)).norm() < 1e-6);
  // file:// with an absolute path.
  const Robot rf = must(load_urdf_text(one_link("file://" + (d / "x.dae").string()), "x.urdf", "/"));
  CHECK(rf.bodies[0].mesh.triangles.size() == 12);
  // An ASCII PLY tetrahedron (metres) through assimp.
  write(d / "t.ply",
        "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
        "element face 4\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n0.1 0 0\n0 0.1 0\n0 0 0.1\n"
        "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n");
  const Robot rp = must(load_urdf_text(one_link("t.ply"), "t.urdf", d.string()));
  CHECK((bounds(rp.bodies[0].mesh).second - Vec3(100, 100, 100)).norm() < 1e-4);
  // Missing file, missing package, unreadable mesh: an Error at the <mesh> line.
  const auto message = [&](const std::string& urdf) {
    const auto r = load_urdf_text(urdf, "m.urdf", d.string());
    if (r) return std::string("no error");
    CHECK(r.error().line == 2);
    return r.error().message;
  };
  CHECK(message(one_link("nothere.dae")).find("no such file") != std::string::npos);
  CHECK(message(one_link("package://nopkg/m.dae")).find("package 'nopkg' not found") != std::string::npos);
  write(d / "bad.dae", "<COLLADA><library_geometries><geometry>");
  CHECK(message(one_link("bad.dae")).find("bad.dae") != std::string::npos);
  write(d / "part.unknownformat", "not a mesh\n");
  CHECK(message(one_link("part.unknownformat")).find("part.unknownformat") != std::string::npos);
}
