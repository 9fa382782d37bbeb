// Runs the asimov executable as a user would and captures exit code, stdout and stderr.
#pragma once
#include "scratch.hpp"

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
