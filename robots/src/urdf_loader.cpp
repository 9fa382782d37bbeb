// URDF -> Robot (chain form). See urdf_loader.hpp for the folding rules.
#include "asimov/robots/urdf_loader.hpp"

#include "mesh_files.hpp"
#include "urdf_error.hpp"
#include "xacro.hpp"

#include "asimov/collision/mesh_io.hpp"
#include "asimov/collision/text_file.hpp"

#include <tinyxml2.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <map>
#include <numbers>
#include <set>
#include <sstream>

namespace asimov::robots {
namespace {
using tinyxml2::XMLElement;
constexpr double kMm = 1000;  // metres -> mm
constexpr double kDeg = 180 / std::numbers::pi;
// A limit is compared with the precision it was written with, at most 0.001 (deg or mm, the
// precision V+ displays joints with): "3.14" still means 179.909 deg, not pi.
constexpr double kMaxLimitTolerance = 1e-3;
constexpr int kCylinderSegments = 24;
constexpr double kSphereToleranceMm = 0.5;  // chordal tolerance, at least 1e-3 of the radius
// Joints from the root to the deepest link: the walks over the tree recurse once per joint, so
// this bounds their stack (a real arm has < 20; docs/limits.md).
constexpr int kMaxLinkDepth = 1000;

struct Geometry {
  Pose pose = Pose::Identity();  // in the URDF link frame [mm]
  collision::Polyhedron mesh;
};

struct Link {
  std::string name;
  int line = 0;
  std::vector<Geometry> geometry;
};

enum class Kind { fixed, revolute, continuous, prismatic };

struct Joint {
  std::string name, parent, child;
  Kind kind = Kind::fixed;
  Pose origin = Pose::Identity();  // [mm]
  Vec3 axis = Vec3::UnitX();
  double lower = 0, upper = 0, velocity = 0;  // display units: deg, mm
  double limit_tolerance = 0;                  // the precision lower / upper were written with (display)
  bool has_velocity = false;
  std::string mimic;  // <mimic joint>: this joint follows that one
  double mimic_multiplier = 1, mimic_offset = 0;  // URDF units (m or rad)
  int line = 0;
};

class Parser {
 public:
  Parser(std::string source, std::string base_dir, const UrdfOptions& options)
      : source_(std::move(source)), base_dir_(std::move(base_dir)), options_(options) {}

  [[noreturn]] void fail(const XMLElement* e, const std::string& what) const {
    throw UrdfError(source_, e ? e->GetLineNum() : 0, what);
  }

  const char* required(const XMLElement* e, const char* attr) const {
    const char* v = e->Attribute(attr);
    if (!v) fail(e, std::string("<") + e->Name() + "> needs the attribute '" + attr + "'");
    return v;
  }

  double number(const XMLElement* e, const char* attr, const std::string& text) const {
    errno = 0;
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    while (end && *end == ' ') ++end;
    if (end == text.c_str() || (end && *end) || errno == ERANGE || !std::isfinite(v))
      fail(e, std::string("<") + e->Name() + " " + attr + "=\"" + text + "\">: a finite number is expected");
    return v;
  }

  double number(const XMLElement* e, const char* attr) const { return number(e, attr, required(e, attr)); }

