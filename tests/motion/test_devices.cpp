// Devices on the simulated clock (motion/device_clock.hpp): conveyors, sensors, feeders, sinks,
// logic rules, as exact functions of time.
#include "asimov/motion/device_clock.hpp"

#include <catch2/catch.hpp>

#include <cmath>

using namespace asimov;
using motion::DeviceClock;
using motion::Holder;
using motion::Workcell;
using collision::Vec3;

namespace {
motion::Location at(double x, double y, double z) { return motion::trans(x, y, z, 0, 0, 0); }

// A belt 1000 mm long along +X, top face at z = 0, from x = 0 to 1000; output 1 runs it.
motion::Conveyor belt(double speed = 100, int signal = 1) {
  motion::Conveyor c;
  c.name = "belt";
  c.body = {at(500, 0, -20), {1000, 200, 40}};
  c.direction = Vec3::UnitX();
  c.speed_mm_s = speed;
  c.signal = signal;
  return c;
}

// A 20 mm cube whose origin is its centre, resting on the belt at x.
motion::PartDef cube(const std::string& name, double x, const std::string& colour = "") {
  return {name, colour, collision::make_box({20, 20, 20}), at(x, 0, 10)};
}

const motion::CellEvent* find(const DeviceClock& c, const std::string& kind, const std::string& subject) {
  for (const auto& e : c.events())
    if (e.kind == kind && e.subject == subject) return &e;
  return nullptr;
}
}  // namespace

TEST_CASE("a part on a running conveyor moves with it and stops at the belt's end") {
  Workcell w;
  w.conveyors.push_back(belt());
  w.parts.push_back(cube("p", 100));
  DeviceClock clock(w);
  REQUIRE(clock.parts()[0].holder == Holder::conveyor);
  clock.advance_to(1.0);
  CHECK(clock.part_pose(0).translation().x() == 100);  // output 1 off: the belt stands
  clock.set_signal(1, true, 7);
  clock.advance_to(3.5);
  CHECK(clock.part_pose(0).translation().x() == Approx(350).margin(1e-9));
  clock.set_signal(1, false);
  clock.advance_to(10);
  CHECK(clock.part_pose(0).translation().x() == Approx(350).margin(1e-9));
  clock.set_signal(1, true);
  clock.advance_to(100);
  CHECK(clock.part_pose(0).translation().x() == Approx(1000).margin(1e-9));  // origin at the end
  const auto* end = find(clock, "conveyor_end", "p");
  REQUIRE(end);
  CHECK(end->time_s == Approx(10 + 6.5).margin(1e-9));
  const auto* sig = find(clock, "signal", "1");
  REQUIRE(sig);
  CHECK(sig->line == 7);
  CHECK(sig->time_s == 1.0);
}

TEST_CASE("a part off the belt's top face does not move") {
  Workcell w;
  w.conveyors.push_back(belt(100, 0));
  w.parts.push_back({"high", "", collision::make_box({20, 20, 20}), at(100, 0, 15)});  // 5 mm above
  w.parts.push_back({"beside", "", collision::make_box({20, 20, 20}), at(100, 300, 10)});
  DeviceClock clock(w);
  clock.advance_to(2);
  CHECK(clock.parts()[0].holder == Holder::world);
  CHECK(clock.part_pose(0).translation().x() == 100);
  CHECK(clock.part_pose(1).translation().x() == 100);
}

TEST_CASE("a sensor switches at the exact instant the part's origin crosses its box") {
  Workcell w;
  w.conveyors.push_back(belt(100, 0));
  w.parts.push_back(cube("p", 0));
  motion::Sensor s;
  s.name = "eye";
  s.signal = 1001;
  s.region = {at(500, 0, 10), {50, 100, 100}};  // x in [475, 525]
  w.sensors.push_back(s);
  DeviceClock clock(w);
  CHECK_FALSE(clock.signal(1001));
  clock.advance_to(4.749);
  CHECK_FALSE(clock.signal(1001));
  clock.advance_to(4.76);  // a tick that straddles the entry: the event carries the exact time
  CHECK(clock.signal(1001));
  const auto* on = find(clock, "signal", "1001");
  REQUIRE(on);
  CHECK(on->time_s == Approx(4.75).margin(1e-12));
  clock.advance_to(6);
  CHECK_FALSE(clock.signal(1001));
  CHECK(clock.events().back().time_s == Approx(5.25).margin(1e-12));
  CHECK(clock.events().back().detail == "off");
}

