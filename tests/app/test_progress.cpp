// `asimov run` progress on a terminal (app/cmd_run.cpp RunProgress): simulated time, program
// step of the motion and poses checked on stderr, redrawn in place and erased at the end; nothing when stderr
// is not a terminal.
#include "support/run_cli.hpp"

#include <catch2/catch.hpp>

#include <cstdlib>
#include <filesystem>

using asimov::test::run_cli;
using asimov::test::slurp;

TEST_CASE("asimov run: progress on a terminal only") {
  const std::string program = asimov::test::source_path("programs/demo/pick_place.v2");
  // Not a terminal (a file): stderr is the usual messages only, even with no delay.
  const auto plain = run_cli("run " + program, "");
  REQUIRE(plain.exit_code == 0);
  CHECK(plain.err.find("poses checked") == std::string::npos);
  CHECK(plain.err.find('\r') == std::string::npos);

  if (std::system("command -v script >/dev/null 2>&1") != 0) return;  // util-linux script(1)
  const auto log = asimov::test::scratch_dir() / "progress-tty.txt";
  const std::string cmd = "ASIMOV_PROGRESS_DELAY_S=0 script -qec \"" + std::string(ASIMOV_BINARY) + " run " + program +
                          "\" /dev/null > " + log.string() + " 2>&1 </dev/null";
  CHECK(std::system(cmd.c_str()) == 0);
  const std::string tty = slurp(log);
  INFO(tty);
  const auto at = tty.find("poses checked");
  REQUIRE(at != std::string::npos);
  CHECK(tty.find("  t = ") != std::string::npos);
  CHECK(tty.find("  step ") != std::string::npos);  // the program step of the motion being carried out
  CHECK(tty.find("\r\033[K", at) != std::string::npos);  // erased before the final message
  CHECK(tty.find("Program completed: pick_place") > at);
}
