// Work-precision data for docs/accuracy.md (scripts/accuracy.sh runs this, then
// scripts/accuracy_plots.py draws the plots and writes the page). Plain main(); writes
//   contact.json  contact instant / point error against run time on the analytic scenes of
//                 bench_accuracy_scenes.hpp, per stepping method, step_mm and toc_tolerance_s;
//   path.json     straight-line deviation (position, orientation) against interpolation step;
//   ik.json       closed-form PUMA residuals; numeric IK (generic6.urdf) residual against
//                 iterations and time.
// into argv[1] (default: <source>/docs/accuracy). Times are medians of repeated runs measured
// with steady_clock around the measured call only (simulator construction excluded).
#include "bench_accuracy_scenes.hpp"

#include "asimov/motion/interpolation.hpp"
#include "asimov/motion/sampler.hpp"
#include "asimov/robots/configuration.hpp"
#include "asimov/robots/displacement_bound.hpp"
#include "asimov/robots/ik.hpp"
#include "asimov/robots/ik_numeric.hpp"
#include "asimov/robots/ik_puma.hpp"
#include "asimov/robots/urdf_loader.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <thread>
#include <vector>

using namespace asimov;
using namespace asimov::accuracy;
using nlohmann::json;

namespace {
using Clock = std::chrono::steady_clock;

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : (v[n / 2 - 1] + v[n / 2]) / 2;
}

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<std::size_t>(q * static_cast<double>(v.size() - 1) + 0.5))];
}

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// ------------------------------------------------------------------------------------ contact

// "plain": no bisection (toc_tolerance_s far above any sample interval, so the report is the
// first colliding checked pose), step_mm swept; "bisection": toc_tolerance_s swept at a fixed
// step_mm; "bisection-step": step_mm swept at the default toc_tolerance_s. Each with fixed
// stepping (step_mm between checked poses) or gap stepping (collision.stepping: gap, longer
// steps while the step-2 containers of every pair are far apart).
struct Method {
  std::string name;
  std::string kind;  // plain | bisection | bisection-step
  std::vector<double> steps_mm;
  std::vector<double> tolerances_s;
  motion::Stepping stepping = motion::Stepping::fixed;
};

constexpr double kNoBisection = 1e9;  // toc_tolerance_s >= every sample interval: bisection off
constexpr int kContactReps = 15;

json contact_run(const AnalyticScene& s, const Method& m, double step_mm, double tol_s) {
  motion::CollisionSettings set = s.cell.collision;
  set.step_mm = step_mm;
  set.toc_tolerance_s = tol_s;
  set.stepping = m.stepping;
  std::vector<double> us;
  motion::CollisionReport c;
  std::uint64_t poses = 0, bisection = 0;
  for (int rep = 0; rep < kContactReps; ++rep) {
    Cell cell = s.cell;
    cell.collision = set;
    motion::Simulator sim(std::move(cell));
    const auto t0 = Clock::now();
    motion::MotionResult r = start(sim, s);
    if (r.status == motion::MotionStatus::ok) r = sim.finish_motion();
    us.push_back(seconds_since(t0) * 1e6);
    if (r.status != motion::MotionStatus::collision)
      throw std::runtime_error(s.name + ": " + m.name + ": no collision reported");
    c = r.collision;
    poses = sim.recorders().counts.poses, bisection = sim.recorders().counts.bisection;
  }
  const double err = c.time_s - s.t_star;
  // How far t* lies outside the reported bracket [time_free_s, time_s] (0 inside).
  const double outside = std::max({0.0, c.time_free_s - s.t_star, s.t_star - c.time_s});
  const bool right_pair = (c.body_a == s.static_body || c.body_b == s.static_body) &&
                          (c.body_a == s.moving_body || c.body_b == s.moving_body);
  return {{"scene", s.name},
          {"method", m.name},
          {"kind", m.kind},
          {"stepping", m.stepping == motion::Stepping::gap ? "gap" : "fixed"},
          {"step_mm", step_mm},
          {"toc_tolerance_s", tol_s},
          {"time_s", c.time_s},
          {"time_free_s", c.time_free_s},
          {"time_error_s", err},
          {"abs_time_error_s", std::abs(err)},
          {"bracket_s", c.time_s - c.time_free_s},
          {"t_star_outside_bracket_s", outside},
          {"point_error_mm", (c.point - s.point_star).norm()},
          {"bodies", c.body_a + "/" + c.body_b},
          {"expected_pair", right_pair},
          {"poses_checked", poses},
          {"bisection_checks", bisection},
          {"wall_us_median", median(us)},
          {"wall_us_all", us}};
}

