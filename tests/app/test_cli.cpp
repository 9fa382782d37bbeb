// End-to-end: the asimov executable as users and suites call it (docs/cli.md).
#include "asimov/cell/cell_loader.hpp"
#include "support/cell_bodies.hpp"
#include "support/geometry.hpp"
#include "support/run_cli.hpp"

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

using namespace asimov;
using test::run_cli;
using test::source_path;

namespace {

nlohmann::json read_json(const std::filesystem::path& p) { return nlohmann::json::parse(test::slurp(p)); }

std::filesystem::path write_file(const std::string& name, const std::string& text) {
  const auto p = test::scratch_dir() / name;
  std::ofstream(p, std::ios::binary) << text;
  return p;
}


}  // namespace

TEST_CASE("pick_place demo completes with exit 0 and a completed report") {
  const auto report = test::scratch_dir() / "pick.json";
  const auto r = run_cli("run " + source_path("programs/demo/pick_place.v2") + " --report " + report.string());
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  CHECK(r.out.find("placed part 3") != std::string::npos);
  const auto doc = read_json(report);
  CHECK(doc["status"] == "completed");
  CHECK(doc["program"] == "pick_place");
  CHECK(doc["poses_checked"].get<std::uint64_t>() > 100);  // gap stepping (docs/collision.md §10)
  CHECK(doc["sim_time_s"].get<double>() > 1.0);
  CHECK(doc["collision_engine"]["used"] == true);
}

TEST_CASE("crash demo halts with exit 3, the contact point lies on both bodies") {
  const auto report = test::scratch_dir() / "crash.json";
  const auto r = run_cli("run " + source_path("programs/demo/crash.v2") + " --report " + report.string());
  INFO(r.out << r.err);
  REQUIRE(r.exit_code == 3);
  CHECK(r.err.find("*Collision*") != std::string::npos);
  const auto doc = read_json(report);
  REQUIRE(doc["status"] == "collision");
  CHECK(doc["program"] == "crash");
  CHECK(doc["line"].get<int>() > 0);
  const auto bodies = doc["collision"]["bodies"];
  const std::string a = bodies[0], b = bodies[1];
  CHECK((a.rfind("link", 0) == 0 || b.rfind("link", 0) == 0));
  CHECK((a == "box" || b == "box"));

  // Contact time bisected to 1e-6 s (motion/README.md): t_free <= t_hit within the bracket.
  const double t_hit = doc["collision"]["time_s"], t_free = doc["collision"]["time_free_s"];
  CHECK(t_free < t_hit);
  CHECK(doc["collision"]["toc_bracket_s"].get<double>() <= 1e-6);
  CHECK(doc["collision_engine"]["bisection_checks"].get<std::uint64_t>() > 0);
  CHECK(doc["collision"]["faces"].size() == 2);

  const auto cell = cell::default_cell();
  robots::JointVector q(cell.robot.joint_count());
  for (int i = 0; i < q.size(); ++i) q[i] = doc["collision"]["joints_deg"][static_cast<std::size_t>(i)];
  const auto p = doc["collision"]["point_mm"];
  const collision::Vec3 point(p[0], p[1], p[2]);
  for (const auto& name : {a, b}) {
    const auto [mesh, pose] = test::body_in_world(cell, name, q);
    CHECK(test::point_surface_distance(point, mesh, pose) <= 0.01);
  }
}

TEST_CASE("trace lists every checked pose with increasing time") {
  const auto trace = test::scratch_dir() / "trace.json";
  const auto report = test::scratch_dir() / "trace-report.json";
  const auto r = run_cli("run " + source_path("programs/demo/pick_place.v2") + " --trace " + trace.string() +
                         " --report " + report.string());
  REQUIRE(r.exit_code == 0);
  const auto doc = read_json(trace);
  const auto& samples = doc["samples"];
  REQUIRE(samples.size() == read_json(report)["poses_checked"].get<std::size_t>());
  double last = -1;
  for (const auto& s : samples) {
    CHECK(s["t"].get<double>() >= last);
    last = s["t"];
    CHECK(s["joints_deg"].size() == 6);
    CHECK(s["tool_xyzoat"].size() == 6);
  }
}

