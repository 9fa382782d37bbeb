// SRDF reader (srdf.hpp). Structure errors are thrown as UrdfError at the element's line and
// returned as an Error, as the URDF loader does.
#include "asimov/robots/srdf.hpp"

#include "urdf_error.hpp"

#include "asimov/collision/text_file.hpp"

#include <tinyxml2.h>

#include <algorithm>
#include <cstring>
#include <set>

namespace asimov::robots {
namespace {
using tinyxml2::XMLElement;

class Reader {
 public:
  explicit Reader(std::string file) { out_.file = std::move(file); }

  Srdf run(const XMLElement* root) {
    if (!root || std::strcmp(root->Name(), "robot") != 0) fail(root, "the root element must be <robot>");
    if (const char* n = root->Attribute("name")) out_.robot = n;
    for (const XMLElement* e = root->FirstChildElement(); e; e = e->NextSiblingElement()) {
      const std::string tag = e->Name();
      if (tag == "disable_collisions" || tag == "enable_collisions") {
        Srdf::Pair p{required(e, "link1"), required(e, "link2"), e->Attribute("reason") ? e->Attribute("reason") : "", e->GetLineNum()};
        (tag == "enable_collisions" ? out_.enabled : out_.disabled).push_back(std::move(p));
      } else if (tag == "disable_default_collisions") {
        out_.disabled_links.emplace_back(required(e, "link"), e->GetLineNum());
      } else if (tag == "group") {
        out_.groups.push_back(group(e));
      } else if (tag == "end_effector") {
        out_.end_effectors.push_back({required(e, "name"), required(e, "group"), required(e, "parent_link"),
                                      e->Attribute("parent_group") ? e->Attribute("parent_group") : "", e->GetLineNum()});
      } else if (tag == "group_state" || tag == "virtual_joint" || tag == "passive_joint" ||
                 tag == "link_sphere_approximation" || tag == "joint_properties") {
        // MoveIt planning data: nothing a simulation of the controller uses.
      } else {
        warn(e, "<" + tag + "> is not an SRDF element: ignored");
      }
    }
    // Names inside the file: every group a group or end effector refers to exists.
    std::set<std::string> groups;
    for (const auto& g : out_.groups)
      if (!groups.insert(g.name).second) throw UrdfError(out_.file, g.line, "duplicate group '" + g.name + "'");
    for (const auto& g : out_.groups)
      for (const auto& sub : g.subgroups)
        if (!groups.count(sub)) throw UrdfError(out_.file, g.line, "group '" + g.name + "': unknown subgroup '" + sub + "'");
    for (const auto& ee : out_.end_effectors) {
      if (!groups.count(ee.group))
        throw UrdfError(out_.file, ee.line, "end_effector '" + ee.name + "': unknown group '" + ee.group + "'");
      if (!ee.parent_group.empty() && !groups.count(ee.parent_group))
        throw UrdfError(out_.file, ee.line, "end_effector '" + ee.name + "': unknown parent_group '" + ee.parent_group + "'");
    }
    return std::move(out_);
  }

 private:
  [[noreturn]] void fail(const XMLElement* e, const std::string& what) const {
    throw UrdfError(out_.file, e ? e->GetLineNum() : 0, what);
  }
  void warn(const XMLElement* e, const std::string& what) {
    out_.warnings.push_back(out_.file + ":" + std::to_string(e->GetLineNum()) + ": " + what);
  }
  std::string required(const XMLElement* e, const char* attr) const {
    const char* v = e->Attribute(attr);
    if (!v || !*v) fail(e, std::string("<") + e->Name() + "> needs the attribute '" + attr + "'");
    return v;
  }
  Srdf::Group group(const XMLElement* e) {
    Srdf::Group g;
    g.name = required(e, "name");
    g.line = e->GetLineNum();
    for (const XMLElement* c = e->FirstChildElement(); c; c = c->NextSiblingElement()) {
      const std::string tag = c->Name();
      if (tag == "link") g.links.push_back(required(c, "name"));
      else if (tag == "joint") g.joints.push_back(required(c, "name"));
      else if (tag == "group") g.subgroups.push_back(required(c, "name"));
      else if (tag == "chain") {
        if (!g.chain_base.empty()) fail(c, "group '" + g.name + "' has more than one <chain>");
        g.chain_base = required(c, "base_link");
        g.chain_tip = required(c, "tip_link");
      } else {
        warn(c, "<" + tag + "> in group '" + g.name + "' is not an SRDF element: ignored");
      }
    }
    return g;
  }

