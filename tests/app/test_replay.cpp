// `asimov run --replay`: the simulator's replay recording and the page's embedded data
// (app/README.md "Replay page"). The page is decoded in node as well: replay_decode.mjs.
#include "asimov/cell/cell_loader.hpp"
#include "app/replay.hpp"
#include "asimov/motion/scene.hpp"
#include "asimov/motion/simulator.hpp"
#include "support/run_cli.hpp"

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>
#include <optional>

using namespace asimov;
using test::run_cli;
using test::source_path;

namespace {

std::vector<unsigned char> unbase64(const std::string& s) {
  std::vector<unsigned char> out;
  unsigned v = 0;
  int bits = 0;
  for (char c : s) {
    int d = c >= 'A' && c <= 'Z' ? c - 'A' : c >= 'a' && c <= 'z' ? c - 'a' + 26 : c >= '0' && c <= '9' ? c - '0' + 52
          : c == '+' ? 62 : c == '/' ? 63 : -1;
    if (d < 0) continue;  // padding
    v = (v << 6) | static_cast<unsigned>(d);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back(static_cast<unsigned char>((v >> bits) & 0xff));
    }
  }
  return out;
}

template <class T>
std::vector<T> typed(const nlohmann::json& b64) {
  const auto bytes = unbase64(b64.get<std::string>());
  REQUIRE(bytes.size() % sizeof(T) == 0);
  std::vector<T> v(bytes.size() / sizeof(T));
  std::memcpy(v.data(), bytes.data(), bytes.size());
  return v;
}

// The JSON of <script id="asimov-replay-data"> (its "</" are written "<\/", valid JSON).
nlohmann::json page_data(const std::string& html) {
  const std::string open = "<script type=\"application/json\" id=\"asimov-replay-data\">";
  const auto a = html.find(open);
  REQUIRE(a != std::string::npos);
  const auto b = html.find("</script>", a);
  REQUIRE(b != std::string::npos);
  return nlohmann::json::parse(html.substr(a + open.size(), b - a - open.size()));
}

struct Run {
  test::CliResult cli;
  std::string html;
  nlohmann::json data, report, trace;
};

Run run_demo(const std::string& name) {
  const auto dir = test::scratch_dir();
  const auto html = dir / (name + ".html"), report = dir / (name + ".json"), trace = dir / (name + ".trace.json");
  Run r;
  r.cli = run_cli("run " + source_path("programs/demo/" + name + ".v2") + " --replay " + html.string() + " --report " +
                  report.string() + " --trace " + trace.string());
  r.html = test::slurp(html);
  r.report = nlohmann::json::parse(test::slurp(report));
  r.trace = nlohmann::json::parse(test::slurp(trace));
  r.data = page_data(r.html);
  return r;
}

Run run_cell(const std::string& name, const std::string& cell) {
  const auto dir = test::scratch_dir();
  const auto html = dir / (name + ".html"), report = dir / (name + ".json"), trace = dir / (name + ".trace.json");
  Run r;
  r.cli = run_cli("run " + source_path("programs/cells/" + name + ".v2") + " --cell " + source_path("programs/cells/" + cell) +
                  " --replay " + html.string() + " --report " + report.string() + " --trace " + trace.string());
  r.html = test::slurp(html);
  r.report = nlohmann::json::parse(test::slurp(report));
  r.trace = nlohmann::json::parse(test::slurp(trace));
  r.data = page_data(r.html);
  return r;
}

