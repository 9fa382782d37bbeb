// Statements added for the whole dialect: PAUSE / HALT, WAIT / WAIT.EVENT, PROMPT, PARAMETER,
// ENABLE / DISABLE / SWITCH, hand (OPEN ... RELAXI, MOVET), DURATION, and the §7 constructs
// (SPEED ... MMPS, GETC ...). Each runs a program and checks its TYPE output or its error.
#include "support/cell_bodies.hpp"
#include "interpreter_fixture.hpp"
#include "asimov/collision/polyhedron.hpp"

#include <catch2/catch.hpp>

#include <atomic>
#include <sstream>

using asimov::test::InterpreterFixture;
using asimov::interpreter::RunStatus;

namespace {

std::string program(const std::string& body) { return ".PROGRAM main()\n" + body + "\n.END\n"; }

// Runs `body` as `main`; the output, or the error message and detail after "ERROR ".
std::string outcome(const std::string& body, const std::string& input = "", bool interactive = false) {
  InterpreterFixture f;
  std::istringstream in(input);
  f.interp.set_input(in, interactive);
  f.interp.limits().max_wait_s = 2;
  return asimov::test::outcome_of(f, program(body));
}

}  // namespace

TEST_CASE("PAUSE stops with a paused status; PROCEED continues with the next step", "[statements]") {
  InterpreterFixture f;
  auto r = f.run(".PROGRAM main()\n  TYPE \"a\"\n  CALL sub()\n  TYPE \"c\"\n.END\n"
                 ".PROGRAM sub()\n  PAUSE\n  TYPE \"b\"\n.END\n");
  REQUIRE(f.loaded);
  CHECK(r.status == RunStatus::paused);
  CHECK(r.program == "sub");
  CHECK(r.step == 1);
  CHECK(asimov::interpreter::format_pause(r) == "Program paused: sub, step 1");
  CHECK(f.out.str() == "a\n");
  REQUIRE(f.interp.can_resume());
  r = f.interp.proceed();
  CHECK(r.status == RunStatus::completed);
  CHECK(f.out.str() == "a\nb\nc\n");
  CHECK_FALSE(f.interp.can_resume());
}

TEST_CASE("PAUSE waits for the motion; RETRY after PAUSE does not run PAUSE again", "[statements]") {
  InterpreterFixture f;
  auto r = f.run(program("  MOVE #PPOINT(10, -80, 100, 0, 20, 30)\n  PAUSE\n  TYPE \"after\""));
  REQUIRE(r.status == RunStatus::paused);
  CHECK_FALSE(f.sim.motion_pending());
  CHECK(f.sim.time_s() > 0);
  r = f.interp.retry();
  CHECK(r.status == RunStatus::completed);
  CHECK(f.out.str() == "after\n");
}

TEST_CASE("HALT stops and cannot be resumed", "[statements]") {
  InterpreterFixture f;
  auto r = f.run(program("  TYPE \"a\"\n  HALT\n  TYPE \"b\""));
  CHECK(r.status == RunStatus::halted);
  CHECK(asimov::interpreter::format_pause(r) == "Program halted: main, step 2");
  CHECK_FALSE(f.interp.can_resume());
  r = f.interp.proceed();
  CHECK(r.error.message == "*No program to resume*");
  CHECK(f.out.str() == "a\n");
}

TEST_CASE("STOP ends the execution from inside a CALL", "[statements]") {
  InterpreterFixture f;
  auto r = f.run(".PROGRAM main()\n  CALL sub()\n  TYPE \"not here\"\n.END\n.PROGRAM sub()\n  TYPE \"s\"\n  STOP\n.END\n");
  CHECK(r.status == RunStatus::completed);
  CHECK(f.out.str() == "s\n");
}

