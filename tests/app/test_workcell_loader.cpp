// The workcell keys of a cell file (docs/cell-format.md "Parts and devices").
#include "asimov/cell/cell_loader.hpp"

#include "support/cell.hpp"

#include <catch2/catch.hpp>

using namespace asimov;

namespace {
std::string message(const std::string& yaml) {
  const auto cell = cell::load_cell_text(yaml, "w.yaml");
  return cell ? std::string() : cell::format_cell_error(cell.error());
}
using test::load_cell_text;
}  // namespace

TEST_CASE("a cell without parts or devices has an empty workcell") {
  CHECK(cell::default_cell().workcell.empty());
  CHECK(load_cell_text("{}", "e.yaml").workcell.empty());
}

TEST_CASE("parts: single, coloured, and a pallet pattern by count and pitch") {
  const auto c = load_cell_text(
      "parts:\n"
      "  - {name: gear, cylinder: {radius: 20, height: 10}, at: [500, 0, -395, 0, 0, 0], colour: red}\n"
      "  - {name: cube, box: [40, 40, 40], at: [600, 100, -380, 90, 0, 0], count: [3, 2, 2], pitch: [50, 60, 40]}\n",
      "p.yaml");
  const auto& parts = c.workcell.parts;
  REQUIRE(parts.size() == 13);
  CHECK(parts[0].name == "gear");
  CHECK(parts[0].colour == "red");
  CHECK(parts[1].name == "cube1");
  CHECK(parts[12].name == "cube12");
  // x fastest along the part frame's X (rotated 90 about Z: world +Y), then y (world -X), then z.
  CHECK(parts[2].pose.translation().isApprox(collision::Vec3(600, 150, -380)));
  CHECK(parts[4].pose.translation().isApprox(collision::Vec3(540, 100, -380)));
  CHECK(parts[7].pose.translation().isApprox(collision::Vec3(600, 100, -340)));
  CHECK(c.objects.empty());  // parts are not static objects
}

TEST_CASE("gripper zone, devices and logic") {
  const auto c = load_cell_text(
      "gripper: {zone: {box: [30, 30, 40], at: [0, 0, 220, 0, 0, 0]}, close_on_air: error}\n"
      "devices:\n"
      "  - {conveyor: belt, box: [1000, 200, 40], at: [500, -300, -420, 0, 0, 0], direction: [2, 0, 0], speed_mm_s: 150, signal: 1}\n"
      "  - {sensor: eye, signal: 1001, box: [20, 200, 100], at: [700, -300, -350, 0, 0, 0], parts: 'box*', colour: red}\n"
      "  - {feeder: hopper, part: {box: [40, 40, 40]}, at: [50, -300, -380, 0, 0, 0], count: 5, colours: [red, blue]}\n"
      "  - {sink: bin, box: [100, 300, 200], at: [1000, -300, -350, 0, 0, 0]}\n"
      "logic:\n"
      "  - {when: 3, is: off, after: 0.5, set: 1003, to: on}\n"
      "  - {at: 2, set: 2001}\n"
      "  - {follow: 4, set: 1004, after: 0.25}\n",
      "d.yaml");
  const auto& w = c.workcell;
  CHECK(w.gripper.declared);
  CHECK(w.gripper.close_on_air_error);
  CHECK(w.gripper.zone.size.z() == 40);
  REQUIRE(w.conveyors.size() == 1);
  CHECK(w.conveyors[0].direction.isApprox(collision::Vec3::UnitX()));
  CHECK(w.conveyors[0].signal == 1);
  REQUIRE(c.objects.size() == 1);  // the belt's body is a static object
  CHECK(c.objects[0].name == "belt");
  REQUIRE(w.sensors.size() == 1);
  CHECK(w.sensors[0].pattern == "box*");
  REQUIRE(w.feeders.size() == 1);
  CHECK(w.feeders[0].when_empty);
  CHECK(w.feeders[0].prefix == "hopper");
  CHECK(w.feeders[0].spot.size.isApprox(collision::Vec3(80, 80, 80)));
  REQUIRE(w.logic.size() == 4);  // follow is two rules
  CHECK(w.logic[0].when == 3);
  CHECK_FALSE(w.logic[0].is_on);
  CHECK(w.logic[1].at_s == 2);
  CHECK(w.logic[1].to_on);
  CHECK(w.logic[3].when == 4);
  CHECK_FALSE(w.logic[3].to_on);
  CHECK(w.drives(1001));
  CHECK(w.drives(1004));
  CHECK_FALSE(w.drives(1002));
}

TEST_CASE("workcell mistakes are cell errors with line and column") {
  CHECK(message("devices:\n  - {sensor: s, signal: 5, box: [1, 1, 1]}\n") ==
        "w.yaml:2:25: sensor signal must be an input (1001-1512) or soft signal (2001-2512), got 5");
  CHECK(message("devices:\n  - {robot: r}\n").find("a device is one of conveyor:") != std::string::npos);
  CHECK(message("devices:\n  - {conveyor: b, box: [1, 1, 1], direction: [0, 0, 1], speed_mm_s: 1}\n")
            .find("must lie in its top face") != std::string::npos);
  CHECK(message("parts:\n  - {name: p, box: [1, 1, 1], count: [2, 1, 1]}\n").find("needs pitch") != std::string::npos);
  CHECK(message("parts:\n  - {name: p, box: [1, 1, 1], count: [100, 100, 2], pitch: [1, 1, 1]}\n")
            .find("more than 10000 parts") != std::string::npos);
  CHECK(message("parts:\n  - {name: p, box: [1, 1, 1]}\n  - {name: p, sphere: {radius: 1}}\n")
            .find("duplicate body name 'p'") != std::string::npos);
  CHECK(message("parts:\n  - {name: link2, box: [1, 1, 1]}\n").find("duplicate body name") != std::string::npos);
  CHECK(message("logic:\n  - {when: 1, at: 2, set: 1001}\n").find("exactly one of when, at, follow") != std::string::npos);
  CHECK(message("logic:\n  - {when: 1, set: 1001, to: maybe}\n").find("on or off") != std::string::npos);
  CHECK(message("logic:\n  - {at: -1, set: 1001}\n").find(">= 0") != std::string::npos);
  CHECK(message("devices:\n  - {feeder: f, part: {box: [1, 1, 1]}, when_empty: false}\n").find("never feeds") !=
        std::string::npos);
  CHECK(message("gripper: {close_on_air: error}\n").find("gripper needs zone") != std::string::npos);
  CHECK(message("devices:\n  - {conveyor: c, box: [1, 1, 1], speed_mm_s: 1, signal: 600}\n").find("not a signal") !=
        std::string::npos);
}
