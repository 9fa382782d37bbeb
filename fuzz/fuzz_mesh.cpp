// The STL (binary and ASCII) and OBJ readers, from the same bytes. An Error is the documented
// outcome of bad input; anything thrown is a finding.
#include "asimov/collision/mesh_io.hpp"

#include <cstddef>
#include <cstdint>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace asimov::collision;
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  (void)parse_stl(bytes, "fuzz.stl");
  (void)parse_obj(bytes, "fuzz.obj");
  return 0;
}