TEST_CASE("WAIT advances the clock tick by tick; WAIT.EVENT , t waits t seconds", "[statements]") {
  CHECK(outcome("TIMER 1 = 0\nWAIT TIMER(1) >= 0.5\nTYPE TIMER(1) >= 0.5, TIMER(1) < 0.5161") == "-1 -1\n");
  CHECK(outcome("TIMER 2 = 10\nWAIT\nTYPE TIMER(2)") == "10.016\n");
  CHECK(outcome("TIMER 3 = 0\nWAIT.EVENT , 1.5\nTYPE TIMER(3)") == "1.5\n");
  CHECK(outcome("SIGNAL 2001\nWAIT SIG(2001)\nTYPE \"at once\"") == "at once\n");
  CHECK(outcome("WAIT SIG(1001)") == "ERROR *Wait limit exceeded* still false after 2 s; no device in the cell drives signal 1001");
  CHECK(outcome("WAIT.EVENT 1, 2") == "ERROR *Not supported in simulation* WAIT.EVENT");
  CHECK(outcome("WAIT.EVENT , -1") == "ERROR *Illegal value* WAIT.EVENT -1");
  CHECK(outcome("WAIT \"x\"") == "ERROR *Illegal value* WAIT condition, not a string");
}

TEST_CASE("WAIT waits for the motion first", "[statements]") {
  InterpreterFixture f;
  const auto r = f.run(program("  TIMER 1 = 0\n  MOVE #PPOINT(10, -80, 100, 0, 20, 30)\n  WAIT\n  TYPE TIMER(1) > 0.016"));
  REQUIRE(r.status == RunStatus::completed);
  CHECK_FALSE(f.sim.motion_pending());
  CHECK(f.out.str() == "-1\n");
}

TEST_CASE("PROMPT reads a line into a string or a real", "[statements]") {
  CHECK(outcome("PROMPT \"Name? \", $n\nPROMPT \"Count? \", n\nTYPE $n, \" \", n * 2", "Ada Lovelace\n 21 \n")
        == "Name? \nCount? \nAda Lovelace 42\n");
  CHECK(outcome("PROMPT \"n? \", a[3]\nTYPE a[3]", "-1.5e2\r\n") == "n? \n-150\n");
  CHECK(outcome("PROMPT \"n? \", n", "abc\n") == "n? \nERROR *Illegal value* \"abc\" is not a number");
  CHECK(outcome("PROMPT \"n? \", n", "inf\n") == "n? \nERROR *Illegal value* \"inf\" is not a number");
  CHECK(outcome("PROMPT \"n? \", n", "") == "n? \nERROR *Illegal value* end of input at PROMPT");
  // Interactive: bad input asks again, the reply is not followed by a newline of ours.
  CHECK(outcome("PROMPT \"n? \", n\nTYPE n", "x\n5\n", true) == "n? n? 5\n");
}

TEST_CASE("PROMPT is checked at load time", "[statements]") {
  InterpreterFixture f;
  CHECK_FALSE(f.load(program("PROMPT \"n? \"")).empty());
  CHECK_FALSE(f.load(program("PROMPT \"n? \", 1 + 2")).empty());
  CHECK_FALSE(f.load(program("PROMPT 5, n")).empty());
}

TEST_CASE("PARAMETER sets and reads HAND.TIME and COLLISION.CLEARANCE", "[statements]") {
  CHECK(outcome("TYPE PARAMETER(HAND.TIME), PARAMETER(collision.clearance)") == "0.05 0\n");
  CHECK(outcome("PARAMETER HAND.TIME = 0.25\nTIMER 1 = 0\nCLOSEI\nTYPE TIMER(1), PARAMETER(HAND.TIME)") == "0.25 0.25\n");
  CHECK(outcome("PARAMETER COLLISION.CLEARANCE = 5\nTYPE PARAMETER(COLLISION.CLEARANCE)") == "5\n");
  CHECK(outcome("PARAMETER HAND.TIME = -1") == "ERROR *Illegal value* HAND.TIME = -1");
}

