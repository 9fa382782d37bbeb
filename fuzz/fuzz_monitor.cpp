// The monitor's command line: each input line is typed at the `.` prompt (run it in a scratch
// folder: STORE writes files there).
#include "common.hpp"

#include "asimov/interpreter/monitor.hpp"

#include <sstream>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace asimov;
  motion::Simulator sim(fuzz::empty_cell());
  std::ostringstream out;
  std::istringstream no_input;
  interpreter::Interpreter interp(sim, out);
  interp.set_input(no_input, false);
  fuzz::small_limits(interp);
  interpreter::Monitor monitor(interp, sim, out);
  std::istringstream lines(fuzz::text(data, size));
  for (std::string line; std::getline(lines, line);) {
    // Commands naming files stay in the scratch folder: no path separators for them (the
    // fuzzer may run as root).
    const auto word = line.substr(0, line.find_first_of(" \t"));
    const auto c = interpreter::match_command(word).command;
    const bool files = c == interpreter::Command::store || c == interpreter::Command::storel ||
                       c == interpreter::Command::load || c == interpreter::Command::directory;
    if (files && line.find_first_of("/\\~$") != std::string::npos) continue;
    (void)monitor.completions(line, line.substr(line.find_last_of(' ') == std::string::npos ? 0 : line.find_last_of(' ') + 1));
    if (monitor.execute(line) == interpreter::CommandStatus::quit) return 0;
  }
  (void)monitor.end_of_input();
  return 0;
}