  // A mesh's "FILE: face N: zero area, dropped" lines (and the "K more faces ..." line after the
  // first hundred) folded into one line with the count and the first few face numbers: a
  // shipped description has hundreds of such slivers, which say nothing one by one.
  static std::vector<std::string> fold_zero_area(const std::vector<std::string>& warnings) {
    constexpr const char* kZero = ": zero area, dropped";
    constexpr std::size_t kListed = 5;
    std::vector<std::string> out;
    std::string source, faces;
    std::size_t count = 0;
    for (const std::string& w : warnings) {
      const std::size_t face = w.rfind(": face ");
      if (face != std::string::npos && w.size() > std::strlen(kZero) && w.compare(w.size() - std::strlen(kZero), std::string::npos, kZero) == 0) {
        source = w.substr(0, face);
        if (count++ < kListed) faces += (faces.empty() ? "" : ", ") + w.substr(face + 7, w.size() - std::strlen(kZero) - face - 7);
        continue;
      }
      if (const std::size_t more = w.find(" more faces of zero area dropped"); more != std::string::npos && w.rfind(": ", more) != std::string::npos) {
        const std::size_t colon = w.rfind(": ", more);
        count += std::strtoull(w.c_str() + colon + 2, nullptr, 10);
        continue;
      }
      out.push_back(w);
    }
    if (count > 0)
      out.insert(out.begin(), source + ": " + std::to_string(count) + (count == 1 ? " face" : " faces") + " of zero area dropped (face" +
                                  (count == 1 ? " " : "s ") + faces + (count > kListed ? ", ..." : "") + ")");
    return out;
  }

  // Half a unit of the last digit a number was written with ("1.04719755": 5e-9, "2.5e-3":
  // 5e-5, "3": 0.5): how far the value the author meant may be from the one written.
  static double written_precision(const std::string& text) {
    const std::size_t b = text.find_first_of("0123456789.");
    if (b == std::string::npos) return 0;
    const std::size_t e = text.find_first_of("eE", b);
    const std::string mantissa = text.substr(b, e == std::string::npos ? std::string::npos : e - b);
    const std::size_t dot = mantissa.find('.');
    std::size_t digits = 0;  // after the point
    if (dot != std::string::npos)
      while (dot + 1 + digits < mantissa.size() && std::isdigit(static_cast<unsigned char>(mantissa[dot + 1 + digits]))) ++digits;
    const int exponent = e == std::string::npos ? 0 : std::clamp(std::atoi(text.c_str() + e + 1), -300, 300);
    return 0.5 * std::pow(10.0, exponent - static_cast<int>(digits));
  }

  Vec3 triple(const XMLElement* e, const char* attr, const Vec3& fallback) const {
    const char* v = e->Attribute(attr);
    if (!v) return fallback;
    std::istringstream in(v);
    std::string a, b, c, extra;
    if (!(in >> a >> b >> c) || (in >> extra))
      fail(e, std::string("<") + e->Name() + " " + attr + "=\"" + v + "\">: three numbers are expected");
    return {number(e, attr, a), number(e, attr, b), number(e, attr, c)};
  }

  // <origin xyz rpy>: R = Rz(yaw) Ry(pitch) Rx(roll), xyz in metres.
  Pose origin(const XMLElement* parent) const {
    Pose t = Pose::Identity();
    const XMLElement* o = parent->FirstChildElement("origin");
    if (!o) return t;
    const Vec3 xyz = triple(o, "xyz", Vec3::Zero()), rpy = triple(o, "rpy", Vec3::Zero());
    t.linear() = (Eigen::AngleAxisd(rpy.z(), Vec3::UnitZ()) * Eigen::AngleAxisd(rpy.y(), Vec3::UnitY()) *
                  Eigen::AngleAxisd(rpy.x(), Vec3::UnitX()))
                     .toRotationMatrix();
    t.translation() = xyz * kMm;
    return t;
  }

  double positive(const XMLElement* e, const char* attr) const {
    const double v = number(e, attr);
    if (!(v > 0)) fail(e, std::string("<") + e->Name() + " " + attr + ">: must be > 0");
    return v;
  }