TEST_CASE("unknown parameters and switches are reported at load", "[statements]") {
  InterpreterFixture f;
  const std::pair<const char*, const char*> cases[] = {
      {"PARAMETER SPEED.X = 1", "unknown parameter SPEED.X"}, {"TYPE PARAMETER(nothing)", "unknown parameter NOTHING"},
      {"ENABLE FOO", "unknown switch FOO"}, {"TYPE SWITCH(BAR)", "unknown switch BAR"},
      {"ENABLE CP, COLOR.SPEED", "unknown switch COLOR.SPEED"}, {"x = SELECT(TASK)", "SELECT() knows ROBOT only"}};
  for (const auto& [line, detail] : cases) {
    INFO(line);
    const auto d = f.load(program(line));
    REQUIRE(d.size() == 1);
    CHECK(d[0].message == "*Syntax error*");
    CHECK(d[0].detail == detail);
  }
}

TEST_CASE("SET of the wrong location kind is reported at load", "[statements]") {
  InterpreterFixture f;
  const std::pair<const char*, const char*> cases[] = {
      {"SET a = #PPOINT(0, 0, 0, 0, 0, 0)", "a cannot hold a precision point"},
      {"SET #x = TRANS(1, 2, 3)", "#x cannot hold a transformation"},
      {"SET #x = HERE", "#x cannot hold a transformation"}, {"SET a = #p", "a cannot hold a precision point"},
      {"SET a = 5", "a cannot hold a real"}, {"SET #x = \"p\"", "#x cannot hold a string"}};
  for (const auto& [line, detail] : cases) {
    INFO(line);
    const auto d = f.load(program(line));
    REQUIRE(d.size() == 1);
    CHECK(d[0].detail == detail);
  }
  for (const char* line : {"SET a = HERE:TRANS(0, 0, 5)", "SET a = b", "SET #x = #PPOINT(1)", "SET #x = #y"}) {
    INFO(line);
    CHECK(f.load(program(line)).empty());
  }
}

TEST_CASE("STATE, TASK, ERROR, $ERROR and SWITCH(POWER) report the simulated controller", "[statements]") {
  CHECK(outcome("TYPE STATE(1), STATE(2), STATE(4), STATE(5), STATE(9)") == "7 0 0 1 0\n");
  CHECK(outcome("MOVE #PPOINT(10, -90, 90, 0, 0, 0)\nTYPE STATE(2), STATE(9)\nBREAK\nTYPE STATE(2), STATE(9)")
        == "1 1\n2 0\n");
  CHECK(outcome("stop = STATE(4) BAND 4\nTYPE stop, SWITCH(POWER), SWITCH(DRY.RUN)\nENABLE POWER") == "0 -1 0\n");
  CHECK(outcome("TYPE TASK(), TASK(1, 0), TASK(1, 1), ERROR(0, 0), ERROR(0)") == "0 4 0 0 0\n");
  CHECK(outcome("TYPE STATE(3)") == "5\n");  // computer control: no pendant mode
  CHECK(outcome("TYPE STATE(6)") == "ERROR *Not supported in simulation* STATE(6)");
  CHECK(outcome("TYPE TASK(2, 0)") == "ERROR *Not supported in simulation* TASK(2, ...)");
  CHECK(outcome("TYPE $ERROR(-402), $ERROR(0), \"|\", $ERROR(-9999)") == "*Illegal value*|*Unknown error code*\n");
  // ERROR() holds the last error's code: after PROCEED the program can read it.
  InterpreterFixture f;
  REQUIRE(f.load(program("x = 1/0\nTYPE ERROR(0, 0), $ERROR(ERROR(0))")).empty());
  CHECK(f.interp.run("main").error.message == "*Division by zero*");
  CHECK(f.interp.proceed().status == RunStatus::completed);
  CHECK(f.out.str() == "-409*Division by zero*\n");
}

TEST_CASE("SELECT(ROBOT), STATUS(\"prog\") and TIMER(0)", "[statements]") {
  CHECK(outcome("TYPE SELECT(ROBOT), STATUS(\"main\"), STATUS(\"nothing\")\nWAIT.EVENT , 0.5\nTYPE TIMER(0), TIMER(-1)")
        == "1 2 0\n0.5 0.5\n");
  InterpreterFixture f;
  REQUIRE(f.load(".PROGRAM other()\n.END\n").empty());
  CHECK(f.run(program("TYPE STATUS(\"other\"), STATUS(\"MAIN\")")).status == RunStatus::completed);
  CHECK(f.out.str() == "1 2\n");
}

