// Continuous checking (docs/collision.md §12) against gap stepping alone, in the same run:
// the same program in the same cell with `collision.continuous` true and false. Thread CPU
// time of the whole run (interpreter, planning, walking, queries; the cell and engine are built
// before the clock starts), median of kRuns runs each, the two settings alternated; ratio =
// continuous / gap stepping alone. `agreement`: whether both ended the same way (status, and
// for a contact the bodies and the time). Cases: the two demos in the default cell, the
// thin-plate programs in their cells (there the settings differ on purpose: the checked poses
// alone miss the plate), and a random-motion suite: 40 random joint moves of the PUMA in the
// default cell from READY, each joint within +-40 deg of it (seeded; a contact ends the run);
// and crash.v2 again without the clearance report, to show what the report costs.
// Writes bench/results/continuous.json (or argv[1]) and prints a table.
#include "cpu_time.hpp"
#include "asimov/cell/cell_loader.hpp"
#include "asimov/interpreter/interpreter.hpp"
#include "asimov/motion/simulator.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <functional>
#include <iostream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

using namespace asimov;

namespace {

// Runs take ~1 ms: medians of 15 moved the ratio by +-0.03 between runs of the bench.
constexpr int kRuns = 101;

struct Outcome {
  std::string status;  // completed | collision | error
  std::string bodies;
  double time_s = 0;
  std::uint64_t poses = 0, probes = 0;
  bool operator==(const Outcome& o) const { return status == o.status && bodies == o.bodies && time_s == o.time_s; }
};

struct Case {
  std::string name;
  std::function<motion::Cell()> cell;
  std::function<Outcome(motion::Simulator&)> run;  // timed
};

// `contact`: the collision that ended the run, null when none did.
Outcome outcome_of(const motion::Simulator& sim, std::string status, const motion::CollisionReport* contact) {
  Outcome o;
  o.status = std::move(status);
  if (contact) {
    o.bodies = contact->body_a + " / " + contact->body_b;
    o.time_s = contact->time_s;
  }
  o.poses = sim.recorders().counts.poses;
  o.probes = sim.recorders().counts.bisection;
  return o;
}

Outcome outcome_of(const motion::Simulator& sim, const motion::MotionResult& r, bool ok) {
  const bool hit = r.status == motion::MotionStatus::collision;
  return outcome_of(sim, hit ? "collision" : ok ? "completed" : "error", hit ? &r.collision : nullptr);
}

Case program_case(const std::string& program, const std::string& cell_file) {
  const std::string path = std::string(ASIMOV_SOURCE_DIR) + "/programs/" + program;
  const std::string cell_path = cell_file.empty() ? "" : std::string(ASIMOV_SOURCE_DIR) + "/programs/" + cell_file;
  return {program,
          [cell_path] {
            if (cell_path.empty()) return cell::default_cell();
            auto cell = cell::load_cell_file(cell_path);
            if (!cell) throw std::runtime_error(cell::format_cell_error(cell.error()));
            return std::move(cell).value();
          },
          [path](motion::Simulator& sim) {
            std::ostringstream out;
            interpreter::Interpreter interp(sim, out);
            interp.load_file(path);
            const auto names = interp.program_names();
            const interpreter::RunResult r = interp.run(names.front());
            const bool hit = r.status == interpreter::RunStatus::collision;
            return outcome_of(sim, r.status == interpreter::RunStatus::completed ? "completed" : hit ? "collision" : "error",
                              hit ? &r.collision : nullptr);
          }};
}

Case random_case() {
  return {"random joint moves (40, seed 14)", [] { return cell::default_cell(); },
          [](motion::Simulator& sim) {
            std::mt19937_64 rng(14);
            std::uniform_real_distribution<double> u(-40, 40);
            const robots::JointVector ready = sim.joints();
            motion::MotionResult r;
            bool ok = true;
            for (int k = 0; k < 40 && ok; ++k) {
              robots::JointVector q = ready;
              for (int j = 0; j < q.size(); ++j) q[j] += u(rng);
              r = sim.start_joint_move(q, {}, k + 1);
              if (r.status == motion::MotionStatus::ok) r = sim.finish_motion();
              ok = r.status == motion::MotionStatus::ok;
            }
            if (ok) r = sim.finish_motion();
            return outcome_of(sim, r, r.status == motion::MotionStatus::ok);
          }};
}

// The same case with no clearance report (report_within_mm 0): continuous checking's own cost,
// without the exact distances the report asks for at checked poses.
Case without_report(Case c) {
  c.name += " (report_within_mm: 0)";
  c.cell = [make = c.cell] {
    motion::Cell cell = make();
    cell.collision.report_within_mm = 0;
    return cell;
  };
  return c;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  const std::string out_path =
      argc > 1 ? argv[1] : std::string(ASIMOV_SOURCE_DIR) + "/bench/results/continuous.json";
  std::vector<Case> cases = {program_case("demo/crash.v2", ""), program_case("demo/pick_place.v2", ""),
                             random_case(), without_report(program_case("demo/crash.v2", "")),
                             program_case("stiff/thin_0_1mm_step20_speed100.v2", "stiff/thin_plate_0_1mm_step20.yaml"),
                             program_case("stiff/thin_1mm_step1.v2", "stiff/thin_plate_1mm_step1.yaml")};
  nlohmann::json rows = nlohmann::json::array();
  fmt::print("{:<48} {:>12} {:>12} {:>7}  {}\n", "case", "continuous", "gap alone", "ratio", "outcomes");
  for (const Case& c : cases) {
    std::vector<double> t[2];
    Outcome o[2];
    for (int run = 0; run < kRuns; ++run)
      for (int mode = 0; mode < 2; ++mode) {
        motion::Cell cell = c.cell();
        cell.collision.continuous = mode == 0;
        motion::Simulator sim(std::move(cell));
        const double t0 = cpu_us();
        o[mode] = c.run(sim);
        t[mode].push_back(cpu_us() - t0);
      }
    const double ours = median(t[0]), peer = median(t[1]);
    const auto describe = [](const Outcome& x) {
      return x.status == "collision" ? fmt::format("{} at {:.15g} s", x.bodies, x.time_s) : x.status;
    };
    fmt::print("{:<48} {:>9.0f} us {:>9.0f} us {:>7.2f}  {} | {}\n", c.name, ours, peer, ours / peer, describe(o[0]),
               describe(o[1]));
    rows.push_back({{"name", c.name},
                    {"ours_us", ours},
                    {"peer", "gap stepping alone (continuous: false)"},
                    {"peer_us", peer},
                    {"ratio", ours / peer},
                    {"agreement", o[0] == o[1]},
                    {"ours_outcome", describe(o[0])},
                    {"peer_outcome", describe(o[1])},
                    {"poses", o[0].poses},
                    {"probes", o[0].probes},
                    {"peer_poses", o[1].poses},
                    {"runs", kRuns}});
  }
  std::ofstream(out_path) << nlohmann::json{{"bench", "bench_continuous"},
                                            {"clock", "thread CPU time, median of runs, modes alternated"},
                                            {"rows", rows}}
                                 .dump(2)
                          << '\n';
  fmt::print("wrote {}\n", out_path);
}
