// Reactions and error traps (dialect §7c): REACT / REACTI on a signal's transition between
// steps, falling edges, IGNORE, LOCK and PRIORITY(), reactions per task, REACTI stopping the
// arm, REACTE and its RETURN.
#include "interpreter_fixture.hpp"
#include "interpreter/src/reactions.hpp"

#include <catch2/catch.hpp>

#include <set>

using asimov::test::InterpreterFixture;
using asimov::interpreter::Reaction;
using asimov::interpreter::Reactions;
using asimov::interpreter::RunStatus;

namespace {

std::string outcome(const std::string& programs, InterpreterFixture& f) { return asimov::test::outcome_of(f, programs); }

std::string outcome(const std::string& programs) {
  InterpreterFixture f;
  return outcome(programs, f);
}

const std::string kHandler = ".PROGRAM handler()\n  TYPE \"reacted at priority \", PRIORITY()\n.END\n";

}  // namespace

TEST_CASE("REACT calls its program between steps when the signal turns on, once", "[reactions]") {
  CHECK(outcome(".PROGRAM main()\n  REACT 2001, handler\n  TYPE \"a\"\n  SIGNAL 2001\n  TYPE \"b\"\n"
                "  SIGNAL -2001\n  SIGNAL 2001\n  TYPE \"c \", PRIORITY()\n.END\n" + kHandler)
        == "a\nreacted at priority 1\nb\nc 0\n");  // one-shot: the second transition is not served
}

TEST_CASE("a signal already on when REACT runs needs a transition", "[reactions]") {
  CHECK(outcome(".PROGRAM main()\n  SIGNAL 2001\n  REACT 2001, handler\n  TYPE \"a\"\n  SIGNAL -2001\n"
                "  TYPE \"b\"\n  SIGNAL 2001\n  TYPE \"c\"\n.END\n" + kHandler)
        == "a\nb\nreacted at priority 1\nc\n");
}

TEST_CASE("a negative signal number reacts to the falling edge", "[reactions]") {
  CHECK(outcome(".PROGRAM main()\n  SIGNAL 2002\n  REACT -2002, handler, 7\n  SIGNAL 2003\n  TYPE \"a\"\n"
                "  SIGNAL -2002\n  TYPE \"b\"\n.END\n" + kHandler)
        == "a\nreacted at priority 7\nb\n");
}

TEST_CASE("IGNORE ends a reaction; REACT again replaces one on the same signal", "[reactions]") {
  CHECK(outcome(".PROGRAM main()\n  REACT 2001, handler\n  IGNORE 2001\n  SIGNAL 2001\n  TYPE \"a\"\n"
                "  SIGNAL -2001\n  REACT 2001, handler\n  REACT 2001, other, 9\n  SIGNAL 2001\n  TYPE \"b\"\n.END\n"
                + kHandler + ".PROGRAM other()\n  TYPE \"other \", PRIORITY()\n.END\n")
        == "a\nother 9\nb\n");
}

TEST_CASE("LOCK defers a reaction of lower or equal priority until the priority drops", "[reactions]") {
  CHECK(outcome(".PROGRAM main()\n  REACT 2001, handler, 5\n  LOCK 5\n  SIGNAL 2001\n  TYPE \"locked \", PRIORITY()\n"
                "  LOCK 4\n  TYPE \"after \", PRIORITY()\n.END\n" + kHandler)
        == "locked 5\nreacted at priority 5\nafter 4\n");
}

