// A reacting cell with 50 parts against the same cell without them (#12, docs/cell-format.md
// "Parts and devices").
//
// The belt sample (programs/cells/belt_pick.v2 in belt_cell.yaml: conveyor, sensor, feeder,
// sink, logic) runs in two cells that differ only in `parts`: both get a rack beside the
// table; one has 50 cubes on it (a 5 x 5 x 2 stack at 60 mm pitch, collision bodies tested
// against the arm at every checked pose), the peer none. Each run is the whole program from a
// fresh Simulator (engine building, devices, motions, collision checks), in thread CPU time;
// median of kRuns runs each, alternated. ratio = ours (50 parts) / peer (no parts); speed
// ratio = 1 / ratio (#32 asks >= 0.9). A third row puts 500 parts on the rack in 100 stacks
// of 5 (parts resting on parts). agreement: both complete with the same output
// and the same final poses of the belt's four cubes.
// Writes bench/results/workcell.json (or argv[1]) and prints a table.
#include "cpu_time.hpp"
#include "asimov/cell/cell_loader.hpp"
#include "asimov/interpreter/interpreter.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <ctime>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

using namespace asimov;

namespace {
constexpr int kRuns = 9;

std::string read(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

struct Outcome {
  double us = 0;
  std::string out;
  std::vector<double> belt_x;  // final x of cube1..cube4
  std::size_t parts = 0;
  std::uint64_t poses = 0;
  bool completed = false;
};

Outcome run_once(const std::string& cell_yaml, const std::string& program) {
  const double t0 = cpu_us();
  auto loaded = cell::load_cell_text(cell_yaml, "belt_cell.yaml", ASIMOV_SOURCE_DIR "/programs/cells");
  if (!loaded) throw std::runtime_error(cell::format_cell_error(loaded.error()));
  motion::Cell cell = std::move(loaded).value();
  motion::Simulator sim(std::move(cell));
  std::ostringstream out;
  interpreter::Interpreter interp(sim, out);
  interp.load_source(program, "belt_pick.v2");
  const interpreter::RunResult r = interp.run("belt_pick");
  Outcome o;
  o.us = cpu_us() - t0;
  o.out = out.str();
  o.completed = r.status == interpreter::RunStatus::completed;
  o.poses = sim.recorders().counts.poses;
  if (const auto* c = interp.cell_state()) {
    o.parts = c->clock().parts().size();
    for (std::size_t i = 0; i < c->clock().parts().size(); ++i)
      if (c->clock().parts()[i].def->name.rfind("cube", 0) == 0) o.belt_x.push_back(c->clock().part_pose(i).translation().x());
  }
  return o;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}
}  // namespace

int main(int argc, char** argv) {
  const std::string out_path = argc > 1 ? argv[1] : ASIMOV_SOURCE_DIR "/bench/results/workcell.json";
  const std::string base = read(ASIMOV_SOURCE_DIR "/programs/cells/belt_cell.yaml");
  const std::string program = read(ASIMOV_SOURCE_DIR "/programs/cells/belt_pick.v2");
  // The rack (top face at z = -400) lies beside the table, within the arm's reach, so the
  // parts' pairs are tested near the path too.
  const std::string rack = "\nobjects:\n"
                           "  - {name: table, box: [400, 200, 40], at: [600, 250, -420, 0, 0, 0]}\n"
                           "  - {name: rack, box: [320, 320, 40], at: [250, 550, -420, 0, 0, 0]}\n";
  std::string without = base;
  const auto objects_at = without.find("objects:");
  const auto devices_at = without.find("devices:");
  without = without.substr(0, objects_at) + rack.substr(1) + without.substr(devices_at);
  const std::string with = without + "parts:\n  - {name: stock, box: [40, 40, 40], at: [130, 430, -380, 0, 0, 0], "
                                     "count: [5, 5, 2], pitch: [60, 60, 40]}\n";
  // 500 parts in 100 stacks of 5 (each resting on the one below, #32) on the same rack: 25 mm
  // cubes, 10 x 10 at a 30 mm pitch, 125 mm high.
  const std::string stacks = without + "parts:\n  - {name: stock, box: [25, 25, 25], at: [115, 415, -387.5, 0, 0, 0], "
                                       "count: [10, 10, 5], pitch: [30, 30, 25]}\n";
  // Rows: the cell's collision settings as written (continuous checking on, the default), with
  // `continuous: false` (sampled poses only), and the 500-part stacks (default settings).
  const auto sampled = [](std::string y) {
    const std::string key = "clearance_mm: 0}";
    return y.replace(y.find(key), key.size(), "clearance_mm: 0, continuous: false}");
  };
  struct Row {
    const char* mode;
    std::string ours, peer;
    int parts;
  };
  const std::vector<Row> rows = {{"continuous checking (default)", with, without, 50},
                                 {"continuous: false", sampled(with), sampled(without), 50},
                                 {"continuous checking (default), in 100 stacks of 5", stacks, without, 500}};
  std::ofstream f(out_path);
  f << "[\n";
  bool all_agree = true;
  for (std::size_t row = 0; row < rows.size(); ++row) {
    const Row& rw = rows[row];
    std::vector<double> ours, peer;
    Outcome a, b;
    for (int k = 0; k < kRuns; ++k) {
      a = run_once(rw.ours, program);
      b = run_once(rw.peer, program);
      ours.push_back(a.us);
      peer.push_back(b.us);
    }
    const bool agree = a.completed && b.completed && a.out == b.out && a.belt_x.size() == 4 && b.belt_x.size() == 4 &&
                       std::equal(a.belt_x.begin(), a.belt_x.end(), b.belt_x.begin(),
                                  [](double x, double y) { return std::abs(x - y) < 1e-9; });
    all_agree = all_agree && agree;
    const double m_ours = median(ours), m_peer = median(peer), ratio = m_ours / m_peer;
    fmt::print("{}: {} parts + conveyor {:.0f} us ({} parts at the end, {} checked poses); no parts {:.0f} us ({} poses)\n",
               rw.mode, rw.parts, m_ours, a.parts, a.poses, m_peer, b.poses);
    fmt::print("  ratio {:.3f} (speed {:.3f} of the cell without parts), agreement {}\n", ratio, 1 / ratio, agree);
    f << fmt::format(
        "  {{\"name\": \"belt sample (conveyor, sensor, feeder, sink, logic) with {} resting parts, {}\", \"ours_us\": {:.1f}, "
        "\"peer\": \"same cell and program without the parts\", \"peer_us\": {:.1f}, \"ratio\": {:.3f}, \"speed\": {:.3f}, "
        "\"agreement\": {}, \"checked_poses\": [{}, {}], \"runs\": {}}}{}\n",
        rw.parts, rw.mode, m_ours, m_peer, ratio, 1 / ratio, agree ? 1 : 0, a.poses, b.poses, kRuns, row + 1 < rows.size() ? "," : "");
  }
  f << "]\n";
  const bool agree = all_agree;
  return agree ? 0 : 1;
}