TEST_CASE("a sensor filters by name pattern and colour") {
  Workcell w;
  w.parts.push_back(cube("bolt1", 0, "red"));
  w.parts.push_back(cube("nut1", 100, "blue"));
  motion::Sensor any{"any", 1001, {at(50, 0, 10), {200, 50, 50}}, "", ""};
  motion::Sensor bolts{"bolts", 1002, {at(100, 0, 10), {50, 50, 50}}, "bolt*", ""};
  motion::Sensor blue{"blue", 1003, {at(100, 0, 10), {50, 50, 50}}, "", "blue"};
  w.sensors = {any, bolts, blue};
  DeviceClock clock(w);
  CHECK(clock.signal(1001));
  CHECK_FALSE(clock.signal(1002));
  CHECK(clock.signal(1003));
  CHECK(motion::name_matches("B?LT*", "bolt12"));
  CHECK_FALSE(motion::name_matches("bolt?", "bolt12"));
  CHECK(motion::name_matches("*", ""));
}

TEST_CASE("a feeder with when_empty refills its spot up to its count") {
  Workcell w;
  w.conveyors.push_back(belt(100, 0));
  motion::Feeder f;
  f.name = "hopper";
  f.prefix = "box";
  f.part = cube("", 0);
  f.when_empty = true;
  f.count = 3;
  f.colours = {"red", "blue"};
  f.spot = {f.part.pose, {40, 40, 40}};  // the origin leaves it after 20 mm: 0.2 s
  w.feeders.push_back(f);
  DeviceClock clock(w);
  REQUIRE(clock.parts().size() == 1);
  clock.advance_to(10);
  REQUIRE(clock.parts().size() == 3);  // the limit
  CHECK(clock.parts()[0].def->name == "box1");
  CHECK(clock.parts()[1].def->colour == "blue");
  CHECK(clock.parts()[2].def->colour == "red");
  const auto* second = find(clock, "feeder", "box2");
  REQUIRE(second);
  CHECK(second->time_s == Approx(0.2).margin(1e-12));
  CHECK(find(clock, "feeder", "box3")->time_s == Approx(0.4).margin(1e-12));
}

TEST_CASE("a feeder on a signal feeds on each rising edge, not while its spot is taken") {
  Workcell w;
  motion::Feeder f;
  f.name = "press";
  f.prefix = "blank";
  f.part = cube("", 0);
  f.signal = 2;
  f.count = 2;
  f.spot = {f.part.pose, {40, 40, 40}};
  w.feeders.push_back(f);
  DeviceClock clock(w);
  CHECK(clock.parts().empty());
  clock.set_signal(2, true);
  CHECK(clock.parts().size() == 1);
  clock.set_signal(2, false);
  clock.set_signal(2, true);  // the first blank still lies there
  CHECK(clock.parts().size() == 1);
  CHECK(find(clock, "feeder_blocked", "press"));
  clock.carry(0, 3);
  clock.put_down(0, at(500, 0, 10), 4);
  clock.set_signal(2, false);
  clock.set_signal(2, true);
  CHECK(clock.parts().size() == 2);
  clock.set_signal(2, false);
  clock.carry(1, 5);
  clock.put_down(1, at(600, 0, 10), 6);
  clock.set_signal(2, true);
  CHECK(clock.parts().size() == 2);  // count reached
}

TEST_CASE("a sink removes parts that enter it") {
  Workcell w;
  w.conveyors.push_back(belt(200, 0));
  w.parts.push_back(cube("p", 0));
  w.sinks.push_back({"chute", {at(900, 0, 10), {100, 300, 100}}});
  DeviceClock clock(w);
  clock.advance_to(10);
  CHECK(clock.parts()[0].holder == Holder::removed);
  const auto* e = find(clock, "sink", "p");
  REQUIRE(e);
  CHECK(e->time_s == Approx(850.0 / 200).margin(1e-12));
  CHECK(clock.part_pose(0).translation().x() == Approx(850).margin(1e-9));
}

