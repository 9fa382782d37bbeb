// The reacting part of a cell as plain data (docs/cell-format.md "parts", "gripper", "devices",
// "logic"): movable parts, the gripper's grasp zone, conveyors, sensors, feeders, sinks and
// logic rules. Loaded from YAML by cell/; a cell without any of them has an empty Workcell and
// pays nothing (Workcell::empty()).
#pragma once
#include "asimov/collision/polyhedron.hpp"
#include "asimov/motion/location.hpp"
#include <string>
#include <vector>

namespace asimov::motion {

// A box region: centre pose in the world and full side lengths along its own axes.
struct Region {
  Location pose = Location::Identity();
  collision::Vec3 size = collision::Vec3::Zero();
  // Closed box: a point on a face is inside.
  bool contains(const collision::Vec3& world_point) const;
};

// A movable part as declared (or as a feeder makes it): its shape in its own frame and where it
// starts. Sensors, sinks and the grasp zone test the part's origin (its frame's position).
struct PartDef {
  std::string name;
  std::string colour;          // free text a sensor can match (e.g. red); empty: none
  collision::Polyhedron mesh;  // local frame
  Location pose = Location::Identity();
};

// Where CLOSE looks for a part: a box in the flange frame. close_on_air_error: a CLOSE/CLOSEI
// with no part in the zone stops the program instead of being reported.
struct Gripper {
  bool declared = false;
  Region zone;  // pose relative to the flange
  bool close_on_air_error = false;
};

// A conveyor: a box body (also a static object of the cell, same name) whose top face carries the
// parts resting on it along `direction` (world, unit) at `speed_mm_s` while `signal` is on
// (0: always). A carried part stops when its origin reaches the downstream end of the top face.
struct Conveyor {
  std::string name;
  Region body;
  collision::Vec3 direction = collision::Vec3::UnitX();
  double speed_mm_s = 0;
  int signal = 0;
};

// What a sensor sees of a part (docs/cell-format.md "sensor"): its origin inside the box, or any
// overlap of the part (its convex hull: exact for boxes, cylinders, spheres) with the box.
enum class Sensing { origin, overlap };

// An input signal that is on while a part is sensed in `region` (a part whose name matches
// `pattern` (* and ? wildcards; empty: any) and whose colour is `colour` (empty: any)). Sensors on
// one signal are wired in parallel: the signal is on while any of them senses a part.
struct Sensor {
  std::string name;
  int signal = 0;  // 1001..1512 or a soft signal 2001..2512
  Region region;
  std::string pattern;
  std::string colour;
  Sensing sensing = Sensing::origin;
};

// Places a new part at `at`: when `signal` turns on (0: never by signal), and/or whenever its spot
// is empty (no part origin inside `spot`, a box centred on `at`), at most `count` parts in all.
// Parts are named prefix1, prefix2, ...; colours cycle through `colours` (empty: none).
struct Feeder {
  std::string name;
  PartDef part;  // shape; pose = the feed pose
  std::string prefix;
  std::vector<std::string> colours;
  int signal = 0;
  bool when_empty = false;
  int count = 1;
  Region spot;  // centred on the feed pose
};

// Removes parts whose origin lies in `region`: always-on (signal 0) every part whose origin enters
// it; gated, every part whose origin is in it at an edge of `signal` (rising, or falling with
// on_rising false). A part riding on a removed part goes with it.
struct Sink {
  std::string name;
  Region region;
  int signal = 0;
  bool on_rising = true;
};

// A logic rule: when `when` changes to `is_on` (or, for `at_s >= 0`, at that simulated time),
// after `after_s` seconds set signal `set` to `to_on`.
struct LogicRule {
  int when = 0;       // 0: a timed rule
  bool is_on = true;
  double at_s = -1;   // >= 0: fires at this time
  double after_s = 0;
  int set = 0;
  bool to_on = true;
  int line = 0;       // in the cell file, for messages
};

struct Workcell {
  std::vector<PartDef> parts;
  Gripper gripper;
  std::vector<Conveyor> conveyors;
  std::vector<Sensor> sensors;
  std::vector<Feeder> feeders;
  std::vector<Sink> sinks;
  std::vector<LogicRule> logic;
  bool empty() const {
    return parts.empty() && !gripper.declared && conveyors.empty() && sensors.empty() && feeders.empty() &&
           sinks.empty() && logic.empty();
  }
  // True when a device (sensor, logic rule) can set signal k; WAIT names the ones none drives.
  bool drives(int k) const;
  // Parts that may exist in a run: declared plus every feeder's count.
  std::size_t max_parts() const;
};

// Signal numbering (V+): outputs 1..512, inputs 1001..1512, soft signals 2001..2512.
inline bool is_output_signal(int k) { return k >= 1 && k <= 512; }
inline bool is_input_signal(int k) { return k >= 1001 && k <= 1512; }
inline bool is_soft_signal(int k) { return k >= 2001 && k <= 2512; }
inline bool is_signal(int k) { return is_output_signal(k) || is_input_signal(k) || is_soft_signal(k); }

// `*` any run, `?` one character; case-insensitive as V+ names are.
bool name_matches(const std::string& pattern, const std::string& name);

}  // namespace asimov::motion