TEST_CASE("check reports syntax errors with file:line:column and exits 2") {
  const auto file = write_file("bad.v2", ".PROGRAM bad()\n    x = 1\n    y = (x + 2\n.END\n");
  const auto r = run_cli("check " + file.string());
  CHECK(r.exit_code == 2);
  CHECK(r.err.find("*Syntax error*") != std::string::npos);
  CHECK(r.err.find("bad.v2:3:") != std::string::npos);
  CHECK(r.err.find('^') != std::string::npos);
}

TEST_CASE("check accepts the demos and runs nothing") {
  const auto r = run_cli("check " + source_path("programs/demo/crash.v2"));
  CHECK(r.exit_code == 0);
  CHECK(r.out.empty());
}

TEST_CASE("run: a syntax error exits 2 with an error report, nothing moves") {
  const auto file = write_file("bad2.v2", ".PROGRAM bad2()\n    MOVE\n.END\n");
  const auto report = test::scratch_dir() / "bad2.json";
  const auto r = run_cli("run " + file.string() + " --report " + report.string());
  CHECK(r.exit_code == 2);
  const auto doc = read_json(report);
  CHECK(doc["status"] == "error");
  CHECK(doc["poses_checked"] == 0);
  CHECK(doc["error"]["message"] == "*Syntax error*");
  CHECK(doc["error"]["line"] == 2);
  CHECK(doc["error"]["column"].get<int>() > 0);
}

TEST_CASE("run: a location out of reach is a program error, exit 2") {
  const auto file = write_file("far.v2", ".PROGRAM far()\n    SET p = TRANS(3000, 0, 0, 0, 180, 0)\n    MOVE p\n.END\n");
  const auto report = test::scratch_dir() / "far.json";
  const auto r = run_cli("run " + file.string() + " --report " + report.string());
  CHECK(r.exit_code == 2);
  CHECK(r.err.find("*Location out of reach*") != std::string::npos);
  const auto doc = read_json(report);
  CHECK(doc["status"] == "error");
  CHECK(doc["error"]["message"] == "*Location out of reach*");
  CHECK(doc["line"] == 3);
}

TEST_CASE("run: the main option selects the program, names are case-insensitive") {
  const auto file = write_file("two.v2",
                               ".PROGRAM first()\n    TYPE \"first\"\n.END\n.PROGRAM Second()\n    TYPE \"second\"\n.END\n");
  CHECK(run_cli("run " + file.string()).out == "first\n");
  CHECK(run_cli("run " + file.string() + " --main SECOND").out == "second\n");
  const auto r = run_cli("run " + file.string() + " --main third");
  CHECK(r.exit_code == 1);
  CHECK(r.err.find("*Undefined program or variable name*") != std::string::npos);
}

TEST_CASE("usage and file errors exit 1") {
  CHECK(run_cli("").exit_code == 0);  // no subcommand starts the monitor; empty stdin ends it
  CHECK(run_cli("bogus").exit_code == 1);
  CHECK(run_cli("run").exit_code == 1);
  CHECK(run_cli("run --bogus x.v2").exit_code == 1);
  const auto missing = run_cli("run /nonexistent/x.v2");
  CHECK(missing.exit_code == 1);
  CHECK(missing.err.find("*File not found*") != std::string::npos);
}

TEST_CASE("a bad cell file exits 1 naming file, line and column") {
  const auto cell = write_file("bad_cell.yaml", "robot: puma560\nobjects:\n  - {name: t, box: [100, -5, 10]}\n");
  const auto r = run_cli("run " + source_path("programs/demo/pick_place.v2") + " --cell " + cell.string());
  CHECK(r.exit_code == 1);
  CHECK(r.err.find("bad_cell.yaml:3:") != std::string::npos);
  CHECK(r.err.find("> 0") != std::string::npos);
}

