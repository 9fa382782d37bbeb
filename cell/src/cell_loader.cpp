#include "asimov/cell/cell_loader.hpp"

#include "duplicate_keys.hpp"
#include "fields.hpp"

#include "asimov/collision/mesh_io.hpp"
#include "asimov/collision/engine.hpp"
#include "asimov/collision/text_file.hpp"
#include "asimov/motion/scene.hpp"
#include "asimov/robots/builtin.hpp"
#include "asimov/robots/puma560.hpp"
#include "asimov/robots/srdf.hpp"
#include "asimov/robots/urdf_loader.hpp"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <ostream>
#include <optional>
#include <set>
#include <string_view>
#include <sstream>

namespace asimov::cell {
namespace {

// Inside the loader a problem unwinds the YAML walk at once; it becomes an Error at the boundary.
struct CellError {
  std::string what, file;
  int line, column;
};

const char* const kDefaultCell = R"(# Built-in default cell: the PUMA 560 with a table and a box in reach.
# World frame = robot frame: origin at the shoulder (J1/J2 axes), Z up; the floor is ~672 mm below.
robot: puma560
base: [0, 0, 0, 0, 0, 0]
tool: [0, 0, 200, 0, 0, 0]            # tool point 200 mm out along the flange Z axis
tool_shape: {box: [50, 80, 140], at: [0, 0, 130, 0, 0, 0]}   # a simple gripper, flange frame
objects:
  - {name: table, box: [700, 1200, 40], at: [750, 0, -420, 0, 0, 0]}   # top face at z = -400
  - {name: box, box: [160, 160, 200], at: [600, 250, -300, 0, 0, 0]}   # standing on the table
collision: {halvings: 9, step_mm: 1.0, clearance_mm: 0}
)";

class Reader : public Fields {
 public:
  Reader(std::string source, std::filesystem::path base_dir, bool source_is_text)
      : source_(std::move(source)), base_dir_(std::move(base_dir)), source_is_text_(source_is_text) {}

  [[noreturn]] void fail(const YAML::Node& node, const std::string& what) const {
    const auto mark = node.Mark();
    throw CellError{what, source_, mark.is_null() ? 0 : mark.line + 1, mark.is_null() ? 0 : mark.column + 1};
  }

  std::string where(const YAML::Node& node) const {
    const auto mark = node.Mark();
    return mark.is_null() ? source_ : fmt::format("{}:{}:{}", source_, mark.line + 1, mark.column + 1);
  }

  double number(const YAML::Node& node, const std::string& what) const {
    if (!node.IsScalar()) fail(node, fmt::format("{} must be a number", what));
    double v = 0;
    try {
      v = node.as<double>();
    } catch (const YAML::Exception&) {
      fail(node, fmt::format("{} must be a number, got '{}'", what, node.Scalar()));
    }
    if (!std::isfinite(v)) fail(node, fmt::format("{} must be finite", what));
    return v;
  }

  bool boolean(const YAML::Node& node, const std::string& what) const {
    bool v = false;
    if (!node.IsScalar() || !YAML::convert<bool>::decode(node, v))
      fail(node, fmt::format("{} must be true or false, got '{}'", what, node.IsScalar() ? node.Scalar() : "a list or map"));
    return v;
  }

  std::string text(const YAML::Node& node, const std::string& what) const {
    if (!node.IsScalar()) fail(node, fmt::format("{} must be a name, not a list or map", what));
    return node.Scalar();
  }

  double positive(const YAML::Node& node, const std::string& what) const {
    const double v = number(node, what);
    if (!(v > 0)) fail(node, fmt::format("{} must be > 0, got {}", what, v));
    return v;
  }

  std::vector<double> numbers(const YAML::Node& node, std::size_t count, const std::string& what) const {
    if (!node.IsSequence() || node.size() != count)
      fail(node, fmt::format("{} must be a list of {} numbers", what, count));
    std::vector<double> v;
    for (const auto& item : node) v.push_back(number(item, what));
    return v;
  }

  motion::Location pose(const YAML::Node& node, const std::string& what) const {
    if (!node) return motion::Location::Identity();
    const auto v = numbers(node, 6, what + " ([x, y, z, o, a, t])");
    return motion::trans(v[0], v[1], v[2], v[3], v[4], v[5]);
  }

