#include "support/scratch.hpp"
#include "asimov/cell/cell_loader.hpp"
#include "asimov/collision/engine.hpp"

#include "collision/src/voxel_grid.hpp"
#include "support/cell.hpp"

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>

using namespace asimov;

using test::load_cell_file;
using test::load_cell_text;

TEST_CASE("the default cell has the PUMA, a table, a box and a tool body") {
  const auto cell = cell::default_cell();
  CHECK(cell.robot.name == "puma560");
  REQUIRE(cell.objects.size() == 2);
  CHECK(cell.objects[0].name == "table");
  CHECK(cell.objects[1].name == "box");
  CHECK(cell.tool_shape.has_value());
  CHECK(cell.tool.translation().z() == Approx(200));
  CHECK(cell.collision.halvings == 9);
  CHECK(cell.collision.step_mm == 1.0);
  REQUIRE(cell.start_joints.size() == 6);
  CHECK(cell.start_joints[1] == -90);  // READY
}

TEST_CASE("an empty cell is the bare PUMA at READY with defaults") {
  const auto cell = load_cell_text("{}", "empty.yaml");
  CHECK(cell.objects.empty());
  CHECK_FALSE(cell.tool_shape.has_value());
  CHECK(cell.base.isApprox(motion::Location::Identity()));
  CHECK(cell.collision.clearance_mm == 0);
}

TEST_CASE("objects: box and cylinder placed by VAL TRANS") {
  const auto cell = load_cell_text(
      "objects:\n"
      "  - {name: post, cylinder: {radius: 50, height: 300, segments: 8}, at: [500, 0, -200, 90, 0, 0]}\n"
      "  - {name: plate, box: [10, 20, 30]}\n",
      "c.yaml");
  REQUIRE(cell.objects.size() == 2);
  CHECK(cell.objects[0].mesh.vertices.size() == 2 * 8 + 2);
  CHECK(cell.objects[0].pose.translation().x() == Approx(500));
  CHECK(cell.objects[0].pose.linear()(1, 0) == Approx(1));  // o = 90: x axis turned onto +Y
  CHECK(cell.objects[1].mesh.triangles.size() == 12);
}

TEST_CASE("collision settings and ignore pairs") {
  const auto cell = load_cell_text(
      "objects: [{name: table, box: [1, 1, 1]}]\n"
      "collision: {halvings: 5, step_mm: 0.5, clearance_mm: 2, ignore: [[link1, table]]}\n",
      "c.yaml");
  CHECK(cell.collision.halvings == 5);
  CHECK(cell.collision.step_mm == 0.5);
  CHECK(cell.collision.clearance_mm == 2);
  REQUIRE(cell.collision.ignore.size() == 1);
  CHECK(cell.collision.ignore[0].first == "link1");
}

namespace {
// The error for `yaml`, with its position.
Error error_of(const std::string& yaml) { return test::cell_error(yaml); }
}  // namespace

TEST_CASE("bad cells are rejected with file, line and column") {
  auto e = error_of("robot: kuka\n");
  CHECK(e.message.find("unknown robot 'kuka'") != std::string::npos);
  CHECK(e.line == 1);

  e = error_of("objects:\n  - {name: a, box: [1, 2]}\n");
  CHECK(e.line == 2);
  CHECK(cell::format_cell_error(e).rfind("bad.yaml:2:", 0) == 0);

  e = error_of("objects:\n  - {name: a, box: [1, 1, 1]}\n  - {name: a, box: [1, 1, 1]}\n");
  CHECK(e.message.find("duplicate body name 'a'") != std::string::npos);
  CHECK(e.line == 3);

  e = error_of("objects:\n  - {name: link3, box: [1, 1, 1]}\n");
  CHECK(e.message.find("duplicate") != std::string::npos);

  e = error_of("collision: {ignore: [[link1, nothing]]}\n");
  CHECK(e.message.find("unknown body 'nothing'") != std::string::npos);

  e = error_of("tabel: {}\n");
  CHECK(e.message.find("unknown key 'tabel'") != std::string::npos);

  e = error_of("base: [0, 0, .nan, 0, 0, 0]\n");
  CHECK(e.message.find("finite") != std::string::npos);

  e = error_of("collision: {step_mm: 0}\n");
  CHECK(e.message.find("> 0") != std::string::npos);

  e = error_of("objects: [{name: a, box: [1, 1, 1]]\n");  // YAML syntax
  CHECK(e.line == 1);

  e = error_of("start: [0, -90, 90, 0, 0, 999]\n");
  CHECK(e.message.find("J6") != std::string::npos);

  e = error_of("objects:\n  - {name: a}\n");
  CHECK(e.message.find("needs a shape") != std::string::npos);
}