TEST_CASE("logic rules: delayed set, timed input, follow") {
  Workcell w;
  w.logic.push_back({3, true, -1, 0.5, 1003, true, 1});
  w.logic.push_back({0, true, 2.0, 0, 1005, true, 2});
  w.logic.push_back({4, true, -1, 0.1, 1004, true, 3});
  w.logic.push_back({4, false, -1, 0.1, 1004, false, 3});
  DeviceClock clock(w);
  clock.advance_to(1);
  clock.set_signal(3, true);
  clock.set_signal(4, true);
  clock.advance_to(1.4);
  CHECK_FALSE(clock.signal(1003));
  CHECK(clock.signal(1004));  // on since 1.1 s
  clock.advance_to(1.5);
  CHECK(clock.signal(1003));
  CHECK(find(clock, "signal", "1003")->time_s == Approx(1.5).margin(1e-12));
  clock.set_signal(4, false);
  clock.advance_to(1.55);
  CHECK(clock.signal(1004));
  clock.advance_to(1.6);
  CHECK_FALSE(clock.signal(1004));
  CHECK_FALSE(clock.signal(1005));
  clock.advance_to(3);
  CHECK(clock.signal(1005));
  CHECK(find(clock, "signal", "1005")->time_s == 2.0);
  CHECK(w.drives(1004));
  CHECK_FALSE(w.drives(1006));
}

TEST_CASE("rules that switch each other without delay are a clear error, not a hang") {
  Workcell w;
  w.logic.push_back({2001, true, -1, 0, 2002, true, 1});
  w.logic.push_back({2002, true, -1, 0, 2001, false, 2});
  w.logic.push_back({2001, false, -1, 0, 2002, false, 3});
  w.logic.push_back({2002, false, -1, 0, 2001, true, 4});
  DeviceClock clock(w);
  CHECK_THROWS_AS(clock.set_signal(2001, true), motion::DeviceError);
}

TEST_CASE("a part released onto a moving conveyor starts moving at the release instant") {
  Workcell w;
  w.conveyors.push_back(belt(100, 0));
  w.parts.push_back({"p", "", collision::make_box({20, 20, 20}), at(200, 500, 10)});  // on the floor
  DeviceClock clock(w);
  clock.carry(0, 10);
  CHECK(clock.parts()[0].holder == Holder::carried);
  clock.advance_to(2);
  clock.put_down(0, at(300, 0, 10), 11);
  CHECK(clock.parts()[0].holder == Holder::conveyor);
  clock.advance_to(3.25);
  CHECK(clock.part_pose(0).translation().x() == Approx(425).margin(1e-9));
  const auto* rel = find(clock, "release", "p");
  REQUIRE(rel);
  CHECK(rel->detail == "belt");
  CHECK(rel->line == 11);
}

TEST_CASE("next_change is infinite for a cell at rest") {
  Workcell w;
  w.parts.push_back(cube("p", 0));
  DeviceClock clock(w);
  CHECK(std::isinf(clock.next_change()));
  clock.advance_to(1e9);
  CHECK(clock.time_s() == 1e9);
}

TEST_CASE("parts queue at the belt's end stop: each stops against the one ahead in its band") {
  Workcell w;
  w.conveyors.push_back(belt(100, 0));  // always running
  w.parts.push_back(cube("a", 900));
  w.parts.push_back(cube("b", 700));
  w.parts.push_back(cube("c", 650));
  w.parts.push_back(cube("beside", 600));
  w.parts.back().pose = at(600, 50, 10);  // its band (y 40..60) overlaps no other part's (y -10..10)
  motion::PartDef turned = cube("turned", 400);  // turned 45 degrees about z: reaches 10√2 ahead
  turned.pose = motion::trans(400, 0, 10, 0, 0, 45);
  w.parts.push_back(turned);
  DeviceClock clock(w);
  clock.advance_to(100);
  const auto x = [&](std::size_t i) { return clock.part_pose(i).translation().x(); };
  CHECK(x(0) == Approx(1000).margin(1e-9));  // origin at the end stop
  CHECK(x(1) == Approx(980).margin(1e-9));   // touching a
  CHECK(x(2) == Approx(960).margin(1e-9));   // touching b
  CHECK(x(3) == Approx(1000).margin(1e-9));  // nothing ahead in its band
  CHECK(x(4) == Approx(950 - 10 * std::sqrt(2.0)).margin(1e-9));
  const auto* b = find(clock, "conveyor_queue", "b");
  REQUIRE(b);
  CHECK(b->detail == "a");
  CHECK(b->time_s == Approx((980 - 700) / 100.0).margin(1e-9));
  CHECK(find(clock, "conveyor_queue", "c")->detail == "b");
  CHECK(find(clock, "conveyor_end", "a"));
  CHECK(find(clock, "conveyor_end", "beside"));
  CHECK_FALSE(find(clock, "conveyor_end", "b"));

  SECTION("the queue moves on when its head is taken away") {
    clock.carry(0, 12);
    clock.advance_to(100.1);
    CHECK(x(1) == Approx(990).margin(1e-9));  // 0.1 s at 100 mm/s
    clock.advance_to(200);
    CHECK(x(1) == Approx(1000).margin(1e-9));
    CHECK(x(2) == Approx(980).margin(1e-9));
    CHECK(x(4) == Approx(970 - 10 * std::sqrt(2.0)).margin(1e-9));
  }
  SECTION("a stopped belt holds the queue where it is, and it closes up when the belt runs again") {
    Workcell v = w;
    v.conveyors[0].signal = 1;
    DeviceClock d(v);
    d.set_signal(1, true);
    d.advance_to(2);  // a at 1000 since 1 s; b at 900, c at 850 (both still moving)
    d.set_signal(1, false);
    d.advance_to(50);
    CHECK(d.part_pose(1).translation().x() == Approx(900).margin(1e-9));
    d.set_signal(1, true);
    d.advance_to(100);
    CHECK(d.part_pose(1).translation().x() == Approx(980).margin(1e-9));
    CHECK(d.part_pose(2).translation().x() == Approx(960).margin(1e-9));
  }
}

