// The devices of a Workcell on the simulated clock (docs/cell-format.md "Time"): part positions on
// conveyors, sensor and logic signals, feeders and sinks as exact functions of time. Every change
// happens at its exact instant (a sensor switches when the part's origin crosses its box face,
// not at the next tick); advance_to(t) processes all changes up to t in time order.
#pragma once
#include "asimov/motion/devices.hpp"
#include "asimov/motion/support.hpp"
#include <deque>
#include <memory>
#include <span>
#include <cstdint>
#include <limits>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

namespace asimov::motion {

// Where a part is: resting in the world (on a table, a pallet, another part), on a conveyor
// (moving while it runs), carried by the gripper, or removed by a sink. A part riding on another
// part (a stack: `support`) has the holder of the part at the bottom of its stack and moves with it.
enum class Holder { world, conveyor, carried, removed };

struct PartState {
  const PartDef* def = nullptr;  // name, colour, shape (the cell's, or the clock's for fed parts)
  Holder holder = Holder::world;
  int conveyor = -1;                      // index when holder == conveyor
  Location anchor = Location::Identity();  // pose at anchor_s
  double anchor_s = 0;
  collision::Vec3 velocity = collision::Vec3::Zero();  // mm/s, world
  double end_s = std::numeric_limits<double>::infinity();  // stops on the conveyor then
  int behind = -1;   // on a conveyor: the part it stops against (-1: the end stop or none)
  int feeder = -1;   // the feeder that placed it (-1: declared in the cell)
  int ordinal = 0;   // declared: index among the cell's parts; fed: 0 for the feeder's first part
  int support = -1;  // the part it rests on (a stack), -1: none; it then moves with that part
  Location rel = Location::Identity();  // while riding: its pose in the support's frame
  int first_rider = -1, next_rider = -1;  // the parts resting on it (a list through next_rider)
  int object = -1;   // resting in the world: the cell object it came to rest on (-1: none known)
  double tolerance_mm = 0;  // resting tolerance of its shape (support.hpp)
  double radius_mm = 0;     // its mesh's reach from its origin
  Location pose_at(double t) const;
};

// One line of the report's `events` list.
struct CellEvent {
  double time_s = 0;
  std::string kind;     // signal, feeder, feeder_blocked, sink, conveyor_end, conveyor_queue, grasp, close_on_air,
                        // release, placed, resting
  std::string subject;  // signal number or part name
  std::string detail;   // on/off, device name, pose text, the body a part rests against
  int line = 0;         // program line when the program caused it; 0: a device
};

// The events a run keeps (docs/limits.md): the first ones; later ones are counted, not kept. An
// event is ~110 bytes in the log and ~1 KB as report JSON: a 0.1 s blink over a 100,000 s wait
// made two million of them.
inline constexpr std::size_t kMaxEvents = 100000;

// A logic loop (rules with no delay switching each other forever at one instant).
struct DeviceError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The time interval [t_in, t_out) in which the point p0 + v (t - t0) lies in region r (closed box
// entered at t_in, left at t_out); empty (t_in >= t_out) when it never does.
struct Interval {
  double in, out;
  bool empty() const { return !(in < out); }
};
class DeviceClock {
 public:
  // Places the declared parts and runs every device at t = 0 (feeders with an empty spot feed,
  // sensors over a part switch on, timed rules at 0 fire). `objects`: the cell's static bodies
  // (objects and conveyor bodies, in the cell's order), for what a part rests on; they must
  // outlive the clock. A part resting on another part (within the lower part's resting
  // tolerance, from above) rides on it.
  explicit DeviceClock(const Workcell& cell, std::span<const Support> objects = {});

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
  // The events up to now (a copy of the clock shares the log; its view ends where it was copied).
  // At most kMaxEvents are kept, the first ones; events_dropped() counts the others.
  std::span<const CellEvent> events() const { return {log_->events.data(), logged_}; }
  std::uint64_t events_dropped() const { return dropped_; }
  // The next instant > time_s() at which a part or signal changes by itself; +inf when none.
  double next_change() const;

  // Gripping, driven by the hand (the geometry of the choice is in parts.hpp): the part leaves
  // the world (or the part it rested on) and is carried with the parts resting on it; release
  // puts it down at `pose` on what it touches below (another part, whose motion it then shares;
  // a conveyor's top face; an object) and records the events.
  void carry(std::size_t part, int line);
  void put_down(std::size_t part, const Location& pose, int line);
  void note(CellEvent e);
  // The carried part follows the flange: its pose now (kept for sensors' and the report's sake);
  // the parts resting on it follow.
  void move_carried(std::size_t part, const Location& pose);
  // Counts every change of a part's holder, motion or presence (the collision world re-reads
  // the parts when it moved on).
  std::uint64_t revision() const { return revision_; }
  // A copy for poses at earlier instants (contact-time bisection): it records no events.
  DeviceClock scratch_copy() const;
  // The static bodies given at construction.
  std::span<const Support> objects() const { return shared_->objects; }

 private:
  struct Timer {
    double time_s;
    long seq;
    int set;
    bool on;
    int line;
  };
  // Shared by every copy of the clock: the event log (each copy sees its prefix), the fed parts'
  // definitions (append-only), what never changes.
  struct Log {
    std::vector<CellEvent> events;
  };
  struct Hulls;  // overlap sensing: the separating axes of each part shape, computed once
  struct Shared {
    std::deque<PartDef> fed;  // stable addresses
    std::shared_ptr<Hulls> hulls;
    std::vector<Support> objects;
    std::vector<double> object_radius;  // each object's mesh reach from its origin
    std::vector<std::pair<int, std::vector<std::size_t>>> sensor_signals;  // signal -> its sensors
    std::size_t max_rounds = 0;
  };
  void record(CellEvent e);
  void settle();                     // apply everything due at now_ until nothing changes
  void note_change() { ++revision_, changed_s_ = now_, next_ok_ = false; }
  void change(int k, bool on, int line);
  void place(std::size_t part, const Location& pose);  // support, holder, velocity, end time from now_
  void queue(int c);                 // motions and stops of conveyor c's parts from now_ (re-anchored)
  bool running(int c) const;
  bool sensed(const Sensor& s) const;
  bool inside(const PartState& p, const Region& r) const;    // origin in r at now_ (entering counts)
  bool overlaps(const PartState& p, const Region& r) const;  // the part meets r at now_
  Interval hull(const PartState& p, const Region& r, const Location& pose, double t0, const collision::Vec3& v) const;
  void feed(std::size_t f, int line);
  bool spot_empty(std::size_t f) const;
  // Support of part i at `pose` among the other parts (-1: none), and the object it rests on.
  int part_below(std::size_t i, const Location& pose) const;
  int object_below(std::size_t i, const Location& pose) const;
  void attach(std::size_t rider, std::size_t support);
  void detach(std::size_t rider);
  void sync(std::size_t i);          // the parts resting on i take its holder and motion
  void remove(std::size_t i, const std::string& by);  // and every part resting on it
  void arrived(std::size_t i, int conveyor, int behind);  // the stop event of a part on a belt

  const Workcell* cell_;
  std::shared_ptr<Shared> shared_;
  std::shared_ptr<Log> log_;
  std::size_t logged_ = 0;
  std::uint64_t dropped_ = 0;       // events past kMaxEvents, not kept
  double last_event_s_ = -std::numeric_limits<double>::infinity();  // of every event, kept or not (rewind)
  bool mute_ = false;               // a scratch copy: no events
  double now_ = 0;
  std::set<int> signals_;
  std::vector<PartState> parts_;
  std::vector<Timer> timers_;
  std::vector<bool> timed_done_;   // per logic rule with at_s
  std::vector<int> fed_;           // parts placed per feeder
  long seq_ = 0;
  std::uint64_t revision_ = 0;
  double changed_s_ = 0;  // time of the last change of revision_ or of a timer set (rewind)
  mutable double next_ = 0;        // next_change() while next_ok_
  mutable bool next_ok_ = false;
};

Interval crossing(const Region& r, const collision::Vec3& p0, double t0, const collision::Vec3& v);
// The same for a part (mesh at pose0 at t0, moving by v): the interval in which its convex hull
// meets the closed box r (separating axes: the box's, the part's face normals, and the box's
// axes crossed with the part's edges).
Interval overlap_interval(const Region& r, const collision::Polyhedron& mesh, const Location& pose0, double t0,
                          const collision::Vec3& v);

}  // namespace asimov::motion