TEST_CASE("robot: a URDF file relative to the cell file") {
  const auto cell = load_cell_file(std::string(ASIMOV_SOURCE_DIR) + "/programs/cells/generic6_cell.yaml");
  CHECK(cell.robot.is_chain());
  CHECK(cell.robot.joint_count() == 6);
  CHECK(cell.objects.size() == 2);
  // The default start is the arm's READY, inside its limits.
  CHECK(robots::first_limit_violation(cell.robot, cell.start_joints) == -1);
}

TEST_CASE("robot: built-in Adept arms by name, a packaged URDF by package:// through packages:") {
  CHECK(load_cell_text("robot: viper_s650\n", "v.yaml").robot.name == "viper_s650");
  CHECK(load_cell_text("robot: cobra_s600\n", "c.yaml").robot.joint_count() == 4);
  const std::string cells = std::string(ASIMOV_SOURCE_DIR) + "/programs/cells";
  const auto demo = load_cell_text("robot: package://asimov_demo_support/urdf/demo6.urdf\npackages: ros_ws/src\n",
                                   "d.yaml", cells);
  CHECK(demo.robot.name == "demo6");
  auto e = error_of("robot: package://asimov_demo_support/urdf/demo6.urdf\npackages: [nowhere]\n");
  CHECK(e.line == 2);
  CHECK(e.message.find("packages: no folder") != std::string::npos);
  e = error_of("packages: {a: 1}\nrobot: x.urdf\n");
  CHECK(e.message.find("packages must be a folder or a list") != std::string::npos);
  e = error_of("robot: package://no_such_pkg/urdf/a.urdf\n");
  CHECK(e.line == 1);
  CHECK(e.message.find("package 'no_such_pkg' not found") != std::string::npos);
}

TEST_CASE("robot: a missing or non-URDF robot is a cell error at the robot key") {
  auto e = error_of("objects: []\nrobot: nowhere/arm.urdf\n");
  CHECK(e.line == 2);
  CHECK(e.message.find("arm.urdf") != std::string::npos);
  e = error_of("robot: [1, 2]\n");
  CHECK(e.message.find("built-in arm (puma560, viper_s650, cobra_s600), a .urdf or .xacro file or a package:// URI") != std::string::npos);
}

namespace {
// Writes an ASCII STL of the closed unit-free box [0,10]^3 (12 facets) or, with `open`, 11 of them.
std::filesystem::path write_stl(const std::string& name, bool open, const std::string& bad_coordinate = "") {
  const auto box = collision::make_box({10, 10, 10});
  std::string text = "solid t\n";
  for (std::size_t i = 0; i < box.triangles.size() - (open ? 1 : 0); ++i) {
    text += " facet normal 0 0 0\n  outer loop\n";
    for (auto v : box.triangles[i]) {
      const auto& p = box.vertices[v];
      text += "   vertex " + (bad_coordinate.empty() || i != 3 ? std::to_string(p.x()) : bad_coordinate) + " " +
              std::to_string(p.y()) + " " + std::to_string(p.z()) + "\n";
    }
    text += "  endloop\n endfacet\n";
  }
  text += "endsolid t\n";
  const auto dir = asimov::test::scratch_dir("cell-tests");
  std::ofstream(dir / name) << text;
  return dir / name;
}
}  // namespace

TEST_CASE("objects from STL meshes (relative to the cell) with scale, and spheres") {
  const auto stl = write_stl("cube.stl", false);
  const auto cell = load_cell_text(
      "objects:\n"
      "  - {name: cube, mesh: cube.stl, scale: 2, at: [500, 0, 0, 0, 0, 0]}\n"
      "  - {name: ball, sphere: {radius: 50, tolerance_mm: 0.1}}\n"
      "collision: {halvings: auto}\n",
      "c.yaml", stl.parent_path().string());
  REQUIRE(cell.objects.size() == 2);
  CHECK(cell.objects[0].mesh.triangles.size() == 12);
  double max_x = 0;
  for (const auto& v : cell.objects[0].mesh.vertices) max_x = std::max(max_x, v.x());
  CHECK(max_x == Approx(10));  // half side 5, scaled by 2
  CHECK(cell.warnings.empty());
  for (const auto& v : cell.objects[1].mesh.vertices) CHECK(v.norm() == Approx(50));
  CHECK(cell.collision.halvings == collision::kAutoHalvings);
}