  // A shape entry: {box: [sx, sy, sz]}, {cylinder: {radius: r, height: h[, segments: n]}},
  // {sphere: {radius: r[, tolerance_mm: t]}} or {mesh: file.stl|obj[, scale: s | [sx, sy, sz]]}.
  // Mesh warnings (dropped faces, open meshes) are appended to `warnings`.
  collision::Polyhedron shape(const YAML::Node& node, const std::string& what,
                              std::vector<std::string>& warnings) const {
    if (!node.IsMap()) fail(node, what + " must be a map");
    if (const auto mesh = node["mesh"]) {
      if (!mesh.IsScalar()) fail(mesh, what + ".mesh must be a file name");
      collision::Vec3 scale = collision::Vec3::Ones();
      if (const auto s = node["scale"]) {
        if (s.IsScalar()) {
          scale.setConstant(positive(s, what + ".scale"));
        } else {
          const auto v = numbers(s, 3, what + ".scale");
          for (double x : v)
            if (!(x > 0)) fail(s, what + ".scale factors must be > 0");
          scale = {v[0], v[1], v[2]};
        }
      }
      const auto path = (base_dir_ / mesh.Scalar()).lexically_normal().string();
      auto loaded = collision::read_mesh(path, scale);
      if (!loaded) fail(mesh, fmt::format("{}: {}", what, loaded.error().message));
      if (loaded->mesh.triangles.empty()) fail(mesh, fmt::format("{}: no valid face in {}", what, path));
      for (auto& w : loaded->warnings) warnings.push_back(std::move(w));
      return std::move(loaded->mesh);
    }
    if (const auto sphere = node["sphere"]) {
      if (!sphere.IsMap()) fail(sphere, what + ".sphere must be {radius: r[, tolerance_mm: t]}");
      const double r = positive(sphere["radius"] ? sphere["radius"] : sphere, what + ".sphere.radius");
      const double tol = sphere["tolerance_mm"] ? positive(sphere["tolerance_mm"], what + ".sphere.tolerance_mm")
                                                : std::max(0.5, r * 1e-3);
      auto p = collision::make_sphere(r, tol);
      if (!p) fail(sphere, fmt::format("{}.sphere: {}", what, p.error().message));
      return std::move(*p);
    }
    if (const auto box = node["box"]) {
      const auto s = numbers(box, 3, what + ".box");
      for (double x : s)
        if (!(x > 0)) fail(box, what + ".box sides must be > 0");
      return collision::make_box({s[0], s[1], s[2]});
    }
    if (const auto cyl = node["cylinder"]) {
      if (!cyl.IsMap()) fail(cyl, what + ".cylinder must be {radius: r, height: h}");
      const double r = positive(cyl["radius"] ? cyl["radius"] : cyl, what + ".cylinder.radius");
      const double h = positive(cyl["height"] ? cyl["height"] : cyl, what + ".cylinder.height");
      int segments = 24;
      if (const auto s = cyl["segments"]) {
        // Range first: casting 1e300 to int is undefined behaviour.
        const double v = number(s, what + ".cylinder.segments");
        if (!(v >= 3 && v <= 4096) || v != std::floor(v)) fail(s, what + ".cylinder.segments must be an integer 3..4096");
        segments = static_cast<int>(v);
      }
      return collision::make_cylinder(r, h, segments);
    }
    fail(node, what + " needs a shape: box, cylinder, sphere or mesh");
  }

  void expect_keys(const YAML::Node& node, std::initializer_list<const char*> keys, const std::string& what) const {
    if (!node.IsMap()) fail(node, what + " must be a map");
    const std::set<std::string> known(keys.begin(), keys.end());
    for (const auto& kv : node) {
      const auto key = text(kv.first, "a key in " + what);
      if (!known.count(key)) {
        std::string list;
        for (const auto* k : keys) list += (list.empty() ? "" : ", ") + std::string(k);
        fail(kv.first, fmt::format("unknown key '{}' in {} (known: {})", key, what, list));
      }
    }
  }

