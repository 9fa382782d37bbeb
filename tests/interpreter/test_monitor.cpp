// The monitor's command table, the WHERE and LISTL formats of dialect §9, completion, and
// the STORE writer (storage.hpp): shortest round-trip numbers, atomic replacement.
#include "support/scratch.hpp"
#include "interpreter/src/evaluator.hpp"
#include "asimov/interpreter/monitor.hpp"
#include "asimov/interpreter/storage.hpp"
#include "interpreter_fixture.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <unistd.h>

using namespace asimov;
using interpreter::Command;
using interpreter::Match;
using interpreter::match_command;

namespace {

std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

using test::MonitorFixture;

}  // namespace

TEST_CASE("command words: unique prefixes, any case, an exact name wins", "[monitor]") {
  CHECK(match_command("LO").command == Command::load);
  CHECK(match_command("lo").command == Command::load);
  CHECK(match_command("STO").match == Match::ambiguous);  // STORE, STOREL
  CHECK(match_command("STORE").command == Command::store);
  CHECK(match_command("store").command == Command::store);
  CHECK(match_command("STOREL").command == Command::storel);
  CHECK(match_command("L").match == Match::ambiguous);
  CHECK(match_command("LISTX").match == Match::unknown);
  CHECK(match_command("").match == Match::unknown);
  CHECK(match_command("EXECUTEX").match == Match::unknown);
  CHECK(match_command("D").match == Match::ambiguous);  // DELETE, DIRECTORY, DO
  CHECK(match_command("DO").command == Command::do_);
  CHECK(match_command("Di").command == Command::directory);
  CHECK(match_command("p").match == Match::ambiguous);  // POINT, PROCEED
  CHECK(match_command("pr").command == Command::proceed);
  // Every command by its full name, and by every prefix that is unique.
  for (int i = 0; i < static_cast<int>(Command::count); ++i) {
    const auto c = static_cast<Command>(i);
    const std::string name(interpreter::command_info(c).name);
    CHECK(match_command(name).command == c);
    int unique_prefixes = 0;
    for (std::size_t n = 1; n <= name.size(); ++n) {
      const std::string prefix = name.substr(0, n);
      const auto m = match_command(prefix);
      if (m.match != Match::found) continue;
      if (interpreter::command_info(m.command).name == prefix && n < name.size()) continue;  // STORE in STOREL
      CHECK(m.command == c);
      ++unique_prefixes;
    }
    CHECK(unique_prefixes >= 1);
  }
}

TEST_CASE("WHERE prints the dialect's table at READY", "[monitor]") {
  test::InterpreterFixture f;  // PUMA 560 at READY, no tool
  CHECK(interpreter::format_where(f.sim.here(), f.sim.joints()) ==
        "          X          Y          Z          O          A          T\n"
        "     20.300   -150.050    863.600      0.000      0.000      0.000\n"
        "         J1         J2         J3         J4         J5         J6\n"
        "      0.000    -90.000     90.000      0.000      0.000      0.000\n");
  robots::JointVector q(6);
  q << -0.0001, -90, 90, 0, 0, 0;  // -0.000 prints as 0.000
  CHECK(interpreter::format_where(motion::trans(-0.0004, 1, 2, 0, 0, 0), q).find("-0.000") == std::string::npos);
}

TEST_CASE("LISTL prints the dialect's table: transformations, then precision points, by name", "[monitor]") {
  MonitorFixture f;
  f.run("POINT pick = TRANS(300, 200, 50, 0, 180, 0)");
  f.run("POINT #safe = #PPOINT(0, -90, 180, 0, 0, 0)");
  f.run("DO SET pal[2] = TRANS(450, -120, 12.5, 90, 90, 0)");
  CHECK(f.run("LISTL") ==
        "Transformation            X          Y          Z          O          A          T\n"
        "pal[2]              450.000   -120.000     12.500     90.000     90.000      0.000\n"
        "pick                300.000    200.000     50.000      0.000    180.000      0.000\n"
        "Precision point          J1         J2         J3         J4         J5         J6\n"
        "#safe                 0.000    -90.000    180.000      0.000      0.000      0.000\n");
  // The name column grows to fit the longest name; empty groups are left out.
  f.run("DELETE #safe");
  f.run("POINT a.very.long.nam[100] = TRANS(1, 2, 3)");  // names keep 15 characters; elements grow
  const std::string wide = f.run("LISTL a.very.long.nam");
  CHECK(wide ==
        "Transformation                X          Y          Z          O          A          T\n"
        "a.very.long.nam[100]      1.000      2.000      3.000      0.000      0.000      0.000\n");
  CHECK(f.run("LISTL") .find("Precision point") == std::string::npos);
}

