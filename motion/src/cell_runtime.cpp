#include "asimov/motion/cell_runtime.hpp"

#include <fmt/format.h>

namespace asimov::motion {

namespace {
std::vector<Support> object_supports(const Cell& cell) {
  std::vector<Support> out;
  for (const auto& o : cell.objects) out.push_back({&o.mesh, o.pose});
  return out;
}
}  // namespace

CellRuntime::CellRuntime(const Cell& cell) : cell_(&cell), clock_(cell.workcell, object_supports(cell)) {}

Location CellRuntime::grip_of(std::size_t part) const {
  const PartState& p = clock_.parts()[part];
  if (carried_ && part == *carried_) return grip_;
  if (p.support < 0) return grip_;  // not carried: unused
  return grip_of(static_cast<std::size_t>(p.support)) * p.rel;
}

std::string CellRuntime::resting_on(std::size_t part) const {
  const PartState& p = clock_.parts()[part];
  if (p.holder == Holder::carried || p.holder == Holder::removed) return "";
  if (p.support >= 0) return clock_.parts()[static_cast<std::size_t>(p.support)].def->name;
  if (p.holder == Holder::conveyor) return cell_->workcell.conveyors[static_cast<std::size_t>(p.conveyor)].name;
  if (p.object >= 0) return cell_->objects[static_cast<std::size_t>(p.object)].name;
  return "";
}

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
  const auto& parts = clock_.parts();
  std::vector<Support> supports(clock_.objects().begin(), clock_.objects().end());
  for (std::size_t k = 0; k < parts.size(); ++k)
    if (parts[k].holder != Holder::carried && parts[k].holder != Holder::removed)
      supports.push_back({&parts[k].def->mesh, clock_.part_pose(k)});
  // The whole carried stack falls until its first part lands.
  std::optional<double> drop;
  for (std::size_t k = 0; k < parts.size(); ++k) {
    if (parts[k].holder != Holder::carried) continue;
    const auto d = drop_distance(parts[k].def->mesh, flange * grip_of(k), supports, parts[k].tolerance_mm);
    if (d && (!drop || *d < *drop)) drop = d;
  }
  if (!drop) {
    const auto t = pose.translation();
    return fmt::format("no support below part {} released at [{:.3f}, {:.3f}, {:.3f}]", parts[i].def->name,
                       t.x(), t.y(), t.z());
  }
  pose.translation().z() -= *drop;
  carried_.reset();
  clock_.put_down(i, pose, line);
  return std::nullopt;
}

}  // namespace asimov::motion