TEST_CASE("the higher priority reaction runs first and may interrupt a lower one", "[reactions]") {
  CHECK(outcome(".PROGRAM main()\n  REACT 2001, low, 3\n  REACT 2002, high, 10\n  SIGNAL 2001, 2002\n"
                "  TYPE \"main \", PRIORITY()\n.END\n"
                ".PROGRAM low()\n  TYPE \"low \", PRIORITY()\n.END\n"
                ".PROGRAM high()\n  TYPE \"high \", PRIORITY()\n.END\n")
        == "high 10\nlow 3\nmain 0\n");
  // Inside a priority 3 reaction a priority 10 one interrupts it; a priority 2 one waits.
  CHECK(outcome(".PROGRAM main()\n  REACT 2001, low, 3\n  SIGNAL 2001\n  TYPE \"main \", PRIORITY()\n.END\n"
                ".PROGRAM low()\n  REACT 2002, high, 10\n  REACT 2003, lower, 2\n  SIGNAL 2003\n  SIGNAL 2002\n"
                "  TYPE \"low \", PRIORITY()\n.END\n"
                ".PROGRAM high()\n  TYPE \"high \", PRIORITY()\n.END\n"
                ".PROGRAM lower()\n  TYPE \"lower \", PRIORITY()\n.END\n")
        == "high 10\nlow 3\nlower 2\nmain 0\n");
}

TEST_CASE("a reaction's RETURN restores the priority it raised, also after a LOCK in it", "[reactions]") {
  CHECK(outcome(".PROGRAM main()\n  LOCK 1\n  REACT 2001, handler, 6\n  SIGNAL 2001\n  TYPE \"main \", PRIORITY()\n.END\n"
                ".PROGRAM handler()\n  LOCK 20\n  TYPE \"in \", PRIORITY()\n  RETURN\n.END\n")
        == "in 20\nmain 1\n");
}

TEST_CASE("a reaction interrupts a WAIT, which goes on after it", "[reactions]") {
  InterpreterFixture f;
  CHECK(outcome(".PROGRAM main()\n  REACT 2001, handler\n  TIMER 1 = 0\n  EXECUTE 1 pulse()\n  WAIT SIG(2002)\n"
                "  TYPE \"done\"\n.END\n"
                ".PROGRAM pulse()\n  WAIT.EVENT , 0.1\n  SIGNAL 2001\n  WAIT.EVENT , 0.1\n  SIGNAL 2002\n.END\n"
                ".PROGRAM handler()\n  TYPE \"reacted at \", TIMER(1) >= 0.1, \" in task \", TASK()\n.END\n",
                f)
        == "reacted at -1 in task 0\ndone\n");
}

TEST_CASE("reactions belong to the task that armed them", "[reactions][tasks]") {
  CHECK(outcome(".PROGRAM main()\n  EXECUTE 1 watcher()\n  WAIT.EVENT , 0.05\n  SIGNAL 2001\n  CYCLE.END 1\n"
                "  TYPE \"main done\"\n.END\n"
                ".PROGRAM watcher()\n  REACT 2001, handler\n  WAIT SIG(2002)\n.END\n"
                ".PROGRAM handler()\n  TYPE \"task \", TASK(), \" reacted\"\n  SIGNAL 2002\n.END\n")
        == "task 1 reacted\nmain done\n");
}

TEST_CASE("REACT checks its arguments", "[reactions]") {
  CHECK(outcome(".PROGRAM main()\n  REACT 1, handler\n.END\n" + kHandler)
        == "ERROR *Illegal value* REACT watches inputs and soft signals, not output 1");
  CHECK(outcome(".PROGRAM main()\n  REACT 2001, handler, 128\n.END\n" + kHandler)
        == "ERROR *Illegal value* REACT priority 128 (allowed: 1 to 127)");
  CHECK(outcome(".PROGRAM main()\n  REACT 2001, nowhere\n.END\n").rfind("ERROR *Undefined", 0) == 0);
  CHECK(outcome(".PROGRAM main()\n  LOCK -1\n.END\n") == "ERROR *Illegal value* LOCK priority -1 (allowed: 0 to 127)");
  InterpreterFixture f;
  const auto diags = f.load(".PROGRAM main()\n  REACT 2001\n  REACTE a, b\n  REACTI 2001, $x\n.END\n");
  REQUIRE(diags.size() == 3);
  CHECK(diags[0].detail == "REACT expects a signal, a program and a priority");
  CHECK(diags[1].detail == "REACTE expects a program name or nothing");
  CHECK(diags[2].detail == "REACTI expects a program name");
}

