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
  std::string replay;       // --replay path (HTML), optional
  std::string files;        // --files DIR: the folder FOPENR ... names resolve in; default: FILE's folder
};

struct MonitorOptions {
  std::string cell;                 // CELL.yaml; empty: the built-in default cell
  std::vector<std::string> files;   // loaded first, as LOAD does
  bool strict = false;              // the first failed command ends the session (exit 2)
};

struct PairsOptions {
  std::string cell;         // CELL.yaml; empty: the built-in default cell
  std::string cache;        // --cache FILE; empty: CELL.yaml.pairs, for the built-in cell
                            //   $XDG_CACHE_HOME (or ~/.cache)/asimov/default-cell.pairs
  bool no_cache = false;    // --no-cache: neither read nor write a cache
  int samples = 10000;      // --samples N: random poses for NEVER
};

struct TestOptions {
  std::vector<std::string> paths;   // folders or case files; empty: the current folder
  std::string filter;               // --filter: substring of the case name, or a glob with * ? [
  std::string junit;                // --junit FILE: JUnit XML of the results
  int jobs = 1;                     // -j N: cases run at once
  int timeout_s = 600;              // --timeout S: a case running longer fails
  bool update = false;              // --update: rewrite the expected files of failed cases
  std::string executable;           // the asimov executable to run; empty: this process's own
  int shard = 0, shards = 0;        // --shard K/N: only the cases whose name hashes to K-1 mod N
                                    //   (0/0: all); docs/scale-out.md
  bool list = false;                // --list: print the selected case names; nothing runs
  std::string merge_junit;          // --merge-junit OUT: merge the JUnit files given as PATHs
};

// Parses "K/N" (1 <= K <= N <= 100000) for --shard; false when malformed.
bool parse_shard(const std::string& text, int& shard, int& shards);
// The shard (0-based) a case named `name` belongs to among `shards`: FNV-1a of the name mod N,
// so the assignment depends on nothing but the name (stable across machines and runs).
int shard_of(const std::string& name, int shards);

// True when `path` is a regular file; otherwise prints "*File not found*  path" to `err`.
bool require_file(const std::string& path, std::ostream& err);

int run_command(const RunOptions& options, std::ostream& out, std::ostream& err);
int check_command(const std::string& file, std::ostream& out, std::ostream& err);
// The VAL monitor (cmd_monitor.cpp): interactive with libedit when stdin is a terminal.
int monitor_command(const MonitorOptions& options, std::istream& in, std::ostream& out, std::ostream& err);
// The generated participation matrix of a cell (cmd_pairs.cpp), cached next to the cell file.
int pairs_command(const PairsOptions& options, std::ostream& out, std::ostream& err);
// Suites of sample programs with expected results (cmd_test.cpp, app/suite.hpp): exit 0 when
// every case passed, 4 when one failed, 1 for usage/file errors.
int test_command(const TestOptions& options, std::ostream& out, std::ostream& err);

}  // namespace asimov::app
