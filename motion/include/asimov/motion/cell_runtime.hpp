// The reacting cell during a run: the devices on the clock plus what the gripper holds. The
// interpreter drives it (signals, hand changes with the flange pose); the walk reads the parts'
// poses. Absent (no object at all) for a cell whose Workcell is empty.
#pragma once
#include "asimov/motion/cell.hpp"
#include "asimov/motion/parts.hpp"
#include <optional>
#include <string>

namespace asimov::motion {

class CellRuntime {
 public:
  explicit CellRuntime(const Cell& cell);

  DeviceClock& clock() { return clock_; }
  const DeviceClock& clock() const { return clock_; }

  // The hand closed at the clock's time with the flange at `flange` (world): grasps the part in
  // the zone (its index) or closes on air (nullopt; an event). Holding a part already: no change.
  std::optional<std::size_t> close(const Location& flange, int line);
  // The hand opened (or relaxed): the carried part (with the parts resting on it) drops onto the
  // highest support below and is put down there. Returns an error message when nothing lies
  // below (the part stays carried).
  std::optional<std::string> open(const Location& flange, int line);

  std::optional<std::size_t> carried() const { return carried_; }
  // The carried part's pose for the flange at `flange`.
  Location carried_pose(const Location& flange) const { return flange * grip_; }
  const Location& grip() const { return grip_; }  // part frame in the flange frame while carried
  // Any carried part's frame in the flange frame: the grasped part's grip, a part resting on it
  // that grip times its place on the part below.
  Location grip_of(std::size_t part) const;
  // What part `part` rests on: the part below it, its conveyor, the object it came to rest on
  // ("" when none is known: in the gripper, removed, or placed in the air by the cell).
  std::string resting_on(std::size_t part) const;
  bool close_on_air_error() const { return cell_->workcell.gripper.close_on_air_error; }

 private:
  const Cell* cell_;
  DeviceClock clock_;
  std::optional<std::size_t> carried_;
  Location grip_ = Location::Identity();  // part frame in the flange frame while carried
};

}  // namespace asimov::motion