TEST_CASE("ENABLE, DISABLE and SWITCH", "[statements]") {
  CHECK(outcome("TYPE SWITCH(CP), SWITCH(COLLISION)") == "-1 -1\n");
  CHECK(outcome("DISABLE CP, COLLISION\nTYPE SWITCH(CP), SWITCH(COLLISION)\nENABLE COLLISION\nTYPE SWITCH(COLLISION)")
        == "0 0\n-1\n");
  InterpreterFixture f;
  const auto r = f.run(program("ENABLE SCALE.ACCEL\nTYPE \"ok\""));
  CHECK(r.status == RunStatus::completed);
  REQUIRE(r.warnings.size() == 1);
  CHECK(r.warnings[0].detail == "ENABLE SCALE.ACCEL");
  CHECK_FALSE(f.load(program("ENABLE 3")).empty());
}

TEST_CASE("the settings persist between runs", "[statements]") {
  InterpreterFixture f;
  f.run(program("DISABLE COLLISION\nPARAMETER HAND.TIME = 1"));
  REQUIRE(f.interp.run("main").status == RunStatus::completed);
  CHECK_FALSE(f.sim.cell().collision.enabled);
  f.load(".PROGRAM show()\nTYPE SWITCH(COLLISION), PARAMETER(HAND.TIME)\n.END\n");
  f.interp.run("show");
  CHECK(f.out.str() == "0 1\n");
}

TEST_CASE("OPEN, CLOSE, RELAX wait for the next motion; OPENI ... act at once", "[statements]") {
  using asimov::motion::HandState;
  InterpreterFixture f;
  auto r = f.run(program("CLOSE"));
  CHECK(f.sim.hand().state == HandState::open);
  CHECK(f.sim.hand().pending.has_value());
  r = f.run(program("CLOSE\nMOVE #PPOINT(10, -80, 100, 0, 20, 30)"));
  CHECK(f.sim.hand().state == HandState::closed);
  r = f.run(program("TIMER 1 = 0\nRELAXI\nTYPE TIMER(1)"));
  CHECK(f.sim.hand().state == HandState::relaxed);
  r = f.run(program("OPENI"));
  CHECK(f.sim.hand().state == HandState::open);
  r = f.run(program("CLOSEI"));
  CHECK(f.sim.hand().state == HandState::closed);
  r = f.run(program("RELAX\nOPEN\nMOVE #PPOINT(0, -80, 100, 0, 20, 30)"));  // the later request wins
  CHECK(f.sim.hand().state == HandState::open);
  CHECK(f.out.str() == "0.05\n");
  CHECK_FALSE(f.load(program("OPEN 1")).empty());
}

TEST_CASE("MOVET and MOVEST set the hand when the motion starts", "[statements]") {
  using asimov::motion::HandState;
  InterpreterFixture f;
  auto r = f.run(program("MOVET #PPOINT(10, -80, 100, 0, 20, 30), 0\nBREAK\nHERE p\nMOVEST p, 1\nBREAK\nMOVET p, 0"));
  INFO(asimov::interpreter::format_diagnostic(r.error));
  REQUIRE(r.status == RunStatus::completed);
  CHECK(f.sim.hand().state == HandState::closed);
  CHECK_FALSE(f.load(program("MOVET p")).empty());
}

TEST_CASE("DURATION sets a minimum motion time, once or ALWAYS", "[statements]") {
  const std::string move = "MOVE #PPOINT(10, -80, 100, 0, 20, 30)\nMOVE #PPOINT(0, -90, 90, 0, 0, 0)\nBREAK\n";
  const std::string timed = "TIMER 1 = 0\nMOVE #PPOINT(10, -80, 100, 0, 20, 30)\nBREAK\nt1 = TIMER(1)\n"
                            "MOVE #PPOINT(0, -90, 90, 0, 0, 0)\nBREAK\nTYPE /F0.3, t1, \" \", TIMER(1) - t1\n";
  CHECK(outcome("DURATION 2\n" + timed).substr(0, 6) == "2.000 ");
  CHECK(outcome("DURATION 2\n" + timed) != "2.000 2.000\n");
  CHECK(outcome("DURATION 2 ALWAYS\n" + timed) == "2.000 2.000\n");
  CHECK(outcome("DURATION 2 ALWAYS\nDURATION 0 ALWAYS\n" + timed).substr(0, 6) != "2.000 ");
  CHECK(outcome("DURATION -1") == "ERROR *Illegal value* DURATION -1");
  CHECK(outcome(move + "TYPE \"ok\"") == "ok\n");
}

