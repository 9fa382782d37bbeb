#include "app/replay.hpp"

#include "app/report.hpp"

#include "asimov/motion/cell_runtime.hpp"
#include "asimov/motion/scene.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>

#ifndef ASIMOV_REPLAY_REL
#define ASIMOV_REPLAY_REL "../share/asimov/replay"
#endif

namespace asimov::app {
namespace {

template <class T>
std::string b64(const std::vector<T>& v) {
  return base64(v.data(), v.size() * sizeof(T));
}

bool read_file(const std::filesystem::path& path, std::string& text) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  std::ostringstream s;
  s << in.rdbuf();
  text = s.str();
  return static_cast<bool>(in) || in.eof();
}

// [x, y, z, qx, qy, qz, qw]: mm and a unit quaternion, as three.js takes them (Float32 for the
// frames, Float64 for the parts' segments).
template <class T>
void push_pose(std::vector<T>& out, const collision::Pose& p) {
  const Eigen::Quaterniond q(p.rotation());
  const auto& t = p.translation();
  for (double v : {t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w()}) out.push_back(static_cast<T>(v));
}

nlohmann::json pose_json(const collision::Pose& p) {
  std::vector<float> v;
  push_pose(v, p);
  return v;
}

// The programs of a source text: each `.PROGRAM` line's number and name, and every line.
struct SourcePrograms {
  std::vector<std::string> lines;
  std::vector<std::pair<int, std::string>> programs;  // (file line of .PROGRAM, lower-case name)
};
SourcePrograms source_programs(const std::string& text) {
  SourcePrograms out;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);) {
    if (!l.empty() && l.back() == '\r') l.pop_back();
    out.lines.push_back(l);
    std::size_t a = l.find_first_not_of(" \t");
    if (a == std::string::npos || l.size() < a + 8) continue;
    std::string head = l.substr(a, 8);
    std::transform(head.begin(), head.end(), head.begin(), [](unsigned char c) { return std::tolower(c); });
    if (head != ".program") continue;
    std::string name = l.substr(a + 8);
    name.erase(0, std::min(name.size(), name.find_first_not_of(" \t")));
    name = name.substr(0, name.find_first_of("( \t;"));
    std::transform(name.begin(), name.end(), name.begin(), [](unsigned char c) { return std::tolower(c); });
    out.programs.emplace_back(static_cast<int>(out.lines.size()), name);
  }
  return out;
}

// The program line of each step in the frames. A motion's step is named from the motions the run
// started, where exactly one motion instruction ran at it (programs of a file may share a step
// number). Any other step (the arm at rest: WAIT, a hand's time, a dwell while the belts run) is
// named from the source when exactly one program that ran has a statement at that step (step =
// file line - .PROGRAM line, as the checker numbers them; blank and comment lines are none);
// otherwise the page shows the bare step.
nlohmann::json step_lines(const std::vector<interpreter::MotionStep>& motions, const std::vector<int>& steps,
                          const std::string& source, const std::vector<std::string>& ran) {
  nlohmann::json out = nlohmann::json::object();
  const SourcePrograms src = source_programs(source);
  for (int step : steps) {
    if (const interpreter::MotionStep* m = interpreter::motion_at_step(motions, step)) {
      out[std::to_string(step)] = {{"program", m->program}, {"line", m->line}, {"text", m->text}};
      continue;
    }
    if (step <= 0) continue;
    const std::pair<int, std::string>* found = nullptr;
    int count = 0;
    for (std::size_t k = 0; k < src.programs.size(); ++k) {
      const auto& [at, name] = src.programs[k];
      const int line = at + step;  // 1-based file line
      const int next = k + 1 < src.programs.size() ? src.programs[k + 1].first : static_cast<int>(src.lines.size()) + 1;
      if (line >= next || std::find(ran.begin(), ran.end(), name) == ran.end()) continue;
      const std::string& text = src.lines[static_cast<std::size_t>(line - 1)];
      const std::size_t a = text.find_first_not_of(" \t");
      if (a == std::string::npos || text[a] == ';') continue;
      found = &src.programs[k];
      ++count;
    }
    if (count == 1) {
      const int line = found->first + step;
      const std::string& text = src.lines[static_cast<std::size_t>(line - 1)];
      out[std::to_string(step)] = {{"program", found->second}, {"line", line}, {"text", text.substr(text.find_first_not_of(" \t"))}};
    }
  }
  return out;
}