json contact_section() {
  const std::vector<double> steps = {0.125, 0.25, 0.5, 1, 2, 4, 8, 16, 32};
  const std::vector<double> tols = {1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9};
  using motion::Stepping;
  const std::vector<Method> methods = {
      {"plain stepping", "plain", steps, {kNoBisection}, Stepping::fixed},
      {"bisection, step_mm 1", "bisection", {1}, tols, Stepping::fixed},
      {"bisection, step_mm 16", "bisection", {16}, tols, Stepping::fixed},
      {"bisection, toc 1e-6 s", "bisection-step", steps, {1e-6}, Stepping::fixed},
      {"gap stepping", "plain", steps, {kNoBisection}, Stepping::gap},
      {"gap + bisection, step_mm 1", "bisection", {1}, tols, Stepping::gap},
      {"gap + bisection, toc 1e-6 s", "bisection-step", steps, {1e-6}, Stepping::gap},
  };

  json scenes = json::array(), runs = json::array();
  for (const AnalyticScene& s : analytic_scenes()) {
    if (s.straight)
      for (double step : steps)
        if (!straight_line_duration_matches(s, step))
          throw std::runtime_error(s.name + ": the translation axis does not set the profile");
    scenes.push_back({{"name", s.name},
                      {"t_star_s", s.t_star},
                      {"point_star_mm", {s.point_star.x(), s.point_star.y(), s.point_star.z()}},
                      {"moving_body", s.moving_body},
                      {"static_body", s.static_body},
                      {"motion", s.straight ? "straight line" : "joint move"}});
    for (const Method& m : methods)
      for (double step : m.steps_mm)
        for (double tol : m.tolerances_s) {
          runs.push_back(contact_run(s, m, step, tol));
          const json& r = runs.back();
          std::printf("%-15s %-22s step %6.3f mm tol %7.1e s: |dt| %9.3e s  |dp| %9.3e mm  %9.1f us\n",
                      s.name.c_str(), m.name.c_str(), step, tol, r["abs_time_error_s"].get<double>(),
                      r["point_error_mm"].get<double>(), r["wall_us_median"].get<double>());
        }
  }
  return {{"scenes", scenes}, {"runs", runs}, {"reps", kContactReps}};
}

// ------------------------------------------------------------------------------- path deviation

struct Line {
  std::string name;
  JointVector start;
  Location target;  // world = robot frame (identity base and tool)
};

// Largest deviation between the joint-interpolated path and the exact line (same sigma), over
// `probes` interior points of every interval of `samples`.
void deviation(const robots::Robot& r, const motion::LinePath& path, const std::vector<motion::LineSample>& samples,
               double& pos_mm, double& rot_deg) {
  pos_mm = rot_deg = 0;
  constexpr int kProbes = 4;
  for (std::size_t i = 1; i < samples.size(); ++i) {
    const auto &a = samples[i - 1], &b = samples[i];
    for (int k = 1; k < kProbes; ++k) {
      const double f = static_cast<double>(k) / kProbes;
      const Location exact = motion::line_pose(path, a.s + f * (b.s - a.s));
      const Location got = robots::flange_pose(r, motion::interpolate_joints(a.joints, b.joints, f));
      pos_mm = std::max(pos_mm, (got.translation() - exact.translation()).norm());
      rot_deg = std::max(rot_deg, Eigen::AngleAxisd(exact.linear().transpose() * got.linear()).angle() * 180 / std::numbers::pi);
    }
  }
}