TEST_CASE("mesh problems: an open mesh warns, a NaN or a missing file is an error at the mesh key") {
  const auto open = write_stl("open.stl", true);
  const auto cell = load_cell_text("objects: [{name: shell, mesh: open.stl}]\n", "c.yaml", open.parent_path().string());
  REQUIRE_FALSE(cell.warnings.empty());
  CHECK(cell.warnings.front().find("open.stl") != std::string::npos);

  const auto nan = write_stl("nan.stl", false, "nan");
  const auto rejected = cell::load_cell_text("objects:\n  - {name: n, mesh: nan.stl}\n", "c.yaml", nan.parent_path().string());
  REQUIRE_FALSE(rejected.ok());  // a NaN coordinate
  CHECK(rejected.error().line == 2);
  CHECK(rejected.error().message.find("nan.stl") != std::string::npos);
  auto e = error_of("objects:\n  - {name: m, mesh: nowhere.stl}\n");
  CHECK(e.line == 2);
  e = error_of("collision: {halvings: sometimes}\n");
  CHECK(e.message.find("auto") != std::string::npos);
}

TEST_CASE("collision keys: contact-time tolerance, generated pairs with a cache beside the cell file") {
  auto cell = load_cell_text("collision: {toc_tolerance_s: 1.0e-5, pairs: generated, pair_samples: 500}\n", "c.yaml");
  CHECK(cell.collision.toc_tolerance_s == 1e-5);
  CHECK(cell.collision.generated_pairs);
  CHECK(cell.collision.pair_samples == 500);
  CHECK(cell.collision.pairs_cache.empty());  // text without a file: no cache
  CHECK_FALSE(load_cell_text("collision: {pairs: joined}\n", "c.yaml").collision.generated_pairs);

  const auto dir = asimov::test::scratch_dir("cell-tests");
  std::ofstream(dir / "gen.yaml") << "collision: {pairs: generated}\n";
  cell = load_cell_file((dir / "gen.yaml").string());
  CHECK(cell.collision.pairs_cache == (dir / "gen.yaml").string() + ".pairs");

  auto e = error_of("collision: {pairs: sometimes}\n");
  CHECK(e.message.find("joined or generated") != std::string::npos);
  e = error_of("collision: {toc_tolerance_s: 0}\n");
  CHECK(e.message.find("> 0") != std::string::npos);
}

TEST_CASE("collision.stepping: gap by default, fixed or gap, anything else is a cell error") {
  CHECK(cell::default_cell().collision.stepping == motion::Stepping::gap);
  CHECK(load_cell_text("{}", "c.yaml").collision.stepping == motion::Stepping::gap);
  CHECK(load_cell_text("collision: {stepping: fixed}\n", "c.yaml").collision.stepping == motion::Stepping::fixed);
  CHECK(load_cell_text("collision: {stepping: gap}\n", "c.yaml").collision.stepping == motion::Stepping::gap);
  const auto e = error_of("collision: {stepping: adaptive}\n");
  CHECK(e.message.find("fixed or gap") != std::string::npos);
  CHECK(e.line == 1);
}

TEST_CASE("sinks gated by a signal and edge, sensors with a sensing rule (#32)") {
  const auto cell = load_cell_text(
      "devices:\n"
      "  - {sink: bin, box: [10, 10, 10], at: [0, 0, 0, 0, 0, 0]}\n"
      "  - {sink: unload, box: [10, 10, 10], at: [100, 0, 0, 0, 0, 0], signal: 11, edge: falling}\n"
      "  - {sink: up, box: [10, 10, 10], at: [200, 0, 0, 0, 0, 0], signal: 12}\n"
      "  - {sensor: eye, signal: 1001, box: [10, 10, 10], at: [0, 100, 0, 0, 0, 0], sensing: overlap}\n"
      "  - {sensor: dot, signal: 1001, box: [10, 10, 10], at: [0, 200, 0, 0, 0, 0]}\n",
      "c.yaml");
  REQUIRE(cell.workcell.sinks.size() == 3);
  CHECK(cell.workcell.sinks[0].signal == 0);
  CHECK(cell.workcell.sinks[1].signal == 11);
  CHECK_FALSE(cell.workcell.sinks[1].on_rising);
  CHECK(cell.workcell.sinks[2].signal == 12);
  CHECK(cell.workcell.sinks[2].on_rising);
  REQUIRE(cell.workcell.sensors.size() == 2);
  CHECK(cell.workcell.sensors[0].sensing == motion::Sensing::overlap);
  CHECK(cell.workcell.sensors[1].sensing == motion::Sensing::origin);

  auto e = error_of("devices:\n  - {sink: s, box: [1, 1, 1], at: [0, 0, 0, 0, 0, 0], signal: 1, edge: sideways}\n");
  CHECK(e.message.find("rising or falling") != std::string::npos);
  CHECK(e.line == 2);
  e = error_of("devices:\n  - {sink: s, box: [1, 1, 1], at: [0, 0, 0, 0, 0, 0], edge: rising}\n");
  CHECK(e.message.find("needs its signal") != std::string::npos);
  e = error_of("devices:\n  - {sensor: s, signal: 1001, box: [1, 1, 1], at: [0, 0, 0, 0, 0, 0], sensing: centre}\n");
  CHECK(e.message.find("origin or overlap") != std::string::npos);
}