// The parts' states as the page numbers them (Holder's order) and names them (the report's).
constexpr motion::Holder kHolders[] = {motion::Holder::world, motion::Holder::conveyor, motion::Holder::carried,
                                       motion::Holder::removed};
std::uint8_t state_code(motion::Holder h) {
  return static_cast<std::uint8_t>(std::find(std::begin(kHolders), std::end(kHolders), h) - std::begin(kHolders));
}

nlohmann::json region_json(const char* kind, const std::string& name, const motion::Region& r) {
  return {{"kind", kind}, {"name", name}, {"pose", pose_json(r.pose)}, {"size", {r.size.x(), r.size.y(), r.size.z()}}};
}

// A cell with parts or devices (docs/cell-format.md "Parts and devices"): its parts (one mesh per
// distinct shape), every state of every part up to end_s (PartSegment: the viewer poses a part at
// any instant from them), the devices' regions, and the events up to end_s (signal changes among
// them: the viewer folds them into the signal states). The carried part's world pose per frame
// goes into `frames` (only when a part was ever carried).
nlohmann::json workcell_data(const motion::Cell& cell, const motion::CellRuntime& runtime, motion::PartHistory history,
                             const std::vector<motion::ReplaySample>& samples, double end_s, nlohmann::json& frames) {
  history.observe(runtime);  // the state at the end of the run
  const motion::DeviceClock& clock = runtime.clock();
  const motion::Workcell& w = cell.workcell;

  auto meshes = nlohmann::json::array();
  std::vector<const collision::Polyhedron*> distinct;
  auto parts = nlohmann::json::array();
  for (const motion::PartState& p : clock.parts()) {
    const collision::Polyhedron& m = p.def->mesh;
    std::size_t k = 0;
    while (k < distinct.size() && !(distinct[k]->vertices == m.vertices && distinct[k]->triangles == m.triangles)) ++k;
    if (k == distinct.size()) {
      distinct.push_back(&m);
      std::vector<float> v;
      v.reserve(m.vertices.size() * 3);
      for (const auto& x : m.vertices)
        for (double c : {x.x(), x.y(), x.z()}) v.push_back(static_cast<float>(c));
      std::vector<std::uint32_t> tri;
      tri.reserve(m.triangles.size() * 3);
      for (const auto& t : m.triangles) tri.insert(tri.end(), t.begin(), t.end());
      meshes.push_back({{"vertex_count", m.vertices.size()},
                        {"triangle_count", m.triangles.size()},
                        {"vertices", b64(v)},
                        {"triangles", b64(tri)}});
    }
    nlohmann::json j = {{"name", p.def->name}, {"mesh", k}};
    if (!p.def->colour.empty()) j["colour"] = p.def->colour;
    if (p.feeder >= 0) j["feeder"] = w.feeders[static_cast<std::size_t>(p.feeder)].name;
    parts.push_back(std::move(j));
  }

  // Segments per part in time order (PartHistory interleaves the parts).
  std::vector<const motion::PartSegment*> segs;
  for (const motion::PartSegment& s : history.segments)
    if (s.time_s <= end_s) segs.push_back(&s);
  std::stable_sort(segs.begin(), segs.end(), [](const auto* a, const auto* b) { return a->part < b->part; });
  std::vector<std::int32_t> seg_part;
  std::vector<std::uint8_t> seg_state;
  std::vector<double> seg_time, seg_pose, seg_velocity, seg_end;
  struct Carry {
    double from, to;
    motion::Location grip;
  };
  std::vector<Carry> carries;
  for (std::size_t i = 0; i < segs.size(); ++i) {
    const motion::PartSegment& s = *segs[i];
    seg_part.push_back(s.part);
    seg_state.push_back(state_code(s.holder));
    seg_time.push_back(s.time_s);
    push_pose(seg_pose, s.pose);
    for (int c = 0; c < 3; ++c) seg_velocity.push_back(s.velocity[c]);
    seg_end.push_back(s.end_s);
    if (s.holder == motion::Holder::carried) {
      const bool next = i + 1 < segs.size() && segs[i + 1]->part == s.part;
      carries.push_back({s.time_s, next ? segs[i + 1]->time_s : std::numeric_limits<double>::infinity(), s.pose});
    }
  }
  if (!carries.empty()) {  // the carried part follows the flange: its pose at every frame
    std::sort(carries.begin(), carries.end(), [](const Carry& a, const Carry& b) { return a.from < b.from; });
    std::vector<float> carried;
    carried.reserve(samples.size() * 7);
    std::size_t k = 0;
    for (const motion::ReplaySample& s : samples) {
      while (k < carries.size() && carries[k].to <= s.time_s) ++k;
      if (k < carries.size() && carries[k].from <= s.time_s)
        push_pose(carried, cell.base * robots::flange_pose(cell.robot, s.joints) * carries[k].grip);
      else
        carried.insert(carried.end(), 7, 0.0f);
    }
    frames["carried"] = b64(carried);  // Float32, count x 7: world pose of the carried part (zeros: none)
  }

  auto devices = nlohmann::json::array();
  for (const motion::Conveyor& c : w.conveyors) {
    nlohmann::json j = region_json("conveyor", c.name, c.body);
    j["direction"] = {c.direction.x(), c.direction.y(), c.direction.z()};
    j["speed_mm_s"] = c.speed_mm_s;
    j["signal"] = c.signal;
    devices.push_back(std::move(j));
  }
  for (const motion::Sensor& s : w.sensors) {
    nlohmann::json j = region_json("sensor", s.name, s.region);
    j["signal"] = s.signal;
    devices.push_back(std::move(j));
  }
  for (const motion::Sink& s : w.sinks) devices.push_back(region_json("sink", s.name, s.region));
  for (const motion::Feeder& f : w.feeders) {
    nlohmann::json j = region_json("feeder", f.name, f.spot);
    j["signal"] = f.signal;
    devices.push_back(std::move(j));
  }

  auto states = nlohmann::json::array();
  for (const motion::Holder h : kHolders) states.push_back(part_state_name(h));
  auto events = nlohmann::json::array();
  for (const motion::CellEvent& e : clock.events()) {
    if (e.time_s > end_s) break;  // events are in time order: after a contact, past the halting pose
    events.push_back(event_json(e));
  }

  return {{"parts", std::move(parts)},
          {"part_meshes", std::move(meshes)},
          {"states", states},
          {"segments", {{"count", segs.size()},
                        {"part", b64(seg_part)},          // Int32: index into parts
                        {"time_s", b64(seg_time)},        // Float64: the state begins
                        {"state", b64(seg_state)},        // Uint8: index into states
                        {"pose", b64(seg_pose)},          // Float64 x 7: world at time_s (carried: in the flange frame)
                        {"velocity", b64(seg_velocity)},  // Float64 x 3: mm/s on a running belt
                        {"end_s", b64(seg_end)}}},        // Float64: the belt's end stop (Infinity: none)
          {"devices", std::move(devices)},
          {"events", std::move(events)}};
}

