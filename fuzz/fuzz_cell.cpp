// The YAML cell loader. An Error result is the documented outcome of bad input; an exception
// escaping (a YAML exception, bad_alloc) or a crash is a bug.
#include "asimov/cell/cell_loader.hpp"

#include <cstddef>
#include <cstdint>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace asimov;
  const auto cell = cell::load_cell_text(std::string(reinterpret_cast<const char*>(data), size), "fuzz.yaml", ".");
  if (!cell) (void)cell::format_cell_error(cell.error());
  return 0;
}
