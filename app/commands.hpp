// The subcommands of the asimov executable. Each returns an ExitCode (app/exit_codes.hpp).
#pragma once
#include <iosfwd>
#include <string>

namespace asimov::app {

struct RunOptions {
  std::string file;         // FILE.v2
  std::string main;         // program to run; empty: the first program in the file
  std::string cell;         // CELL.yaml; empty: the built-in default cell
  std::string report;       // --report path, optional
  std::string trace;        // --trace path, optional
};

int run_command(const RunOptions& options, std::ostream& out, std::ostream& err);
int check_command(const std::string& file, std::ostream& out, std::ostream& err);

}  // namespace asimov::app