double max_spacing_mm(const motion::LinePath& path, const std::vector<motion::LineSample>& samples) {
  double m = 0;
  for (std::size_t i = 1; i < samples.size(); ++i) m = std::max(m, (samples[i].s - samples[i - 1].s) * path.length);
  return m;
}

json path_section() {
  const robots::Robot r = robots::puma560();
  std::vector<robots::BodyReach> reach;
  for (const auto& b : r.bodies) reach.push_back(robots::body_reach(r, b.mesh, b.link));
  const JointVector q0 = joints({10, -60, 170, 10, 30, 20});
  const Location f0 = robots::flange_pose(r, q0);
  const std::vector<Line> lines = {
      {"translation 300 mm", q0, motion::trans(-100, 250, 120, 0, 0, 0) * f0},
      {"200 mm and 45 deg", q0, [&] {
         Location t = motion::trans(120, -100, 120, 0, 0, 0) * f0;
         t.linear() = rot(45, Vec3(1, 1, 0)) * t.linear();
         return t;
       }()},
  };
  json series = json::array();
  for (const Line& line : lines) {
    const motion::LinePath path = motion::make_line(f0, line.target);
    const robots::Configuration config = robots::configuration_of(r, line.start);
    // Uniform interpolation step h along the line: IK at sigma = i / n, joints linear between.
    json uniform = json::array();
    for (double h : {0.25, 0.5, 1.0, 2.0, 4.0, 8.0, 16.0, 32.0, 64.0}) {
      const int n = std::max(1, static_cast<int>(std::ceil(path.length / h)));
      std::vector<motion::LineSample> samples{{0, line.start}};
      const auto t0 = Clock::now();
      for (int i = 1; i <= n; ++i) {
        const double s = static_cast<double>(i) / n;
        const robots::IkResult ik = robots::solve_ik(r, motion::line_pose(path, s), samples.back().joints, config, false);
        if (ik.status != robots::IkStatus::ok) throw std::runtime_error(line.name + ": IK failed on the line");
        samples.push_back({s, ik.joints});
      }
      const double us = seconds_since(t0) * 1e6;
      double pos, rotd;
      deviation(r, path, samples, pos, rotd);
      uniform.push_back({{"h_mm", path.length / n}, {"samples", n + 1}, {"position_mm", pos}, {"orientation_deg", rotd},
                         {"solve_us", us}});
      std::printf("path %-20s uniform h %7.3f mm: %9.3e mm %9.3e deg\n", line.name.c_str(), path.length / n, pos, rotd);
    }
    // The simulator's own samples (plan_line: 1 mm / 0.5 deg validation, refined to 0.9 step_mm).
    json planned = json::array();
    for (double step : {0.125, 0.25, 0.5, 1.0, 2.0, 4.0}) {
      motion::LineRequest req;
      req.path = path;
      req.start = line.start;
      req.config = config;
      req.step_mm = step;
      motion::LinePlan plan;
      const auto t0 = Clock::now();
      if (motion::plan_line(r, reach, req, plan) != motion::LineStatus::ok)
        throw std::runtime_error(line.name + ": plan_line failed");
      const double us = seconds_since(t0) * 1e6;
      double pos, rotd;
      deviation(r, path, plan.samples, pos, rotd);
      planned.push_back({{"step_mm", step}, {"h_mm", max_spacing_mm(path, plan.samples)}, {"samples", plan.samples.size()},
                         {"position_mm", pos}, {"orientation_deg", rotd}, {"solve_us", us}});
      std::printf("path %-20s plan_line step %5.3f mm: h %7.3f mm %9.3e mm %9.3e deg\n", line.name.c_str(), step,
                  max_spacing_mm(path, plan.samples), pos, rotd);
    }
    series.push_back({{"line", line.name}, {"length_mm", path.length}, {"angle_deg", path.angle_deg()},
                      {"uniform", uniform}, {"planned", planned}});
  }
  return {{"robot", r.name}, {"lines", series}};
}

