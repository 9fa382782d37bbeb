// Loads the input as a .v2 file and runs its first program with small limits in an empty cell.
#include "common.hpp"

#include <sstream>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace asimov;
  motion::Simulator sim(fuzz::empty_cell());  // fresh each input: a run moves the arm
  std::ostringstream out;
  std::istringstream no_input;
  interpreter::Interpreter interp(sim, out);
  interp.set_input(no_input, false);
  fuzz::small_limits(interp);
  const auto diags = interp.load_source(fuzz::text(data, size), "fuzz.v2");
  for (const auto& d : diags)
    if (!d.warning) return 0;
  const auto names = interp.program_names();
  if (names.empty()) return 0;
  const auto r = interp.run(names.front());
  (void)interpreter::format_diagnostic(r.error);
  (void)interpreter::format_pause(r);
  return 0;
}