// The page's frames against the run: times strictly increase and end at `end_s`; every checked
// frame is a trace sample (same instant, same joints, bodies where FK puts them) and every
// trace sample up to the end is a checked frame.
void check_frames(const Run& r, double end_s) {
  const auto& f = r.data["frames"];
  const std::size_t count = f["count"];
  const auto time = typed<double>(f["time_s"]);
  const auto joints = typed<float>(f["joints_deg"]);
  const auto poses = typed<float>(f["poses"]);
  const auto checked = unbase64(f["checked"]);
  const auto steps = typed<std::int32_t>(f["step"]);
  const std::vector<std::size_t> moving = r.data["moving"];
  const int n = r.data["joint_count"];
  REQUIRE(time.size() == count);
  REQUIRE(checked.size() == count);
  REQUIRE(steps.size() == count);
  REQUIRE(joints.size() == count * static_cast<std::size_t>(n));
  REQUIRE(poses.size() == count * moving.size() * 7);
  for (std::size_t i = 1; i < count; ++i) REQUIRE(time[i] > time[i - 1]);
  CHECK(time.back() == end_s);

  const motion::Cell cell = cell::default_cell();
  const motion::Scene scene = motion::scene_bodies(cell);
  std::vector<collision::Pose> frames, world;
  std::size_t k = 0, compared = 0;
  for (const auto& s : r.trace["samples"]) {
    const double t = s["t"];
    if (t > end_s) break;  // the colliding checked pose, after the halting pose
    while (k < count && time[k] < t) ++k;
    REQUIRE(k < count);
    REQUIRE(time[k] == t);
    CHECK(checked[k] == 1);
    robots::JointVector q(n);
    for (int j = 0; j < n; ++j) {
      q[j] = s["joints_deg"][static_cast<std::size_t>(j)];
      REQUIRE(joints[k * static_cast<std::size_t>(n) + static_cast<std::size_t>(j)] == Approx(q[j]).margin(1e-4));
    }
    motion::scene_poses(cell, scene, q, frames, world);
    for (std::size_t m = 0; m < moving.size(); ++m) {
      const float* p = &poses[(k * moving.size() + m) * 7];
      const collision::Pose& want = world[moving[m]];
      for (int c = 0; c < 3; ++c) REQUIRE(p[c] == Approx(want.translation()[c]).margin(1e-3));
      const Eigen::Quaterniond qw(want.rotation()), qp(p[6], p[3], p[4], p[5]);
      REQUIRE(std::abs(qw.dot(qp)) == Approx(1).margin(1e-6));
    }
    ++compared;
  }
  CHECK(compared > 100);
  std::size_t n_checked = 0;
  for (auto c : checked) n_checked += c;
  CHECK(n_checked == compared);
  CHECK(count > compared);  // the 1/30 s grid between sparse checked poses
}

void check_page(const Run& r) {
  CHECK(r.html.rfind("<!DOCTYPE html>", 0) == 0);
  CHECK(r.html.find("<script type=\"importmap\">{\"imports\":{\"three\":\"data:text/javascript;base64,") != std::string::npos);
  CHECK(r.html.find("id=\"asimov-replay-viewer\"") != std::string::npos);
  CHECK(r.html.find("export function decodeReplay") != std::string::npos);
  CHECK(r.html.find("http://") == std::string::npos);  // nothing is fetched: no address at all
  CHECK(r.html.find("https://") == std::string::npos);
  const std::size_t bodies = motion::scene_bodies(cell::default_cell()).bodies.size();
  REQUIRE(r.data["bodies"].size() == bodies);
  std::size_t moving = 0;
  for (const auto& b : r.data["bodies"]) {
    const auto v = typed<float>(b["vertices"]);
    const auto t = typed<std::uint32_t>(b["triangles"]);
    CHECK(v.size() == 3 * b["vertex_count"].get<std::size_t>());
    CHECK(t.size() == 3 * b["triangle_count"].get<std::size_t>());
    CHECK(b["triangle_count"].get<std::size_t>() > 0);
    moving += b["moving"].get<bool>() ? 1 : 0;
    CHECK(b.contains("pose") != b["moving"].get<bool>());
  }
  CHECK(r.data["moving"].size() == moving);
  CHECK(moving == 7);  // link1..link6 and the tool of the built-in cell
  // A static cell: no parts, devices, signals or carried poses, not even empty ones.
  CHECK(!r.data.contains("workcell"));
  CHECK(!r.data["frames"].contains("carried"));
}

}  // namespace

TEST_CASE("replay page of pick_place: exit 0, every body, frames up to the end of the run") {
  const Run r = run_demo("pick_place");
  INFO(r.cli.err);
  REQUIRE(r.cli.exit_code == 0);
  check_page(r);
  CHECK(r.data["status"] == "completed");
  CHECK(!r.data.contains("collision"));
  check_frames(r, r.report["sim_time_s"].get<double>());
  // Steps map to the motion lines of both programs (CALL transfer).
  CHECK(r.data["steps"]["3"]["program"] == "transfer");
  CHECK(r.data["steps"]["3"]["text"] == "MOVES src");
  CHECK(r.data["steps"]["13"]["line"] == 14);
}

