// Runs the asimov executable as a user would and captures exit code, stdout and stderr.
#pragma once
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <sys/wait.h>
#include <unistd.h>

namespace asimov::test {

struct CliResult {
  int exit_code = -1;
  std::string out, err;
};

inline std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

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

// `args` is appended to the executable path as is (quote paths with spaces yourself).
inline CliResult run_cli(const std::string& args, const std::string& stdin_text = "") {
  static int counter = 0;
  const auto dir = scratch_dir();
  const auto tag = std::to_string(++counter);
  const auto out = dir / ("out" + tag), err = dir / ("err" + tag), in = dir / ("in" + tag);
  std::ofstream(in) << stdin_text;
  const std::string cmd = std::string(ASIMOV_BINARY) + " " + args + " <" + in.string() + " >" +
                          out.string() + " 2>" + err.string();
  const int status = std::system(cmd.c_str());
  CliResult r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = slurp(out);
  r.err = slurp(err);
  return r;
}

inline std::string source_path(const std::string& relative) {
  return std::string(ASIMOV_SOURCE_DIR) + "/" + relative;
}

}  // namespace asimov::test
