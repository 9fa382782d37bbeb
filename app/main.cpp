// asimov: runs VAL II programs in simulation and halts them the instant the arm touches
// something. Subcommands: run, check, pairs, monitor, test, serve; no subcommand starts the monitor (README.md
// has the contract).
#include "app/commands.hpp"
#include "app/exit_codes.hpp"
#include "app/serve/cmd_serve.hpp"
#include "asimov/version.hpp"

#include <CLI/CLI.hpp>

#include <iostream>

int main(int argc, char** argv) {
  using namespace asimov::app;
  CLI::App cli{"asimov: VAL II programs in simulation, halted on contact"};
  cli.require_subcommand(0, 1);  // none: the monitor
  cli.set_version_flag("--version", std::string("asimov ") + asimov::kVersion, "print the version and exit");
  cli.footer("Without a subcommand asimov starts the monitor (as `asimov monitor`).");

  RunOptions run;
  auto* run_cmd = cli.add_subcommand("run", "load FILE.v2 and run a program in the cell");
  run_cmd->add_option("file", run.file, "the .v2 file")->required();
  run_cmd->add_option("--main", run.main, "program to run (default: the first in the file)");
  run_cmd->add_option("--cell", run.cell, "cell file (YAML); default: the built-in cell");
  run_cmd->add_option("--report", run.report, "write a JSON report of the run (- : stdout)");
  run_cmd->add_option("--trace", run.trace, "write every checked pose as JSON (- : stdout)");
  run_cmd->add_option("--replay", run.replay, "write a self-contained HTML page replaying the run in 3D");
  run_cmd->add_option("--files", run.files, "folder the program's files are read and written in (default: FILE's folder)");

  std::string check_file;
  auto* check_cmd = cli.add_subcommand("check", "load and check FILE.v2; nothing runs");
  check_cmd->add_option("file", check_file, "the .v2 file")->required();

  PairsOptions pairs;
  auto* pairs_cmd = cli.add_subcommand("pairs", "print the generated collision pair matrix of a cell (cached)");
  pairs_cmd->add_option("cell", pairs.cell, "cell file (YAML); default: the built-in cell");
  pairs_cmd->add_option("--samples", pairs.samples, "random poses for NEVER (default 10000)")
      ->check(CLI::Range(1, 10000000));  // as collision.pair_samples in a cell
  pairs_cmd->add_option("--cache", pairs.cache, "cache file (default: CELL.yaml.pairs)");
  pairs_cmd->add_flag("--no-cache", pairs.no_cache, "neither read nor write a cache");

  MonitorOptions monitor;
  auto* monitor_cmd = cli.add_subcommand("monitor", "the VAL monitor: commands from the terminal or stdin");
  monitor_cmd->add_option("files", monitor.files, "FILE.v2 files to load first");
  monitor_cmd->add_option("--cell", monitor.cell, "cell file (YAML); default: the built-in cell");
  monitor_cmd->add_flag("--strict", monitor.strict, "the first failed command ends the session with exit code 2");

  TestOptions test;
  auto* test_cmd = cli.add_subcommand("test", "run the sample-program cases under PATHs against their expected results");
  test_cmd->add_option("paths", test.paths, "folders (searched recursively) or case files; default: .");
  test_cmd->add_option("--filter", test.filter, "only cases whose name contains PATTERN (a glob if it has * ? [)");
  test_cmd->add_option("--junit", test.junit, "write the results as JUnit XML to FILE");
  test_cmd->add_option("-j,--jobs", test.jobs, "cases run at once (default 1)")->check(CLI::Range(1, 64));
  test_cmd->add_option("--timeout", test.timeout_s, "seconds before a case is stopped and fails (default 600)")
      ->check(CLI::Range(1, 86400));
  test_cmd->add_flag("--update", test.update, "maintainers: rewrite the expected files of failed cases");
  std::string shard;
  test_cmd->add_option("--shard", shard, "run only shard K of N (K/N; by a hash of the case name, docs/scale-out.md)");
  test_cmd->add_flag("--list", test.list, "print the selected case names, one a line; nothing runs");
  test_cmd->add_option("--merge-junit", test.merge_junit,
                       "write OUT merging the JUnit files given as PATHs (from --shard runs); nothing runs");

  asimov::serve::ServeOptions serve;
  auto* serve_cmd = cli.add_subcommand("serve", "the studio: editor, monitor and 3D cell in the browser (prints the URL)");
  serve_cmd->add_option("--workspace", serve.workspace, "folder files are opened from and saved to (default: .)");
  serve_cmd->add_option("--cell", serve.cell, "cell file (YAML); default: the built-in cell");
  serve_cmd->add_option("--address", serve.address, "address to listen on (default 127.0.0.1: this machine only)");
  serve_cmd->add_option("--port", serve.port, "port (default 0: any free port)")->check(CLI::Range(0, 65535));
  serve_cmd->add_option("--open", serve.file, "file of the workspace the editor opens (default: the sample program)");

  try {
    cli.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return cli.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return cli.exit(e);
  } catch (const CLI::ParseError& e) {
    cli.exit(e);
    return kExitUsage;  // our contract: every usage error exits 1
  }

  try {
    if (*run_cmd) return run_command(run, std::cout, std::cerr);
    if (*check_cmd) return check_command(check_file, std::cout, std::cerr);
    if (*pairs_cmd) return pairs_command(pairs, std::cout, std::cerr);
    if (*serve_cmd) return asimov::serve::serve_command(serve, std::cout, std::cerr);
    if (*test_cmd) {
      if (!shard.empty() && !parse_shard(shard, test.shard, test.shards)) {
        std::cerr << "*Invalid argument*  --shard " << shard << ": expected K/N with 1 <= K <= N\n";
        return kExitUsage;
      }
      return test_command(test, std::cout, std::cerr);
    }
    return monitor_command(monitor, std::cin, std::cout, std::cerr);  // `monitor` or no subcommand
  } catch (const std::exception& e) {
    // The layers report problems as values; anything reaching here is a defect, still no crash.
    std::cerr << "*Internal error*  " << e.what() << '\n';
    return kExitUsage;
  }
  return kExitUsage;
}
