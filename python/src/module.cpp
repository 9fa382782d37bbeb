// The `asimov` Python module (pybind11): cells, programs and their reports, monitor sessions,
// traces as NumPy arrays, FK/IK of any arm and the collision engine (docs/python.md). Problems
// become the exceptions of asimov/errors.py carrying the VAL message, file, line and column.
// The GIL is released while programs run, monitor commands execute and engine batches check.
#include "app/report.hpp"
#include "asimov/cell/cell_loader.hpp"
#include "asimov/collision/engine.hpp"
#include "asimov/collision/mesh_io.hpp"
#include "asimov/interpreter/interpreter.hpp"
#include "asimov/interpreter/monitor.hpp"
#include "asimov/motion/location.hpp"
#include "app/atomic_file.hpp"
#include "app/replay.hpp"
#include "asimov/robots/builtin.hpp"
#include "asimov/robots/ik.hpp"
#include "asimov/robots/puma560.hpp"
#include "asimov/robots/urdf_loader.hpp"
#include "asimov/version.hpp"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <filesystem>
#include <memory>
#include <optional>
#include <map>
#include <sstream>

namespace py = pybind11;
using namespace asimov;
using collision::Pose;

namespace {

// ---- exceptions (asimov/errors.py) ---------------------------------------------------------

[[noreturn]] void raise(const char* cls, py::dict fields) {
  py::object type = py::module_::import("asimov.errors").attr(cls);
  py::object instance = type(**fields);
  PyErr_SetObject(type.ptr(), instance.ptr());
  throw py::error_already_set();
}

py::dict diagnostic_dict(const interpreter::Diagnostic& d) {
  py::dict f;
  f["message"] = d.message;
  f["detail"] = d.detail;
  f["file"] = d.file;
  f["line"] = d.line;
  f["column"] = d.column;
  f["program"] = d.program;
  f["step"] = d.step;
  f["text"] = interpreter::format_diagnostic(d);
  return f;
}

[[noreturn]] void raise_cell_error(const Error& e) {
  py::dict f;
  f["message"] = "*Cell error*";
  f["detail"] = e.message;
  f["file"] = e.file;
  f["line"] = e.line;
  f["column"] = e.column;
  f["text"] = cell::format_cell_error(e);
  raise("CellError", f);
}

[[noreturn]] void raise_message(const char* cls, const std::string& message, const std::string& detail,
                                const std::string& file = {}, int line = 0) {
  py::dict f;
  f["message"] = message;
  f["detail"] = detail;
  f["file"] = file;
  f["line"] = line;
  raise(cls, f);
}

// One Session or Engine is used by one thread at a time (their C++ objects are not shared
// safely, and the GIL is released while they work): a second thread entering while the first is
// inside gets asimov.BusyError instead of a crash.
class InUse {
 public:
  InUse(std::atomic<bool>& flag, const char* what) : flag_(flag) {
    if (flag_.exchange(true)) {
      py::dict f;
      f["message"] = "*Busy*";
      f["detail"] = std::string(what) + " is in use by another thread (use one per thread, or a lock)";
      raise("BusyError", f);
    }
  }
  ~InUse() { flag_.store(false); }
  InUse(const InUse&) = delete;
  InUse& operator=(const InUse&) = delete;

 private:
  std::atomic<bool>& flag_;
};

// ---- conversions -----------------------------------------------------------------------

py::object to_python(const nlohmann::json& j) {
  switch (j.type()) {
    case nlohmann::json::value_t::null: return py::none();
    case nlohmann::json::value_t::boolean: return py::bool_(j.get<bool>());
    case nlohmann::json::value_t::number_integer: return py::int_(j.get<std::int64_t>());
    case nlohmann::json::value_t::number_unsigned: return py::int_(j.get<std::uint64_t>());
    case nlohmann::json::value_t::number_float: return py::float_(j.get<double>());
    case nlohmann::json::value_t::string: return py::str(j.get_ref<const std::string&>());
    case nlohmann::json::value_t::array: {
      py::list out;
      for (const auto& e : j) out.append(to_python(e));
      return out;
    }
    case nlohmann::json::value_t::object: {
      py::dict out;
      for (const auto& [k, v] : j.items()) out[py::str(k)] = to_python(v);
      return out;
    }
    default: return py::none();
  }
}

using Array = py::array_t<double, py::array::c_style | py::array::forcecast>;

std::string fmt_number(double v) {
  std::ostringstream o;
  o << v;
  return o.str();
}

py::array_t<double> pose_array(const Pose& p) {
  py::array_t<double> out({4, 4});
  auto m = out.mutable_unchecked<2>();
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) m(r, c) = p.matrix()(r, c);
  return out;
}

Pose pose_from(const double* m) {  // row-major 4x4
  Pose p = Pose::Identity();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) p.matrix()(r, c) = m[r * 4 + c];
  return p;
}

Pose to_pose(const Array& a) {
  if (a.ndim() != 2 || a.shape(0) != 4 || a.shape(1) != 4)
    throw py::value_error("a pose is a 4x4 homogeneous matrix (mm)");
  return pose_from(a.data());
}

py::array_t<double> joints_array(const robots::JointVector& q) {
  py::array_t<double> out(q.size());
  std::copy(q.data(), q.data() + q.size(), out.mutable_data());
  return out;
}