  // A built-in arm by name (robots/builtin.hpp) or a URDF file, relative to the cell file's folder.
  // `packages`: folders (relative to the cell file) searched for package://NAME before
  // ROS_PACKAGE_PATH; a package is the folder whose package.xml names it.
  // `xacro_args`: {NAME: value} for $(arg NAME) of a .xacro description.
  std::vector<std::filesystem::path> package_roots(const YAML::Node& packages) const {
    std::vector<std::filesystem::path> roots;
    if (!packages) return roots;
    if (packages.IsScalar()) {
      roots.push_back((base_dir_ / packages.Scalar()).lexically_normal());
    } else {
      if (!packages.IsSequence()) fail(packages, "packages must be a folder or a list of folders");
      for (const auto& p : packages) {
        if (!p.IsScalar()) fail(p, "packages entries are folder names");
        roots.push_back((base_dir_ / p.Scalar()).lexically_normal());
      }
    }
    for (std::size_t i = 0; i < roots.size(); ++i) {
      std::error_code ec;
      if (!std::filesystem::is_directory(roots[i], ec))
        fail(packages.IsScalar() ? packages : packages[i], fmt::format("packages: no folder {}", roots[i].string()));
    }
    return roots;
  }

  // `srdf: FILE` (relative to the cell, package:// or file://): read, structure checked.
  std::optional<robots::Srdf> srdf(const YAML::Node& node, const robots::PackagePath& packages) const {
    if (!node) return std::nullopt;
    if (!node.IsScalar()) fail(node, "srdf must be a file name or a package:// URI");
    std::string error;
    const auto path = robots::resolve_uri(node.Scalar(), base_dir_, packages, error);
    if (!error.empty()) fail(node, "srdf: " + error);
    auto s = robots::load_srdf(path.string());
    if (!s) fail(node, fmt::format("srdf: {}", s.error().message));
    return std::move(*s);
  }

  robots::Robot robot(const YAML::Node& node, const robots::PackagePath& packages, const YAML::Node& xacro_args,
                      const YAML::Node& tip, const std::string& srdf_tip) const {
    const std::string usage = fmt::format("a built-in arm ({}), a .urdf or .xacro file or a package:// URI", robots::builtin_robot_names());
    if (node && !node.IsScalar()) fail(node, "robot must be " + usage);
    const auto name = node ? node.Scalar() : std::string("puma560");
    if (auto builtin = robots::builtin_robot(name)) {
      if (tip) fail(tip, "tip: names a link of a URDF description; a built-in arm has its own");
      return std::move(*builtin);
    }
    robots::UrdfOptions options;
    options.packages = packages;
    options.tip = tip ? text(tip, "tip") : srdf_tip;
    if (xacro_args) {
      if (!xacro_args.IsMap()) fail(xacro_args, "xacro_args must be a map {name: value}");
      for (const auto& kv : xacro_args) {
        if (!kv.second.IsScalar()) fail(kv.second, "xacro_args values are scalars");
        options.xacro_args[kv.first.Scalar()] = kv.second.Scalar();
      }
    }
    std::string error;
    const auto path = robots::resolve_uri(name, base_dir_, options.packages, error);
    if (!error.empty()) fail(node, "robot: " + error);
    if (path.extension() != ".urdf" && path.extension() != ".xacro") fail(node, fmt::format("unknown robot '{}' ({})", name, usage));
    auto robot = robots::load_urdf(path.string(), options);
    if (!robot) fail(tip && robot.error().message.find("tip: ") != std::string::npos ? tip : node,
                     fmt::format("robot: {}", robot.error().message));
    return std::move(*robot);
  }

  // Body coordinates beyond kMaxCoordinateMm lose the engine's precision (positions round to
  // 1e-16 of their size: at 1e18 mm a whole link rounds away) and overflow its products near
  // 1e150 mm (an arm inside a 1e150 mm box went unseen): a cell error (docs/stiff-cases.md).
  static constexpr double kMaxCoordinateMm = 1e9;
  // Objects in one cell (docs/limits.md): far above a real cell (hundreds). The pair set-up is
  // linear (static objects pair only with the bodies that move, the matrix is sparse); what
  // bounds it is the memory of the objects' meshes and pairs, and the YAML parse.
  static constexpr std::size_t kMaxObjects = 100000;
  void within_extent(const YAML::Node& node, const collision::Polyhedron& mesh, const collision::Pose& pose,
                     const std::string& what) const {
    double far = pose.translation().cwiseAbs().maxCoeff();
    for (const auto& v : mesh.vertices) far = std::max(far, (pose * v).cwiseAbs().maxCoeff());
    if (!(far <= kMaxCoordinateMm))
      fail(node, fmt::format("{} reaches {} mm from the origin; coordinates are limited to {:g} mm", what, far,
                             kMaxCoordinateMm));
  }

