#include "asimov/motion/parts.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace asimov::motion {
using collision::Vec3;

std::optional<std::size_t> grasp_candidate(const DeviceClock& clock, const Region& zone_world) {
  std::optional<std::size_t> best;
  double best_d = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < clock.parts().size(); ++i) {
    const Holder h = clock.parts()[i].holder;
    if (h != Holder::world && h != Holder::conveyor) continue;
    const Vec3 o = clock.part_pose(i).translation();
    if (!zone_world.contains(o)) continue;
    const double d = (o - zone_world.pose.translation()).norm();
    if (d < best_d) best = i, best_d = d;
  }
  return best;
}

}  // namespace asimov::motion
