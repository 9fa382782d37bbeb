// A test process's own scratch folder: every file a test writes goes there, so parallel test
// processes never share one and nothing is left in the temp folder.
#pragma once
#include <filesystem>
#include <string>
#include <unistd.h>

namespace asimov::test {

// This test process's scratch folder, TMPDIR/asimov-test-PID, created on first use and removed
// with everything in it when the process exits (a failed test too: Catch2's main returns). Not by
// a forked child (it ends with _exit, and the removal checks the pid). Only a crash or a kill
// leaves it.
inline std::filesystem::path scratch_dir() {
  struct Folder {
    pid_t owner = ::getpid();
    std::filesystem::path dir = std::filesystem::temp_directory_path() / ("asimov-test-" + std::to_string(owner));
    ~Folder() {
      std::error_code ignored;
      if (::getpid() == owner) std::filesystem::remove_all(dir, ignored);
    }
  };
  static const Folder folder;
  std::filesystem::create_directories(folder.dir);
  return folder.dir;
}

// A named folder inside scratch_dir(), created on first use.
inline std::filesystem::path scratch_dir(const std::string& name) {
  auto dir = scratch_dir() / name;
  std::filesystem::create_directories(dir);
  return dir;
}

}  // namespace asimov::test