// Text inlined into a <script> element must not end it early (`</script`) nor put the HTML
// tokenizer into its "double escaped" state (`<!--` then `<script`), where the real `</script>`
// no longer closes it and the rest of the page is swallowed. In JSON every `<` is inside a
// string, so `\u003c` is the same text to JSON.parse; the viewer's own code gets `<\/`, `<\!--`
// and `<\script`, which JavaScript strings read unchanged (viewer.js has none in a regex).
std::string json_script_safe(const std::string& s) {
  std::string out;
  out.reserve(s.size());
  for (char c : s) {
    if (c == '<') out += "\\u003c";
    else out += c;
  }
  return out;
}

std::string script_safe(const std::string& s) {
  const auto at = [&s](std::size_t i, const char* word) {  // ASCII case-insensitive, as the tokenizer
    for (std::size_t k = 0; word[k]; ++k)
      if (i + k >= s.size() || std::tolower(static_cast<unsigned char>(s[i + k])) != word[k]) return false;
    return true;
  };
  std::string out;
  out.reserve(s.size());
  for (std::size_t i = 0; i < s.size(); ++i) {
    out += s[i];
    if (s[i] == '<' && (at(i + 1, "/") || at(i + 1, "!--") || at(i + 1, "script"))) out += '\\';
  }
  return out;
}