TEST_CASE("LISTP numbers the steps, DIRECTORY lists name(params) alphabetically", "[monitor]") {
  MonitorFixture f;
  REQUIRE(f.load(".PROGRAM zeta(a, $b, c[])\n; comment\n\n    TYPE a\n.END\n.PROGRAM alpha()\n.END\n").empty());
  CHECK(f.run("LISTP zeta") == ".PROGRAM zeta(a, $b, c[])\n   1  ; comment\n   2  \n   3      TYPE a\n.END\n");
  CHECK(f.run("DIRECTORY") == "alpha()\nzeta(a, $b, c[])\n");
  CHECK(f.run("LISTP alpha") == ".PROGRAM alpha()\n.END\n");
}

TEST_CASE("a program typed at the prompt is loaded at its .END", "[monitor]") {
  MonitorFixture f;
  CHECK(f.monitor.execute(".PROGRAM t(n)") == interpreter::CommandStatus::ok);
  CHECK(f.monitor.entering_program());
  CHECK(f.monitor.execute("  WHERE") == interpreter::CommandStatus::ok);  // a line, not a command
  f.monitor.execute("  TYPE n * 2");
  f.monitor.execute(".END");
  CHECK_FALSE(f.monitor.entering_program());
  // WHERE is not a statement: t is loaded marked not executable, as the V+ editor marks it
  CHECK(f.interp.not_executable_from("t") == "t");
  f.monitor.execute(".PROGRAM t(n)");
  f.monitor.execute("  TYPE n * 2");
  CHECK(f.monitor.execute(".end") == interpreter::CommandStatus::ok);
  CHECK(f.run("EXECUTE t(21)") == "42\nProgram completed: t\n");
}

TEST_CASE("completion offers commands, instructions, programs and variables", "[monitor]") {
  MonitorFixture f;
  REQUIRE(f.load(".PROGRAM pick()\n.END\n.PROGRAM place()\n.END\n").empty());
  f.run("DO pos.count = 1");
  using V = std::vector<std::string>;
  CHECK(f.monitor.completions("WH", "WH") == V{"WHERE"});
  CHECK(f.monitor.completions("st", "st") == V{"status", "store", "storel"});
  CHECK(f.monitor.completions("DO MO", "MO") == V{"MOVE", "MOVES", "MOVEST", "MOVET"});
  CHECK(f.monitor.completions("EXECUTE p", "p") == V{"pick", "place", "pos.count"});
  CHECK(f.monitor.completions("LISTP p", "p") == V{"pick", "place"});
  CHECK(f.monitor.completions("LISTR po", "po") == V{"pos.count"});
  CHECK(f.monitor.completions("WHERE x", "x").empty());
  // The DO words come from instructions.def: WAIT, WAIT.EVENT and PROMPT too, no control flow.
  CHECK(f.monitor.completions("DO WA", "WA") == V{"WAIT", "WAIT.EVENT"});
  CHECK(f.monitor.completions("DO PR", "PR") == V{"PROMPT"});
  CHECK(f.monitor.completions("DO RE", "RE") == V{"READY", "RELAX", "RELAXI"});  // no RETURN
  CHECK(f.monitor.completions("DO ST", "ST").empty());                           // no STOP
}

TEST_CASE("DO refuses the control-flow and declaration words of the instruction table", "[monitor]") {
  MonitorFixture f;
  for (const char* w : {"IF x THEN", "FOR i = 1 TO 2", "GOTO 10", "RETURN", "STOP", "PAUSE", "HALT", "AUTO x",
                        "GLOBAL y", ".END", "ELIF x", "CASE x OF", "WHILE 1 DO"}) {
    INFO(w);
    CHECK(f.run(std::string("DO ") + w).find("control flow and declarations are not allowed in DO") != std::string::npos);
  }
  CHECK(f.run("DO WAIT") == "");
}