TEST_CASE("SPEED ... MMPS, V+ functions and statements stop the program", "[statements]") {
  CHECK(outcome("SPEED 50 MMPS") == "ERROR *Not supported in simulation* SPEED MMPS");
  CHECK(outcome("SPEED 50 IPS ALWAYS") == "ERROR *Not supported in simulation* SPEED IPS");
  CHECK(outcome("TYPE IOSTAT(1), IOSTAT(1, 0)") == "0 0\n");  // nothing done on unit 1 yet
  CHECK(outcome("x = IOSTAT(1, 2)") == "ERROR *Not supported in simulation* IOSTAT(lun, 2)");
  CHECK(outcome("FOPEN (5) \"x\"").rfind("ERROR *Not supported in simulation* FOPEN; network", 0) == 0);
  InterpreterFixture f;
  CHECK_FALSE(f.load(program("MOVE a MMPS")).empty());  // units only after SPEED
}

TEST_CASE("instruction keywords are variables in `name =` lines and expressions", "[statements]") {
  CHECK(outcome("wait = 1\nprompt = 2\nopen = 3\nclosei = 4\nmovet = 5\nduration = 6\nenable = 7\nparameter = 8\n"
                "TYPE wait + prompt + open + closei + movet + duration + enable + parameter") == "36\n");
  CHECK(outcome("LOCAL stop, mode\nstop = 4 BAND 4\nIF stop THEN\n  TYPE \"stop \", stop\nEND\nSTOP\nTYPE \"not here\"")
        == "stop 4\n");
  CHECK(outcome("wait.x = 1\nopen_count = 2\nTYPE wait.x + open_count") == "3\n");
  InterpreterFixture f;
  for (const char* word : {"here", "pi", "tool", "then"}) {  // never names
    const auto d = f.load(program(std::string(word) + " = 1"));
    REQUIRE_FALSE(d.empty());
    CHECK(d[0].message == "*Syntax error*");
    CHECK(d[0].detail == "\"" + std::string(word) + "\" is a keyword, not a variable");
  }
}

TEST_CASE("DISABLE COLLISION lets a colliding motion through; the clearance widens contact", "[statements][collision]") {
  using namespace asimov;
  // A box at the tool point halfway through a J1 sweep (as in test_motion_programs).
  motion::Location work;
  {
    InterpreterFixture probe;
    REQUIRE(probe.run(program(" MOVE #PPOINT(25, -60, 150, 10, 40, 20)")).status == RunStatus::completed);
    work = probe.sim.here();
  }
  auto run_in_box_cell = [&](const std::string& prefix, std::string& text) {
    motion::Cell cell = test::empty_puma_cell();
    cell.objects.push_back(test::box_object("box", collision::Vec3(60, 60, 60), work.translation()));
    motion::Simulator sim(cell);
    std::ostringstream out;
    interpreter::Interpreter interp(sim, out);
    REQUIRE(interp.load_source(program(prefix + "\nMOVE #PPOINT(10, -60, 150, 10, 40, 20)\nMOVE #PPOINT(40, -60, 150, 10, 40, 20)\n"
                                       "BREAK\nTYPE SWITCH(COLLISION)"), "box.v2").empty());
    const interpreter::RunResult r = interp.run("main");
    text = out.str();
    return r;
  };
  std::string text;
  CHECK(run_in_box_cell("", text).status == RunStatus::collision);
  auto r = run_in_box_cell("DISABLE COLLISION", text);
  CHECK(r.status == RunStatus::completed);
  CHECK(text == "0\n");
  r = run_in_box_cell("DISABLE COLLISION\nENABLE COLLISION", text);
  CHECK(r.status == RunStatus::collision);
  // With a clearance the contact is found earlier along the same sweep.
  const double t_plain = run_in_box_cell("", text).collision.time_s;
  const double t_clear = run_in_box_cell("PARAMETER COLLISION.CLEARANCE = 20", text).collision.time_s;
  CHECK(t_clear < t_plain);
}