robots::JointVector to_joints(const robots::Robot& robot, const Array& a) {
  if (a.ndim() != 1 || a.shape(0) != robot.joint_count())
    throw py::value_error("expected " + std::to_string(robot.joint_count()) + " joint values (display: deg, mm)");
  robots::JointVector q(robot.joint_count());
  std::copy(a.data(), a.data() + a.shape(0), q.data());
  return q;
}

// ---- cells and robots --------------------------------------------------------------------

motion::Cell load_cell_any(const py::object& source, const std::string& base_dir) {
  if (source.is_none()) return cell::default_cell();
  if (py::isinstance<motion::Cell>(source)) return source.cast<motion::Cell>();
  auto checked = [](Result<motion::Cell> cell) {
    if (!cell) raise_cell_error(cell.error());
    return std::move(cell).value();
  };
  if (py::isinstance<py::dict>(source)) {
    // JSON is YAML: the dict goes through the same loader as a file.
    const std::string text = py::module_::import("json").attr("dumps")(source, py::arg("indent") = 1).cast<std::string>();
    return checked(cell::load_cell_text(text, "<dict>", base_dir.empty() ? std::string(".") : base_dir));
  }
  const std::string path = py::str(py::module_::import("os").attr("fspath")(source));
  if (!std::filesystem::is_regular_file(path)) raise_message("CellError", "*File not found*", path, path);
  return checked(cell::load_cell_file(path));
}

// config={...}: V+'s words as keys (righty / lefty, above / below, noflip / flip), each True or
// False; the words not given keep those of `q`. Unknown keys, non-bool values and a word given
// both ways inconsistently are refused.
robots::Configuration to_configuration(const py::object& o, const robots::Robot& robot, const robots::JointVector& q) {
  robots::Configuration c = robots::configuration_of(robot, q);
  if (o.is_none()) return c;
  if (!py::isinstance<py::dict>(o)) throw py::type_error("config: a dict of V+ configuration words, e.g. {'lefty': True}");
  struct Word {
    const char* name;
    bool robots::Configuration::*field;
    bool positive;
  };
  static const Word kWords[] = {{"righty", &robots::Configuration::righty, true}, {"lefty", &robots::Configuration::righty, false},
                                {"above", &robots::Configuration::above, true},   {"below", &robots::Configuration::above, false},
                                {"noflip", &robots::Configuration::noflip, true}, {"flip", &robots::Configuration::noflip, false}};
  std::vector<std::pair<bool robots::Configuration::*, std::pair<std::string, bool>>> set;
  for (const auto& [key, value] : o.cast<py::dict>()) {
    const std::string k = py::str(key);
    std::string lower = k;
    std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char ch) { return std::tolower(ch); });
    const Word* w = nullptr;
    for (const Word& x : kWords)
      if (lower == x.name) w = &x;
    if (!w) throw py::value_error("config: unknown word '" + k + "' (righty, lefty, above, below, noflip, flip)");
    if (!py::isinstance<py::bool_>(value))
      throw py::type_error("config['" + k + "']: True or False, not " + std::string(py::str(py::type::of(value).attr("__name__"))));
    const bool v = value.cast<bool>() == w->positive;
    for (const auto& [field, given] : set)
      if (field == w->field && given.second != v)
        throw py::value_error("config: '" + given.first + "' and '" + k + "' contradict each other");
    set.push_back({w->field, {k, v}});
    c.*(w->field) = v;
  }
  return c;
}

py::dict configuration_dict(const robots::Configuration& c) {
  py::dict d;
  d["righty"] = c.righty;
  d["above"] = c.above;
  d["noflip"] = c.noflip;
  return d;
}

py::array_t<double> robot_ik(const robots::Robot& robot, const Array& flange, const std::optional<Array>& current,
                             const py::object& config, bool single) {
  const Pose target = to_pose(flange);
  const robots::JointVector from = current ? to_joints(robot, *current) : robots::ready_joints(robot);
  const robots::Configuration want = to_configuration(config, robot, from);
  robots::IkResult r;
  {
    py::gil_scoped_release release;
    r = robots::solve_ik(robot, target, from, want, single);
  }
  if (r.status == robots::IkStatus::out_of_reach)
    raise_message("KinematicsError", "*Location out of reach*", robot.name);
  if (r.status == robots::IkStatus::joint_limit) {
    py::dict f;
    f["message"] = "*Joint limit exceeded*";
    f["detail"] = "J" + std::to_string(r.joint + 1) + " = " + std::to_string(r.value);
    f["joint"] = r.joint;
    f["value"] = r.value;
    raise("KinematicsError", f);
  }
  return joints_array(r.joints);
}

// Every IK solution of the pose (display joints, each with its configuration), in the nearest
// 2pi-equivalent to `current` within limits: the 8 closed-form candidates of PUMA-, Viper- and
// spherical-wrist arms, one per configuration that solve_ik reaches otherwise.
py::list robot_ik_all(const robots::Robot& robot, const Array& flange, const std::optional<Array>& current) {
  const Pose target = to_pose(flange);
  const robots::JointVector from = current ? to_joints(robot, *current) : robots::ready_joints(robot);
  std::vector<robots::JointVector> found;
  {
    py::gil_scoped_release release;
    for (int k = 0; k < 8; ++k) {
      robots::Configuration want;
      want.righty = (k & 4) == 0, want.above = (k & 2) == 0, want.noflip = (k & 1) == 0;
      const robots::IkResult r = robots::solve_ik(robot, target, from, want, false);
      if (r.status != robots::IkStatus::ok) continue;
      const bool seen = std::any_of(found.begin(), found.end(), [&](const robots::JointVector& q) {
        return (q - r.joints).cwiseAbs().maxCoeff() < 1e-6;
      });
      if (!seen) found.push_back(r.joints);
    }
  }
  py::list out;
  for (const auto& q : found) out.append(joints_array(q));
  return out;
}

