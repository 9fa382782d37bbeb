// What a part rests on (docs/cell-format.md "Resting contact", docs/collision.md §15): the
// resting tolerance of a part's shape, and the vertical drop of a part onto the bodies below it.
// Plain geometry on meshes and poses: no clock, no engine.
#pragma once
#include "asimov/collision/polyhedron.hpp"
#include "asimov/motion/location.hpp"
#include <optional>
#include <span>
#include <vector>

namespace asimov::motion {

// Relative size of the resting tolerance: a part may touch what it rests on, or sink into it, by
// at most this fraction of its bounding-box diagonal (a 100 mm part: 1.4e-3 mm).
constexpr double kRestingRelative = 1e-5;
// The resting tolerance [mm] of a part's shape: kRestingRelative times its bounding-box diagonal
// (the same verdicts at any scale of the cell).
double resting_tolerance(const collision::Polyhedron& mesh);

// A body a part can rest on: a static object, a conveyor's body, another part.
struct Support {
  const collision::Polyhedron* mesh = nullptr;
  Location pose = Location::Identity();
};

// How far the part (mesh at `pose`) falls straight down (-Z) before it touches the highest
// support below it: the least vertical distance from a part vertex down to a support face, from
// a support vertex up to a part face, or between a part edge above a support edge. 0 when it
// touches already (or sinks in by at most `tolerance_mm`); nullopt when nothing lies below.
// Supports the part penetrates deeper than the tolerance (a face above one of its vertices only)
// are not below it.
std::optional<double> drop_distance(const collision::Polyhedron& part, const Location& pose,
                                    std::span<const Support> supports, double tolerance_mm = 0);

// The vertical gap from the part down to one support (as drop_distance for that support alone);
// nullopt when the support is not below the part.
std::optional<double> gap_below(const collision::Polyhedron& part, const Location& pose, const Support& support,
                                double tolerance_mm = 0);

// The bodies a part at `pose` rests on: the indices of `supports` within `tolerance_mm` below it
// (vertically), in the order given.
std::vector<std::size_t> resting_on(const collision::Polyhedron& part, const Location& pose,
                                    std::span<const Support> supports, double tolerance_mm);

}  // namespace asimov::motion
