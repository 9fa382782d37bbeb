// .v2 loader: parse + check of arbitrary text (never runs anything).
#include "common.hpp"

#include <sstream>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace asimov;
  static motion::Simulator sim(fuzz::empty_cell());
  std::ostringstream out;
  interpreter::Interpreter interp(sim, out);
  const auto diags = interp.load_source(fuzz::text(data, size), "fuzz.v2");
  for (const auto& d : diags) (void)interpreter::format_diagnostic(d);  // the printing path too
  return 0;
}
