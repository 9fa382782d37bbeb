// Cells read strictly (issue 29): a key given twice is a load error naming its line and column,
// and degenerate device values (conveyor speed and direction, parts inside bodies, a feeder into a
// sink) are refused at load or read correctly, never a wrong collision later.
#include "support/cell.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <string>

using namespace asimov;
using test::cell_error;

namespace {

const std::string kTable = "objects:\n  - {name: table, box: [700, 1200, 40], at: [750, 0, -420, 0, 0, 0]}\n";

}  // namespace

TEST_CASE("a second objects: is a load error at its line and column", "[cell][strict]") {
  const auto e = cell_error(kTable + "objects:\n  - {name: box, box: [160, 160, 200], at: [600, 250, -300, 0, 0, 0]}\n");
  CHECK(e.message == "duplicate key 'objects' (first given at line 1); a key is given once per map");
  CHECK(e.file == "bad.yaml");
  CHECK(e.line == 3);
  CHECK(e.column == 1);
}

TEST_CASE("duplicate keys at any depth are load errors", "[cell][strict]") {
  struct Case {
    const char* yaml;
    const char* key;
    int line, column;
  };
  const Case cases[] = {
      {"collision: {halvings: 9}\ncollision: {halvings: 5}\n", "collision", 2, 1},
      {"robot: puma560\nrobot: puma560\n", "robot", 2, 1},
      {"objects:\n  - {name: b, box: [1, 1, 1], box: [500, 500, 500]}\n", "box", 2, 31},
      {"objects:\n  - name: b\n    box: [1, 1, 1]\n    at: [0, 0, -900, 0, 0, 0]\n    name: c\n", "name", 5, 5},
      {"collision:\n  halvings: 9\n  step_mm: 1\n  halvings: 4\n", "halvings", 4, 3},
  };
  for (const Case& c : cases) {
    INFO(c.yaml);
    const auto e = cell_error(c.yaml);
    CHECK(e.message.find(std::string("duplicate key '") + c.key + "'") != std::string::npos);
    CHECK(e.line == c.line);
    CHECK(e.column == c.column);
  }
}

TEST_CASE("the same key in different maps, and aliases, are not duplicates", "[cell][strict]") {
  const auto cell = test::load_cell_text(
      "objects:\n  - {name: a, box: &s [10, 10, 10], at: [600, 0, -900, 0, 0, 0]}\n"
      "  - {name: b, box: *s, at: [600, 100, -900, 0, 0, 0]}\n",
      "ok.yaml");
  CHECK(cell.objects.size() == 2);
}

TEST_CASE("conveyor speed: at most 10000 mm/s", "[cell][strict]") {
  for (const char* speed : {"1e308", "1e20", "10000.5"}) {
    INFO(speed);
    const auto e = cell_error(std::string("devices:\n  - {conveyor: belt, box: [1000, 200, 20], at: [600, 0, -600, 0, 0, 0], "
                                          "direction: [1, 0, 0], speed_mm_s: ") + speed + "}\n");
    CHECK(e.message.find("speed_mm_s must be at most 10000 mm/s") != std::string::npos);
    CHECK(e.line == 2);
  }
  const auto cell = test::load_cell_text(
      "devices:\n  - {conveyor: belt, box: [1000, 200, 20], at: [600, 0, -600, 0, 0, 0], direction: [1, 0, 0], "
      "speed_mm_s: 10000}\n",
      "ok.yaml");
  CHECK(cell.workcell.conveyors.at(0).speed_mm_s == 10000);
}

