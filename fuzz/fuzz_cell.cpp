// The YAML cell loader. A CellError is the documented outcome of bad input; anything else
// escaping (a YAML exception, bad_alloc) or a crash is a bug.
#include "asimov/cell/cell_loader.hpp"

#include <cstddef>
#include <cstdint>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace asimov;
  try {
    (void)cell::load_cell_text(std::string(reinterpret_cast<const char*>(data), size), "fuzz.yaml", ".");
  } catch (const cell::CellError& e) {
    (void)e.format();
  }
  return 0;
}