  motion::Cell cell(const YAML::Node& root) const {
    if (!root.IsMap()) fail(root, "a cell file is a YAML map (see docs/cell-format.md)");
    expect_keys(root, {"robot", "packages", "xacro_args", "srdf", "tip", "base", "tool", "tool_shape", "objects", "collision", "start", "parts",
                       "gripper", "devices", "logic"},
                "the cell");
    motion::Cell cell;
    const robots::PackagePath packages = robots::PackagePath::with_environment(package_roots(root["packages"]));
    const std::optional<robots::Srdf> semantic = srdf(root["srdf"], packages);
    cell.robot = robot(root["robot"], packages, root["xacro_args"], root["tip"], semantic ? robots::srdf_tip(*semantic) : "");
    cell.warnings = cell.robot.warnings;  // URDF mesh notes, already prefixed with urdf:line
    if (semantic) use_srdf(root["srdf"], *semantic, cell);
    cell.base = pose(root["base"], "base");
    within_extent(root["base"], {}, cell.base, "base");
    cell.tool = pose(root["tool"], "tool");
    const int n = cell.robot.joint_count();
    cell.start_joints = robots::ready_joints(cell.robot);
    if (const auto start = root["start"]) {
      const auto v = numbers(start, static_cast<std::size_t>(n), "start (joint values in degrees)");
      for (int i = 0; i < n; ++i) cell.start_joints[i] = v[static_cast<std::size_t>(i)];
      const int bad = robots::first_limit_violation(cell.robot, cell.start_joints);
      if (bad >= 0)
        fail(start, fmt::format("start: J{} = {} is outside [{}, {}]", bad + 1, cell.start_joints[bad],
                                cell.robot.lower[bad], cell.robot.upper[bad]));
    }
    if (const auto ts = root["tool_shape"]) {
      expect_keys(ts, {"box", "cylinder", "sphere", "mesh", "scale", "at"}, "tool_shape");
      cell.tool_shape =
          collision::transformed(shape(ts, "tool_shape", cell.warnings), pose(ts["at"], "tool_shape.at"));
      within_extent(ts, *cell.tool_shape, cell.base, "tool_shape");
    }
    std::set<std::string> names;
    for (const auto& b : cell.robot.bodies) names.insert(b.name);
    names.insert("tool");
    if (const auto objects = root["objects"]) {
      if (!objects.IsSequence()) fail(objects, "objects must be a list");
      if (objects.size() > kMaxObjects)
        fail(objects, fmt::format("{} objects; a cell has at most {}", objects.size(), kMaxObjects));
      for (const auto& o : objects) {
        if (!o.IsMap()) fail(o, "an object is a map like {name: n, box: [x, y, z], at: [x, y, z, o, a, t]}");
        expect_keys(o, {"name", "box", "cylinder", "sphere", "mesh", "scale", "at"}, "an object");
        if (!o["name"]) fail(o, "every object needs a name");
        motion::CellObject obj;
        obj.name = text(o["name"], "an object's name");
        if (!names.insert(obj.name).second) fail(o["name"], fmt::format("duplicate body name '{}'", obj.name));
        obj.mesh = shape(o, "object '" + obj.name + "'", cell.warnings);
        obj.pose = pose(o["at"], "object '" + obj.name + "' at");
        within_extent(o, obj.mesh, obj.pose, "object '" + obj.name + "'");
        cell.objects.push_back(std::move(obj));
      }
    }
    read_workcell(root, *this, cell, names);  // workcell.cpp
    if (const auto c = root["collision"]) {
      expect_keys(c, {"halvings", "step_mm", "clearance_mm", "ignore", "enabled", "toc_tolerance_s", "pairs",
                      "pair_samples", "stepping", "continuous", "report_within_mm", "on_clearance"},
                  "collision");
      auto& s = cell.collision;
      if (c["halvings"] && c["halvings"].IsScalar() && c["halvings"].Scalar() == "auto") {
        s.halvings = collision::kAutoHalvings;
      } else if (c["halvings"]) {
        const double m = number(c["halvings"], "collision.halvings (auto or an integer 0..20)");
        if (m < 0 || m > 20 || m != std::floor(m)) fail(c["halvings"], "collision.halvings must be auto or an integer 0..20");
        s.halvings = static_cast<int>(m);
      }
      if (c["step_mm"]) {
        s.step_mm = positive(c["step_mm"], "collision.step_mm");
        // The simulator never steps finer than motion::kMinStepMm: a smaller value would be raised
        // silently while the report claims it, so it is refused here.
        if (s.step_mm < motion::kMinStepMm)
          fail(c["step_mm"], fmt::format("collision.step_mm must be >= {:g}, got {:g}", motion::kMinStepMm, s.step_mm));
      }
      if (c["clearance_mm"]) {
        s.clearance_mm = number(c["clearance_mm"], "collision.clearance_mm");
        if (s.clearance_mm < 0) fail(c["clearance_mm"], "collision.clearance_mm must be >= 0");
      }
      if (c["enabled"]) s.enabled = boolean(c["enabled"], "collision.enabled");
      if (c["toc_tolerance_s"]) s.toc_tolerance_s = positive(c["toc_tolerance_s"], "collision.toc_tolerance_s");
      if (const auto pairs = c["pairs"]) {
        const auto v = pairs.IsScalar() ? pairs.Scalar() : std::string();
        if (v != "joined" && v != "generated") fail(pairs, "collision.pairs must be joined or generated");
        s.generated_pairs = v == "generated";
        // Shared with `asimov pairs CELL.yaml`: both build the same input, so one cache serves both.
        if (s.generated_pairs && !source_is_text_) s.pairs_cache = source_ + ".pairs";
      }
      if (const auto st = c["stepping"]) {
        const auto v = st.IsScalar() ? st.Scalar() : std::string();
        if (v != "fixed" && v != "gap") fail(st, "collision.stepping must be fixed or gap");
        s.stepping = v == "gap" ? motion::Stepping::gap : motion::Stepping::fixed;
      }
      if (c["continuous"]) s.continuous = boolean(c["continuous"], "collision.continuous");
      if (c["report_within_mm"]) {
        s.report_within_mm = number(c["report_within_mm"], "collision.report_within_mm");
        if (!(s.report_within_mm >= 0) || s.report_within_mm > 1e9)
          fail(c["report_within_mm"], "collision.report_within_mm must be 0..1e9");
      }
      if (const auto oc = c["on_clearance"]) {
        const auto v = oc.IsScalar() ? oc.Scalar() : std::string();
        if (v != "halt" && v != "warn") fail(oc, "collision.on_clearance must be halt or warn");
        s.on_clearance = v == "warn" ? motion::OnClearance::warn : motion::OnClearance::halt;
      }
      if (c["pair_samples"]) {
        const double n = number(c["pair_samples"], "collision.pair_samples");
        if (n < 1 || n > 1e7 || n != std::floor(n)) fail(c["pair_samples"], "collision.pair_samples must be 1..10000000");
        s.pair_samples = static_cast<int>(n);
      }
      if (const auto ig = c["ignore"]) {
        if (!ig.IsSequence()) fail(ig, "collision.ignore must be a list of [body, body] pairs");
        for (const auto& pair : ig) {
          if (!pair.IsSequence() || pair.size() != 2) fail(pair, "collision.ignore entries are [body, body]");
          const auto a = text(pair[0], "a body in collision.ignore"), b = text(pair[1], "a body in collision.ignore");
          for (const auto& [node, name] : {std::pair{pair[0], a}, std::pair{pair[1], b}})
            if (!names.count(name)) fail(node, fmt::format("collision.ignore: unknown body '{}'", name));
          s.ignore.emplace_back(a, b);
        }
      }
    }
    if (cell.collision.enabled) disable_start_contacts(cell);
    return cell;
  }

