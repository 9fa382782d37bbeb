#include "asimov/motion/cell_runtime.hpp"

#include <fmt/format.h>

namespace asimov::motion {

CellRuntime::CellRuntime(const Cell& cell) : cell_(&cell), clock_(cell.workcell) {}

std::optional<std::size_t> CellRuntime::close(const Location& flange, int line) {
  if (carried_) return carried_;
  const Region zone{flange * cell_->workcell.gripper.zone.pose, cell_->workcell.gripper.zone.size};
  const auto i = cell_->workcell.gripper.declared ? grasp_candidate(clock_, zone) : std::nullopt;
  if (!i) {
    clock_.note({clock_.time_s(), "close_on_air", "", "", line});
    return std::nullopt;
  }
  grip_ = flange.inverse() * clock_.part_pose(*i);
  carried_ = i;
  clock_.carry(*i, line);
  return i;
}

std::optional<std::string> CellRuntime::open(const Location& flange, int line) {
  if (!carried_) return std::nullopt;
  const std::size_t i = *carried_;
  Location pose = carried_pose(flange);
  std::vector<Support> supports;
  for (const auto& o : cell_->objects) supports.push_back({&o.mesh, o.pose});
  for (std::size_t k = 0; k < clock_.parts().size(); ++k) {
    const Holder h = clock_.parts()[k].holder;
    if (k != i && h != Holder::carried && h != Holder::removed)
      supports.push_back({&clock_.parts()[k].def.mesh, clock_.part_pose(k)});
  }
  const auto drop = drop_distance(clock_.parts()[i].def.mesh, pose, supports);
  if (!drop) {
    const auto t = pose.translation();
    return fmt::format("no support below part {} released at [{:.3f}, {:.3f}, {:.3f}]", clock_.parts()[i].def.name,
                       t.x(), t.y(), t.z());
  }
  pose.translation().z() -= *drop;
  carried_.reset();
  clock_.put_down(i, pose, line);
  return std::nullopt;
}

}  // namespace asimov::motion