TEST_CASE("replay page of crash: exit 3, ends at the halting pose, the contact bodies named") {
  const Run r = run_demo("crash");
  INFO(r.cli.err);
  REQUIRE(r.cli.exit_code == 3);
  check_page(r);
  CHECK(r.data["status"] == "collision");
  const auto& c = r.report["collision"];
  check_frames(r, c["time_free_s"].get<double>());
  CHECK(r.data["end_time_s"] == c["time_free_s"]);
  REQUIRE(r.data.contains("collision"));
  CHECK(r.data["collision"]["bodies"] == c["bodies"]);
  CHECK(r.data["collision"]["point_mm"] == c["point_mm"]);
  for (int k = 0; k < 2; ++k) {
    const int i = r.data["collision"]["body_index"][static_cast<std::size_t>(k)];
    REQUIRE(i >= 0);
    CHECK(r.data["bodies"][static_cast<std::size_t>(i)]["name"] == c["bodies"][static_cast<std::size_t>(k)]);
  }
}

TEST_CASE("replay page of belt_pick: every state of every part, continuous, as the report has them") {
  const Run r = run_cell("belt_pick", "belt_cell.yaml");
  INFO(r.cli.err);
  REQUIRE(r.cli.exit_code == 0);
  REQUIRE(r.data.contains("workcell"));
  const auto& w = r.data["workcell"];
  const auto& seg = w["segments"];
  const std::size_t n = seg["count"];
  const auto part = typed<std::int32_t>(seg["part"]);
  const auto time = typed<double>(seg["time_s"]);
  const auto state = unbase64(seg["state"]);
  const auto pose = typed<double>(seg["pose"]);
  const auto velocity = typed<double>(seg["velocity"]);
  const auto end = typed<double>(seg["end_s"]);
  REQUIRE(part.size() == n);
  REQUIRE(time.size() == n);
  REQUIRE(state.size() == n);
  REQUIRE(pose.size() == 7 * n);
  REQUIRE(velocity.size() == 3 * n);
  REQUIRE(end.size() == n);
  const auto& parts = r.report["parts"];
  REQUIRE(w["parts"].size() == parts.size());
  REQUIRE(w["states"] == nlohmann::json({"resting", "on_conveyor", "carried", "removed"}));
  // Each fed part's first state begins at its feeder event, on the belt at the feed pose.
  std::map<std::string, double> fed;
  for (const auto& e : r.report["events"])
    if (e["kind"] == "feeder") fed[e["subject"].get<std::string>()] = e["time_s"];
  std::size_t moving = 0, links = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t k = static_cast<std::size_t>(part[i]);
    REQUIRE(k < parts.size());
    const bool first = i == 0 || part[i - 1] != part[i];
    if (first) {
      REQUIRE((i == 0 || part[i - 1] < part[i]));  // grouped by part
      CHECK(time[i] == fed.at(parts[k]["name"].get<std::string>()));
      CHECK(state[i] == 1);
      CHECK(pose[7 * i] == 220);  // the feeder's spot, x
      continue;
    }
    REQUIRE(time[i] > time[i - 1]);
    if (velocity[3 * (i - 1)] != 0) ++moving;
    // Continuity: a resting or belt-borne part is where its previous state took it (a carried
    // one follows the flange; a release drops it onto its support).
    if (state[i - 1] != 2 && state[i] != 2) {
      const double dt = std::min(time[i], end[i - 1]) - time[i - 1];
      for (int c = 0; c < 3; ++c)
        CHECK(pose[7 * i + c] == Approx(pose[7 * (i - 1) + c] + velocity[3 * (i - 1) + c] * dt).margin(1e-9));
      ++links;
    }
    const bool last = i + 1 == n || part[i + 1] != part[i];
    if (last) CHECK(w["states"][state[i]] == parts[k]["state"]);
  }
  CHECK(moving >= 8);  // every cube rode the running belt, some twice or more
  CHECK(links > 15);
  REQUIRE(r.data["frames"].contains("carried"));
  CHECK(typed<float>(r.data["frames"]["carried"]).size() == 7 * r.data["frames"]["count"].get<std::size_t>());
  CHECK(w["events"].size() == r.report["events"].size());
  std::size_t sensors = 0;
  for (const auto& d : w["devices"]) sensors += d["kind"] == "sensor" ? 1 : 0;
  CHECK(sensors == 1);
  CHECK(r.report["signals_on"] == nlohmann::json({3, 2001}));  // output 3 and the belt it runs
}