  // The SRDF's link names must be the robot's; its disabled pairs of bodies go to the pair
  // matrix (source SRDF); its groups and end effectors are reported as a note.
  void use_srdf(const YAML::Node& node, const robots::Srdf& s, motion::Cell& cell) const {
    std::vector<std::string> bodies;
    for (const auto& b : cell.robot.bodies) bodies.push_back(b.name);
    if (auto ok = robots::check_srdf_links(s, cell.robot.links.empty() ? bodies : cell.robot.links); !ok)
      fail(node, fmt::format("srdf: {}", ok.error().message));
    cell.collision.srdf_disabled = robots::srdf_disabled_pairs(s, bodies);
    for (const auto& w : s.warnings) cell.warnings.push_back(w);
    cell.notes.push_back(fmt::format("{}: {}; {} body pairs disabled (SRDF)", s.file, robots::describe_srdf(s),
                                     cell.collision.srdf_disabled.size()));
  }

  // The default pair policy (docs/cell-format.md "Pair selection"): the robot's own bodies that
  // touch at the start joints are not tested (source DEFAULT), with one warning naming them, so
  // no arm collides with itself at t = 0. A clearance that only warns does not count.
  static void disable_start_contacts(motion::Cell& cell) {
    const motion::Scene scene = motion::scene_bodies(cell, false);  // robot bodies only take part
    const double clearance = cell.collision.on_clearance == motion::OnClearance::halt ? cell.collision.clearance_mm : 0;
    std::string list;
    for (const collision::BodyPair& p : motion::start_contacts(cell, scene, clearance)) {
      const std::string &a = scene.bodies[p.a].name, &b = scene.bodies[p.b].name;
      cell.collision.start_contacts.emplace_back(a, b);
      list += (list.empty() ? "" : ", ") + a + " / " + b;
    }
    if (!list.empty())
      cell.warnings.push_back(fmt::format("the robot touches itself at the start joints; not tested (DEFAULT): {}", list));
  }