  Srdf out_;
};

Error as_error(const UrdfError& e) { return Error{e.what(), "", e.file(), e.line()}; }
}  // namespace

Result<Srdf> load_srdf_text(const std::string& xml, const std::string& source_name) {
  tinyxml2::XMLDocument doc;
  try {
    if (doc.Parse(xml.c_str(), xml.size()) != tinyxml2::XML_SUCCESS)
      throw UrdfError(source_name, doc.ErrorLineNum(), std::string("XML error: ") + doc.ErrorStr());
    return Reader(source_name).run(doc.RootElement());
  } catch (const UrdfError& e) {
    return as_error(e);
  }
}

Result<Srdf> load_srdf(const std::string& path) {
  Result<std::string> xml = collision::read_file_bounded(path, collision::kMaxTextFileBytes);
  if (!xml) return as_error(UrdfError(path, 0, xml.error().message));
  return load_srdf_text(*xml, path);
}

Result<void> check_srdf_links(const Srdf& srdf, const std::vector<std::string>& links) {
  const std::set<std::string> known(links.begin(), links.end());
  auto check = [&](const std::string& name, int line, const std::string& where) -> Result<void> {
    if (known.count(name)) return {};
    return as_error(UrdfError(srdf.file, line, where + ": the robot has no link '" + name + "'"));
  };
  for (const auto* list : {&srdf.disabled, &srdf.enabled})
    for (const auto& p : *list)
      for (const auto* l : {&p.link1, &p.link2})
        if (auto r = check(*l, p.line, list == &srdf.disabled ? "disable_collisions" : "enable_collisions"); !r) return r;
  for (const auto& [l, line] : srdf.disabled_links)
    if (auto r = check(l, line, "disable_default_collisions"); !r) return r;
  for (const auto& g : srdf.groups) {
    for (const auto& l : g.links)
      if (auto r = check(l, g.line, "group '" + g.name + "'"); !r) return r;
    if (!g.chain_base.empty())
      for (const auto* l : {&g.chain_base, &g.chain_tip})
        if (auto r = check(*l, g.line, "group '" + g.name + "' chain"); !r) return r;
  }
  for (const auto& ee : srdf.end_effectors)
    if (auto r = check(ee.parent_link, ee.line, "end_effector '" + ee.name + "' parent_link"); !r) return r;
  return {};
}

std::vector<std::pair<std::string, std::string>> srdf_disabled_pairs(const Srdf& srdf, const std::vector<std::string>& bodies) {
  using Key = std::pair<std::string, std::string>;
  const auto key = [](const std::string& a, const std::string& b) { return a < b ? Key{a, b} : Key{b, a}; };
  std::set<Key> off, on;
  for (const auto& p : srdf.disabled) off.insert(key(p.link1, p.link2));
  for (const auto& p : srdf.enabled) on.insert(key(p.link1, p.link2));
  std::set<std::string> all_off;
  for (const auto& l : srdf.disabled_links) all_off.insert(l.first);
  std::vector<Key> out;
  for (std::size_t i = 0; i < bodies.size(); ++i)
    for (std::size_t j = i + 1; j < bodies.size(); ++j) {
      const Key k = key(bodies[i], bodies[j]);
      if (on.count(k)) continue;
      if (off.count(k) || all_off.count(bodies[i]) || all_off.count(bodies[j])) out.emplace_back(bodies[i], bodies[j]);
    }
  return out;
}

std::string srdf_tip(const Srdf& srdf) {
  std::string tip;
  for (const auto& ee : srdf.end_effectors) {
    if (!tip.empty() && tip != ee.parent_link) return {};
    tip = ee.parent_link;
  }
  return tip;
}

std::string describe_srdf(const Srdf& srdf) {
  std::string out = "groups:";
  if (srdf.groups.empty()) out += " none";
  for (std::size_t i = 0; i < srdf.groups.size(); ++i) {
    const auto& g = srdf.groups[i];
    out += (i ? ", " : " ") + g.name;
    if (!g.chain_base.empty()) out += " (chain " + g.chain_base + " -> " + g.chain_tip + ")";
    else out += " (" + std::to_string(g.links.size()) + " links, " + std::to_string(g.joints.size()) + " joints)";
  }
  out += "; end effectors:";
  if (srdf.end_effectors.empty()) out += " none";
  for (std::size_t i = 0; i < srdf.end_effectors.size(); ++i) {
    const auto& ee = srdf.end_effectors[i];
    out += (i ? ", " : " ") + ee.name + " (parent " + ee.parent_link + ", group " + ee.group + ")";
  }
  return out;
}

}  // namespace asimov::robots