TEST_CASE("a conveyor direction of huge components is normalised, not zeroed", "[cell][strict]") {
  const auto cell = test::load_cell_text(
      "devices:\n  - {conveyor: belt, box: [1000, 200, 20], at: [600, 0, -600, 0, 0, 0], direction: [1e308, 1e308, 0], "
      "speed_mm_s: 100}\n",
      "ok.yaml");
  const auto d = cell.workcell.conveyors.at(0).direction;
  CHECK(d.x() == Approx(std::sqrt(0.5)));
  CHECK(d.y() == Approx(std::sqrt(0.5)));
  CHECK(d.z() == 0);
  const auto tiny = test::load_cell_text(
      "devices:\n  - {conveyor: belt, box: [1000, 200, 20], at: [600, 0, -600, 0, 0, 0], direction: [1e-320, 0, 0], "
      "speed_mm_s: 100}\n",
      "ok.yaml");
  CHECK(tiny.workcell.conveyors.at(0).direction.x() == 1);
}

TEST_CASE("a part inside an object or another part is refused at load", "[cell][strict]") {
  // Resting on the table (top face z = -400) and side by side: accepted.
  const auto ok = test::load_cell_text(kTable +
                                           "parts:\n  - {name: a, box: [50, 50, 50], at: [600, 0, -375, 0, 0, 0]}\n"
                                           "  - {name: b, box: [50, 50, 50], at: [650, 0, -375, 0, 0, 0]}\n",
                                       "ok.yaml");
  CHECK(ok.workcell.parts.size() == 2);
  // Sunk 5 mm into the table.
  auto e = cell_error(kTable + "parts:\n  - {name: a, box: [50, 50, 50], at: [600, 0, -380, 0, 0, 0]}\n");
  CHECK(e.message.find("part 'a' sinks into object 'table' at the start") != std::string::npos);
  CHECK(e.line == 4);
  // Wholly inside the table.
  e = cell_error(kTable + "parts:\n  - {name: a, box: [10, 10, 10], at: [600, 0, -420, 0, 0, 0]}\n");
  CHECK(e.message.find("part 'a' and object 'table' lie one inside the other") != std::string::npos);
  // Two parts overlapping: the later one is named.
  e = cell_error(kTable +
                 "parts:\n  - {name: a, box: [50, 50, 50], at: [600, 0, -375, 0, 0, 0]}\n"
                 "  - {name: b, box: [50, 50, 50], at: [630, 0, -375, 0, 0, 0]}\n");
  CHECK(e.message.find("part 'b' sinks into part 'a'") != std::string::npos);
  CHECK(e.line == 5);
  // A pattern whose pitch is smaller than its parts.
  e = cell_error(kTable + "parts:\n  - {name: p, box: [50, 50, 50], at: [600, 0, -375, 0, 0, 0], count: [2, 1, 1], pitch: [20, 0, 0]}\n");
  CHECK(e.message.find("part 'p2' sinks into part 'p1'") != std::string::npos);
}

TEST_CASE("a feeder into an always-open sink is refused, a gated sink is allowed", "[cell][strict]") {
  const std::string feeder = "devices:\n  - {feeder: f, part: {box: [20, 20, 20]}, at: [600, 0, -390, 0, 0, 0], count: 10000}\n";
  const auto e = cell_error(kTable + feeder + "  - {sink: s, box: [200, 200, 200], at: [600, 0, -300, 0, 0, 0]}\n");
  CHECK(e.message.find("feeder 'f' feeds into sink 's'") != std::string::npos);
  CHECK(e.line == 4);
  const auto ok = test::load_cell_text(kTable + feeder + "  - {sink: s, box: [200, 200, 200], at: [600, 0, -300, 0, 0, 0], signal: 2001}\n",
                                       "ok.yaml");
  CHECK(ok.workcell.sinks.size() == 1);
}