// The geometric Jacobian at display joints: (6, n), rows vx, vy, vz [mm per unit of the joint],
// wx, wy, wz [rad per unit], in the robot base frame; a revolute joint's unit is one degree, a
// prismatic joint's one millimetre (the display units), so J @ dq is the flange's twist for a
// display step dq.
py::array_t<double> robot_jacobian(const robots::Robot& robot, const Array& joints) {
  const robots::JointVector q = to_joints(robot, joints);
  const robots::JointVector internal = robots::display_to_dh(robot, q);
  const int n = robot.joint_count();
  std::vector<robots::JointScrews> screws(static_cast<std::size_t>(n));
  Pose f = Pose::Identity();
  for (int k = 0; k < n; ++k) f = robots::joint_screws(robot, k, internal[k], f, screws[static_cast<std::size_t>(k)]);
  py::array_t<double> out({py::ssize_t{6}, py::ssize_t{n}});
  auto m = out.mutable_unchecked<2>();
  for (int k = 0; k < n; ++k) {
    // Display to internal: d(internal)/d(display) = sign * pi/180 (revolute) or 1 (prismatic).
    const double scale = robot.prismatic(k) ? 1.0 : (robot.mapping.empty() ? 1.0 : robot.mapping[static_cast<std::size_t>(k)].sign) * M_PI / 180;
    collision::Vec3 v = collision::Vec3::Zero(), w = collision::Vec3::Zero();
    const robots::JointScrews& s = screws[static_cast<std::size_t>(k)];
    for (int i = 0; i < s.count; ++i) {  // its own axis and those of its coupled joints
      const robots::JointScrew& x = s.screw[static_cast<std::size_t>(i)];
      if (x.type == robots::JointType::prismatic) v += x.rate * x.axis;
      else v += x.rate * x.axis.cross(f.translation() - x.point), w += x.rate * x.axis;
    }
    for (int r = 0; r < 3; ++r) m(r, k) = v[r] * scale, m(r + 3, k) = w[r] * scale;
  }
  return out;
}

// ---- sessions: programs, reports, monitor ----------------------------------------------

// One simulated cell with its interpreter and monitor; everything printed goes to `out`.
class Session {
 public:
  Session(motion::Cell cell, bool trace, bool replay)
      : sim_(std::move(cell)), interp_(sim_, out_), monitor_(interp_, sim_, out_) {
    sim_.recorders().trace.on = trace;
    if (replay) sim_.recorders().replay.grid_s = app::kReplayGridS;
    interp_.set_input(no_input_, false);  // PROMPT has nobody to ask: *Illegal value*
  }

  std::vector<std::string> load(const std::string& path) {
    const InUse busy(busy_, "this Session");
    if (!std::filesystem::is_regular_file(path)) raise_message("LoadError", "*File not found*", path, path);
    return check_loaded(timed_load([&] { return interp_.load_file(path); }), path);
  }
  std::vector<std::string> load_source(const std::string& text, const std::string& name) {
    const InUse busy(busy_, "this Session");
    return check_loaded(timed_load([&] { return interp_.load_source(text, name); }), name);
  }
  std::vector<std::string> programs() const { return interp_.program_names(); }

  py::object run(const std::optional<std::string>& name) {
    const InUse busy(busy_, "this Session");
    std::string main = name.value_or("");
    if (main.empty()) {
      const auto names = interp_.program_names();
      if (names.empty()) raise_message("ProgramError", "*Undefined program or variable name*", "no program loaded");
      main = names.front();
    }
    std::transform(main.begin(), main.end(), main.begin(), [](unsigned char c) { return std::tolower(c); });
    if (!interp_.has_program(main)) raise_message("ProgramError", "*Undefined program or variable name*", main);
    const auto start = std::chrono::steady_clock::now();
    interpreter::RunResult result;
    {
      py::gil_scoped_release release;
      result = interp_.run(main);
    }
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    monitor_.record_run(result, main);  // STATUS tells this run, as after an EXECUTE
    const bool failed = result.status == interpreter::RunStatus::error;
    const interpreter::Diagnostic error = result.error;
    py::object report = report_of(result, wall);
    if (failed) {
      py::dict f = diagnostic_dict(error);
      f["report"] = report;
      raise("ProgramError", f);
    }
    return report;
  }