 private:
  std::string source_;
  std::filesystem::path base_dir_;  // relative file names in the cell resolve here
  bool source_is_text_;             // no file behind the text: nowhere to put a pairs cache
};

}  // namespace

namespace {
// yaml-cpp parses nested collections by recursion and has no limit of its own: 100,000 '['
// overflow the stack. The text is scanned first and refused past kMaxYamlDepth levels. The
// scan over-counts rather than under-counts: block levels (a deeper indent, each "- " or "? "
// starting an entry) plus flow brackets outside quotes and comments.
constexpr int kMaxYamlDepth = 64;

struct DepthError {
  int line = 0, column = 0;
};

std::optional<DepthError> yaml_too_deep(const std::string& text) {
  std::vector<std::size_t> indents;  // indents of the open block levels
  int flow = 0, line = 1;
  char quote = 0;                    // inside '...' or "..." (they may span lines)
  std::size_t literal_indent = std::string::npos;  // inside a | or > block scalar deeper than this
  std::size_t pos = 0;
  while (pos <= text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string::npos) end = text.size();
    const std::string_view l(text.data() + pos, end - pos);
    std::size_t i = 0;
    while (i < l.size() && l[i] == ' ') ++i;
    const bool blank = i == l.size() || l[i] == '#' || l[i] == '\r';
    if (literal_indent != std::string::npos && (blank || i > literal_indent)) {
      pos = end + 1, ++line;
      continue;
    }
    literal_indent = std::string::npos;
    if (!blank && !quote && flow == 0) {
      while (!indents.empty() && indents.back() >= i) indents.pop_back();
      indents.push_back(i);
    }
    int depth = static_cast<int>(indents.size());
    bool colon = false;  // one "key: value" level per line (a: b: c is not YAML)
    std::size_t last = std::string_view::npos;  // the last character that is not a space or comment
    for (std::size_t k = i; k < l.size(); ++k) {
      const char c = l[k];
      if (quote) {
        if (c == '\\' && quote == '"') ++k;
        else if (c == quote) quote = 0;
        continue;
      }
      if (c == '#' && (k == 0 || l[k - 1] == ' ' || l[k - 1] == '\t')) break;
      const bool ends_word = k + 1 == l.size() || l[k + 1] == ' ' || l[k + 1] == '\r';
      // A quote opens a quoted scalar only where a scalar starts (it's, 5'10" are plain text).
      const bool scalar_start = last == std::string_view::npos || std::string_view("[{,").find(l[last]) != std::string_view::npos ||
                                (std::string_view(":-?").find(l[last]) != std::string_view::npos && l[k - 1] == ' ');
      if ((c == '"' || c == '\'') && scalar_start) quote = c;
      else if (c == '[' || c == '{') ++flow;
      else if ((c == ']' || c == '}') && flow > 0) --flow;
      else if (flow == 0 && (c == '-' || c == '?') && ends_word) ++depth;
      else if (flow == 0 && c == ':' && ends_word && !colon) colon = true, ++depth;
      if (c != ' ' && c != '\t' && c != '\r') last = k;
      if (depth + flow > kMaxYamlDepth) return DepthError{line, static_cast<int>(k + 1)};
    }
    // "key: |", "- >-", "|2": a block scalar; its lines (deeper than this one) are text.
    if (!quote && flow == 0 && last != std::string_view::npos) {
      std::size_t b = last;
      while (b > i && (l[b] == '-' || l[b] == '+' || (l[b] >= '0' && l[b] <= '9'))) --b;
      if ((l[b] == '|' || l[b] == '>') && (b == i || l[b - 1] == ' ')) literal_indent = i;
    }
    pos = end + 1, ++line;
  }
  return std::nullopt;
}
}  // namespace