TEST_CASE("a feeder placing its parts into an object or a part is refused at load (#32)", "[cell][strict]") {
  // Resting on the table (top face at z = -400): accepted.
  const auto ok = test::load_cell_text(kTable + "devices:\n  - {feeder: f, part: {box: [40, 40, 40]}, at: [600, 0, -380, 0, 0, 0]}\n",
                                       "ok.yaml");
  CHECK(ok.workcell.feeders.size() == 1);
  // Sunk 10 mm into the table.
  auto e = cell_error(kTable + "devices:\n  - {feeder: f, part: {box: [40, 40, 40]}, at: [600, 0, -390, 0, 0, 0]}\n");
  CHECK(e.message.find("feeder 'f' places its parts sunk into object 'table'") != std::string::npos);
  CHECK(e.line == 4);
  // Wholly inside it.
  e = cell_error(kTable + "devices:\n  - {feeder: f, part: {box: [10, 10, 10]}, at: [600, 0, -420, 0, 0, 0]}\n");
  CHECK(e.message.find("feeder 'f' places its parts inside object 'table'") != std::string::npos);
  // Into a long declared part whose origin lies outside the feeder's spot (it never waits for it).
  const std::string bar = "parts:\n  - {name: bar, box: [200, 40, 40], at: [600, 0, -380, 0, 0, 0]}\n";  // x 500..700
  e = cell_error(kTable + bar + "devices:\n  - {feeder: f, part: {box: [40, 40, 40]}, at: [690, 0, -380, 0, 0, 0]}\n");
  CHECK(e.message.find("feeder 'f' places its parts sunk into part 'bar'") != std::string::npos);
  CHECK(e.line == 6);
  // A declared part waiting on the feeder's spot: the feeder feeds once it has left. Accepted.
  const auto waiting = test::load_cell_text(
      kTable + "parts:\n  - {name: first, box: [40, 40, 40], at: [600, 0, -380, 0, 0, 0]}\n" +
          "devices:\n  - {feeder: f, part: {box: [40, 40, 40]}, at: [600, 0, -380, 0, 0, 0], count: 3}\n",
      "ok.yaml");
  CHECK(waiting.workcell.parts.size() == 1);
  // Two feeders whose parts overlap and whose spots do not hold each other's feed pose.
  e = cell_error(kTable + "devices:\n  - {feeder: f, part: {box: [40, 40, 40]}, at: [600, 0, -380, 0, 0, 0], spot: [10, 10, 10]}\n"
                          "  - {feeder: g, part: {box: [40, 40, 40]}, at: [620, 0, -380, 0, 0, 0], spot: [10, 10, 10]}\n");
  CHECK(e.message.find("feeder 'g' places its parts sunk into feeder 'f'") != std::string::npos);
  CHECK(e.line == 5);
  // A feeder into a conveyor's body (conveyors are objects).
  e = cell_error("devices:\n  - {conveyor: belt, box: [800, 150, 40], at: [600, -300, -420, 0, 0, 0], speed_mm_s: 100}\n"
                 "  - {feeder: f, part: {box: [40, 40, 40]}, at: [600, -300, -390, 0, 0, 0]}\n");
  CHECK(e.message.find("feeder 'f' places its parts sunk into object 'belt'") != std::string::npos);
  CHECK(e.line == 3);
}

TEST_CASE("degenerate belts: zero length refused, zero speed a warning with its place (#32)", "[cell][strict]") {
  auto e = cell_error("devices:\n  - {conveyor: belt, box: [0, 150, 40], at: [600, -300, -420, 0, 0, 0], speed_mm_s: 100}\n");
  CHECK(e.message.find("conveyor 'belt'.box sides must be > 0") != std::string::npos);
  CHECK(e.line == 2);
  const auto still = test::load_cell_text(
      "devices:\n  - {conveyor: belt, box: [800, 150, 40], at: [600, -300, -420, 0, 0, 0], speed_mm_s: 0}\n", "still.yaml");
  REQUIRE(still.warnings.size() == 1);
  CHECK(still.warnings[0].find("still.yaml:2:") == 0);
  CHECK(still.warnings[0].find("conveyor 'belt' has speed_mm_s 0") != std::string::npos);
  CHECK(still.workcell.conveyors.at(0).speed_mm_s == 0);
}