TEST_CASE("replay page of 51 parts: one mesh per shape, two states per can, the data stays small") {
  // 50 cans fed onto a running belt and taken by a sink at its end, and a ball on the table.
  const auto dir = test::scratch_dir("replay-fifty");
  std::ofstream(dir / "cell.yaml") << R"(robot: puma560
objects:
  - {name: table, box: [400, 200, 40], at: [600, 250, -420, 0, 0, 0]}
devices:
  - {conveyor: belt, box: [800, 150, 40], at: [600, -300, -420, 0, 0, 0], direction: [1, 0, 0], speed_mm_s: 200}
  - {feeder: infeed, part: {cylinder: {radius: 15, height: 30}}, at: [220, -300, -385, 0, 0, 0], count: 50,
     prefix: can, spot: [50, 50, 50]}
  - {sink: chute, box: [60, 200, 200], at: [980, -300, -380, 0, 0, 0]}
  - {feeder: pile, part: {sphere: {radius: 20}}, at: [600, 250, -380, 0, 0, 0], count: 1, prefix: ball}
)";
  std::ofstream(dir / "fifty.v2") << ".PROGRAM fifty()\n    WAIT.EVENT , 12\n    MOVE #PPOINT(20, -30, 170, 0, 40, 0)\n"
                                     "    WAIT.EVENT , 3\n.END\n";
  const auto html = dir / "fifty.html", report = dir / "fifty.json";
  const auto cli = run_cli("run " + (dir / "fifty.v2").string() + " --cell " + (dir / "cell.yaml").string() + " --replay " +
                           html.string() + " --report " + report.string());
  INFO(cli.err);
  REQUIRE(cli.exit_code == 0);
  const nlohmann::json data = page_data(test::slurp(html)), rep = nlohmann::json::parse(test::slurp(report));
  const auto& w = data["workcell"];
  REQUIRE(w["parts"].size() == 51);
  CHECK(w["part_meshes"].size() == 2);  // the cans share one cylinder
  std::size_t removed = 0, balls = 0;
  for (std::size_t k = 0; k < 51; ++k) {  // in the report's order (fed in time order: ball1 second)
    REQUIRE(w["parts"][k]["name"] == rep["parts"][k]["name"]);
    const bool ball = w["parts"][k]["name"] == "ball1";
    balls += ball ? 1 : 0;
    CHECK(w["parts"][k]["mesh"] == (ball ? 1 : 0));
    CHECK(w["parts"][k]["feeder"] == (ball ? "pile" : "infeed"));
    removed += rep["parts"][k]["state"] == "removed" ? 1 : 0;
  }
  CHECK(balls == 1);
  CHECK(removed == 50);
  CHECK(w["segments"]["count"] == 101);  // each can: on the belt, then removed; the ball: resting
  CHECK(!data["frames"].contains("carried"));  // nothing was ever carried
  CHECK(w.dump().size() < 50000);  // about 0.7 KB per part with its events, whatever the frames
}

TEST_CASE("replay without its viewer files: exit 1 with the fix, nothing written") {
  const auto html = test::scratch_dir() / "missing.html";
  ::setenv("ASIMOV_REPLAY_DIR", (test::scratch_dir() / "no-such-dir").c_str(), 1);
  const auto r = run_cli("run " + source_path("programs/demo/crash.v2") + " --replay " + html.string());
  ::unsetenv("ASIMOV_REPLAY_DIR");
  CHECK(r.exit_code == 1);
  CHECK(r.err.find("three.module.min.js is missing") != std::string::npos);
  CHECK(r.err.find("install-deps.sh") != std::string::npos);
  CHECK(r.out.empty());  // refused before the run
  CHECK(!std::filesystem::exists(html));
}

TEST_CASE("trace and replay recordings keep their first max_samples samples and say so") {
  motion::Simulator sim(cell::default_cell());
  sim.recorders().trace.on = true;
  sim.recorders().trace.max_samples = 5;
  sim.recorders().replay.grid_s = app::kReplayGridS;
  sim.recorders().replay.max_samples = 9;
  robots::JointVector a = sim.joints();
  a[0] += 40;
  REQUIRE(sim.start_joint_move(a, motion::SpeedSettings{}, 1).status == motion::MotionStatus::ok);
  REQUIRE(sim.finish_motion().status == motion::MotionStatus::ok);
  CHECK(sim.recorders().counts.poses > 5);  // more checked poses than the trace keeps
  CHECK(sim.recorders().trace.samples.size() == 5);
  CHECK(sim.recorders().trace.truncated);
  CHECK(sim.recorders().replay.samples.size() == 9);
  CHECK(sim.recorders().replay.truncated);
  CHECK(sim.recorders().trace.samples.front().time_s == 0);  // the first ones are kept
  CHECK(motion::kMaxRecordedSamples == 250000);              // docs/limits.md
}

