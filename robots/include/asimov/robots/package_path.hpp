// ROS resource URIs as the ROS tools resolve them: `package://NAME/rest` against a package
// search path (each root searched, depth first, for folders holding a package.xml whose <name>
// is NAME; a package's folder is not searched further, CATKIN_IGNORE / COLCON_IGNORE folders are
// skipped), `file:///absolute/path`, and plain paths relative to the referring file's folder.
#pragma once
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace asimov::robots {

class PackagePath {
 public:
  PackagePath() = default;
  // `first` (e.g. a cell's `packages:`), then every entry of ROS_PACKAGE_PATH (':'-separated).
  static PackagePath with_environment(std::vector<std::filesystem::path> first);
  void add_root(std::filesystem::path root) { roots_.push_back(std::move(root)); }
  const std::vector<std::filesystem::path>& roots() const { return roots_; }
  // The folder of package NAME, or nothing.
  std::optional<std::filesystem::path> find(const std::string& name) const;

 private:
  std::vector<std::filesystem::path> roots_;
  mutable std::map<std::string, std::optional<std::filesystem::path>> cache_;
};

// The file a URI names, or an error message in `error` (empty path). `base_dir` resolves
// relative paths.
std::filesystem::path resolve_uri(const std::string& uri, const std::filesystem::path& base_dir, const PackagePath& packages,
                                  std::string& error);

// The <name> of the package.xml in `dir`, empty when there is none or it cannot be read.
std::string package_name(const std::filesystem::path& dir);

}  // namespace asimov::robots
