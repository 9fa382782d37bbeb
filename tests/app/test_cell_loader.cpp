#include "app/cell_loader.hpp"

#include <catch2/catch.hpp>

using namespace asimov;
using app::CellError;
using app::load_cell_text;

TEST_CASE("the default cell has the PUMA, a table, a box and a tool body") {
  const auto cell = app::default_cell();
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
CellError error_of(const std::string& yaml) {
  try {
    load_cell_text(yaml, "bad.yaml");
  } catch (const CellError& e) {
    return e;
  }
  FAIL("no error for: " << yaml);
  return CellError("", "", 0, 0);
}
}  // namespace

TEST_CASE("bad cells are rejected with file, line and column") {
  auto e = error_of("robot: kuka\n");
  CHECK(std::string(e.what()).find("unknown robot 'kuka'") != std::string::npos);
  CHECK(e.line == 1);

  e = error_of("objects:\n  - {name: a, box: [1, 2]}\n");
  CHECK(e.line == 2);
  CHECK(e.format().rfind("bad.yaml:2:", 0) == 0);

  e = error_of("objects:\n  - {name: a, box: [1, 1, 1]}\n  - {name: a, box: [1, 1, 1]}\n");
  CHECK(std::string(e.what()).find("duplicate body name 'a'") != std::string::npos);
  CHECK(e.line == 3);

  e = error_of("objects:\n  - {name: link3, box: [1, 1, 1]}\n");
  CHECK(std::string(e.what()).find("duplicate") != std::string::npos);

  e = error_of("collision: {ignore: [[link1, nothing]]}\n");
  CHECK(std::string(e.what()).find("unknown body 'nothing'") != std::string::npos);

  e = error_of("tabel: {}\n");
  CHECK(std::string(e.what()).find("unknown key 'tabel'") != std::string::npos);

  e = error_of("base: [0, 0, .nan, 0, 0, 0]\n");
  CHECK(std::string(e.what()).find("finite") != std::string::npos);

  e = error_of("collision: {step_mm: 0}\n");
  CHECK(std::string(e.what()).find("> 0") != std::string::npos);

  e = error_of("objects: [{name: a, box: [1, 1, 1]]\n");  // YAML syntax
  CHECK(e.line == 1);

  e = error_of("start: [0, -90, 90, 0, 0, 999]\n");
  CHECK(std::string(e.what()).find("J6") != std::string::npos);

  e = error_of("objects:\n  - {name: a}\n");
  CHECK(std::string(e.what()).find("needs a shape") != std::string::npos);
}

TEST_CASE("robot: a URDF file relative to the cell file") {
  const auto cell = app::load_cell_file(std::string(ASIMOV_SOURCE_DIR) + "/programs/cells/generic6_cell.yaml");
  CHECK(cell.robot.is_chain());
  CHECK(cell.robot.joint_count() == 6);
  CHECK(cell.objects.size() == 2);
  // The default start is the arm's READY, inside its limits.
  CHECK(robots::first_limit_violation(cell.robot, cell.start_joints) == -1);
}

TEST_CASE("robot: a missing or non-URDF robot is a cell error at the robot key") {
  auto e = error_of("objects: []\nrobot: nowhere/arm.urdf\n");
  CHECK(e.line == 2);
  CHECK(std::string(e.what()).find("arm.urdf") != std::string::npos);
  e = error_of("robot: [1, 2]\n");
  CHECK(std::string(e.what()).find("puma560 or a .urdf") != std::string::npos);
}
