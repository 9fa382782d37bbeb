// Shared by the libFuzzer targets: the input as text, and one Simulator per process (building
// a cell is the slow part; every target that runs programs starts from the same empty cell).
#pragma once
#include "asimov/cell/cell_loader.hpp"
#include "asimov/interpreter/interpreter.hpp"
#include "asimov/motion/simulator.hpp"

#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>

namespace asimov::fuzz {

inline std::string text(const std::uint8_t* data, std::size_t size) {
  return std::string(reinterpret_cast<const char*>(data), size);
}

// The PUMA 560 alone: nothing to hit, so a run goes as far as its limits let it.
inline motion::Cell empty_cell() { return std::move(cell::load_cell_text("robot: puma560\n", "<fuzz cell>")).value(); }

// Small limits: an input must end in well under a second, whatever it loops on.
inline void small_limits(interpreter::Interpreter& interp) {
  auto& l = interp.limits();
  l.max_statements = 2000;
  l.max_wait_s = 5;
}

}  // namespace asimov::fuzz
