// The devices of a Workcell on the simulated clock (docs/cell-format.md "Time"): part positions on
// conveyors, sensor and logic signals, feeders and sinks as exact functions of time. Every change
// happens at its exact instant (a sensor switches when the part's origin crosses its box face,
// not at the next tick); advance_to(t) processes all changes up to t in time order.
#pragma once
#include "asimov/motion/devices.hpp"
#include <cstdint>
#include <limits>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

namespace asimov::motion {

// Where a part is: resting in the world (on a table, a pallet, another part), on a conveyor
// (moving while it runs), carried by the gripper, or removed by a sink.
enum class Holder { world, conveyor, carried, removed };

struct PartState {
  PartDef def;
  Holder holder = Holder::world;
  int conveyor = -1;                      // index when holder == conveyor
  Location anchor = Location::Identity();  // pose at anchor_s
  double anchor_s = 0;
  collision::Vec3 velocity = collision::Vec3::Zero();  // mm/s, world
  double end_s = std::numeric_limits<double>::infinity();  // stops on the conveyor then
  int behind = -1;   // on a conveyor: the part it stops against (-1: the end stop or none)
  int feeder = -1;   // the feeder that placed it (-1: declared in the cell)
  int ordinal = 0;   // declared: index among the cell's parts; fed: 0 for the feeder's first part
  Location pose_at(double t) const;
};

// One line of the report's `events` list.
struct CellEvent {
  double time_s = 0;
  std::string kind;     // signal, feeder, sink, conveyor_end, conveyor_queue, grasp, close_on_air, release, placed
  std::string subject;  // signal number or part name
  std::string detail;   // on/off, device name, pose text
  int line = 0;         // program line when the program caused it; 0: a device
};

// A logic loop (rules with no delay switching each other forever at one instant).
struct DeviceError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class DeviceClock {
 public:
  // Places the declared parts and runs every device at t = 0 (feeders with an empty spot feed,
  // sensors over a part switch on, timed rules at 0 fire).
  explicit DeviceClock(const Workcell& cell);

  double time_s() const { return now_; }
  // Every change in (time_s(), t] in time order; t <= time_s() does nothing.
  void advance_to(double t);
  // Back to an earlier t when nothing changed after it (the state at t is this one with the
  // clock at t: a run halted at a contact between two checked poses). False, and nothing done,
  // when something changed after t (then an earlier copy of the clock, advanced to t, is the
  // state at t).
  bool rewind(double t);
  // The program sets a signal (SIGNAL, RESET) at time_s(); `line` goes into the event.
  void set_signal(int k, bool on, int line = 0);
  bool signal(int k) const { return signals_.count(k) > 0; }
  const std::set<int>& signals() const { return signals_; }

  const std::vector<PartState>& parts() const { return parts_; }
  Location part_pose(std::size_t i) const { return parts_[i].pose_at(now_); }
  const std::vector<CellEvent>& events() const { return events_; }
  // The next instant > time_s() at which a part or signal changes by itself; +inf when none.
  double next_change() const;

  // Gripping, driven by the hand (the geometry of the choice is in parts.hpp): the part leaves
  // the world and is carried; release puts it down at `pose` (resting on a conveyor when it
  // lies on one's top face) and records the events.
  void carry(std::size_t part, int line);
  void put_down(std::size_t part, const Location& pose, int line);
  void note(CellEvent e) { events_.push_back(std::move(e)); }
  // The carried part follows the flange: its pose now (kept for sensors' and the report's sake).
  void move_carried(std::size_t part, const Location& pose);
  // Counts every change of a part's holder, motion or presence (the collision world re-reads
  // the parts when it moved on).
  std::uint64_t revision() const { return revision_; }

 private:
  struct Timer {
    double time_s;
    long seq;
    int set;
    bool on;
    int line;
  };
  void settle();                     // apply everything due at now_ until nothing changes
  void note_change() { ++revision_, changed_s_ = now_; }
  void change(int k, bool on, int line);
  void place(std::size_t part, const Location& pose);  // holder, velocity, end time from now_
  void queue(int c);                 // motions and stops of conveyor c's parts from now_ (re-anchored)
  bool running(int c) const;
  bool sensed(const Sensor& s) const;
  bool inside(const PartState& p, const Region& r) const;  // origin in r at now_ (entering counts)
  void feed(std::size_t f, int line);
  bool spot_empty(std::size_t f) const;

  const Workcell* cell_;
  double now_ = 0;
  std::set<int> signals_;
  std::vector<PartState> parts_;
  std::vector<CellEvent> events_;
  std::vector<Timer> timers_;
  std::vector<bool> timed_done_;   // per logic rule with at_s
  std::vector<int> fed_;           // parts placed per feeder
  long seq_ = 0;
  std::uint64_t revision_ = 0;
  double changed_s_ = 0;  // time of the last change of revision_ or of a timer set (rewind)
};

// The time interval [t_in, t_out) in which the point p0 + v (t - t0) lies in region r (closed box
// entered at t_in, left at t_out); empty (t_in >= t_out) when it never does.
struct Interval {
  double in, out;
  bool empty() const { return !(in < out); }
};
Interval crossing(const Region& r, const collision::Vec3& p0, double t0, const collision::Vec3& v);

}  // namespace asimov::motion