TEST_CASE("rewind: back to an instant after the last change only") {
  // A run that halts at a contact between two checked poses goes back to the contact instant
  // (World::rewind_to). The belt runs from 0 s; the sensor switches on at 4.75 s.
  Workcell w;
  w.conveyors.push_back(belt(100, 0));
  w.parts.push_back(cube("p", 0));
  motion::Sensor s;
  s.name = "eye";
  s.signal = 1001;
  s.region = {at(500, 0, 10), {50, 100, 100}};  // x in [475, 525]
  w.sensors.push_back(s);
  DeviceClock clock(w);
  clock.advance_to(4.7);
  CHECK(clock.rewind(4.7));  // no time back: nothing to do
  CHECK(clock.rewind(4.65));
  CHECK(clock.time_s() == 4.65);
  CHECK(clock.part_pose(0).translation().x() == Approx(465).margin(1e-9));
  CHECK_FALSE(clock.rewind(4.7));  // never forward
  clock.advance_to(4.8);  // the sensor switched at 4.75
  REQUIRE(clock.signal(1001));
  const std::size_t events = clock.events().size();
  CHECK_FALSE(clock.rewind(4.74));  // before the switch: refused, nothing changed
  CHECK(clock.time_s() == 4.8);
  CHECK(clock.signal(1001));
  CHECK(clock.events().size() == events);
  CHECK(clock.rewind(4.76));  // after it: allowed
  CHECK(clock.part_pose(0).translation().x() == Approx(476).margin(1e-9));
  CHECK(clock.signal(1001));
}

TEST_CASE("two sensors on one input are wired in parallel (#32): on while either sees a part") {
  Workcell w;
  w.conveyors.push_back(belt());
  w.parts.push_back(cube("p", 100));
  w.sensors.push_back({"left", 1001, {at(300, 0, 10), {20, 200, 100}}, "", ""});
  w.sensors.push_back({"right", 1001, {at(600, 0, 10), {20, 200, 100}}, "", ""});
  DeviceClock clock(w);  // neither sees it: off, and no error
  CHECK_FALSE(clock.signal(1001));
  clock.set_signal(1, true);
  clock.advance_to(2.0);  // origin at 300: under left
  CHECK(clock.signal(1001));
  clock.advance_to(3.0);  // at 400: between them
  CHECK_FALSE(clock.signal(1001));
  clock.advance_to(5.0);  // at 600: under right
  CHECK(clock.signal(1001));
  // The switch instants are exact: left from 1.9 to 2.1 s, right from 4.9 s.
  std::vector<double> on;
  for (const auto& e : clock.events())
    if (e.kind == "signal" && e.subject == "1001") on.push_back(e.time_s);
  REQUIRE(on.size() == 3);
  CHECK(on[0] == Approx(1.9).margin(1e-9));
  CHECK(on[1] == Approx(2.1).margin(1e-9));
  CHECK(on[2] == Approx(4.9).margin(1e-9));
}