// The source of `file` for step_lines ("" when it cannot be read: steps stay bare).
std::string file_text(const std::string& file) {
  std::string text;
  if (file.empty() || !read_file(file, text)) return {};
  return text;
}

// The programs that ran: those of its motions, its tasks', and where it ended.
std::vector<std::string> programs_run(const interpreter::RunResult& result) {
  std::vector<std::string> out;
  const auto add = [&out](const std::string& p) {
    if (!p.empty() && std::find(out.begin(), out.end(), p) == out.end()) out.push_back(p);
  };
  add(result.program);
  for (const auto& m : result.motion_times) add(m.program);
  for (const auto& m : result.motions) add(m.program);
  for (const auto& t : result.tasks) add(t.program);
  return out;
}

}  // namespace

std::string base64(const void* bytes, std::size_t size) {
  static const char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  const auto* p = static_cast<const unsigned char*>(bytes);
  std::string out;
  out.reserve((size + 2) / 3 * 4);
  for (std::size_t i = 0; i < size; i += 3) {
    const unsigned v = (p[i] << 16) | (i + 1 < size ? p[i + 1] << 8 : 0) | (i + 2 < size ? p[i + 2] : 0);
    out += kAlphabet[(v >> 18) & 63];
    out += kAlphabet[(v >> 12) & 63];
    out += i + 1 < size ? kAlphabet[(v >> 6) & 63] : '=';
    out += i + 2 < size ? kAlphabet[v & 63] : '=';
  }
  return out;
}

std::string replay_asset_dir() {
  if (const char* env = std::getenv("ASIMOV_REPLAY_DIR"); env && *env) return env;
  // Relative to the executable, so an installed tree (and a moved one) finds its own copy.
  std::error_code ec;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (ec) return {};
  return (exe.parent_path() / ASIMOV_REPLAY_REL).lexically_normal().string();
}

Result<ReplayAssets> load_replay_assets() {
  ReplayAssets assets;
  const std::filesystem::path dir = replay_asset_dir();
  const std::pair<const char*, std::string*> files[] = {
      {"three.module.min.js", &assets.three}, {"OrbitControls.js", &assets.orbit_controls}, {"viewer.js", &assets.viewer}};
  for (const auto& [name, text] : files) {
    if (dir.empty() || !read_file(dir / name, *text))
      return Error{fmt::format("{} is missing: install three.js with scripts/install-deps.sh (npm ci in app/replay), "
                               "then re-run cmake (and install again); or point ASIMOV_REPLAY_DIR at a folder holding "
                               "three.module.min.js, OrbitControls.js and viewer.js",
                               (dir / name).string()),
                   {}, (dir / name).string(), 0};
  }
  return assets;
}