  // One monitor line (DO, HERE, WHERE, POINT, EXECUTE, ...): what it printed.
  std::string execute(const std::string& line, bool check) {
    const InUse busy(busy_, "this Session");
    const auto mark = out_.tellp();
    const std::uint64_t runs = monitor_.run_count();
    interpreter::CommandStatus status;
    const auto start = std::chrono::steady_clock::now();
    {
      py::gil_scoped_release release;
      status = monitor_.execute(line);
    }
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const std::string all = out_.str();
    std::string printed = all.substr(static_cast<std::size_t>(mark) <= all.size() ? static_cast<std::size_t>(mark) : 0);
    if (check && status == interpreter::CommandStatus::failed) {
      const auto first = printed.substr(0, printed.find('\n'));
      py::dict f;
      f["message"] = first;
      const auto& run = monitor_.last_run();
      if (monitor_.run_count() != runs && run && run->status != interpreter::RunStatus::completed) {
        // A program the command ran stopped (a collision, an error, Ctrl-C): its kind, where,
        // and the run's report, as Session.run gives them.
        f = diagnostic_dict(run->error);
        f["kind"] = run->status == interpreter::RunStatus::collision ? "collision"
                    : run->status == interpreter::RunStatus::interrupted ? "interrupted" : "error";
        f["report"] = report_of(*run, wall);
      } else {
        f["kind"] = "command";
      }
      f["text"] = printed;
      f["output"] = printed;
      raise("CommandError", f);
    }
    if (status == interpreter::CommandStatus::quit) quit_ = true;
    return printed;
  }

  // Everything printed since the last call (TYPE output, monitor replies).
  std::string output() {
    std::string s = out_.str().substr(taken_);
    taken_ = out_.str().size();
    return s;
  }

  py::dict trace() const {
    if (!sim_.recorders().trace.on) {
      py::dict f;
      f["message"] = "*No trace*";
      f["detail"] = "this Session records no trace: create it with Session(..., trace=True) (asimov.run(..., trace=True))";
      raise("ProgramError", f);
    }
    const auto& samples = sim_.recorders().trace.samples;
    const auto n = static_cast<py::ssize_t>(samples.size());
    const py::ssize_t j = sim_.robot().joint_count();
    py::array_t<double> t(n), joints({n, j}), tool({n, py::ssize_t{4}, py::ssize_t{4}}), xyzoat({n, py::ssize_t{6}});
    auto tt = t.mutable_unchecked<1>();
    auto jj = joints.mutable_unchecked<2>();
    auto pp = tool.mutable_unchecked<3>();
    auto xx = xyzoat.mutable_unchecked<2>();
    for (py::ssize_t i = 0; i < n; ++i) {
      const auto& s = samples[static_cast<std::size_t>(i)];
      tt(i) = s.time_s;
      for (py::ssize_t k = 0; k < j; ++k) jj(i, k) = s.joints[k];
      for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) pp(i, r, c) = s.tool.matrix()(r, c);
      const auto x = motion::decompose(s.tool);
      for (int k = 0; k < 6; ++k) xx(i, k) = x[static_cast<std::size_t>(k)];
    }
    py::dict d;
    d["time_s"] = t;
    d["joints"] = joints;
    d["tool"] = tool;
    d["xyzoat"] = xyzoat;
    return d;
  }

  // The replay page of the last run (Session(replay=True)), as `asimov run --replay` writes it.
  void write_replay(const std::string& path) {
    const InUse busy(busy_, "this Session");
    if (!(sim_.recorders().replay.grid_s > 0)) {
      py::dict f;
      f["message"] = "*No replay*";
      f["detail"] = "this Session records no replay: create it with Session(..., replay=True)";
      raise("ProgramError", f);
    }
    const auto& run = monitor_.last_run();
    if (!run) raise_message("ProgramError", "*No replay*", "nothing has run yet in this Session");
    Result<app::ReplayAssets> assets = app::load_replay_assets();
    if (!assets) raise_message("ProgramError", "*Cannot write file*", assets.error().message, path);
    const std::string html = app::replay_html(*assets, app::replay_data(file_, sim_, *run));
    if (const auto written = app::write_file_atomically(path, html); !written)
      raise_message("ProgramError", "*Cannot write file*", written.error().message, path);
  }

  motion::Simulator& sim() { return sim_; }
  bool quit() const { return quit_; }
  std::atomic<bool>& busy() { return busy_; }
  const std::string& file() const { return file_; }
  std::string status_word() const {
    const auto& run = monitor_.last_run();
    if (!run) return "idle";
    switch (run->status) {
      case interpreter::RunStatus::completed: return "completed";
      case interpreter::RunStatus::collision: return "collision";
      case interpreter::RunStatus::paused: return "paused";
      case interpreter::RunStatus::halted: return "halted";
      case interpreter::RunStatus::interrupted: return "interrupted";
      case interpreter::RunStatus::error: return "error";
    }
    return "idle";
  }

 private:
  py::object report_of(const interpreter::RunResult& result, double wall) {
    app::RunSummary summary = app::summarize_run(file_, result, sim_, wall);
    if (const auto* cell = interp_.cell_state()) summary.workcell = app::workcell_json(*cell);
    return to_python(app::run_report(summary));
  }
  template <class F>
  std::vector<interpreter::Diagnostic> timed_load(F load) {
    const auto t0 = std::chrono::steady_clock::now();
    auto diags = load();
    sim_.recorders().timing.timing.parse_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return diags;
  }
  std::vector<std::string> check_loaded(const std::vector<interpreter::Diagnostic>& diags, const std::string& file) {
    py::list all;
    const interpreter::Diagnostic* first = nullptr;
    for (const auto& d : diags) {
      all.append(diagnostic_dict(d));
      if (!d.warning && !first) first = &d;
    }
    if (first) {
      py::dict f = diagnostic_dict(*first);
      f["diagnostics"] = all;
      raise("LoadError", f);
    }
    file_ = file;
    return interp_.program_names();
  }

  std::ostringstream out_;
  std::istringstream no_input_;
  motion::Simulator sim_;
  interpreter::Interpreter interp_;
  interpreter::Monitor monitor_;
  std::string file_;
  std::size_t taken_ = 0;
  bool quit_ = false;
  std::atomic<bool> busy_{false};
};