TEST_CASE("format_real is the shortest text that reads back bit-equal", "[monitor][storage]") {
  CHECK(interpreter::format_real(0.1) == "0.1");
  CHECK(interpreter::format_real(300) == "300");
  CHECK(interpreter::format_real(-0.0) == "0");
  CHECK(interpreter::format_real(1e-7) == "1e-07");
  std::mt19937_64 rng(20261128);
  std::uniform_real_distribution<double> mantissa(-1, 1);
  std::uniform_int_distribution<int> exponent(-300, 300);
  for (int i = 0; i < 20000; ++i) {
    const double x = std::ldexp(mantissa(rng), exponent(rng));
    const std::string s = interpreter::format_real(x);
    INFO(s);
    CHECK(std::strtod(s.c_str(), nullptr) == x);
  }
}

TEST_CASE("STORE text loads back: reals bit-equal, transformations within 1e-12", "[monitor][storage]") {
  MonitorFixture f;
  REQUIRE(f.load(".PROGRAM p(a)\n    TYPE a ; kept as loaded\n.END\n").empty());
  f.run("DO r = 1/3");
  f.run("DO arr[1,2] = -2.5e-300");
  f.run("DO $s = \"a b\"");
  f.run("POINT t = TRANS(1.25, -3.5, 7, 33.3, 77.7, -121.1)");
  f.run("POINT #j = #PPOINT(1, 2, 3, 4, 5, 6)");
  const std::string text = interpreter::store_text(f.interp.memory(), {"p"}, false);
  CHECK(text.find(".PROGRAM p(a)\n    TYPE a ; kept as loaded\n.END\n") == 0);
  MonitorFixture g;
  const auto diags = g.load(text);
  INFO(text);
  REQUIRE(diags.empty());
  CHECK(interpreter::store_text(g.interp.memory(), {"p"}, false).substr(text.find(".REALS")) == text.substr(text.find(".REALS")));
  const auto a = interpreter::global_entries(f.interp.memory()), b = interpreter::global_entries(g.interp.memory());
  REQUIRE(a.size() == b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    CHECK(a[i].name == b[i].name);
    if (const auto* t = std::get_if<motion::Location>(a[i].value))
      CHECK((t->matrix() - std::get<motion::Location>(*b[i].value).matrix()).cwiseAbs().maxCoeff() < 1e-12);
    else if (const auto* r = std::get_if<double>(a[i].value))
      CHECK(*r == std::get<double>(*b[i].value));
  }
  CHECK(interpreter::store_text(f.interp.memory(), {}, true).find(".REALS") == std::string::npos);  // STOREL
}

TEST_CASE("write_file_atomic replaces whole files and leaves nothing on failure", "[monitor][storage]") {
  namespace fs = std::filesystem;
  const fs::path dir = asimov::test::scratch_dir("storage");
  const std::string path = (dir / "f.v2").string();
  REQUIRE(interpreter::write_file_atomic(path, "old\n").ok());
  REQUIRE(interpreter::write_file_atomic(path, "new\n").ok());
  CHECK(slurp(path) == "new\n");
  fs::create_directories(dir / "taken.v2");  // a folder is never replaced: refused before writing
  const auto taken = interpreter::write_file_atomic((dir / "taken.v2").string(), "x\n");
  REQUIRE_FALSE(taken.ok());
  CHECK(taken.error().message.find("is a folder") != std::string::npos);
  CHECK(taken.error().file == (dir / "taken.v2").string());
  CHECK_FALSE(interpreter::write_file_atomic((dir / "missing" / "f.v2").string(), "x\n").ok());
  int files = 0;
  for (const auto& e : fs::directory_iterator(dir)) {
    ++files;
    CHECK(e.path().filename().string().find(".tmp-") == std::string::npos);
  }
  CHECK(files == 2);
}

TEST_CASE("STATUS names the CALLed program where the execution stopped", "[monitor]") {
  MonitorFixture f;
  REQUIRE(f.load(".PROGRAM outer()\n  x = 1\n  CALL inner()\n.END\n.PROGRAM inner()\n  y = 2\n  z = 1 / 0\n.END\n")
              .empty());
  f.run("EXECUTE outer");
  const std::string status = f.run("STATUS");
  CHECK(status.find("Program: outer\n") != std::string::npos);
  CHECK(status.find("State: stopped by error at step 2 of inner\n") != std::string::npos);
  REQUIRE(f.load(".PROGRAM flat()\n  z = 1 / 0\n.END\n").empty());
  f.run("EXECUTE flat");
  CHECK(f.run("STATUS").find("State: stopped by error at step 1\n") != std::string::npos);
}