TEST_CASE("RETRY after an interrupt runs the interrupted step (also inside WAIT)", "[statements][resume]") {
  InterpreterFixture f;
  std::atomic<bool> interrupt{true};
  f.interp.limits().interrupt = &interrupt;
  REQUIRE(f.load(program("TYPE 1\nTYPE 2")).empty());
  auto r = f.interp.run("main");
  REQUIRE(r.error.message == "*Program interrupted*");
  interrupt = false;
  r = f.interp.retry();
  CHECK(r.status == RunStatus::completed);
  CHECK(f.out.str() == "1\n2\n");
  // An interrupt seen inside WAIT stops at the WAIT; PROCEED waits again.
  REQUIRE(f.load(".PROGRAM w()\nTYPE \"a\"\nWAIT SIG(2001)\nTYPE \"b\"\n.END\n.PROGRAM s()\nSIGNAL 2001\n.END\n").empty());
  f.out.str("");
  f.interp.limits().interrupt = nullptr;
  f.interp.limits().max_wait_s = 1;
  r = f.interp.run("w");
  CHECK(r.error.message == "*Wait limit exceeded*");
  CHECK(r.step == 2);
  CHECK(f.interp.run("s").status == RunStatus::completed);  // a DO SIGNAL at the monitor
  r = f.interp.retry();
  CHECK(r.status == RunStatus::completed);
  CHECK(f.out.str() == "a\nb\n");
}

TEST_CASE("every V+ statement and function of dialect §7 loads and stops or warns", "[statements]") {
  // (REACT, REACTI, REACTE, IGNORE, LOCK and PRIORITY() are simulated: test_reactions.cpp.)
  for (const char* line : {"SELECT TASK = 2", "SET.EVENT 1", "CLEAR.EVENT 1",
                           "TEACH p", "CALIBRATE , status"}) {
    const std::string text = line;
    std::string keyword;
    for (char c : text.substr(0, text.find(' '))) keyword += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    CHECK(outcome(text) == "ERROR *Not supported in simulation* " + keyword);
  }
  // Warn once per execution and continue; the robot's ATTACH () / DETACH () are simulated (§7b).
  InterpreterFixture f;
  const auto r = f.run(program("ATTACH ()\nDETACH ()\nSELECT ROBOT = 1\nACCEL 50, 50\nACCEL 60\nATTACH ()\nTYPE \"on\""));
  CHECK(r.status == RunStatus::completed);
  CHECK(r.warnings.size() == 1);  // SELECT; ACCEL (docs/blending.md) and ATTACH () / DETACH () are simulated
  CHECK(f.out.str() == "on\n");
  CHECK(outcome("DETACH ()\nMOVE #PPOINT(10, -90, 90, 0, 0, 0)") == "ERROR *Robot not attached to this program* task 0");
  // Devices other than the disk stop; network and serial ones with the hint (dialect §7a).
  CHECK(outcome("ATTACH (lun) \"dev\"") == "ERROR *Not supported in simulation* ATTACH \"DEV\"");
  CHECK(outcome("ATTACH (lun) \"SERIAL:1\"").find("SERIAL:1\"; network and serial I/O are not simulated") != std::string::npos);
}