// ---- the collision engine ----------------------------------------------------------------

class PyEngine {
 public:
  // A failed add leaves the engine as it was: the name is taken only once the body is in.
  collision::BodyId add(const std::string& name, collision::Polyhedron mesh, int group, bool is_static, int halvings) {
    const InUse busy(busy_, "this Engine");
    if (std::find(names_.begin(), names_.end(), name) != names_.end())
      throw py::value_error("a body named '" + name + "' is already in the engine (names must be unique)");
    const collision::BodyId id =
        engine_.add_body({.name = name, .mesh = std::move(mesh), .group = group, .is_static = is_static, .halvings = halvings});
    names_.push_back(name);
    return id;
  }
  // Sizes as the cell files take them (docs/limits.md): finite and > 0, at most 4096 segments.
  static double size_value(const char* what, double v) {
    if (!(std::isfinite(v) && v > 0)) throw py::value_error(std::string(what) + " must be a finite number > 0 [mm], not " + std::to_string(v));
    return v;
  }
  collision::BodyId add_box(const std::string& name, const std::array<double, 3>& size, int group, bool st, int h) {
    for (double v : size) size_value("box size", v);
    return add(name, collision::make_box(collision::Vec3(size[0], size[1], size[2])), group, st, h);
  }
  collision::BodyId add_cylinder(const std::string& name, double radius, double height, long long segments, int group, bool st, int h) {
    size_value("radius", radius);
    size_value("height", height);
    if (segments < 3 || segments > kMaxSegments)
      throw py::value_error("segments: 3 to " + std::to_string(kMaxSegments) + " (as cell files), not " + std::to_string(segments));
    return add(name, collision::make_cylinder(radius, height, static_cast<int>(segments)), group, st, h);
  }
  static constexpr long long kMaxSegments = 4096;
  collision::BodyId add_arrays(const std::string& name, const Array& vertices,
                               const py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>& triangles,
                               int group, bool is_static, int halvings) {
    if (vertices.ndim() != 2 || vertices.shape(1) != 3) throw py::value_error("vertices: an (n, 3) array [mm]");
    if (triangles.ndim() != 2 || triangles.shape(1) != 3) throw py::value_error("triangles: an (m, 3) array of vertex indices");
    collision::Polyhedron mesh;
    const auto v = vertices.unchecked<2>();
    for (py::ssize_t i = 0; i < v.shape(0); ++i) mesh.vertices.emplace_back(v(i, 0), v(i, 1), v(i, 2));
    const auto t = triangles.unchecked<2>();
    for (py::ssize_t i = 0; i < t.shape(0); ++i) {
      collision::Triangle tri;
      for (int k = 0; k < 3; ++k) {
        if (t(i, k) < 0 || t(i, k) >= v.shape(0))
          throw py::value_error("triangle " + std::to_string(i) + ": vertex index " + std::to_string(t(i, k)) + " out of range");
        tri[static_cast<std::size_t>(k)] = static_cast<std::uint32_t>(t(i, k));
      }
      mesh.triangles.push_back(tri);
    }
    auto checked = collision::validate_mesh(std::move(mesh), "body '" + name + "'");
    if (!checked) raise_message("RobotError", "*Mesh error*", checked.error().message);
    warn(checked->warnings);
    return add(name, std::move(checked->mesh), group, is_static, halvings);
  }
  collision::BodyId add_mesh(const std::string& path, const std::optional<std::string>& name, double scale, int group,
                             bool is_static, int halvings) {
    auto loaded = collision::read_mesh(path, collision::Vec3::Constant(scale));
    if (!loaded) raise_message("RobotError", "*Mesh error*", loaded.error().message, path);
    warn(loaded->warnings);
    return add(name.value_or(std::filesystem::path(path).stem().string()), std::move(loaded->mesh), group, is_static, halvings);
  }

  void set_pose(collision::BodyId id, const Array& pose) {
    const InUse busy(busy_, "this Engine");
    check_id(id);
    engine_.set_pose(id, to_pose(pose));
  }

  py::object check() {
    const InUse busy(busy_, "this Engine");
    collision::QueryResult r;
    {
      py::gil_scoped_release release;
      r = engine_.check();
    }
    if (!r.collided) return py::none();
    const auto& c = r.contact;
    py::dict d;
    d["bodies"] = py::make_tuple(names_[c.body_a], names_[c.body_b]);
    d["ids"] = py::make_tuple(c.body_a, c.body_b);
    d["kind"] = c.kind == collision::ContactKind::faces ? "faces" : c.kind == collision::ContactKind::clearance ? "clearance" : "containment";
    d["distance"] = c.distance;
    d["faces"] = py::make_tuple(c.face_a, c.face_b);
    d["point"] = py::make_tuple(c.point.x(), c.point.y(), c.point.z());
    return d;
  }

