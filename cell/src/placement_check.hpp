// Parts placed where no part can be: inside an object, a conveyor or another part. The run would
// start with a part sunk into a body (a collision at t = 0 between bodies the program never
// moved, or a part that never rests), so the cell is refused at load (docs/cell-format.md
// "Placement"). Touching is fine: a part resting on a table touches it within its resting
// tolerance (docs/collision.md §15), the same rule as at run time.
#pragma once
#include "asimov/motion/cell.hpp"
#include <optional>
#include <string>

namespace asimov::cell {

struct Misplaced {
  std::size_t part = 0;   // index into cell.workcell.parts
  std::string message;    // "part 'a' lies inside object 'table' ..."
};

// The first declared part that sinks into an object (conveyors are objects) or into a part
// declared before it deeper than its resting tolerance, or lies inside one.
std::optional<Misplaced> first_misplaced_part(const motion::Cell& cell);

}  // namespace asimov::cell