// ------------------------------------------------------------------------------------------ IK

json histogram_log10(const std::vector<double>& v, double lo, double hi, double width) {
  const int bins = static_cast<int>(std::round((hi - lo) / width));
  std::vector<int> counts(static_cast<std::size_t>(bins), 0);
  int zeros = 0;
  for (double x : v) {
    if (x <= 0) {
      ++zeros;
      continue;
    }
    const int b = std::clamp(static_cast<int>(std::floor((std::log10(x) - lo) / width)), 0, bins - 1);
    ++counts[static_cast<std::size_t>(b)];
  }
  return {{"log10_lo", lo}, {"width", width}, {"counts", counts}, {"exact_zero", zeros}};
}

json stats(const std::vector<double>& v) {
  return {{"median", quantile(v, 0.5)}, {"p90", quantile(v, 0.9)}, {"p99", quantile(v, 0.99)},
          {"max", v.empty() ? 0 : *std::max_element(v.begin(), v.end())}};
}

json ik_section() {
  json out;
  {  // PUMA closed form, as the simulator calls it (truth configuration, READY as `current`).
    const robots::Robot r = robots::puma560();
    constexpr int kPoses = 100000;
    std::mt19937 rng(20261128);
    std::uniform_real_distribution<double> u(0, 1);
    const JointVector ready = robots::ready_joints(r);
    std::vector<double> pos, rotr, us;
    int failed = 0;
    for (int k = 0; k < kPoses; ++k) {
      JointVector q(6);
      for (int i = 0; i < 6; ++i) q[i] = r.lower[i] + u(rng) * (r.upper[i] - r.lower[i]);
      const collision::Pose t = robots::flange_pose(r, q);
      const robots::Configuration want = robots::configuration_of(r, q);
      const auto t0 = Clock::now();
      const robots::IkResult ik = robots::solve_puma(r, t, ready, want, false);
      us.push_back(seconds_since(t0) * 1e6);
      if (ik.status != robots::IkStatus::ok) {
        ++failed;
        continue;
      }
      double p, a;
      robots::pose_error(r, ik.joints, t, p, a);
      pos.push_back(p), rotr.push_back(a);
    }
    std::printf("IK puma closed form: %d poses, %d not solved, position median %.2e max %.2e mm, rotation median %.2e max %.2e rad, %.2f us\n",
                kPoses, failed, quantile(pos, 0.5), stats(pos)["max"].get<double>(), quantile(rotr, 0.5),
                stats(rotr)["max"].get<double>(), median(us));
    out["puma_closed_form"] = {{"poses", kPoses},
                               {"not_solved", failed},
                               {"position_mm", stats(pos)},
                               {"rotation_rad", stats(rotr)},
                               {"position_hist", histogram_log10(pos, -17, -5, 0.25)},
                               {"rotation_hist", histogram_log10(rotr, -17, -5, 0.25)},
                               {"solve_us_median", median(us)}};
  }
  {  // Numeric LM on generic6.urdf: one descent of at most k iterations, tolerances 0.
    const robots::Robot r = robots::load_urdf(std::string(ASIMOV_SOURCE_DIR) + "/robots/data/generic6.urdf").value();
    constexpr int kPoses = 4000;
    std::mt19937 rng(424242);
    std::uniform_real_distribution<double> u(0, 1), near(-0.1, 0.1);
    std::vector<collision::Pose> targets;
    std::vector<JointVector> seeds_near;
    for (int k = 0; k < kPoses; ++k) {
      JointVector q(6);
      for (int i = 0; i < 6; ++i) q[i] = r.lower[i] + u(rng) * (r.upper[i] - r.lower[i]);
      targets.push_back(robots::flange_pose(r, q));
      JointVector dh = robots::display_to_dh(r, q);
      for (int i = 0; i < 6; ++i) dh[i] += near(rng);
      seeds_near.push_back(robots::dh_to_display(r, dh));
    }
    const JointVector ready = robots::ready_joints(r);
    json series = json::array();
    for (const std::string seed_name : {"seed near the truth (+-0.1 rad)", "seed READY"}) {
      json points = json::array();
      for (int iters : {1, 2, 3, 4, 5, 6, 8, 10, 13, 16, 20, 30, 45, 60}) {
        robots::NumericIkOptions o;
        o.position_tol_mm = 0;
        o.rotation_tol_rad = 0;
        o.max_iterations = iters;
        o.max_attempts = 1;
        std::vector<double> pos, rotr, us;
        int reached = 0;
        for (int k = 0; k < kPoses; ++k) {
          const JointVector& seed = seed_name == "seed READY" ? ready : seeds_near[static_cast<std::size_t>(k)];
          const auto t0 = Clock::now();
          const robots::NumericIkResult res = robots::solve_numeric(r, targets[static_cast<std::size_t>(k)], seed, o);
          us.push_back(seconds_since(t0) * 1e6);
          pos.push_back(res.position_error_mm), rotr.push_back(res.rotation_error_rad);
          reached += res.position_error_mm <= 1e-6 && res.rotation_error_rad <= 1e-9;
        }
        points.push_back({{"max_iterations", iters}, {"position_mm", stats(pos)}, {"rotation_rad", stats(rotr)},
                          {"solve_us_median", median(us)}, {"within_1e-6mm_1e-9rad", static_cast<double>(reached) / kPoses}});
        std::printf("IK numeric %-32s %2d it: position median %9.2e mm, p90 %9.2e, %6.2f us, %.3f within tol\n",
                    seed_name.c_str(), iters, quantile(pos, 0.5), quantile(pos, 0.9), median(us),
                    static_cast<double>(reached) / kPoses);
      }
      series.push_back({{"seed", seed_name}, {"points", points}});
    }
    // The simulator's setting (defaults: 1e-6 mm / 1e-9 rad, 60 iterations, restarts) for reference.
    std::vector<double> pos, us;
    int ok = 0;
    for (int k = 0; k < kPoses; ++k) {
      const auto t0 = Clock::now();
      const robots::NumericIkResult res = robots::solve_numeric(r, targets[static_cast<std::size_t>(k)], ready);
      us.push_back(seconds_since(t0) * 1e6);
      pos.push_back(res.position_error_mm);
      ok += res.success;
    }
    out["numeric_generic6"] = {{"poses", kPoses},
                               {"series", series},
                               {"defaults_from_ready", {{"position_mm", stats(pos)}, {"solve_us_median", median(us)},
                                                        {"success", static_cast<double>(ok) / kPoses}}}};
  }
  return out;
}