  // poses: (N, 4, 4) for one body, (N, k, 4, 4) for k bodies; every other body stays where it
  // is. Result: collided per pose (bool, N). The loop runs in C++ without the GIL.
  py::array_t<bool> check_poses(const py::object& bodies, const Array& poses) {
    const InUse busy(busy_, "this Engine");
    const std::vector<collision::BodyId> ids = py::isinstance<py::int_>(bodies)
                                                   ? std::vector<collision::BodyId>{bodies.cast<collision::BodyId>()}
                                                   : bodies.cast<std::vector<collision::BodyId>>();
    for (auto id : ids) check_id(id);
    const auto k = static_cast<py::ssize_t>(ids.size());
    const bool single = poses.ndim() == 3 && k == 1;
    if (!(single || (poses.ndim() == 4 && poses.shape(1) == k)) || poses.shape(poses.ndim() - 1) != 4 ||
        poses.shape(poses.ndim() - 2) != 4)
      throw py::value_error("poses: an (N, 4, 4) array for one body, (N, k, 4, 4) for k bodies");
    const py::ssize_t n = poses.shape(0);
    py::array_t<bool> out(n);
    bool* hit = out.mutable_data();
    const double* m = poses.data();
    {
      py::gil_scoped_release release;
      for (py::ssize_t i = 0; i < n; ++i) {
        for (py::ssize_t b = 0; b < k; ++b) engine_.set_pose(ids[static_cast<std::size_t>(b)], pose_from(m + (i * k + b) * 16));
        hit[i] = engine_.check().collided;
      }
    }
    return out;
  }

  // Minimum distance between two bodies at the current poses (Engine::distance).
  py::dict distance(collision::BodyId a, collision::BodyId b, double upper_mm) {
    const InUse busy(busy_, "this Engine");
    check_id(a);
    check_id(b);
    if (a == b) throw py::value_error("distance: two different bodies");
    collision::DistanceResult r;
    {
      py::gil_scoped_release release;
      r = engine_.distance(a, b, {.upper_mm = upper_mm});
    }
    py::dict d;
    d["status"] = r.status == collision::DistanceStatus::exact ? "exact" : r.status == collision::DistanceStatus::contact ? "contact" : "beyond";
    d["distance"] = r.distance;
    d["bodies"] = py::make_tuple(names_[a], names_[b]);
    d["faces"] = py::make_tuple(r.face_a, r.face_b);
    d["point_a"] = py::make_tuple(r.point_a.x(), r.point_a.y(), r.point_a.z());
    d["point_b"] = py::make_tuple(r.point_b.x(), r.point_b.y(), r.point_b.z());
    if (r.status == collision::DistanceStatus::contact)
      d["kind"] = r.kind == collision::ContactKind::containment ? "containment" : "faces";
    return d;
  }

  collision::Engine& engine() { return engine_; }
  std::atomic<bool>& busy() { return busy_; }
  std::size_t size() const { return names_.size(); }
  const std::string& name(collision::BodyId id) const {
    check_id(id);
    return names_[id];
  }

 private:
  void check_id(collision::BodyId id) const {
    if (id >= names_.size()) throw py::index_error("no body " + std::to_string(id));
  }
  static void warn(const std::vector<std::string>& warnings) {
    for (const auto& w : warnings) PyErr_WarnEx(PyExc_UserWarning, w.c_str(), 1);
  }
  collision::Engine engine_;
  std::vector<std::string> names_;
  std::atomic<bool> busy_{false};
};

}  // namespace