TEST_CASE("replay to a folder that does not exist: exit 1, cannot write") {
  const auto r = run_cli("run " + source_path("programs/demo/pick_place.v2") + " --replay " +
                         (test::scratch_dir() / "no-dir" / "x.html").string());
  CHECK(r.exit_code == 1);
  CHECK(r.err.find("*Cannot write file*") != std::string::npos);
}

TEST_CASE("replay recording: off by default, and on it leaves the run unchanged") {
  const auto run = [](bool replay, motion::Simulator& sim) {
    sim.recorders().trace.on = true;
    if (replay) sim.recorders().replay.grid_s = app::kReplayGridS;
    motion::SpeedSettings speed;
    robots::JointVector a = sim.joints(), b = sim.joints();
    a[0] += 40, a[2] -= 30, a[4] += 30, b[0] -= 30, b[2] -= 20;
    REQUIRE(sim.start_joint_move(a, speed, 1).status == motion::MotionStatus::ok);
    const motion::MotionResult line = sim.start_move(sim.dest() * motion::trans(0, 0, -150, 0, 0, 0), true, speed, 2);
    INFO(line.error.message << ' ' << line.error.detail);
    REQUIRE(line.status == motion::MotionStatus::ok);
    REQUIRE(sim.finish_motion().status == motion::MotionStatus::ok);  // the joint move (forward processing)
    REQUIRE(sim.finish_motion().status == motion::MotionStatus::ok);  // the straight line
    REQUIRE(sim.wait(0.5).status == motion::MotionStatus::ok);
    REQUIRE(sim.start_joint_move(b, speed, 3).status == motion::MotionStatus::ok);
    return sim.finish_motion().status;
  };
  motion::Simulator off(cell::default_cell()), on(cell::default_cell());
  REQUIRE(run(false, off) == motion::MotionStatus::ok);
  REQUIRE(run(true, on) == motion::MotionStatus::ok);
  CHECK(off.recorders().replay.samples.empty());
  CHECK(on.recorders().counts.poses == off.recorders().counts.poses);
  CHECK(on.time_s() == off.time_s());
  CHECK(on.recorders().accuracy.figures.ik_solves == off.recorders().accuracy.figures.ik_solves);
  CHECK(on.recorders().accuracy.figures.ik_residual.position_mm == off.recorders().accuracy.figures.ik_residual.position_mm);
  REQUIRE(on.recorders().trace.samples.size() == off.recorders().trace.samples.size());

  // Every checked pose, in order, and the grid between them: no gap in a motion wider than
  // the grid (the WAIT is the one longer gap: the arm stands still there).
  const auto& rep = on.recorders().replay.samples;
  std::size_t k = 0, wide = 0;
  for (std::size_t i = 0; i < rep.size(); ++i) {
    if (i > 0) {
      REQUIRE(rep[i].time_s > rep[i - 1].time_s);
      if (rep[i].time_s - rep[i - 1].time_s > app::kReplayGridS + 1e-12) ++wide;
    }
    if (!rep[i].checked) continue;
    REQUIRE(k < on.recorders().trace.samples.size());
    CHECK(rep[i].time_s == on.recorders().trace.samples[k].time_s);
    CHECK(rep[i].joints == on.recorders().trace.samples[k].joints);
    ++k;
  }
  CHECK(k == on.recorders().trace.samples.size());
  CHECK(wide == 1);
  CHECK(rep.back().step == 3);
  CHECK(rep.back().time_s == on.time_s());
  CHECK(rep.size() > on.recorders().trace.samples.size());

  // The straight line (step 2) is replayed on the line: its tool points, checked or on the grid,
  // lie on the segment from where the joint move ended to where the line ended.
  const auto tool_at = [&on](const robots::JointVector& q) {
    return Eigen::Vector3d((on.settings().base * robots::flange_pose(on.robot(), q) * on.settings().tool).translation());
  };
  std::optional<Eigen::Vector3d> from, to;
  std::vector<Eigen::Vector3d> line;
  for (const auto& s : rep) {
    if (s.step == 1) from = tool_at(s.joints);
    if (s.step == 2) line.push_back(tool_at(s.joints)), to = line.back();
  }
  REQUIRE(from);
  REQUIRE(line.size() > 10);
  const Eigen::Vector3d u = (*to - *from).normalized();
  CHECK((*to - *from).norm() == Approx(150).margin(1e-3));
  double worst = 0;
  for (const auto& x : line) worst = std::max(worst, ((x - *from) - (x - *from).dot(u) * u).norm());
  CHECK(worst < 0.01);
}
