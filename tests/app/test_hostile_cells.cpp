// Hostile cell files (issue 17): every one ends at once with an Error naming the place,
// never a crash, a hang or a message a user cannot act on.
#include "support/scratch.hpp"
#include "asimov/cell/cell_loader.hpp"
#include "asimov/collision/mesh_io.hpp"
#include "support/cell.hpp"

#include <catch2/catch.hpp>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>

using namespace asimov;

namespace {

using test::cell_error;

double seconds(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

std::string repeat(const std::string& s, int n) {
  std::string out;
  for (int i = 0; i < n; ++i) out += s;
  return out;
}

}  // namespace

TEST_CASE("cylinder.segments out of int range is an error, not a cast", "[cell][hostile]") {
  for (const char* v : {"1e300", "-1e300", "2.5", "2", "4097", ".nan", ".inf"}) {
    const auto e = cell_error(std::string("objects:\n  - {name: c, cylinder: {radius: 1, height: 1, segments: ") + v + "}}\n");
    INFO(v);
    CHECK_THAT(e.message, Catch::Contains("segments must be") || Catch::Contains("finite"));
    CHECK(e.line == 2);
  }
}

TEST_CASE("enabled: maybe, an object written as a number, a list as a name", "[cell][hostile]") {
  auto e = cell_error("collision: {enabled: maybe}\n");
  CHECK(e.message == "collision.enabled must be true or false, got 'maybe'");
  CHECK(e.line == 1);
  CHECK(e.column == 22);
  e = cell_error("objects:\n  - 5\n");
  CHECK(e.message == "an object is a map like {name: n, box: [x, y, z], at: [x, y, z, o, a, t]}");
  CHECK(e.line == 2);
  e = cell_error("objects:\n  - {name: [a, b], box: [1, 1, 1]}\n");
  CHECK(e.message == "an object's name must be a name, not a list or map");
  e = cell_error("collision: {ignore: [[[x], link1]]}\n");
  CHECK(e.message == "a body in collision.ignore must be a name, not a list or map");
  e = cell_error("tool_shape: 5\n");
  CHECK(e.message == "tool_shape must be a map");
  e = cell_error("collision: 5\n");
  CHECK(e.message == "collision must be a map");
  e = cell_error("objects: {a: 1}\n");
  CHECK(e.message == "objects must be a list");
  e = cell_error("{[a]: 1}\n");
  CHECK(e.message == "a key in the cell must be a name, not a list or map");
}

TEST_CASE("NaN and infinity anywhere in a cell's numbers", "[cell][hostile]") {
  for (const char* yaml : {"base: [0, 0, .inf, 0, 0, 0]\n", "tool: [.nan, 0, 0, 0, 0, 0]\n",
                           "objects:\n  - {name: b, box: [1, -.inf, 1]}\n",
                           "objects:\n  - {name: b, box: [1, 1, 1], at: [0, 0, 0, .nan, 0, 0]}\n",
                           "objects:\n  - {name: s, sphere: {radius: .inf}}\n",
                           "collision: {clearance_mm: .nan}\n", "collision: {step_mm: .inf}\n",
                           "start: [0, .nan, 0, 0, 0, 0]\n"}) {
    INFO(yaml);
    CHECK_THAT(cell_error(yaml).message, Catch::Contains("must be finite"));
  }
}

TEST_CASE("step_mm below the simulator's finest step is refused, not silently raised", "[cell][hostile]") {
  const auto e = cell_error("collision: {step_mm: 1e-4}\n");
  CHECK(e.message == "collision.step_mm must be >= 0.001, got 0.0001");
  CHECK(test::load_cell_text("collision: {step_mm: 0.001}\n", "ok.yaml").collision.step_mm == 0.001);
}

TEST_CASE("a sphere past the face budget is an error at once", "[cell][hostile]") {
  const auto t0 = std::chrono::steady_clock::now();
  const auto e = cell_error("objects:\n  - {name: s, sphere: {radius: 1e8, tolerance_mm: 1e-6}}\n");
  CHECK(seconds(t0) < 5);
  CHECK(e.message ==
        "object 's'.sphere: a sphere of radius 1e+08 mm within 1e-06 mm needs more than 100000 faces, the limit "
        "for one primitive; use a larger tolerance_mm");
  CHECK(e.line == 2);
  // Just inside the budget it is built, and within it.
  const auto ok = test::load_cell_text("objects:\n  - {name: s, sphere: {radius: 1000, tolerance_mm: 0.1}}\n", "ok.yaml");
  CHECK(ok.objects[0].mesh.triangles.size() <= collision::kMaxPrimitiveFaces);
  CHECK(ok.objects[0].mesh.triangles.size() > 10000);
}

TEST_CASE("nesting deeper than the YAML limit is refused before yaml-cpp recurses", "[cell][hostile]") {
  for (const std::string& yaml : {repeat("[", 100000), repeat("{a: ", 100000), repeat("- ", 100000) + "1\n"}) {
    const auto e = cell_error(yaml);
    CHECK(e.message == "nested more than 64 levels deep");
    CHECK(e.line == 1);
  }
  // Block nesting by indentation.
  std::string indented;
  for (int i = 0; i < 5000; ++i) indented += std::string(static_cast<std::size_t>(i), ' ') + "a:\n";
  const auto e = cell_error(indented);
  CHECK(e.message == "nested more than 64 levels deep");
  CHECK(e.line == 64);
  // Brackets inside quotes, comments and block scalars do not count.
  CHECK_THAT(cell_error("x: '" + repeat("[", 1000) + "'\n# " + repeat("{", 1000) + "\ny: |\n  " + repeat("[", 1000) + "\n").message,
             Catch::Contains("unknown key 'x'"));
}

TEST_CASE("aliases that multiply (billion laughs) stay shared and end at once", "[cell][hostile]") {
  std::string yaml = "a0: &a0 [lol, lol, lol, lol, lol, lol, lol, lol, lol, lol]\n";
  for (int i = 1; i < 10; ++i) {
    yaml += "a" + std::to_string(i) + ": &a" + std::to_string(i) + " [";
    for (int k = 0; k < 10; ++k) yaml += std::string(k ? ", " : "") + "*a" + std::to_string(i - 1);
    yaml += "]\n";
  }
  const auto t0 = std::chrono::steady_clock::now();
  CHECK_THAT(cell_error(yaml).message, Catch::Contains("unknown key 'a0'"));
  CHECK_THAT(cell_error("x: &x [1, 1, 1, 1, 1, 1, 1, 1, 1, 1]\nobjects: [*x, *x, *x, *x]\n").message,
             Catch::Contains("unknown key 'x'"));
  CHECK_THAT(cell_error("objects: &o [{name: a, box: [1, 1, 1]}]\ncollision: {ignore: [*o, *o]}\n").message,
             Catch::Contains("collision.ignore entries are [body, body]"));
  CHECK(seconds(t0) < 5);
}

TEST_CASE("20,000 objects load in seconds, more than 100,000 are refused", "[cell][hostile]") {
  std::string yaml = "objects:\n";
  for (int i = 0; i < 20000; ++i)
    yaml += "  - {name: o" + std::to_string(i) + ", box: [1, 1, 1], at: [" + std::to_string(i % 100 * 3 + 400) + ", " +
            std::to_string(i / 100 * 3) + ", -500, 0, 0, 0]}\n";
  const auto t0 = std::chrono::steady_clock::now();
  const auto cell = test::load_cell_text(yaml, "many.yaml");
  CHECK(cell.objects.size() == 20000);
  CHECK(seconds(t0) < 10);
  std::string too_many = "objects: [";
  for (int i = 0; i <= 100000; ++i) too_many += i ? ", 1" : "1";
  too_many += "]\n";
  CHECK(cell_error(too_many).message == "100001 objects; a cell has at most 100000");
}

TEST_CASE("cell files that are folders, devices or missing: bounded reads", "[cell][hostile]") {
  const auto file_error = [](const std::string& path) -> std::string {
    const auto cell = cell::load_cell_file(path);
    return cell ? std::string("no error") : cell::format_cell_error(cell.error());
  };
  const auto dir = asimov::test::scratch_dir("hostile-cell");
  CHECK(file_error(dir.string()) == dir.string() + ": is a directory, not a file");
  const auto t0 = std::chrono::steady_clock::now();
  CHECK(file_error("/dev/zero") == "/dev/zero: is larger than 64 MiB, the limit for this kind of file");
  CHECK(seconds(t0) < 10);
  CHECK(file_error((dir / "none.yaml").string()) ==
        (dir / "none.yaml").string() + ": cannot open the file (No such file or directory)");
}