TEST_CASE("a sensor with overlap sensing switches when any part of the part enters (#32)") {
  Workcell w;
  w.conveyors.push_back(belt());
  w.parts.push_back(cube("p", 100));  // faces at x = 90 and 110
  w.sensors.push_back({"barrier", 1001, {at(300, 0, 10), {2, 200, 100}}, "", "", motion::Sensing::overlap});
  w.sensors.push_back({"centre", 1002, {at(300, 0, 10), {2, 200, 100}}, "", ""});
  DeviceClock clock(w);
  clock.set_signal(1, true);
  clock.advance_to(5.0);
  const auto time_of = [&](const std::string& k, const std::string& d) {
    for (const auto& e : clock.events())
      if (e.kind == "signal" && e.subject == k && e.detail == d) return e.time_s;
    return -1.0;
  };
  // The leading face (x + 10) reaches the barrier's near face (299) at 1.89 s; the trailing
  // face (x - 10) leaves its far face (301) at 2.11 s. The origin: 1.99 s to 2.01 s.
  CHECK(time_of("1001", "on") == Approx(1.89).margin(1e-9));
  CHECK(time_of("1001", "off") == Approx(2.11).margin(1e-9));
  CHECK(time_of("1002", "on") == Approx(1.99).margin(1e-9));
  CHECK(time_of("1002", "off") == Approx(2.01).margin(1e-9));
}

TEST_CASE("a gated sink removes what lies in it at its edge, with the parts resting on them (#32)") {
  Workcell w;
  w.parts.push_back({"pallet", "", collision::make_box({100, 100, 20}), at(0, 0, 10)});
  w.parts.push_back({"box", "", collision::make_box({20, 20, 20}), at(0, 0, 30)});  // on the pallet
  w.parts.push_back({"spare", "", collision::make_box({20, 20, 20}), at(500, 0, 10)});
  motion::Sink s;
  s.name = "unload";
  s.region = {at(0, 0, 0), {50, 50, 30}};  // z -15..15: the pallet's origin only
  s.signal = 11;
  s.on_rising = false;
  w.sinks.push_back(s);
  DeviceClock clock(w);
  REQUIRE(clock.parts()[1].support == 0);  // the box rests on the pallet
  clock.set_signal(11, true);
  CHECK(clock.parts()[0].holder == Holder::world);  // rising edge: nothing
  clock.advance_to(1);
  clock.set_signal(11, false);
  CHECK(clock.parts()[0].holder == Holder::removed);
  CHECK(clock.parts()[1].holder == Holder::removed);  // rode on it
  CHECK(clock.parts()[2].holder == Holder::world);
}

TEST_CASE("the event log keeps its first kMaxEvents events and counts the rest (issue 29)") {
  // A 0.1 s blink: 2001 switches every 0.05 s, one event per switch.
  Workcell w;
  w.logic.push_back({0, true, 0, 0, 2001, true, 1});           // at 0 s: on
  w.logic.push_back({2001, true, -1, 0.05, 2001, false, 2});  // on -> 0.05 s later off
  w.logic.push_back({2001, false, -1, 0.05, 2001, true, 3});  // off -> 0.05 s later on
  DeviceClock clock(w);
  const double end = 0.05 * static_cast<double>(motion::kMaxEvents + 1000) - 0.025;
  clock.advance_to(end);
  CHECK(clock.events().size() == motion::kMaxEvents);
  CHECK(clock.events_dropped() == 1000);
  CHECK(clock.events().front().time_s == 0);
  CHECK(clock.events().back().time_s == Approx(0.05 * static_cast<double>(motion::kMaxEvents - 1)).margin(1e-6));
  // The signal still blinks: the cap drops events, never changes.
  const bool on = clock.signal(2001);
  clock.advance_to(end + 0.05);
  CHECK(clock.signal(2001) != on);
  CHECK(clock.events_dropped() == 1001);
  // Rewind still sees the last change, kept or not: back before it is refused.
  CHECK_FALSE(clock.rewind(end + 0.01));
  CHECK(clock.rewind(end + 0.04));
  // A scratch copy records nothing, capped or not.
  DeviceClock scratch = clock.scratch_copy();
  scratch.advance_to(end + 1);
  CHECK(scratch.events_dropped() == clock.events_dropped());
}
