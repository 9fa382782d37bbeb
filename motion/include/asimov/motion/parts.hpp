// Gripping geometry without physics (docs/cell-format.md "Gripping"): which part CLOSE takes,
// and where a released part comes to rest.
#pragma once
#include "asimov/motion/device_clock.hpp"
#include <optional>
#include <span>

namespace asimov::motion {

// The part CLOSE grasps: among resting and conveyor-borne parts whose origin lies in the grasp
// zone (`zone_world`: the gripper zone posed at the flange), the one whose origin is nearest
// the zone's centre; on a tie the one declared or fed first [decision: deterministic and what
// a centred gripper takes]. nullopt: the gripper closes on air.
std::optional<std::size_t> grasp_candidate(const DeviceClock& clock, const Region& zone_world);

// A body a released part can land on: a static object, a conveyor's body, another part.
struct Support {
  const collision::Polyhedron* mesh;
  Location pose;
};

// How far the part (mesh at `pose`) falls straight down (-Z) before it touches the highest
// support below it: the least vertical distance from a part vertex down to a support face, from
// a support vertex up to a part face, or between a part edge above a support edge. 0 when it
// touches already; nullopt when nothing lies below. Supports the part already penetrates
// (a face above one of its vertices only) are not below it.
std::optional<double> drop_distance(const collision::Polyhedron& part, const Location& pose,
                                    std::span<const Support> supports);

}  // namespace asimov::motion
