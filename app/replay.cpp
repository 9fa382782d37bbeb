#include "app/replay.hpp"

#include "app/report.hpp"

#include "asimov/motion/scene.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
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

// [x, y, z, qx, qy, qz, qw]: mm and a unit quaternion, as three.js takes them.
void push_pose(std::vector<float>& out, const collision::Pose& p) {
  const Eigen::Quaterniond q(p.rotation());
  const auto& t = p.translation();
  for (double v : {t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w()}) out.push_back(static_cast<float>(v));
}

nlohmann::json pose_json(const collision::Pose& p) {
  std::vector<float> v;
  push_pose(v, p);
  return v;
}

// The program line of each step in the frames, from the motions the run started: a step is
// named where exactly one motion instruction ran at it (programs of a file may share a step
// number), otherwise the page shows the bare step.
nlohmann::json step_lines(const std::vector<interpreter::MotionStep>& motions, const std::vector<int>& steps) {
  nlohmann::json out = nlohmann::json::object();
  for (int step : steps)
    if (const interpreter::MotionStep* m = interpreter::motion_at_step(motions, step))
      out[std::to_string(step)] = {{"program", m->program}, {"line", m->line}, {"text", m->text}};
  return out;
}


// "</script" inside an inlined script would end it early.
std::string script_safe(std::string s) {
  for (std::size_t at = 0; (at = s.find("</", at)) != std::string::npos; at += 3) s.replace(at, 2, "<\\/");
  return s;
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

nlohmann::json replay_data(const std::string& file, const motion::Simulator& sim, const interpreter::RunResult& result) {
  const motion::Cell& cell = sim.cell();
  const motion::Scene scene = motion::scene_bodies(cell);
  const int n = cell.robot.joint_count();

  std::vector<motion::ReplaySample> samples = sim.recorders().replay.samples;
  // The arm stands still after its last motion (WAIT, hand, a motionless program): one frame
  // at the end of the run shows that, except after a contact, where the halting pose ends it.
  const double end_s = result.status == interpreter::RunStatus::collision ? result.collision.time_free_s : sim.time_s();
  if (samples.empty() || samples.back().time_s < end_s)
    samples.push_back({end_s, sim.joints(), samples.empty() ? 0 : samples.back().step, false});

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
  std::vector<float> joints, world;
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
                  {"poses", b64(world)}}},         // Float32, count x moving x 7
      {"steps", step_lines(result.motions, distinct_steps)},
      {"end_time_s", samples.back().time_s}};
  const auto body = [&index_of](const std::string& name) { return index_of.count(name) ? index_of[name] : -1; };
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
  html += "<script type=\"application/json\" id=\"asimov-replay-data\">" + script_safe(data.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace)) + "</script>\n";
  html += "<script type=\"importmap\">" + script_safe(imports.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace)) + "</script>\n";
  html += "<script type=\"module\" id=\"asimov-replay-viewer\">\n" + script_safe(assets.viewer) + "\n</script>\n";
  html += "</body>\n</html>\n";
  return html;
}

}  // namespace asimov::app
