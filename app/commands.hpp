// The subcommands of the asimov executable. Each returns an ExitCode (app/exit_codes.hpp).
#pragma once
#include <iosfwd>
#include <string>
#include <vector>

namespace asimov::app {

struct RunOptions {
  std::string file;         // FILE.v2
  std::string main;         // program to run; empty: the first program in the file
  std::string cell;         // CELL.yaml; empty: the built-in default cell
  std::string report;       // --report path, optional
  std::string trace;        // --trace path, optional
};

struct MonitorOptions {
  std::string cell;                 // CELL.yaml; empty: the built-in default cell
  std::vector<std::string> files;   // loaded first, as LOAD does
  bool strict = false;              // the first failed command ends the session (exit 2)
};

int run_command(const RunOptions& options, std::ostream& out, std::ostream& err);
int check_command(const std::string& file, std::ostream& out, std::ostream& err);
// The VAL monitor (cmd_monitor.cpp): interactive with libedit when stdin is a terminal.
int monitor_command(const MonitorOptions& options, std::istream& in, std::ostream& out, std::ostream& err);

}  // namespace asimov::app
