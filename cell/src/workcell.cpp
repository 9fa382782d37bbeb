// The reacting cell's keys: parts (alone or in patterns), the gripper's grasp zone, devices
// (conveyor, sensor, feeder, sink) and logic rules -> motion::Workcell (docs/cell-format.md).
#include "fields.hpp"
#include "placement_check.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace asimov::cell {
namespace {
using motion::is_input_signal;
using motion::is_signal;
using motion::is_soft_signal;

// Parts in one cell, declared and fed (docs/limits.md): each is a moving body of the scene.
constexpr double kMaxParts = 10000;
// Conveyor speed (docs/limits.md): 10 m/s, twice the fastest belts in industry.
constexpr double kMaxConveyorSpeed = 10000;

int integer(const Fields& f, const YAML::Node& n, double lo, double hi, const std::string& what) {
  const double v = f.number(n, what);
  if (!(v >= lo && v <= hi) || v != std::floor(v)) f.fail(n, fmt::format("{} must be an integer {:g}..{:g}", what, lo, hi));
  return static_cast<int>(v);
}

int signal(const Fields& f, const YAML::Node& n, const std::string& what) {
  const int k = integer(f, n, 0, 2512, what);
  if (k != 0 && !is_signal(k))
    f.fail(n, fmt::format("{}: {} is not a signal (outputs 1-512, inputs 1001-1512, soft 2001-2512)", what, k));
  return k;
}

// A signal a device sets: an input or a soft signal (outputs belong to the program).
int device_signal(const Fields& f, const YAML::Node& n, const std::string& what) {
  const int k = signal(f, n, what);
  if (!is_input_signal(k) && !is_soft_signal(k))
    f.fail(n, fmt::format("{} must be an input (1001-1512) or soft signal (2001-2512), got {}", what, k));
  return k;
}

bool on_off(const Fields& f, const YAML::Node& n, const std::string& what) {
  const auto v = f.text(n, what);
  if (v != "on" && v != "off") f.fail(n, what + " must be on or off");
  return v == "on";
}

motion::Region region(const Fields& f, const YAML::Node& n, const std::string& what) {
  if (!n["box"]) f.fail(n, what + " needs box: [sx, sy, sz]");
  const auto s = f.numbers(n["box"], 3, what + ".box");
  for (double x : s)
    if (!(x > 0)) f.fail(n["box"], what + ".box sides must be > 0");
  return {f.pose(n["at"], what + " at"), {s[0], s[1], s[2]}};
}

void add_name(const Fields& f, const YAML::Node& n, const std::string& name, std::set<std::string>& names) {
  if (!names.insert(name).second) f.fail(n, fmt::format("duplicate body name '{}'", name));
}

// {name, shape, at[, colour][, count: [nx, ny, nz], pitch: [px, py, pz]]}: a pattern is named
// name1..nameN, x fastest, then y, then z, offset by the pitch along the `at` frame's axes.
void parts(const Fields& f, const YAML::Node& list, motion::Cell& cell, std::set<std::string>& names,
           std::vector<YAML::Node>& nodes) {
  if (!list.IsSequence()) f.fail(list, "parts must be a list");
  for (const auto& p : list) {
    f.expect_keys(p, {"name", "box", "cylinder", "sphere", "mesh", "scale", "at", "colour", "count", "pitch"}, "a part");
    if (!p["name"]) f.fail(p, "every part needs a name");
    const auto name = f.text(p["name"], "a part's name");
    motion::PartDef d;
    d.mesh = f.shape(p, "part '" + name + "'", cell.warnings);
    d.pose = f.pose(p["at"], "part '" + name + "' at");
    if (p["colour"]) d.colour = f.text(p["colour"], "part '" + name + "' colour");
    int n[3] = {1, 1, 1};
    collision::Vec3 pitch = collision::Vec3::Zero();
    if (p["count"]) {
      if (!p["count"].IsSequence() || p["count"].size() != 3) f.fail(p["count"], "count must be [nx, ny, nz]");
      for (int a = 0; a < 3; ++a) n[a] = integer(f, p["count"][a], 1, kMaxParts, "count");
      if (!p["pitch"]) f.fail(p, "a pattern (count) needs pitch: [px, py, pz]");
    }
    if (p["pitch"]) {
      const auto v = f.numbers(p["pitch"], 3, "pitch");
      pitch = {v[0], v[1], v[2]};
    }
    const double total = static_cast<double>(n[0]) * n[1] * n[2];
    if (total + static_cast<double>(cell.workcell.parts.size()) > kMaxParts)
      f.fail(p, fmt::format("more than {:g} parts in the cell", kMaxParts));
    const bool pattern = total > 1;
    int k = 0;
    for (int z = 0; z < n[2]; ++z)
      for (int y = 0; y < n[1]; ++y)
        for (int x = 0; x < n[0]; ++x) {
          motion::PartDef e = d;
          e.name = pattern ? fmt::format("{}{}", name, ++k) : name;
          e.pose.translation() += d.pose.linear() * collision::Vec3(x * pitch.x(), y * pitch.y(), z * pitch.z());
          add_name(f, p["name"], e.name, names);
          cell.workcell.parts.push_back(std::move(e));
          nodes.push_back(p);
        }
  }
}

// gripper.fingers: {JOINT: [closed, open]} (display mm, or deg for a revolute follower's
// leader): the travel of the robot's fingers instead of their limits (CLOSE = lower, OPEN =
// upper); followers follow.
void fingers(const Fields& f, const YAML::Node& node, motion::Cell& cell) {
  if (!node.IsMap()) f.fail(node, "gripper.fingers must be a map {finger_joint: [closed, open]}");
  auto& hand = cell.robot.hand;
  std::string known;
  for (const auto& h : hand)
    if (h.leader < 0) known += (known.empty() ? "" : ", ") + h.name;
  for (const auto& kv : node) {
    const std::string name = f.text(kv.first, "a finger joint in gripper.fingers");
    const auto it = std::find_if(hand.begin(), hand.end(), [&](const robots::HandJoint& h) { return h.name == name && h.leader < 0; });
    if (it == hand.end())
      f.fail(kv.first, fmt::format("gripper.fingers: '{}' is no finger of the robot (fingers: {})", name, known.empty() ? "none" : known));
    const auto v = f.numbers(kv.second, 2, "gripper.fingers." + name + " ([closed, open])");
    for (const double x : v)
      if (!(x >= it->lower && x <= it->upper))
        f.fail(kv.second, fmt::format("gripper.fingers.{}: {} is outside the joint's limits [{}, {}]", name, x, it->lower, it->upper));
    it->closed = v[0], it->open = v[1];
  }
  robots::update_hand_followers(cell.robot);
}

void gripper(const Fields& f, const YAML::Node& g, motion::Cell& cell) {
  f.expect_keys(g, {"zone", "close_on_air", "fingers"}, "gripper");
  if (const auto fs = g["fingers"]) fingers(f, fs, cell);
  if (g["fingers"] && !g["zone"] && !g["close_on_air"]) return;  // finger travel only: no grasping
  auto& out = cell.workcell.gripper;
  out.declared = true;
  if (!g["zone"]) f.fail(g, "gripper needs zone: {box: [sx, sy, sz], at: [x, y, z, o, a, t]} (flange frame)");
  f.expect_keys(g["zone"], {"box", "at"}, "gripper.zone");
  out.zone = region(f, g["zone"], "gripper.zone");
  if (const auto a = g["close_on_air"]) {
    const auto v = f.text(a, "gripper.close_on_air");
    if (v != "report" && v != "error") f.fail(a, "gripper.close_on_air must be report or error");
    out.close_on_air_error = v == "error";
  }
}

void conveyor(const Fields& f, const YAML::Node& d, motion::Cell& cell, std::set<std::string>& names) {
  f.expect_keys(d, {"conveyor", "box", "at", "direction", "speed_mm_s", "signal"}, "a conveyor");
  motion::Conveyor c;
  c.name = f.text(d["conveyor"], "a conveyor's name");
  c.body = region(f, d, "conveyor '" + c.name + "'");
  if (d["direction"]) {
    const auto v = f.numbers(d["direction"], 3, "conveyor '" + c.name + "' direction");
    c.direction = {v[0], v[1], v[2]};
    // Scaled before it is normalised: the norm of [1e308, 1e308, 0] overflows to infinity and
    // a plain normalize() gave the zero vector (a belt that never moved).
    const double scale = c.direction.cwiseAbs().maxCoeff();
    if (!(scale > 0)) f.fail(d["direction"], "a conveyor's direction must not be zero");
    c.direction /= scale;
    c.direction.normalize();
  }
  // The belt carries along its top face: a direction out of that plane would lift parts.
  if (std::abs(c.direction.dot(c.body.pose.linear().col(2))) > 1e-9)
    f.fail(d["direction"] ? d["direction"] : d, "a conveyor's direction must lie in its top face (normal to its box's Z axis)");
  if (!d["speed_mm_s"]) f.fail(d, "a conveyor needs speed_mm_s");
  c.speed_mm_s = f.number(d["speed_mm_s"], "speed_mm_s");
  if (c.speed_mm_s < 0) f.fail(d["speed_mm_s"], "speed_mm_s must be >= 0 (reverse the direction instead)");
  // A belt faster than any real one only breaks the arithmetic: at 1e20 mm/s a part crossed
  // its belt in less than the clock's resolution (docs/limits.md).
  if (c.speed_mm_s > kMaxConveyorSpeed)
    f.fail(d["speed_mm_s"], fmt::format("speed_mm_s must be at most {:g} mm/s, got {:g}", kMaxConveyorSpeed, c.speed_mm_s));
  if (d["signal"]) c.signal = signal(f, d["signal"], "conveyor signal");
  // A still belt is a documented behaviour, not an error: its body is an object the parts on it
  // rest on (a belt set up before its speed is known), but it is worth a word.
  if (c.speed_mm_s == 0)
    cell.warnings.push_back(fmt::format("{}: conveyor '{}' has speed_mm_s 0: it never moves the parts on it (they rest on "
                                        "it as on a table)", f.where(d["speed_mm_s"]), c.name));
  add_name(f, d["conveyor"], c.name, names);
  cell.objects.push_back({c.name, collision::make_box(c.body.size), c.body.pose});
  cell.workcell.conveyors.push_back(std::move(c));
}

void sensor(const Fields& f, const YAML::Node& d, motion::Cell& cell) {
  f.expect_keys(d, {"sensor", "box", "at", "signal", "parts", "colour", "sensing"}, "a sensor");
  motion::Sensor s;
  s.name = f.text(d["sensor"], "a sensor's name");
  if (!d["signal"]) f.fail(d, "a sensor needs signal: (an input 1001-1512 or soft signal 2001-2512)");
  s.signal = device_signal(f, d["signal"], "sensor signal");
  s.region = region(f, d, "sensor '" + s.name + "'");
  if (d["parts"]) s.pattern = f.text(d["parts"], "sensor parts pattern");
  if (d["colour"]) s.colour = f.text(d["colour"], "sensor colour");
  if (d["sensing"]) {
    const std::string how = f.text(d["sensing"], "sensor sensing");
    if (how != "origin" && how != "overlap") f.fail(d["sensing"], "sensor sensing must be origin or overlap");
    s.sensing = how == "overlap" ? motion::Sensing::overlap : motion::Sensing::origin;
  }
  cell.workcell.sensors.push_back(std::move(s));
}

void feeder(const Fields& f, const YAML::Node& d, motion::Cell& cell, std::set<std::string>& names) {
  f.expect_keys(d, {"feeder", "part", "at", "signal", "when_empty", "count", "prefix", "colours", "spot"}, "a feeder");
  motion::Feeder fd;
  fd.name = f.text(d["feeder"], "a feeder's name");
  const std::string what = "feeder '" + fd.name + "'";
  if (!d["part"]) f.fail(d, what + " needs part: {box: [sx, sy, sz]} (or another shape)");
  f.expect_keys(d["part"], {"box", "cylinder", "sphere", "mesh", "scale"}, what + " part");
  fd.part.mesh = f.shape(d["part"], what + " part", cell.warnings);
  fd.part.pose = f.pose(d["at"], what + " at");
  fd.prefix = d["prefix"] ? f.text(d["prefix"], what + " prefix") : fd.name;
  if (d["signal"]) fd.signal = signal(f, d["signal"], what + " signal");
  if (d["when_empty"]) fd.when_empty = f.boolean(d["when_empty"], what + " when_empty");
  if (!d["signal"] && !d["when_empty"]) fd.when_empty = true;
  if (fd.signal == 0 && !fd.when_empty) f.fail(d, what + " never feeds: give signal or when_empty: true");
  fd.count = d["count"] ? integer(f, d["count"], 0, kMaxParts, what + " count") : 1;
  double total = static_cast<double>(cell.workcell.parts.size()) + fd.count;
  for (const auto& other : cell.workcell.feeders) total += other.count;
  if (total > kMaxParts) f.fail(d["count"] ? d["count"] : d, fmt::format("more than {:g} parts in the cell (declared and fed)", kMaxParts));
  if (const auto c = d["colours"]) {
    if (!c.IsSequence()) f.fail(c, what + " colours must be a list");
    for (const auto& x : c) fd.colours.push_back(f.text(x, what + " colour"));
  }
  // The spot: by default twice the part's extent, so a part has left it when its origin is one
  // part length away from the feed pose (room for the next one).
  collision::Vec3 lo = collision::Vec3::Constant(1e300), hi = -lo;
  for (const auto& v : fd.part.mesh.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
  collision::Vec3 spot = 2 * (hi - lo);
  if (d["spot"]) {
    const auto v = f.numbers(d["spot"], 3, what + " spot");
    for (double x : v)
      if (!(x > 0)) f.fail(d["spot"], what + " spot sides must be > 0");
    spot = {v[0], v[1], v[2]};
  }
  fd.spot = {fd.part.pose, spot};
  for (int i = 1; i <= fd.count; ++i) add_name(f, d["feeder"], fmt::format("{}{}", fd.prefix, i), names);
  cell.workcell.feeders.push_back(std::move(fd));
}

void sink(const Fields& f, const YAML::Node& d, motion::Cell& cell) {
  f.expect_keys(d, {"sink", "box", "at", "signal", "edge"}, "a sink");
  motion::Sink s;
  s.name = f.text(d["sink"], "a sink's name");
  s.region = region(f, d, "sink '" + s.name + "'");
  // Gated: removes what lies in it at an edge of the signal (docs/cell-format.md "sink").
  if (d["signal"]) s.signal = signal(f, d["signal"], "sink '" + s.name + "' signal");
  if (d["edge"]) {
    if (!d["signal"]) f.fail(d["edge"], "a sink's edge needs its signal:");
    const std::string e = f.text(d["edge"], "sink edge");
    if (e != "rising" && e != "falling") f.fail(d["edge"], "a sink's edge must be rising or falling");
    s.on_rising = e == "rising";
  }
  cell.workcell.sinks.push_back(std::move(s));
}

// {when: N, is: on|off, [after: T,] set: M, to: on|off} | {at: T, set: M, to: on|off} |
// {follow: N, set: M[, after: T]} (M follows N both ways).
void logic(const Fields& f, const YAML::Node& list, motion::Cell& cell, std::vector<YAML::Node>& nodes) {
  if (!list.IsSequence()) f.fail(list, "logic must be a list of rules");
  for (const auto& r : list) {
    f.expect_keys(r, {"when", "is", "at", "follow", "after", "set", "to"}, "a logic rule");
    motion::LogicRule rule;
    rule.line = r.Mark().is_null() ? 0 : r.Mark().line + 1;
    if (!r["set"]) f.fail(r, "a logic rule needs set: (the input or soft signal it sets)");
    rule.set = device_signal(f, r["set"], "logic set");
    if (r["after"]) {
      rule.after_s = f.number(r["after"], "logic after");
      if (rule.after_s < 0) f.fail(r["after"], "logic after must be >= 0 s");
    }
    const int forms = (r["when"] ? 1 : 0) + (r["at"] ? 1 : 0) + (r["follow"] ? 1 : 0);
    if (forms != 1) f.fail(r, "a logic rule has exactly one of when, at, follow");
    if (r["follow"]) {
      if (r["to"] || r["is"]) f.fail(r, "a follow rule has no is/to (the signal follows both ways)");
      rule.when = signal(f, r["follow"], "logic follow");
      if (rule.when == 0) f.fail(r["follow"], "logic follow needs a signal");
      rule.is_on = rule.to_on = true;
      cell.workcell.logic.push_back(rule);
      rule.is_on = rule.to_on = false;
      cell.workcell.logic.push_back(rule);
      nodes.push_back(r), nodes.push_back(r);
      continue;
    }
    rule.to_on = r["to"] ? on_off(f, r["to"], "logic to") : true;
    if (r["at"]) {
      if (r["is"]) f.fail(r["is"], "a timed rule (at) has no is");
      rule.at_s = f.number(r["at"], "logic at");
      if (rule.at_s < 0) f.fail(r["at"], "logic at must be >= 0 s");
    } else {
      rule.when = signal(f, r["when"], "logic when");
      if (rule.when == 0) f.fail(r["when"], "logic when needs a signal");
      rule.is_on = r["is"] ? on_off(f, r["is"], "logic is") : true;
    }
    cell.workcell.logic.push_back(rule);
    nodes.push_back(r);
  }
}
}  // namespace

// A feeder whose feed pose lies in a sink that is always open: each part would be removed as it
// appears and the next one fed at the same instant (a 10,000-part feeder ran 17 s into an
// internal error). A gated sink (signal:) takes parts only at its edges and is allowed.
void feeder_into_sink(const Fields& f, const YAML::Node& devices, const motion::Cell& cell) {
  std::vector<YAML::Node> sinks;
  for (const auto& dev : devices)
    if (dev["sink"]) sinks.push_back(dev);
  std::size_t k = 0;
  for (const auto& dev : devices) {
    if (!dev["feeder"]) continue;
    const motion::Feeder& fd = cell.workcell.feeders[k++];
    for (std::size_t i = 0; i < cell.workcell.sinks.size(); ++i) {
      const auto& s = cell.workcell.sinks[i];
      if (s.signal == 0 && s.region.contains(fd.part.pose.translation()))
        f.fail(dev, fmt::format("feeder '{}' feeds into sink '{}' ({}), which removes every part at once; move the feeder "
                                "or gate the sink with signal:", fd.name, s.name, f.where(sinks[i])));
    }
  }
}

// Contradictory devices and rules (docs/cell-format.md "Checked at load"):
// - a logic rule setting a signal a sensor drives (the sensor sets it back at once: two drivers
//   of one signal, other than sensors together, which are wired-OR);
// - rules without delay that switch a signal on and off in a loop at one instant.
void contradictions(const Fields& f, const motion::Cell& cell, const std::vector<YAML::Node>& sensor_nodes,
                    const std::vector<YAML::Node>& rule_nodes) {
  const auto& w = cell.workcell;
  for (std::size_t r = 0; r < w.logic.size(); ++r)
    for (std::size_t s = 0; s < w.sensors.size(); ++s)
      if (w.sensors[s].signal == w.logic[r].set)
        f.fail(rule_nodes[r]["set"] ? rule_nodes[r]["set"] : rule_nodes[r],
               fmt::format("signal {} is driven by sensor '{}' ({}) and set by this logic rule: the sensor sets it back "
                           "at once; let the rule set another signal", w.logic[r].set, w.sensors[s].name, f.where(sensor_nodes[s])));
  // Zero-delay `when` rules as edges (signal, state) -> (signal, state). A signal that such rules
  // lead from on to off and from off back to on switches forever once either edge happens.
  const auto node = [](int k, bool on) { return 2 * k + (on ? 1 : 0); };
  std::vector<std::vector<std::size_t>> out(2 * 2513);
  for (std::size_t r = 0; r < w.logic.size(); ++r)
    if (w.logic[r].at_s < 0 && w.logic[r].after_s == 0) out[static_cast<std::size_t>(node(w.logic[r].when, w.logic[r].is_on))].push_back(r);
  // The rules of a shortest path from a to b (empty: none).
  const auto path = [&](int a, int b) {
    std::vector<int> from(out.size(), -2);  // rule that reached the node; -1: the start
    std::vector<int> frontier{a};
    from[static_cast<std::size_t>(a)] = -1;
    for (std::size_t i = 0; i < frontier.size() && from[static_cast<std::size_t>(b)] == -2; ++i)
      for (const std::size_t r : out[static_cast<std::size_t>(frontier[i])]) {
        const int n = node(w.logic[r].set, w.logic[r].to_on);
        if (from[static_cast<std::size_t>(n)] != -2) continue;
        from[static_cast<std::size_t>(n)] = static_cast<int>(r);
        frontier.push_back(n);
      }
    std::vector<std::size_t> rules;
    if (from[static_cast<std::size_t>(b)] == -2 || a == b) return rules;
    for (int n = b; n != a;) {
      const auto r = static_cast<std::size_t>(from[static_cast<std::size_t>(n)]);
      rules.insert(rules.begin(), r);
      n = node(w.logic[r].when, w.logic[r].is_on);
    }
    return rules;
  };
  for (std::size_t r = 0; r < w.logic.size(); ++r) {
    if (w.logic[r].at_s >= 0 || w.logic[r].after_s != 0) continue;
    const int k = w.logic[r].when;
    const auto up = path(node(k, false), node(k, true)), down = path(node(k, true), node(k, false));
    if (up.empty() || down.empty()) continue;
    std::string chain = fmt::format("{} on", k), lines;
    for (const auto& leg : {down, up})
      for (const std::size_t x : leg) {
        chain += fmt::format(" -> {} {}", w.logic[x].set, w.logic[x].to_on ? "on" : "off");
        lines += (lines.empty() ? "" : ", ") + f.where(rule_nodes[x]);
      }
    f.fail(rule_nodes[down.front()],
           fmt::format("logic rules without delay switch signal {} on and off forever at one instant ({}; rules at {}); "
                       "give one of them an after: delay", k, chain, lines));
  }
}

void read_workcell(const YAML::Node& root, const Fields& f, motion::Cell& cell, std::set<std::string>& names) {
  std::vector<YAML::Node> part_nodes;  // the entry that declared each part
  std::vector<YAML::Node> sensor_nodes, feeder_nodes, rule_nodes;
  if (const auto p = root["parts"]) parts(f, p, cell, names, part_nodes);
  if (const auto g = root["gripper"]) gripper(f, g, cell);
  if (const auto d = root["devices"]) {
    if (!d.IsSequence()) f.fail(d, "devices must be a list");
    for (const auto& dev : d) {
      if (!dev.IsMap()) f.fail(dev, "a device is a map starting with conveyor:, sensor:, feeder: or sink:");
      if (dev["conveyor"]) conveyor(f, dev, cell, names);
      else if (dev["sensor"]) sensor(f, dev, cell), sensor_nodes.push_back(dev);
      else if (dev["feeder"]) feeder(f, dev, cell, names), feeder_nodes.push_back(dev);
      else if (dev["sink"]) sink(f, dev, cell);
      else f.fail(dev, "a device is one of conveyor:, sensor:, feeder:, sink: (with its name)");
    }
  }
  if (const auto l = root["logic"]) logic(f, l, cell, rule_nodes);
  if (const auto d = root["devices"]) feeder_into_sink(f, d, cell);
  contradictions(f, cell, sensor_nodes, rule_nodes);
  if (const auto bad = first_misplaced_part(cell)) f.fail(bad->feeder ? feeder_nodes[bad->part] : part_nodes[bad->part], bad->message);
}

}  // namespace asimov::cell
