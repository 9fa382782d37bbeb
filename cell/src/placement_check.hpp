// Parts placed where no part can be (declared or fed): inside an object, a conveyor or another part. The run would
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
  std::size_t part = 0;   // index into cell.workcell.parts (feeder: into cell.workcell.feeders)
  bool feeder = false;    // a feeder's part at its feed pose
  std::string message;    // "part 'a' lies inside object 'table' ..."
};

// The first declared part that sinks into an object (conveyors are objects) or into a part
// declared before it deeper than its resting tolerance, or lies inside one; then the first
// feeder whose part, at its feed pose, does so with an object, a declared part or another
// feeder's part (a part whose origin lies in the feeder's spot is not met: the feeder waits).
std::optional<Misplaced> first_misplaced_part(const motion::Cell& cell);

}  // namespace asimov::cell