TEST_CASE("REACTE calls the trap program instead of stopping; its RETURN goes on after the step", "[reactions]") {
  CHECK(outcome(".PROGRAM main()\n  REACTE trap\n  TYPE \"a\"\n  x = undefined_one + 1\n  TYPE \"b \", PRIORITY()\n"
                "  REACTE\n  y = undefined_two\n  TYPE \"not reached\"\n.END\n"
                ".PROGRAM trap()\n  TYPE \"trapped \", ERROR(-1), \" at priority \", PRIORITY()\n.END\n")
        == "a\ntrapped -401 at priority 254\nb 0\nERROR *Undefined value* undefined_two");
  // An error in the trap program stops the task; a reaction does not interrupt the trap.
  CHECK(outcome(".PROGRAM main()\n  REACTE trap\n  REACT 2001, handler, 127\n  x = undefined_one\n.END\n"
                ".PROGRAM trap()\n  SIGNAL 2001\n  TYPE \"in trap\"\n  y = undefined_two\n.END\n" + kHandler)
        == "in trap\nERROR *Undefined value* undefined_two");
}

TEST_CASE("REACTI stops the pending motion where the arm is and calls its program", "[reactions][motion]") {
  InterpreterFixture f;
  const auto r = f.run(".PROGRAM main()\n  REACTI 2001, handler\n  MOVE #PPOINT(60, -90, 90, 0, 0, 0)\n  SIGNAL 2001\n"
                       "  BREAK\n  TYPE \"after\"\n  MOVE #PPOINT(30, -90, 90, 0, 0, 0)\n.END\n" + kHandler);
  REQUIRE(f.loaded);
  REQUIRE(r.status == RunStatus::completed);
  CHECK(f.out.str() == "reacted at priority 1\nafter\n");
  REQUIRE(r.reaction_stops.size() == 1);
  CHECK(r.reaction_stops[0].signal == 2001);
  CHECK(r.reaction_stops[0].task == 0);
  CHECK(r.reaction_stops[0].at.step == 2);
  CHECK(r.reaction_stops[0].at.path_fraction == 0);
  CHECK(r.reaction_stops[0].at.time_s == 0);
  CHECK(f.sim.joints()[0] == Approx(30));  // the next motion went on from where the arm stopped
  CHECK(r.motion_times.size() == 2);
}

TEST_CASE("the reaction table: edges, one shot, priorities, REACTI's signal", "[reactions]") {
  Reactions t;
  std::set<int> on{2002};
  const auto look = [&] { return t.see([&](int k) { return on.count(k) > 0; }); };
  t.arm({.signal = 2001, .falling = false, .program = 1, .priority = 2});
  t.arm({.signal = 2002, .falling = true, .program = 2, .priority = 5, .stops_arm = true, .was_on = true});
  CHECK(look() == 0);
  CHECK_FALSE(t.due());
  on.insert(2001);  // rising on 2001; 2002 still on
  on.erase(2002);   // falling on 2002: a REACTI, its signal negative
  CHECK(look() == -2002);
  CHECK(look() == 0);  // seen once
  t.set_priority(5);   // 2002's priority 5 is not above 5: only 2001 waits too
  CHECK_FALSE(t.due());
  t.set_priority(1);
  REQUIRE(t.due());
  CHECK(t.take_due()->program == 2);  // the higher priority first
  CHECK(t.take_due()->program == 1);
  CHECK(t.empty());
  CHECK_FALSE(t.take_due());
  // IGNORE removes a reaction that was triggered and still waits.
  t.arm({.signal = 2003, .program = 3});
  on.insert(2003);
  look();
  CHECK(t.ignore(2003));
  CHECK_FALSE(t.due());
  CHECK_FALSE(t.ignore(2003));
  // A REACTI without a program is dropped once triggered.
  t.arm({.signal = 2004, .program = -1, .stops_arm = true});
  on.insert(2004);
  CHECK(look() == 2004);
  CHECK(t.due());
  CHECK_FALSE(t.take_due());
  CHECK(t.empty());
}