TEST_CASE("a cell with collision disabled never uses the engine") {
  const auto cell = write_file("free.yaml", "collision: {enabled: false}\n");
  const auto report = test::scratch_dir() / "free.json";
  const auto r = run_cli("run " + source_path("programs/demo/crash.v2") + " --cell " + cell.string() + " --report " +
                         report.string());
  CHECK(r.exit_code == 0);
  const auto doc = read_json(report);
  CHECK(doc["collision_engine"]["used"] == false);
  CHECK(doc["collision_engine"]["face_pairs"] == 0);
}

TEST_CASE("run: a URDF arm from a cell file completes its demo") {
  const auto r = run_cli("run " + source_path("programs/cells/generic6_demo.v2") + " --cell " +
                         source_path("programs/cells/generic6_cell.yaml"));
  INFO(r.err);
  CHECK(r.exit_code == 0);
  CHECK(r.out.find("done") != std::string::npos);
}

TEST_CASE("run: the Viper's pick and place stops on the PUMA with the same tool on the same floor") {
  // programs/cells/viper_pick.v2 completes in viper_cell.yaml (its expect.json); the
  // PUMA cannot reach its places tool-down in any configuration (tests/robots/test_viper_s650.cpp).
  const auto r = run_cli("run " + source_path("programs/cells/viper_pick.v2") + " --cell " +
                         source_path("programs/cells/puma_floor_cell.yaml"));
  INFO(r.err);
  CHECK(r.exit_code == 2);
  CHECK(r.out.empty());
  CHECK((r.err.find("*Joint limit exceeded*") != std::string::npos ||
         r.err.find("*Location out of reach*") != std::string::npos));
  CHECK(r.err.find("viper_pick.v2:13") != std::string::npos);  // the first APPRO
}

TEST_CASE("run: V+ constructs that only warn are reported once, in stderr and the report") {
  const auto file = write_file("warn.v2",
                               ".PROGRAM warn()\n    FOR i = 1 TO 3\n        SELECT ROBOT = 1\n    END\n    TYPE \"ok\"\n.END\n");
  const auto report = test::scratch_dir() / "warn.json";
  const auto r = run_cli("run " + file.string() + " --report " + report.string());
  INFO(r.err);
  CHECK(r.exit_code == 0);
  CHECK(r.out == "ok\n");
  CHECK(r.err.find("Warning: *Not supported in simulation*") != std::string::npos);
  const auto doc = read_json(report);
  REQUIRE(doc["warnings"].size() == 1);
  CHECK(doc["warnings"][0]["line"] == 3);
}

TEST_CASE("run: PAUSE ends a batch run with exit 0 and status paused") {
  const auto file = write_file("pause.v2", ".PROGRAM p()\n    TYPE \"before\"\n    PAUSE\n    TYPE \"after\"\n.END\n");
  const auto report = test::scratch_dir() / "pause.json";
  const auto r = run_cli("run " + file.string() + " --report " + report.string());
  INFO(r.err);
  CHECK(r.exit_code == 0);
  CHECK(r.out == "before\n");
  CHECK(r.err.find("Program paused: p, step 2") != std::string::npos);
  CHECK(read_json(report)["status"] == "paused");
}

TEST_CASE("run: PROMPT reads standard input, bad input when not at a terminal is an error") {
  const auto file = write_file("prompt.v2", ".PROGRAM p()\n    PROMPT \"n? \", n\n    TYPE \"twice: \", 2 * n\n.END\n");
  const auto ok = run_cli("run " + file.string(), "21\n");
  CHECK(ok.exit_code == 0);
  CHECK(ok.out.find("twice: 42") != std::string::npos);
  const auto bad = run_cli("run " + file.string(), "abc\n");
  CHECK(bad.exit_code == 2);
  CHECK(bad.err.find("*Illegal value*") != std::string::npos);
}