  collision::Polyhedron shape(const XMLElement* geometry) const {
    if (!geometry) return {};
    if (const XMLElement* b = geometry->FirstChildElement("box")) {
      const Vec3 s = triple(b, "size", Vec3::Zero());
      if (!b->Attribute("size") || !(s.minCoeff() > 0)) fail(b, "<box size>: three numbers > 0 are expected");
      return collision::make_box(s * kMm);
    }
    if (const XMLElement* c = geometry->FirstChildElement("cylinder"))
      return collision::make_cylinder(positive(c, "radius") * kMm, positive(c, "length") * kMm, kCylinderSegments);
    if (const XMLElement* s = geometry->FirstChildElement("sphere")) {
      const double r = positive(s, "radius") * kMm;
      Result<collision::Polyhedron> p = collision::make_sphere(r, std::max(kSphereToleranceMm, r * 1e-3));  // as cell files
      if (!p) fail(s, p.error().message);
      return std::move(*p);
    }
    if (const XMLElement* m = geometry->FirstChildElement("mesh")) {
      const std::string file = required(m, "filename");
      std::string error;
      const std::filesystem::path p = resolve_uri(file, base_dir_, options_.packages, error);
      if (!error.empty()) fail(m, "<mesh filename>: " + error);
      std::error_code ec;
      if (!std::filesystem::is_regular_file(p, ec))  // a collision mesh is never skipped
        fail(m, "<mesh filename=\"" + file + "\">: no such file: " + p.string());
      const Vec3 scale = triple(m, "scale", Vec3::Ones()) * kMm;
      // By extension (STL, OBJ, assimp formats); the Error names the file and face.
      Result<collision::LoadedMesh> loaded = read_mesh_file(p.string(), scale);
      if (!loaded) fail(m, loaded.error().message);
      for (auto& w : fold_zero_area(loaded->warnings)) warnings_.push_back(source_ + ":" + std::to_string(m->GetLineNum()) + ": " + w);
      return std::move(loaded->mesh);
    }
    fail(geometry, "<geometry> needs a box, cylinder, sphere or mesh");
  }

  Link link(const XMLElement* e) const {
    Link l;
    l.name = required(e, "name");
    l.line = e->GetLineNum();
    for (const XMLElement* c = e->FirstChildElement("collision"); c; c = c->NextSiblingElement("collision")) {
      const XMLElement* g = c->FirstChildElement("geometry");
      if (!g) fail(c, "<collision> needs a <geometry>");
      l.geometry.push_back({origin(c), shape(g)});
    }
    return l;
  }

  Joint joint(const XMLElement* e) const {
    Joint j;
    j.name = required(e, "name");
    j.line = e->GetLineNum();
    const std::string type = required(e, "type");
    if (type == "fixed") j.kind = Kind::fixed;
    else if (type == "revolute") j.kind = Kind::revolute;
    else if (type == "continuous") j.kind = Kind::continuous;
    else if (type == "prismatic") j.kind = Kind::prismatic;
    else fail(e, "joint '" + j.name + "': unsupported joint type '" + type + "' (revolute, continuous, prismatic, fixed)");
    const XMLElement* parent = e->FirstChildElement("parent");
    const XMLElement* child = e->FirstChildElement("child");
    if (!parent) fail(e, "joint '" + j.name + "' needs a <parent link>");
    if (!child) fail(e, "joint '" + j.name + "' needs a <child link>");
    j.parent = required(parent, "link");
    j.child = required(child, "link");
    j.origin = origin(e);
    if (j.kind == Kind::fixed) return j;
    if (const XMLElement* a = e->FirstChildElement("axis")) {
      j.axis = triple(a, "xyz", Vec3::UnitX());
      if (!(j.axis.norm() > 1e-12)) fail(a, "joint '" + j.name + "': the axis must not be zero");
      j.axis.normalize();
    }
    const XMLElement* lim = e->FirstChildElement("limit");
    const double unit = j.kind == Kind::prismatic ? kMm : kDeg;
    if (j.kind == Kind::continuous) {
      j.lower = -360, j.upper = 360;
    } else {
      if (!lim) fail(e, "joint '" + j.name + "' (" + type + ") needs <limit lower upper velocity>");
      j.lower = number(lim, "lower") * unit;
      j.upper = number(lim, "upper") * unit;
      j.limit_tolerance = std::max(written_precision(required(lim, "lower")), written_precision(required(lim, "upper"))) * unit;
      j.limit_tolerance = std::min(j.limit_tolerance, kMaxLimitTolerance);
      if (!(j.lower <= j.upper)) fail(lim, "joint '" + j.name + "': lower limit above the upper one");
    }
    if (const XMLElement* m = e->FirstChildElement("mimic")) {
      j.mimic = required(m, "joint");
      if (j.mimic == j.name) fail(m, "joint '" + j.name + "' mimics itself");
      if (m->Attribute("multiplier")) j.mimic_multiplier = number(m, "multiplier");
      if (m->Attribute("offset")) j.mimic_offset = number(m, "offset");
    }
    if (lim && lim->Attribute("velocity")) {
      j.velocity = positive(lim, "velocity") * unit;
      j.has_velocity = true;
    }
    return j;
  }