TEST_CASE("a feeder into an always-open sink names both devices (#32)", "[cell][strict]") {
  const auto e = cell_error(kTable +
                            "devices:\n  - {feeder: f, part: {box: [20, 20, 20]}, at: [600, 0, -390, 0, 0, 0]}\n"
                            "  - {sink: s, box: [200, 200, 200], at: [600, 0, -300, 0, 0, 0]}\n",
                            "c.yaml");
  CHECK(e.message.find("feeder 'f' feeds into sink 's' (c.yaml:5:") != std::string::npos);
  CHECK(e.line == 4);
}

TEST_CASE("logic rules without delay that switch a signal on and off forever are refused at load (#32)", "[cell][strict]") {
  // A ring of four rules: 2001 on -> 2002 on -> 2001 off -> 2002 off -> 2001 on.
  const std::string ring = "logic:\n"
                           "  - {when: 2001, is: on, set: 2002, to: on}\n"
                           "  - {when: 2002, is: on, set: 2001, to: off}\n"
                           "  - {when: 2001, is: off, set: 2002, to: off}\n"
                           "  - {when: 2002, is: off, set: 2001, to: on}\n";
  auto e = cell_error(ring, "ring.yaml");
  CHECK(e.message.find("switch signal 2001 on and off forever") != std::string::npos);
  CHECK(e.message.find("2001 on -> 2002 on -> 2001 off -> 2002 off -> 2001 on") != std::string::npos);
  CHECK(e.message.find("ring.yaml:2:") != std::string::npos);
  CHECK(e.message.find("ring.yaml:5:") != std::string::npos);
  CHECK(e.line == 2);
  // One rule that inverts its own signal at once.
  e = cell_error("logic:\n  - {when: 2001, is: on, set: 2001, to: off}\n  - {when: 2001, is: off, set: 2001, to: on}\n");
  CHECK(e.message.find("switch signal 2001 on and off forever") != std::string::npos);
  // The same ring with a delay is a clock (a blinker): accepted.
  const auto blink = test::load_cell_text("logic:\n"
                                          "  - {when: 2001, is: on, set: 2002, to: on}\n"
                                          "  - {when: 2002, is: on, after: 0.1, set: 2001, to: off}\n"
                                          "  - {when: 2001, is: off, set: 2002, to: off}\n"
                                          "  - {when: 2002, is: off, set: 2001, to: on}\n",
                                          "ok.yaml");
  CHECK(blink.workcell.logic.size() == 4);
  // A pulse (on, then off at once) and signals following each other both ways end: accepted.
  const auto pulse = test::load_cell_text("logic:\n"
                                          "  - {when: 2001, is: on, set: 2002, to: on}\n"
                                          "  - {when: 2002, is: on, set: 2001, to: off}\n"
                                          "  - {follow: 2003, set: 2004}\n"
                                          "  - {follow: 2004, set: 2003}\n",
                                          "ok.yaml");
  CHECK(pulse.workcell.logic.size() == 6);
}

TEST_CASE("a logic rule setting a signal a sensor drives names both (#32)", "[cell][strict]") {
  const auto e = cell_error("devices:\n  - {sensor: eye, signal: 1001, box: [10, 10, 10], at: [0, 0, 0, 0, 0, 0]}\n"
                            "logic:\n  - {when: 1, is: on, set: 1001, to: on}\n",
                            "c.yaml");
  CHECK(e.message.find("signal 1001 is driven by sensor 'eye' (c.yaml:2:") != std::string::npos);
  CHECK(e.line == 4);
  // Two sensors on one signal are wired-OR, not a contradiction.
  const auto ok = test::load_cell_text("devices:\n  - {sensor: a, signal: 1001, box: [10, 10, 10], at: [0, 0, 0, 0, 0, 0]}\n"
                                       "  - {sensor: b, signal: 1001, box: [10, 10, 10], at: [0, 50, 0, 0, 0, 0]}\n",
                                       "ok.yaml");
  CHECK(ok.workcell.sensors.size() == 2);
}
