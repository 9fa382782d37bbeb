#include "asimov/robots/package_path.hpp"

#include <tinyxml2.h>

#include <algorithm>
#include <cstdlib>
#include <sstream>
#include <system_error>

namespace asimov::robots {
namespace fs = std::filesystem;
namespace {
constexpr int kMaxDepth = 8;  // crawl depth below a root (a workspace's src/ is 1-3 deep)

std::optional<fs::path> crawl(const fs::path& dir, const std::string& name, int depth) {
  std::error_code ec;
  if (depth > kMaxDepth || !fs::is_directory(dir, ec)) return std::nullopt;
  if (fs::exists(dir / "package.xml", ec)) {
    if (package_name(dir) == name) return dir;
    return std::nullopt;  // another package: its folders are its own
  }
  if (fs::exists(dir / "CATKIN_IGNORE", ec) || fs::exists(dir / "COLCON_IGNORE", ec)) return std::nullopt;
  std::vector<fs::path> subdirs;
  for (fs::directory_iterator it(dir, fs::directory_options::skip_permission_denied, ec), end; !ec && it != end;
       it.increment(ec)) {
    const auto leaf = it->path().filename().string();
    if (!leaf.empty() && leaf[0] != '.' && it->is_directory(ec)) subdirs.push_back(it->path());
  }
  std::sort(subdirs.begin(), subdirs.end());  // the same answer on every file system
  for (const auto& s : subdirs)
    if (auto found = crawl(s, name, depth + 1)) return found;
  return std::nullopt;
}
}  // namespace

std::string package_name(const fs::path& dir) {
  tinyxml2::XMLDocument doc;
  if (doc.LoadFile((dir / "package.xml").string().c_str()) != tinyxml2::XML_SUCCESS) return {};
  const tinyxml2::XMLElement* root = doc.RootElement();
  const tinyxml2::XMLElement* n = root ? root->FirstChildElement("name") : nullptr;
  if (!n || !n->GetText()) return {};
  std::string s = n->GetText();
  const auto b = s.find_first_not_of(" \t\r\n"), e = s.find_last_not_of(" \t\r\n");
  return b == std::string::npos ? std::string() : s.substr(b, e - b + 1);
}

PackagePath PackagePath::with_environment(std::vector<fs::path> first) {
  PackagePath p;
  for (auto& r : first) p.add_root(std::move(r));
  if (const char* env = std::getenv("ROS_PACKAGE_PATH")) {
    std::stringstream in(env);
    std::string item;
    while (std::getline(in, item, ':'))
      if (!item.empty()) p.add_root(item);
  }
  return p;
}

std::optional<fs::path> PackagePath::find(const std::string& name) const {
  if (auto it = cache_.find(name); it != cache_.end()) return it->second;
  std::optional<fs::path> found;
  for (const auto& r : roots_)
    if ((found = crawl(r, name, 0))) break;
  cache_[name] = found;
  return found;
}

fs::path resolve_uri(const std::string& uri, const fs::path& base_dir, const PackagePath& packages, std::string& error) {
  error.clear();
  constexpr std::string_view kPackage = "package://", kFile = "file://";
  if (uri.rfind(kPackage, 0) == 0) {
    const std::string rest = uri.substr(kPackage.size());
    const auto slash = rest.find('/');
    const std::string name = rest.substr(0, slash);
    if (name.empty()) {
      error = "'" + uri + "': no package name";
      return {};
    }
    const auto dir = packages.find(name);
    if (!dir) {
      std::string roots;
      for (const auto& r : packages.roots()) roots += (roots.empty() ? "" : ", ") + r.string();
      error = "'" + uri + "': package '" + name + "' not found (searched: " + (roots.empty() ? "nothing; give `packages:` in the cell or set ROS_PACKAGE_PATH" : roots) + ")";
      return {};
    }
    return slash == std::string::npos ? *dir : (*dir / rest.substr(slash + 1)).lexically_normal();
  }
  if (uri.rfind(kFile, 0) == 0) {
    const fs::path p = uri.substr(kFile.size());
    return p.is_relative() ? (base_dir / p).lexically_normal() : p;
  }
  if (uri.find("://") != std::string::npos) {
    error = "'" + uri + "': only package:// and file:// URIs are supported";
    return {};
  }
  const fs::path p = uri;
  return p.is_relative() ? (base_dir / p).lexically_normal() : p;
}

}  // namespace asimov::robots