void write(const std::filesystem::path& file, json j) {
  std::ofstream f(file);
  if (!f) throw std::runtime_error("cannot write " + file.string());
  f << j.dump(1) << '\n';
  std::printf("wrote %s\n", file.c_str());
}

json machine() {
  const std::time_t now = std::time(nullptr);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
  return {{"generated_utc", buf}, {"hardware_threads", std::thread::hardware_concurrency()}};
}
}  // namespace

int main(int argc, char** argv) {
  const std::filesystem::path dir = argc > 1 ? argv[1] : std::string(ASIMOV_SOURCE_DIR) + "/docs/accuracy";
  const std::string only = argc > 2 ? argv[2] : "";
  try {
    std::filesystem::create_directories(dir);
    const auto t0 = Clock::now();
    if (only.empty() || only == "contact") {
      json j = contact_section();
      j["machine"] = machine();
      write(dir / "contact.json", j);
    }
    if (only.empty() || only == "path") {
      json j = path_section();
      j["machine"] = machine();
      write(dir / "path.json", j);
    }
    if (only.empty() || only == "ik") {
      json j = ik_section();
      j["machine"] = machine();
      write(dir / "ik.json", j);
    }
    std::printf("bench_accuracy: %.1f s\n", seconds_since(t0));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_accuracy: %s\n", e.what());
    return 1;
  }
  return 0;
}
