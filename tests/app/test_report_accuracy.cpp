// The --report "accuracy" and "timing" objects (docs/cli.md "--report") on the demos, with fixed and
// gap stepping (docs/collision.md §10): sane values, and the same contact either way.
#include "support/run_cli.hpp"

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <fstream>

using asimov::test::run_cli;
using asimov::test::source_path;

namespace {

nlohmann::json read_json(const std::filesystem::path& p) { return nlohmann::json::parse(asimov::test::slurp(p)); }

// The built-in cell with collision.stepping set.
std::filesystem::path stepping_cell(const std::string& stepping) {
  const auto p = asimov::test::scratch_dir() / ("cell-" + stepping + ".yaml");
  std::ofstream(p) << "tool: [0, 0, 200, 0, 0, 0]\n"
                      "tool_shape: {box: [50, 80, 140], at: [0, 0, 130, 0, 0, 0]}\n"
                      "objects:\n"
                      "  - {name: table, box: [700, 1200, 40], at: [750, 0, -420, 0, 0, 0]}\n"
                      "  - {name: box, box: [160, 160, 200], at: [600, 250, -300, 0, 0, 0]}\n"
                      "collision: {halvings: 9, step_mm: 1.0, clearance_mm: 0, stepping: "
                   << stepping << "}\n";
  return p;
}

nlohmann::json run_report(const std::string& demo, const std::string& stepping, int expected_exit) {
  const auto report = asimov::test::scratch_dir() / (demo + "-" + stepping + ".json");
  const auto r = run_cli("run " + source_path("programs/demo/" + demo + ".v2") + " --cell " +
                         stepping_cell(stepping).string() + " --report " + report.string());
  INFO(r.err);
  REQUIRE(r.exit_code == expected_exit);
  return read_json(report);
}

void check_timing(const nlohmann::json& doc) {
  const auto& t = doc["timing"];
  double sum = 0;
  for (const char* k : {"parse_s", "preprocess_s", "motion_s", "collision_s"}) {
    INFO(k);
    REQUIRE(t[k].is_number());
    CHECK(t[k].get<double>() >= 0);
    sum += t[k].get<double>();
  }
  CHECK(t["parse_s"].get<double>() > 0);
  CHECK(t["motion_s"].get<double>() > 0);
  CHECK(sum <= t["wall_s"].get<double>() * 1.01 + 1e-4);  // the phases are parts of the run
}

}  // namespace

TEST_CASE("report: pick_place states its accuracy and timing, and gap checks fewer poses than fixed") {
  const auto fixed = run_report("pick_place", "fixed", 0);
  const auto gap = run_report("pick_place", "gap", 0);
  for (const auto* doc : {&fixed, &gap}) {
    const auto& a = (*doc)["accuracy"];
    CHECK(a["motions"].get<int>() == 19);  // 3 x (APPRO, MOVES, DEPART) x 2 + the final MOVE
    CHECK(a["contact_bracket_s"].is_null());
    CHECK(a["ik_residual"]["solves"].get<std::uint64_t>() > 100);
    CHECK(a["ik_residual"]["position_mm"].get<double>() <= 1e-9);
    CHECK(a["ik_residual"]["rotation_rad"].get<double>() <= 1e-12);
    CHECK(a["line_deviation"]["intervals"].get<std::uint64_t>() > 0);
    CHECK(a["line_deviation"]["position_mm"].get<double>() > 0);
    CHECK(a["line_deviation"]["position_mm"].get<double>() < 1.0);
    check_timing(*doc);
  }
  CHECK(fixed["accuracy"]["stepping"] == "fixed");
  CHECK(gap["accuracy"]["stepping"] == "gap");
  CHECK(fixed["accuracy"]["step_displacement_mm"].get<double>() <= 1.0);  // step_mm
  CHECK(gap["accuracy"]["step_displacement_mm"].get<double>() > 1.0);     // far from everything
  CHECK(gap["poses_checked"].get<std::uint64_t>() * 10 < fixed["poses_checked"].get<std::uint64_t>());
  CHECK(gap["sim_time_s"] == fixed["sim_time_s"]);
}

TEST_CASE("report: crash finds the same contact with fixed and gap stepping, bracket within tolerance") {
  const auto fixed = run_report("crash", "fixed", 3);
  const auto gap = run_report("crash", "gap", 3);
  for (const auto* doc : {&fixed, &gap}) {
    const auto& a = (*doc)["accuracy"];
    REQUIRE(a["contact_bracket_s"].is_number());
    CHECK(a["contact_bracket_s"].get<double>() <= 1e-6);  // toc_tolerance_s
    CHECK(a["contact_bracket_s"] == (*doc)["collision"]["toc_bracket_s"]);
    CHECK(a["motions"].get<int>() == 2);
    check_timing(*doc);
  }
  CHECK(gap["collision"]["bodies"] == fixed["collision"]["bodies"]);
  CHECK(std::abs(gap["collision"]["time_s"].get<double>() - fixed["collision"]["time_s"].get<double>()) <= 1e-6);
  CHECK(gap["poses_checked"].get<std::uint64_t>() < fixed["poses_checked"].get<std::uint64_t>());
}
