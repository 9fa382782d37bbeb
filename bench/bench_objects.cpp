// A cell of many small objects (docs/limits.md "objects in a cell"; issue 17): the built-in
// default cell plus N boxes of 1 mm on a 10 mm grid in a slab beside and behind the PUMA
// (x -1250..-260, y -500..490, z -450..-360: 100 x 100 x 10 at N = 10^5), and a program of two
// MOVEs that sweeps J1 from -40 to -150 degrees over them and back. Times in thread CPU: the
// engine build (Simulator construction: bodies, pairs) and the program; one run (a run is long).
// Prints one line per N (argv: N values; default 100000) and writes nothing.
#include "cpu_time.hpp"
#include "asimov/cell/cell_loader.hpp"
#include "asimov/interpreter/interpreter.hpp"

#include <fmt/format.h>

#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

using namespace asimov;

int main(int argc, char** argv) {
  std::vector<int> counts;
  for (int i = 1; i < argc; ++i) counts.push_back(std::atoi(argv[i]));
  if (counts.empty()) counts.push_back(100000);
  const std::string program = ".PROGRAM two()\n"
                              "    MOVE #PPOINT(-40, -20, 169, 90, -90, 0)\n"
                              "    MOVE #PPOINT(-150, -20, 169, 90, -90, 0)\n"
                              ".END\n";
  int rc = 0;
  for (const int n : counts) {
    motion::Cell cell = cell::default_cell();
    const collision::Polyhedron box = collision::make_box({1, 1, 1});
    for (int i = 0; i < n; ++i) {
      motion::CellObject o;
      o.name = "b" + std::to_string(i);
      o.mesh = box;
      o.pose = motion::Location::Identity();
      o.pose.translation() = collision::Vec3(-1250 + 10 * (i % 100), -500 + 10 * (i / 100 % 100), -450 + 10 * (i / 10000));
      cell.objects.push_back(std::move(o));
    }
    const double t0 = cpu_us();
    motion::Simulator sim(std::move(cell));
    const double t1 = cpu_us();
    std::ostringstream out;
    interpreter::Interpreter interp(sim, out);
    interp.load_source(program, "two.v2");
    const interpreter::RunResult r = interp.run("two");
    const double t2 = cpu_us();
    const bool ok = r.status == interpreter::RunStatus::completed;
    rc |= ok ? 0 : 1;
    fmt::print("{} objects: build {:.3f} s, program {:.3f} s CPU ({} checked poses, {})\n", n, (t1 - t0) / 1e6,
               (t2 - t1) / 1e6, sim.recorders().counts.poses, ok ? "completed" : "did not complete");
  }
  return rc;
}
