// The URDF loader (tinyxml2 + our folding into a chain). An Error is the documented outcome of
// bad input (anything thrown is a finding); meshes resolve in the current folder.
#include "asimov/robots/urdf_loader.hpp"

#include <cstddef>
#include <cstdint>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace asimov::robots;
  (void)load_urdf_text(std::string(reinterpret_cast<const char*>(data), size), "fuzz.urdf", ".");
  return 0;
}