nlohmann::json replay_data(const std::string& file, const motion::Simulator& sim, const interpreter::RunResult& result,
                           const std::string& source) {
  const motion::Cell& cell = sim.cell();
  const motion::Scene scene = motion::scene_bodies(cell);
  const int n = cell.robot.joint_count();

  std::vector<motion::ReplaySample> samples = sim.recorders().replay.samples;
  // The arm stands still after its last motion (WAIT, hand, a motionless program): one frame
  // at the end of the run shows that, except after a contact, where the halting pose ends it.
  const double end_s = result.status == interpreter::RunStatus::collision ? result.collision.time_free_s : sim.time_s();
  if (samples.empty() || samples.back().time_s < end_s)
    samples.push_back({end_s, sim.joints(), samples.empty() ? 0 : samples.back().step, false, sim.here().translation()});

  auto bodies = nlohmann::json::array();
  std::vector<std::size_t> moving;
  std::map<std::string, int> index_of;
  std::vector<collision::Pose> frames, poses;
  motion::scene_poses(cell, scene, samples.front().joints, frames, poses);
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
    const motion::SceneBody& b = scene.bodies[i];
    std::vector<float> v;
    v.reserve(b.mesh.vertices.size() * 3);
    for (const auto& p : b.mesh.vertices)
      for (double c : {p.x(), p.y(), p.z()}) v.push_back(static_cast<float>(c));
    std::vector<std::uint32_t> tri;
    tri.reserve(b.mesh.triangles.size() * 3);
    for (const auto& t : b.mesh.triangles) tri.insert(tri.end(), t.begin(), t.end());
    nlohmann::json body = {{"name", b.name},
                           {"kind", b.object >= 0 ? "object" : b.name == "tool" ? "tool" : "link"},
                           {"moving", !b.is_static},
                           {"vertex_count", b.mesh.vertices.size()},
                           {"triangle_count", b.mesh.triangles.size()},
                           {"vertices", b64(v)},
                           {"triangles", b64(tri)}};
    if (b.is_static) body["pose"] = pose_json(poses[i]);
    else moving.push_back(i);
    index_of[b.name] = static_cast<int>(i);
    bodies.push_back(std::move(body));
  }

  std::vector<double> times;
  std::vector<float> joints, world, tool_path;
  std::vector<std::int32_t> steps;
  std::vector<std::uint8_t> checked;
  std::vector<int> distinct_steps;
  for (const motion::ReplaySample& s : samples) {
    times.push_back(s.time_s);
    for (int j = 0; j < n; ++j) joints.push_back(static_cast<float>(s.joints[j]));
    motion::scene_poses(cell, scene, s.joints, frames, poses);
    for (std::size_t i : moving) push_pose(world, poses[i]);
    steps.push_back(s.step);
    checked.push_back(s.checked ? 1 : 0);
    for (int c = 0; c < 3; ++c) tool_path.push_back(static_cast<float>(s.tool_mm[c]));
    if (std::find(distinct_steps.begin(), distinct_steps.end(), s.step) == distinct_steps.end())
      distinct_steps.push_back(s.step);
  }

  nlohmann::json doc = {
      {"schema_version", kSchemaVersion},
      {"format", "asimov-replay 1"},
      {"file", file},
      {"program", result.program},
      {"robot", cell.robot.name},
      {"status", status_name(result)},
      {"units", {{"length", "mm"}, {"time", "s"}, {"joints", "deg"}, {"pose", "x y z qx qy qz qw"}}},
      {"joint_count", n},
      {"tool_xyzoat", motion::decompose(cell.tool)},
      {"bodies", std::move(bodies)},
      {"moving", moving},
      {"frames", {{"count", samples.size()},
                  {"time_s", b64(times)},          // Float64
                  {"step", b64(steps)},            // Int32: the motion's program step
                  {"checked", b64(checked)},       // Uint8: 1 at a checked pose (the trace's)
                  {"joints_deg", b64(joints)},     // Float32, count x joint_count
                  {"tool_mm", b64(tool_path)},     // Float32, count x 3: the tool point (world)
                  {"poses", b64(world)}}},         // Float32, count x moving x 7
      {"steps", step_lines(result.motions, distinct_steps, source.empty() ? file_text(file) : source, programs_run(result))},
      {"end_time_s", samples.back().time_s}};
  if (const motion::CellRuntime* runtime = sim.cell_runtime())
    doc["workcell"] = workcell_data(cell, *runtime, sim.recorders().replay.parts, samples, samples.back().time_s, doc["frames"]);
  const auto body = [&index_of](const std::string& name) { return index_of.count(name) ? index_of[name] : -1; };
  // A part's index into workcell.parts from its body name ("part:NAME", "carried part:NAME"); -1: none.
  const auto part = [&sim](const std::string& name) {
    const motion::CellRuntime* runtime = sim.cell_runtime();
    std::string part_name;
    for (const char* prefix : {"part:", "carried part:"})
      if (name.rfind(prefix, 0) == 0) part_name = name.substr(std::strlen(prefix));
    if (!runtime || part_name.empty()) return -1;
    const auto& parts = runtime->clock().parts();
    for (std::size_t i = 0; i < parts.size(); ++i)
      if (parts[i].def->name == part_name) return static_cast<int>(i);
    return -1;
  };
  // The closest approach of the clearance report (docs/collision.md §12): the page marks it.
  if (const auto near = sim.recorders().clearance.nearest_first(); !near.empty()) {
    const motion::ClearanceApproach& a = near.front();
    const std::string name_a = sim.body_name(a.pair.a), name_b = sim.body_name(a.pair.b);
    doc["closest"] = {{"bodies", {name_a, name_b}},
                      {"body_index", {body(name_a), body(name_b)}},
                      {"distance_mm", a.distance_mm},
                      {"time_s", a.time_s},
                      {"point_a_mm", {a.point_a.x(), a.point_a.y(), a.point_a.z()}},
                      {"point_b_mm", {a.point_b.x(), a.point_b.y(), a.point_b.z()}}};
  }
  if (result.status == interpreter::RunStatus::collision) {
    const motion::CollisionReport& c = result.collision;
    doc["collision"] = {{"bodies", {c.body_a, c.body_b}},
                        {"body_index", {body(c.body_a), body(c.body_b)}},
                        {"point_mm", {c.point.x(), c.point.y(), c.point.z()}},
                        {"time_s", c.time_s},
                        {"time_free_s", c.time_free_s}};
    if (doc.contains("workcell")) doc["collision"]["part_index"] = {part(c.body_a), part(c.body_b)};
  }
  return doc;
}

std::string replay_html(const ReplayAssets& assets, const nlohmann::json& data) {
  const nlohmann::json imports = {
      {"imports",
       {{"three", "data:text/javascript;base64," + base64(assets.three.data(), assets.three.size())},
        {"three/addons/controls/OrbitControls.js",
         "data:text/javascript;base64," + base64(assets.orbit_controls.data(), assets.orbit_controls.size())}}}};
  std::string html;
  html += "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n";
  html += "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n";
  html += "<title>asimov replay</title>\n";
  html += "<!-- written by `asimov run --replay`; three.js (MIT, three.js authors) is inlined below -->\n";
  html += "</head>\n<body>\n";
  html += "<script type=\"application/json\" id=\"asimov-replay-data\">" + json_script_safe(data.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace)) + "</script>\n";
  html += "<script type=\"importmap\">" + json_script_safe(imports.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace)) + "</script>\n";
  html += "<script type=\"module\" id=\"asimov-replay-viewer\">\n" + script_safe(assets.viewer) + "\n</script>\n";
  html += "</body>\n</html>\n";
  return html;
}

}  // namespace asimov::app
