// The studio's one folder of files (`asimov serve --workspace DIR`): programs opened from it and
// saved into it, replay pages exported into it, nothing read or written anywhere else. Every name
// is resolved beneath the folder by core::ConfinedFolder (docs/design.md "Confinement"), the
// same confinement the interpreter applies to a program's files.
#pragma once
#include "asimov/core/confined_folder.hpp"
#include "asimov/core/result.hpp"

#include <filesystem>
#include <string>
#include <vector>

namespace asimov::serve {

constexpr std::size_t kMaxFileBytes = 16 << 20;  // a file opened in the studio
constexpr std::size_t kMaxListed = 2000;         // names listed

class Workspace {
 public:
  // Opens the folder (which must exist); the error says why not.
  static Result<Workspace> open(const std::filesystem::path& folder);
  const std::filesystem::path& path() const { return folder_.path(); }

  // A file's bytes (at most kMaxFileBytes); "*File not found*" and kin when it cannot be read.
  Result<std::string> read(const std::string& name) const;
  // Writes `bytes` whole under `name` (a temporary file renamed over it: a reader never sees
  // half a file); replaces an existing regular file.
  Result<void> write(const std::string& name, const std::string& bytes) const;
  // The names of the folder's files that the studio opens (.v2, .yaml, .dat, .html, .txt), in
  // the folder itself (not below), sorted.
  std::vector<std::string> list() const;
  // Whether `name` is a regular file beneath the folder.
  bool is_file(const std::string& name) const { return folder_.is_file(name); }

 private:
  explicit Workspace(core::ConfinedFolder folder) : folder_(std::move(folder)) {}
  core::ConfinedFolder folder_;
};

}  // namespace asimov::serve