  Robot robot(const XMLElement* root) const {
    if (!root || std::string(root->Name()) != "robot") fail(root, "the root element must be <robot>");
    std::map<std::string, Link> links;
    std::vector<Joint> joints;
    for (const XMLElement* e = root->FirstChildElement(); e; e = e->NextSiblingElement()) {
      const std::string tag = e->Name();
      if (tag == "link") {
        Link l = link(e);
        if (links.count(l.name)) fail(e, "duplicate link '" + l.name + "'");
        links.emplace(l.name, std::move(l));
      } else if (tag == "joint") {
        joints.push_back(joint(e));
      }
    }
    if (links.empty()) fail(root, "no <link>");
    std::map<std::string, std::vector<const Joint*>> children;
    std::map<std::string, const Joint*> parent_of;
    for (const auto& j : joints) {
      for (const auto* name : {&j.parent, &j.child})
        if (!links.count(*name)) throw UrdfError(source_, j.line, "joint '" + j.name + "': unknown link '" + *name + "'");
      if (parent_of.count(j.child))
        throw UrdfError(source_, j.line, "link '" + j.child + "' has two parent joints");
      parent_of[j.child] = &j;
      children[j.parent].push_back(&j);
    }
    std::vector<std::string> roots;
    for (const auto& [name, l] : links)
      if (!parent_of.count(name)) roots.push_back(name);
    if (roots.size() != 1)
      fail(root, roots.empty() ? "the joints form a loop (no root link)" : "more than one root link ('" + roots[0] + "', '" + roots[1] + "')");
    // Every link reachable from the root, at most kMaxLinkDepth joints down (the walks below
    // recurse once per joint). Each link has one parent, so a link never reached sits on a loop.
    {
      std::map<std::string, int> level{{roots[0], 0}};
      std::vector<std::string> todo{roots[0]};
      while (!todo.empty()) {
        const std::string l = std::move(todo.back());
        todo.pop_back();
        for (const Joint* j : children[l]) {
          const int d = level[l] + 1;
          if (d > kMaxLinkDepth)
            throw UrdfError(source_, j->line, "joint '" + j->name + "': the chain is more than " +
                                                  std::to_string(kMaxLinkDepth) + " joints deep");
          level[j->child] = d;
          todo.push_back(j->child);
        }
      }
      for (const auto& j : joints)
        if (!level.count(j.child))
          throw UrdfError(source_, j.line, "joint '" + j.name + "': link '" + j.child + "' is not connected to the root link '" +
                                               roots[0] + "' (the joints form a loop)");
    }

    // Longest path in independent movable joints (not <mimic> followers) from each link.
    const auto independent = [](const Joint& j) { return static_cast<int>(j.kind != Kind::fixed && j.mimic.empty()); };
    std::function<int(const std::string&, int)> depth = [&](const std::string& l, int guard) -> int {
      if (guard > static_cast<int>(joints.size())) fail(root, "the joints form a loop");
      int best = 0;
      for (const Joint* j : children[l]) best = std::max(best, independent(*j) + depth(j->child, guard + 1));
      return best;
    };
    Robot r;
    r.name = root->Attribute("name") ? root->Attribute("name") : "urdf";
    std::vector<Joint> chain;  // movable joints, origins with fixed ones folded in
    struct Placed {
      int frame;
      std::string link;
      Pose pose;      // link frame in the arm frame (a finger's: at its joints' 0)
      int hand = -1;  // the hand joint moving it
    };
    std::vector<Placed> placed;
    struct Branch {
      const Joint* joint;
      int frame;
      Pose pose;  // the joint's parent link in the arm frame
    };
    std::vector<Branch> branches;  // joints leaving the chain, attached after the walk
    // With a tip, the arm is the path from the root to it; everything below the tip hangs on the
    // flange. Without one, the one chain of movable joints (a second movable branch makes the
    // choice ambiguous: an error asking for tip:), continued by the first fixed joint in file order.
    const std::string& tip = options_.tip;
    std::set<std::string> to_tip;
    if (!tip.empty()) {
      if (!links.count(tip)) fail(root, "tip: the description has no link '" + tip + "'");
      for (std::string l = tip;;) {
        to_tip.insert(l);
        const auto it = parent_of.find(l);
        if (it == parent_of.end()) break;
        l = it->second->parent;
      }
    }
    const auto movable_depth = [&](const Joint* j) { return independent(*j) + depth(j->child, 0); };
    // The leaf a branch ends in, following its longest movable path (ties: file order).
    const auto leaf_of = [&](const Joint* j) {
      while (!children[j->child].empty()) {
        const Joint* next = nullptr;
        for (const Joint* c : children[j->child])
          if (!next || movable_depth(c) > movable_depth(next)) next = c;
        j = next;
      }
      return j->child;
    };
    std::string at = roots[0];
    std::map<std::size_t, std::vector<CoupledJoint>> coupled;  // chain index -> its followers
    std::size_t since_movable = 0;  // the first entry of `placed` after the last movable (or coupled) joint
    Pose acc = Pose::Identity();  // from the current movable frame to link `at`
    int frame = 0;
    placed.push_back({0, at, acc});
    while (!children[at].empty() && at != tip) {
      const Joint* next = nullptr;
      int best = -1;
      std::vector<const Joint*> movable;
      for (const Joint* j : children[at]) {
        const int d = tip.empty() ? movable_depth(j) : static_cast<int>(to_tip.count(j->child));
        if (d > best) best = d, next = j;
        if (movable_depth(j) > 0) movable.push_back(j);
      }
      if (tip.empty() && movable.size() > 1) {
        std::string joints_list, leaves;
        for (const Joint* j : movable) {
          joints_list += (joints_list.empty() ? "'" : ", '") + j->name + "'";
          leaves += (leaves.empty() ? "" : ", ") + leaf_of(j);
        }
        fail(root, "the arm is ambiguous: at link '" + at + "' the movable joints " + joints_list +
                       " branch off; name the arm's last link with tip: in the cell (or an SRDF end effector). Candidate leaves: " +
                       leaves);
      }
      if (tip.empty() && best == 0 && next->kind != Kind::fixed) {
        // Past the last independent joint only fixed joints continue the flange (the first in
        // file order); a follower there is a branch.
        next = nullptr;
        for (const Joint* j : children[at])
          if (!next && j->kind == Kind::fixed) next = j;
        if (!next) {
          for (const Joint* j : children[at]) branches.push_back({j, frame, acc});
          break;
        }
      }
      for (const Joint* j : children[at])
        if (j != next) branches.push_back({j, frame, acc});
      if (next->kind == Kind::fixed) {
        acc = acc * next->origin;
      } else {
        if (!next->mimic.empty()) {
          // A coupled joint (IRB 5400's joint5b follows joint5): folded into the transform of the
          // movable joint just before it, which it must follow; the links between the two are
          // then posed by both, so they must carry no collision geometry (split-joint modelling).
          if (chain.empty() || chain.back().name != next->mimic)
            throw UrdfError(source_, next->line, "joint '" + next->name + "' on the arm chain mimics '" + next->mimic +
                                                     "', not the movable joint just before it" +
                                                     (chain.empty() ? std::string() : " ('" + chain.back().name + "')") +
                                                     ": such coupled arm joints are not modelled");
          for (std::size_t p = since_movable; p < placed.size(); ++p)
            if (!links.at(placed[p].link).geometry.empty())
              throw UrdfError(source_, next->line, "joint '" + next->name + "' follows '" + next->mimic + "', and link '" +
                                                       placed[p].link + "' between them has collision geometry: not modelled");
          std::vector<CoupledJoint>& followers = coupled[chain.size() - 1];
          if (followers.size() >= static_cast<std::size_t>(kMaxCoupled))
            throw UrdfError(source_, next->line, "joint '" + next->mimic + "' has more than " + std::to_string(kMaxCoupled) + " coupled followers");
          const Joint& leader = chain.back();
          const double u_leader = leader.kind == Kind::prismatic ? kMm : 1.0, u_follower = next->kind == Kind::prismatic ? kMm : 1.0;
          CoupledJoint c;
          c.name = next->name;
          c.origin = acc * next->origin;
          c.axis = next->axis;
          c.type = next->kind == Kind::prismatic ? JointType::prismatic : JointType::revolute;
          c.multiplier = next->mimic_multiplier * u_follower / u_leader;  // internal units: rad, mm
          c.offset = next->mimic_offset * u_follower;
          followers.push_back(c);
          for (std::size_t p = since_movable; p < placed.size(); ++p) placed[p].pose = Pose::Identity();  // no geometry
          acc = Pose::Identity();
          at = next->child;
          placed.push_back({frame, at, acc});
          since_movable = placed.size() - 1;
          continue;
        }
        Joint j = *next;
        j.origin = acc * next->origin;
        chain.push_back(j);
        if (chain.size() > static_cast<std::size_t>(kMaxJoints))
          fail(root, "more than " + std::to_string(kMaxJoints) + " movable joints in the chain");
        acc = Pose::Identity();
        ++frame;
      }
      at = next->child;
      placed.push_back({frame, at, acc});
      if (next->kind != Kind::fixed) since_movable = placed.size() - 1;
    }
    if (at == tip)
      for (const Joint* j : children[at]) branches.push_back({j, frame, acc});
    if (chain.empty()) fail(root, "no movable joint (revolute, continuous or prismatic)");
    const int n = static_cast<int>(chain.size());
    r.flange_offset = acc;
    const Pose to_flange = r.flange_offset.inverse();  // frame n includes flange_offset
    const auto in_frame = [&](int f, const Pose& p) { return f == n ? to_flange * p : p; };
    if (tip.empty() && chain.back().kind == Kind::prismatic && n > 1 && chain[n - 2].kind != Kind::prismatic)
      warnings_.push_back(source_ + ":" + std::to_string(chain.back().line) + ": joint '" + chain.back().name +
                          "' (prismatic) is the arm's last axis, J" + std::to_string(n) +
                          "; if it is a gripper finger, name the link it hangs on with tip: (OPEN/CLOSE then drive it)");

    // Side branches: fixed joints stay rigid, prismatic joints are fingers the hand drives, and
    // <mimic> followers of a finger follow it; any other movable joint is an error.
    std::map<std::string, int> hand_of;  // joint name -> index into r.hand
    const auto unit = [](const Joint& j) { return j.kind == Kind::prismatic ? kMm : kDeg; };
    std::set<std::string> on_chain;
    for (const Joint& j : chain) on_chain.insert(j.name);
    std::vector<const Joint*> hand_joints;  // parallel to r.hand
    std::function<void(const Joint*, int, const Pose&, int)> branch;
    const std::function<void(const std::string&, int, const Pose&, int)> attach = [&](const std::string& l, int f, const Pose& pose,
                                                                                       int hand) {
      placed.push_back({f, l, pose, hand});
      for (const Joint* j : children[l]) branch(j, f, pose, hand);
    };
    branch = [&](const Joint* j, int f, const Pose& pose, int hand) {
      const Pose at_joint = pose * j->origin;
      if (j->kind == Kind::fixed) return attach(j->child, f, at_joint, hand);
      if (j->kind != Kind::prismatic && j->mimic.empty())
        throw UrdfError(source_, j->line, "joint '" + j->name + "' (" + (j->kind == Kind::revolute ? "revolute" : "continuous") +
                                              ") branches off the arm chain at link '" + j->parent +
                                              "': only fixed joints, prismatic fingers and their <mimic> followers can; if it "
                                              "belongs to the arm, name the arm's last link with tip:");
      HandJoint h;
      h.name = j->name;
      h.frame = f;
      h.parent = hand;
      h.origin = in_frame(f, at_joint);
      h.axis = j->axis;
      h.type = j->kind == Kind::prismatic ? JointType::prismatic : JointType::revolute;
      h.lower = j->lower, h.upper = j->upper;
      h.open = j->upper, h.closed = j->lower;  // OPEN = the upper limit, CLOSE = the lower one
      const int k = static_cast<int>(r.hand.size());
      r.hand.push_back(h);
      hand_joints.push_back(j);
      hand_of[j->name] = k;
      attach(j->child, f, at_joint, k);
    };
    for (const Branch& b : branches) branch(b.joint, b.frame, b.pose, -1);
    // Followers: of a finger (or of a follower of one), or of an arm joint (a parallel-link
    // lever; straight on the arm, with no hand joint on it).
    for (std::size_t k = 0; k < r.hand.size(); ++k) {
      const Joint& j = *hand_joints[k];
      if (j.mimic.empty()) continue;
      const auto leader = hand_of.find(j.mimic);
      HandJoint& h = r.hand[k];
      if (leader == hand_of.end()) {
        const auto arm = std::find_if(chain.begin(), chain.end(), [&](const Joint& c) { return c.name == j.mimic; });
        if (arm == chain.end())
          throw UrdfError(source_, j.line, "joint '" + j.name + "' mimics '" + j.mimic +
                                               "', which is neither an arm joint nor a finger of the hand");
        if (&*arm == &chain.back() && arm->kind == Kind::prismatic)
          throw UrdfError(source_, j.line, "joint '" + j.name + "' mimics '" + j.mimic + "', the arm's last axis: if '" + j.mimic +
                                               "' is a gripper finger, name the link the hand hangs on with tip:");
        if (h.parent >= 0)
          throw UrdfError(source_, j.line, "joint '" + j.name + "' follows the arm joint '" + j.mimic + "' but rides on the finger '" +
                                               r.hand[static_cast<std::size_t>(h.parent)].name + "': not modelled");
        h.arm_joint = static_cast<int>(arm - chain.begin());
        h.multiplier = j.mimic_multiplier * unit(j) / unit(*arm);
        h.offset = j.mimic_offset * unit(j);
        continue;
      }
      const Joint& l = *hand_joints[static_cast<std::size_t>(leader->second)];
      h.leader = leader->second;
      h.multiplier = j.mimic_multiplier * unit(j) / unit(l);
      h.offset = j.mimic_offset * unit(j);
    }
    for (std::size_t k = 0; k < r.hand.size(); ++k) {  // no cycle of followers
      int at_k = static_cast<int>(k);
      for (std::size_t steps = 0; at_k >= 0 && r.hand[static_cast<std::size_t>(at_k)].leader >= 0; ++steps) {
        if (steps > r.hand.size())
          throw UrdfError(source_, hand_joints[k]->line, "joint '" + r.hand[k].name + "': its <mimic> joints form a cycle");
        at_k = r.hand[static_cast<std::size_t>(at_k)].leader;
      }
    }
    for (const HandJoint& h : r.hand)
      if (h.parent >= 0 && r.hand[static_cast<std::size_t>(h.parent)].arm_joint >= 0)
        throw UrdfError(source_, hand_joints[static_cast<std::size_t>(&h - r.hand.data())]->line,
                        "joint '" + h.name + "' rides on '" + r.hand[static_cast<std::size_t>(h.parent)].name +
                            "', a follower of an arm joint: not modelled");
    update_hand_followers(r);
    r.lower.resize(n), r.upper.resize(n), r.limit_tolerance.resize(n), r.max_velocity.resize(n), r.max_acceleration.resize(n), r.ready.resize(n);
    for (int i = 0; i < n; ++i) {
      const Joint& j = chain[static_cast<std::size_t>(i)];
      ChainJoint cj;
      cj.name = j.name;
      cj.origin = j.origin;
      cj.axis = j.axis;
      cj.type = j.kind == Kind::prismatic ? JointType::prismatic : JointType::revolute;
      if (auto it = coupled.find(static_cast<std::size_t>(i)); it != coupled.end()) cj.coupled = it->second;
      r.chain.push_back(std::move(cj));
      r.mapping.push_back({1.0, 0.0});
      r.lower[i] = j.lower, r.upper[i] = j.upper;
      r.limit_tolerance[i] = j.limit_tolerance;
      const double v = j.has_velocity ? j.velocity : (j.kind == Kind::prismatic ? 250.0 : 180.0);
      r.max_velocity[i] = v;
      r.max_acceleration[i] = 4 * v;
      r.ready[i] = std::clamp(0.0, j.lower, j.upper);
    }
    // Bodies: one per URDF link with collision geometry, in the frame of its movable joint.
    for (const Placed& p : placed) {
      const Link& l = links.at(p.link);
      if (l.geometry.empty()) continue;
      collision::Polyhedron body;
      const Pose pose = in_frame(p.frame, p.pose);
      for (const auto& g : l.geometry) body = collision::merged(body, collision::transformed(g.mesh, pose * g.pose));
      r.bodies.push_back({p.frame, l.name, std::move(body), p.hand});
    }
    for (const auto& [name, l] : links) r.links.push_back(name);
    r.warnings = warnings_;
    return r;
  }