TEST_CASE("binary records: $LNGB LNGB $INTB INTB $FLTB FLTB as the V+ reference defines them", "[statements][vplus]") {
  // The reference's own examples.
  CHECK(outcome("TYPE LNGB($INTB(1)+$INTB(5))") == "65541\n");
  CHECK(outcome("TYPE $LNGB(67*65536+12345) == $INTB(67)+$INTB(12345)") == "-1\n");
  CHECK(outcome("TYPE FLTB($CHR(^H3F)+$CHR(^H80)+$CHR(0)+$CHR(0)), FLTB($CHR(^HC0)+$CHR(^H40)+$CHR(0)+$CHR(0))") == "1 -3\n");
  CHECK(outcome("TYPE INTB($CHR(10)+$CHR(5)), INTB($CHR(255)+$CHR(255)), INTB($CHR(255)+$CHR(255)) BAND ^HFFFF") == "2565 -1 65535\n");
  // Big-endian bytes, two's complement; the real is rounded (halves away from zero).
  CHECK(outcome("$s = $LNGB(-2)\nTYPE LEN($s), ASC($s, 1), ASC($s, 4), LNGB($s)") == "4 255 254 -2\n");
  CHECK(outcome("TYPE LNGB($LNGB(2.5)), LNGB($LNGB(-2147483648)), LNGB($LNGB(2147483647))") == "3 -2147483648 2147483647\n");
  CHECK(outcome("TYPE LEN($INTB(1)), INTB($INTB(70000))") == "2 4464\n");  // the low 16 bits
  // first_char: omitted, 0 or 1 the first byte; past the end an error.
  CHECK(outcome("$s = \"ab\"+$LNGB(7)\nTYPE LNGB($s, 3), INTB($s, 5), LNGB($LNGB(9), 0)") == "7 7 9\n");
  CHECK(outcome("x = LNGB(\"abc\")") == "ERROR *Illegal value* LNGB: 4 bytes from position 1 of a 3-byte string");
  CHECK(outcome("x = INTB($INTB(1), 2)") == "ERROR *Illegal value* INTB: 2 bytes from position 2 of a 2-byte string");
  CHECK(outcome("$s = $LNGB(2147483648)").rfind("ERROR *Illegal value* $LNGB(2147483648) is outside", 0) == 0);
  // IEEE single precision: rounded to the nearest single; exponent 0 reads as 0, 255 is an error.
  CHECK(outcome("TYPE FLTB($FLTB(0.1)) == 0.1, ABS(FLTB($FLTB(0.1)) - 0.1) < 1E-8, FLTB($FLTB(-1.5E30)) == -1.5E30") == "0 -1 0\n");
  CHECK(outcome("TYPE FLTB($FLTB(1.5)), FLTB($FLTB(-1E-30)), FLTB($CHR(0)+$CHR(0)+$CHR(0)+$CHR(1))") == "1.5 -1e-30 0\n");
  CHECK(outcome("x = FLTB($CHR(^H7F)+$CHR(^H80)+$CHR(0)+$CHR(0))") == "ERROR *Illegal value* FLTB: exponent 255 (infinity or not a number)");
  CHECK(outcome("$s = $FLTB(1E39)").rfind("ERROR *Illegal value* $FLTB(", 0) == 0);
  // A string holds any byte: $CHR takes 0..255.
  CHECK(outcome("TYPE ASC($CHR(0)), ASC($CHR(255)), LEN($CHR(0)+$CHR(0))") == "0 255 2\n");
  CHECK(outcome("$s = $CHR(256)") == "ERROR *Illegal value* $CHR(256)");
  CHECK(outcome("$s = $CHR(-1)") == "ERROR *Illegal value* $CHR(-1)");
}

TEST_CASE("PARAMETER(NOT.CALIBRATED): no robot is uncalibrated in simulation", "[statements][vplus]") {
  // As ACE-generated start-up code reads it: IF PARAMETER(NOT.CALIBRATED) <> 0 THEN CALIBRATE ...
  CHECK(outcome("TYPE PARAMETER(NOT.CALIBRATED)\nIF PARAMETER(NOT.CALIBRATED) <> 0 THEN\n  CALIBRATE , err\nEND\nTYPE \"ready\"")
        == "0\nready\n");
  CHECK(outcome("PARAMETER NOT.CALIBRATED = 1").rfind("ERROR *Not supported in simulation* PARAMETER NOT.CALIBRATED", 0) == 0);
}
