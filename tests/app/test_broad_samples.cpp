// The broad phase (docs/collision.md §14) on the workcell samples of programs/cells: belts that
// run and stop, feeders, sinks, parts gripped, carried and placed. Each sample runs with the
// broad phase on and off (every pair at every pose, the reference), continuous and sampled, as
// written and with 50 resting parts on a rack beside the path (bench/bench_workcell.cpp's).
// Everything the user sees must agree: status, output, the contact (bodies, time), the events,
// every part's final pose and the clearance report.
#include "asimov/cell/cell_loader.hpp"
#include "asimov/interpreter/interpreter.hpp"
#include "asimov/motion/simulator.hpp"

#include "support/cell.hpp"
#include "support/run_cli.hpp"

#include <catch2/catch.hpp>

#include <sstream>

using namespace asimov;

namespace {
struct Outcome {
  interpreter::RunResult result;
  std::string out;
  std::vector<std::string> events;
  std::vector<motion::Location> poses;
  std::vector<motion::ClearanceApproach> clearance;
  std::uint64_t pairs_tested = 0;
};

Outcome run(motion::Cell cell, const std::string& program_path) {
  motion::Simulator sim(std::move(cell));
  Outcome o;
  std::ostringstream out;
  interpreter::Interpreter interp(sim, out);
  interp.load_file(program_path);
  o.result = interp.run(interp.program_names().front());
  o.out = out.str();
  if (const auto* c = interp.cell_state()) {
    for (const auto& e : c->clock().events()) o.events.push_back(e.kind + " " + e.subject + " " + e.detail);
    for (std::size_t i = 0; i < c->clock().parts().size(); ++i) o.poses.push_back(c->clock().part_pose(i));
  }
  o.clearance = sim.recorders().clearance.pairs;
  o.pairs_tested = sim.recorders().counts.counts.pairs_enabled;
  return o;
}
}  // namespace

TEST_CASE("the broad phase changes nothing a user sees in the workcell samples, with 50 parts beside the path") {
  const std::string dir = std::string(ASIMOV_SOURCE_DIR) + "/programs/cells/";
  const std::vector<std::pair<std::string, std::string>> samples = {{"belt_pick.v2", "belt_cell.yaml"},
                                                                    {"belt_jam.v2", "belt_jam_cell.yaml"},
                                                                    {"palletizer.v2", "palletizer_cell.yaml"},
                                                                    {"sorter.v2", "sorter_cell.yaml"},
                                                                    {"carried_crash.v2", "carried_crash_cell.yaml"}};
  const std::string rack = "  - {name: stock, box: [40, 40, 40], at: [130, 430, -380, 0, 0, 0], count: [5, 5, 2], pitch: [60, 60, 40]}\n";
  int runs = 0, fewer = 0;
  for (const auto& [program, cell_file] : samples)
    for (const bool stock : {false, true})
      for (const bool continuous : {true, false}) {
        CAPTURE(program, stock, continuous);
        std::string yaml = test::slurp(dir + cell_file);
        REQUIRE(!yaml.empty());
        // The rack's parts: first in the cell's own `parts:` list, or a new one.
        if (const auto at = yaml.find("\nparts:\n"); stock && at != std::string::npos) yaml.insert(at + 8, rack);
        else if (stock) yaml += "\nparts:\n" + rack;
        motion::Cell on = test::load_cell_text(yaml, cell_file, dir);
        on.collision.continuous = continuous;
        motion::Cell off = on;
        off.collision.broad_phase = false;
        const Outcome a = run(on, dir + program), b = run(off, dir + program);
        ++runs;
        CHECK(a.result.status == b.result.status);
        CHECK(a.out == b.out);
        CHECK(a.result.collision.body_a == b.result.collision.body_a);
        CHECK(a.result.collision.body_b == b.result.collision.body_b);
        CHECK(std::abs(a.result.collision.time_s - b.result.collision.time_s) <= 2e-6 + 1e-12);
        CHECK(a.events == b.events);
        REQUIRE(a.poses.size() == b.poses.size());
        for (std::size_t i = 0; i < a.poses.size(); ++i)
          CHECK((a.poses[i].matrix() - b.poses[i].matrix()).cwiseAbs().maxCoeff() <= 1e-9);
        CHECK(a.clearance.size() == b.clearance.size());
        for (const auto& x : b.clearance) {
          const auto it = std::find_if(a.clearance.begin(), a.clearance.end(), [&](const auto& y) { return y.pair == x.pair; });
          REQUIRE(it != a.clearance.end());
          CHECK(std::abs(it->distance_mm - x.distance_mm) <= 1e-6);
        }
        if (a.pairs_tested < b.pairs_tested) ++fewer;
      }
  CHECK(runs >= 12);
  CHECK(fewer >= runs / 2);  // the broad phase did leave pairs out
}