 private:
  std::string source_;
  std::string base_dir_;
  const UrdfOptions& options_;
  mutable std::vector<std::string> warnings_;  // mesh warnings, "urdf:line: mesh: face N: ..."
};
}  // namespace

namespace {
Error as_error(const UrdfError& e) { return Error{e.what(), "", e.file(), e.line()}; }

Robot load_text_or_throw(const std::string& xml, const std::string& source_name, const std::string& base_dir,
                         const UrdfOptions& options) {
  tinyxml2::XMLDocument doc;
  if (doc.Parse(xml.c_str(), xml.size()) != tinyxml2::XML_SUCCESS)
    throw UrdfError(source_name, doc.ErrorLineNum(), std::string("XML error: ") + doc.ErrorStr());
  return Parser(source_name, base_dir, options).robot(doc.RootElement());
}

}  // namespace

Result<Robot> load_urdf_text(const std::string& xml, const std::string& source_name, const std::string& base_dir,
                             const UrdfOptions& options) {
  try {
    return load_text_or_throw(xml, source_name, base_dir, options);
  } catch (const UrdfError& e) {
    return as_error(e);
  }
}

Result<Robot> load_urdf(const std::string& path, const UrdfOptions& options) {
  const std::filesystem::path dir = std::filesystem::path(path).parent_path();
  const std::string base_dir = dir.empty() ? "." : dir.string();
  try {
    if (std::filesystem::path(path).extension() == ".xacro")
      return load_text_or_throw(expand_xacro(path, options.packages, options.xacro_args), path + " (expanded)", base_dir,
                                options);
  } catch (const UrdfError& e) {
    return as_error(e);
  }
  Result<std::string> xml = collision::read_file_bounded(path, collision::kMaxTextFileBytes);
  if (!xml) return as_error(UrdfError(path, 0, xml.error().message));  // one "file:line: message" form
  return load_urdf_text(*xml, path, base_dir, options);
}

}  // namespace asimov::robots