PYBIND11_MODULE(_asimov, m) {
  m.doc() = "asimov's C++ core (use the asimov package)";
  m.attr("__version__") = asimov::kVersion;
  m.attr("SCHEMA_VERSION") = app::kSchemaVersion;

  py::class_<robots::Robot>(m, "Robot", "A serial arm: the built-in PUMA 560 or a URDF arm. Joints are display values (deg, mm).")
      .def_property_readonly("name", [](const robots::Robot& r) { return r.name; })
      .def_property_readonly("joint_count", &robots::Robot::joint_count)
      .def_property_readonly("ready", [](const robots::Robot& r) { return joints_array(robots::ready_joints(r)); })
      .def_property_readonly("lower", [](const robots::Robot& r) { return joints_array(r.lower); })
      .def_property_readonly("upper", [](const robots::Robot& r) { return joints_array(r.upper); })
      .def_property_readonly("link_names", [](const robots::Robot& r) {
        std::vector<std::string> names;
        for (const auto& b : r.bodies) names.push_back(b.name);
        return names;
      })
      .def("fk", [](const robots::Robot& r, const Array& q) { return pose_array(robots::flange_pose(r, to_joints(r, q))); },
           py::arg("joints"), "Flange pose (4x4, mm) in the robot base frame at display joints.")
      .def("link_frames", [](const robots::Robot& r, const Array& q) {
             std::vector<Pose> frames;
             robots::link_frames(r, to_joints(r, q), frames);
             py::array_t<double> out({static_cast<py::ssize_t>(frames.size()), py::ssize_t{4}, py::ssize_t{4}});
             auto o = out.mutable_unchecked<3>();
             for (std::size_t k = 0; k < frames.size(); ++k)
               for (int a = 0; a < 4; ++a)
                 for (int b = 0; b < 4; ++b) o(static_cast<py::ssize_t>(k), a, b) = frames[k].matrix()(a, b);
             return out;
           }, py::arg("joints"), "Frames of the base (0) and of every link (1..n), (n+1, 4, 4).")
      .def("ik", &robot_ik, py::arg("flange"), py::arg("current") = py::none(), py::arg("config") = py::none(),
           py::arg("single") = true,
           "Joints reaching the flange pose (4x4, mm) nearest `current` (default READY), in `config` "
           "(V+'s words as keys, each True or False: righty / lefty, above / below, noflip / flip; the words "
           "not given: those of `current`). Raises KinematicsError; ValueError / TypeError for a bad config.")
      .def("ik_all", &robot_ik_all, py::arg("flange"), py::arg("current") = py::none(),
           "Every IK solution of the flange pose (one per configuration reached; closed-form arms up to 8), "
           "each the equivalent nearest `current` within limits: a list of joint arrays.")
      .def("jacobian", &robot_jacobian, py::arg("joints"),
           "Geometric Jacobian (6, n) at display joints, base frame: rows vx, vy, vz [mm], wx, wy, wz [rad] "
           "per degree of a revolute joint (per mm of a prismatic one).")
      .def("configuration", [](const robots::Robot& r, const Array& q) { return configuration_dict(robots::configuration_of(r, to_joints(r, q))); },
           py::arg("joints"))
      .def("first_limit_violation", [](const robots::Robot& r, const Array& q) { return robots::first_limit_violation(r, to_joints(r, q)); },
           py::arg("joints"), "Index of the first joint outside its limits, -1 when all are inside.")
      .def("__repr__", [](const robots::Robot& r) {
        std::string kinds;
        for (int j = 0; j < r.joint_count(); ++j) kinds += r.prismatic(j) ? 'P' : 'R';
        return "<asimov.Robot '" + r.name + "': " + std::to_string(r.joint_count()) + " joints (" + kinds + "), " +
               std::to_string(r.bodies.size()) + " bodies>";
      });

  py::class_<motion::Cell>(m, "Cell", "A work cell: robot, BASE, TOOL, tool body, objects, collision settings.")
      .def_property_readonly("robot", [](const motion::Cell& c) { return c.robot; })
      .def_property_readonly("objects", [](const motion::Cell& c) {
        std::vector<std::string> names;
        for (const auto& o : c.objects) names.push_back(o.name);
        return names;
      })
      .def_property_readonly("base", [](const motion::Cell& c) { return pose_array(c.base); })
      .def_property_readonly("tool", [](const motion::Cell& c) { return pose_array(c.tool); })
      .def_property_readonly("start_joints", [](const motion::Cell& c) { return joints_array(c.start_joints); })
      .def_property_readonly("warnings", [](const motion::Cell& c) { return c.warnings; })
      .def("__repr__", [](const motion::Cell& c) {
        return "<asimov.Cell robot '" + c.robot.name + "', " + std::to_string(c.objects.size()) + " objects, step_mm " +
               fmt_number(c.collision.step_mm) + ">";
      });

  m.def("load_cell", [](const py::object& source, const std::string& base_dir) { return load_cell_any(source, base_dir); },
        py::arg("source"), py::arg("base_dir") = "",
        "A cell from a YAML file (path) or a dict of the same shape (docs/cell-format.md); "
        "`base_dir` resolves the dict's relative file names. Raises CellError.");
  m.def("default_cell", [] { return cell::default_cell(); }, "The built-in cell (PUMA 560, table, box).");
  m.def("puma560", &robots::puma560, "The built-in PUMA 560.");
  m.def("robot", [](const std::string& name) {
    auto r = robots::builtin_robot(name);
    if (!r) {
      py::dict f;
      f["message"] = "*Unknown robot*";
      f["detail"] = "'" + name + "': the built-in arms are " + robots::builtin_robot_names();
      raise("RobotError", f);
    }
    return std::move(*r);
  }, py::arg("name"), "A built-in arm by name: puma560, viper_s650, cobra_s600. Raises RobotError.");
  m.def("load_urdf", [](const std::string& path) {
    auto robot = robots::load_urdf(path);
    if (!robot) raise_message("RobotError", "*URDF error*", robot.error().message, robot.error().file, robot.error().line);
    return std::move(*robot);
  }, py::arg("path"), "A robot from a URDF file. Raises RobotError.");
  m.def("trans", [](double x, double y, double z, double o, double a, double t) { return pose_array(motion::trans(x, y, z, o, a, t)); },
        py::arg("x"), py::arg("y"), py::arg("z"), py::arg("o") = 0.0, py::arg("a") = 0.0, py::arg("t") = 0.0,
        "VAL TRANS(x, y, z, o, a, t): mm, ZYZ Euler angles in degrees, as a 4x4 matrix.");
  m.def("decompose", [](const Array& pose) {
    const auto x = motion::decompose(to_pose(pose));
    return py::make_tuple(x[0], x[1], x[2], x[3], x[4], x[5]);
  }, py::arg("pose"), "VAL DECOMPOSE: (x, y, z, o, a, t) of a 4x4 pose.");

  py::class_<Session>(m, "Session", "One simulated cell: load programs, run them, type monitor commands.")
      .def(py::init([](const py::object& cell, bool trace, const std::string& base_dir, bool replay) {
             return std::make_unique<Session>(load_cell_any(cell, base_dir), trace, replay);
           }),
           py::arg("cell") = py::none(), py::arg("trace") = false, py::arg("base_dir") = "", py::arg("replay") = false)
      .def("load", &Session::load, py::arg("path"), "Loads a .v2 file; its program names. Raises LoadError.")
      .def("load_source", &Session::load_source, py::arg("text"), py::arg("name") = "<string>")
      .def_property_readonly("programs", &Session::programs)
      .def("run", &Session::run, py::arg("name") = py::none(),
           "Runs a program (default: the first loaded); the report as a dict. Raises ProgramError.")
      .def("execute", &Session::execute, py::arg("line"), py::arg("check") = true,
           "One monitor command line (DO, HERE, WHERE, POINT, EXECUTE, ...); what it printed. "
           "Raises CommandError when it fails and `check`.")
      .def("output", &Session::output, "Everything printed since the last call.")
      .def("trace", &Session::trace, "Checked poses (Session(trace=True)): time_s (n), joints (n, j), tool (n, 4, 4), xyzoat (n, 6).")
      .def_property_readonly("joints", [](Session& s) { return joints_array(s.sim().joints()); })
      .def_property_readonly("here", [](Session& s) { return pose_array(s.sim().here()); })
      .def_property_readonly("time_s", [](Session& s) { return s.sim().time_s(); })
      .def_property_readonly("poses_checked", [](Session& s) { return s.sim().recorders().counts.poses; })
      .def_property_readonly("robot", [](Session& s) { return s.sim().robot(); })
      .def_property_readonly("cell", [](Session& s) { return s.sim().cell(); })
      .def_property_readonly("quit", &Session::quit)
      .def_property_readonly("status", &Session::status_word,
                             "How the last run ended: 'idle' (nothing ran), 'completed', 'collision', 'error', 'paused', 'halted', 'interrupted'.")
      .def("write_replay", &Session::write_replay, py::arg("path"),
           "Writes the 3D replay page of the last run (Session(replay=True)), as `asimov run --replay`.")
      .def("__repr__", [](Session& s) {
        return "<asimov.Session robot '" + s.sim().robot().name + "', " + (s.file().empty() ? std::string("no file") : "file '" + s.file() + "'") +
               ", " + s.status_word() + ", t = " + fmt_number(s.sim().time_s()) + " s>";
      });

  py::class_<PyEngine>(m, "Engine", "The four-step collision engine: add bodies, pose them, query contact.")
      .def(py::init([](double clearance) {
             auto e = std::make_unique<PyEngine>();
             e->engine().set_default_clearance(clearance);
             return e;
           }),
           py::arg("clearance") = 0.0)
      .def("add_body", &PyEngine::add_arrays, py::arg("name"), py::arg("vertices"), py::arg("triangles"),
           py::arg("group") = -1, py::arg("static") = false, py::arg("halvings") = 9,
           "A body from arrays: vertices (n, 3) [mm], triangles (m, 3) outward. Its id.")
      .def("add_mesh", &PyEngine::add_mesh, py::arg("path"), py::arg("name") = py::none(), py::arg("scale") = 1.0,
           py::arg("group") = -1, py::arg("static") = false, py::arg("halvings") = 9, "A body from an STL or OBJ file.")
      .def("add_box", &PyEngine::add_box, py::arg("name"), py::arg("size"), py::arg("group") = -1, py::arg("static") = false, py::arg("halvings") = 9)
      .def("add_cylinder", &PyEngine::add_cylinder, py::arg("name"), py::arg("radius"), py::arg("height"), py::arg("segments") = 24, py::arg("group") = -1,
           py::arg("static") = false, py::arg("halvings") = 9)
      .def("set_pose", &PyEngine::set_pose, py::arg("body"), py::arg("pose"))
      .def("set_pair_enabled", [](PyEngine& e, collision::BodyId a, collision::BodyId b, bool on) {
             const InUse busy(e.busy(), "this Engine");
             e.name(a);  // an unknown id raises IndexError
             e.name(b);
             e.engine().set_pair_enabled(a, b, on);
           }, py::arg("a"), py::arg("b"), py::arg("enabled"))
      .def("set_clearance", [](PyEngine& e, double c) {
             const InUse busy(e.busy(), "this Engine");
             if (!(std::isfinite(c) && c >= 0)) throw py::value_error("clearance: a finite number >= 0 [mm]");
             e.engine().set_default_clearance(c);
           }, py::arg("clearance_mm"))
      .def("check", &PyEngine::check, "The first contact at the current poses (dict), or None.")
      .def("collides", [](PyEngine& e) { return !e.check().is_none(); })
      .def("check_poses", &PyEngine::check_poses, py::arg("bodies"), py::arg("poses"),
           "Batch: poses (N, 4, 4) for one body or (N, k, 4, 4) for k bodies; collided per pose (bool, N).")
      .def("distance", &PyEngine::distance, py::arg("a"), py::arg("b"), py::arg("upper") = std::numeric_limits<double>::infinity(),
           "Minimum distance [mm] between two bodies at their current poses, with witness points: "
           "{'status': 'exact'|'contact'|'beyond', 'distance', 'point_a', 'point_b', 'faces', 'bodies'}; "
           "beyond: at least `upper` apart (distance is a lower bound).")
      .def("body_name", &PyEngine::name, py::arg("body"))
      .def("body_closed", [](PyEngine& e, collision::BodyId id) { e.name(id); return e.engine().body_closed(id); }, py::arg("body"))
      .def("__len__", &PyEngine::size)
      .def("__repr__", [](const PyEngine& e) {
        std::string names;
        for (std::size_t k = 0; k < e.size() && k < 8; ++k) names += (k ? ", " : "") + e.name(static_cast<collision::BodyId>(k));
        if (e.size() > 8) names += ", ...";
        return "<asimov.Engine " + std::to_string(e.size()) + (e.size() == 1 ? " body" : " bodies") + (names.empty() ? "" : ": " + names) + ">";
      });
}
