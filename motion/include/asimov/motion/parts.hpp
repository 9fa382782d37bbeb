// Gripping without physics (docs/cell-format.md "Gripping"): which part CLOSE takes. Where a
// released part comes to rest is support.hpp's drop.
#pragma once
#include "asimov/motion/device_clock.hpp"
#include "asimov/motion/support.hpp"
#include <optional>
#include <span>

namespace asimov::motion {

// The part CLOSE grasps: among resting and conveyor-borne parts whose origin lies in the grasp
// zone (`zone_world`: the gripper zone posed at the flange), the one whose origin is nearest
// the zone's centre; on a tie the one declared or fed first [decision: deterministic and what
// a centred gripper takes]. nullopt: the gripper closes on air.
std::optional<std::size_t> grasp_candidate(const DeviceClock& clock, const Region& zone_world);

}  // namespace asimov::motion