std::string format_cell_error(const Error& e) {
  // Messages quote the file's text (yaml-cpp's too): printable, whatever bytes it holds.
  if (e.line > 0) return collision::printable(fmt::format("{}:{}:{}: {}", e.file, e.line, e.column, e.message));
  return collision::printable(fmt::format("{}: {}", e.file, e.message));
}

namespace {
motion::Cell parse_cell_or_throw(const std::string& yaml, const std::string& source_name,
                                 const std::string& base_dir, bool from_file) {
  Reader reader(source_name, base_dir, !from_file);
  if (const auto deep = yaml_too_deep(yaml))
    throw CellError{fmt::format("nested more than {} levels deep", kMaxYamlDepth), source_name, deep->line, deep->column};
  YAML::Node root;
  try {
    root = YAML::Load(yaml);
  } catch (const YAML::ParserException& e) {
    throw CellError{e.msg, source_name, e.mark.line + 1, e.mark.column + 1};
  }
  if (const auto dup = first_duplicate_key(yaml))
    throw CellError{fmt::format("duplicate key '{}' (first given at line {}); a key is given once per map", dup->key,
                                dup->first_line),
                    source_name, dup->line, dup->column};
  try {
    return reader.cell(root);
  } catch (const YAML::Exception& e) {  // e.g. a map where a string was expected
    throw CellError{e.msg, source_name, e.mark.is_null() ? 0 : e.mark.line + 1,
                    e.mark.is_null() ? 0 : e.mark.column + 1};
  }
}

Result<motion::Cell> parse_cell(const std::string& yaml, const std::string& source_name,
                                const std::string& base_dir, bool from_file) {
  try {
    return parse_cell_or_throw(yaml, source_name, base_dir, from_file);
  } catch (const CellError& e) {
    return Error{.message = e.what, .detail = {}, .file = e.file, .line = e.line, .column = e.column};
  }
}
}  // namespace

Result<motion::Cell> load_cell_text(const std::string& yaml, const std::string& source_name,
                                    const std::string& base_dir) {
  return parse_cell(yaml, source_name, base_dir, false);
}

Result<motion::Cell> load_cell_file(const std::string& path) {
  const Result<std::string> text = collision::read_file_bounded(path, collision::kMaxTextFileBytes);
  if (!text) return Error{.message = text.error().message, .detail = {}, .file = path};
  return parse_cell(*text, path, std::filesystem::path(path).parent_path().string(), true);
}

const std::string& default_cell_yaml() {
  static const std::string text = kDefaultCell;
  return text;
}

motion::Cell default_cell() { return std::move(load_cell_text(default_cell_yaml(), "<default cell>")).value(); }

std::optional<motion::Cell> load_cell_for_command(const std::string& path, std::ostream& err) {
  Result<motion::Cell> cell = path.empty() ? Result<motion::Cell>(default_cell()) : load_cell_file(path);
  if (!cell) {
    err << "*Cell error*  " << format_cell_error(cell.error()) << '\n';
    return std::nullopt;
  }
  for (const auto& w : cell->warnings) err << "Warning: " << w << '\n';
  for (const auto& n : cell->notes) err << "Note: " << n << '\n';
  return std::move(cell).value();
}

}  // namespace asimov::cell
