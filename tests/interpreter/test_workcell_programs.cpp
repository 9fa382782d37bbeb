// Programs against a reacting cell: SIGNAL / SIG / WAIT through the devices' clock, CLOSEI /
// OPENI grasping and releasing parts (interpreter/src/cell_signals.cpp).
#include "interpreter_fixture.hpp"

#include "asimov/motion/support.hpp"
#include "asimov/robots/robot.hpp"

using namespace asimov;

namespace {
motion::Location at(double x, double y, double z) { return motion::trans(x, y, z, 0, 0, 0); }

// The default PUMA with a belt far from the arm (output 1 runs it), a 20 mm cube on it and a
// sensor (input 1001) 475 mm down the belt; a table under the flange and a cube in the grasp
// zone (the zone is centred on the flange at READY).
motion::Cell reacting_cell(bool close_on_air_error = false) {
  motion::Cell cell = test::empty_puma_cell();
  cell.collision.enabled = false;  // devices and hand only (the table stands in the arm)
  auto& w = cell.workcell;
  motion::Conveyor belt{"belt", {at(0, -3000, -20), {1000, 200, 40}}, collision::Vec3::UnitX(), 100, 1};
  w.conveyors.push_back(belt);
  cell.objects.push_back({"belt", collision::make_box(belt.body.size), belt.body.pose});
  w.parts.push_back({"riding", "", collision::make_box({20, 20, 20}), at(-500, -3000, 10)});
  w.sensors.push_back({"eye", 1001, {at(0, -3000, 10), {50, 200, 100}}, "", ""});
  const motion::Location flange = robots::flange_pose(cell.robot, cell.start_joints);
  const collision::Vec3 f = flange.translation();
  cell.objects.push_back({"table", collision::make_box({300, 300, 40}), at(f.x(), f.y(), f.z() - 300)});
  w.parts.push_back({"held", "", collision::make_box({20, 20, 20}), at(f.x(), f.y(), f.z())});
  w.gripper.declared = true;
  w.gripper.zone = {motion::Location::Identity(), {40, 40, 40}};
  w.gripper.close_on_air_error = close_on_air_error;
  return cell;
}

struct CellFixture {
  explicit CellFixture(bool air_error = false) : sim(reacting_cell(air_error)), interp(sim, out) {}
  interpreter::RunResult run(const std::string& text) {
    const auto diags = interp.load_source(text, "test.v2");
    for (const auto& d : diags) REQUIRE(d.warning);
    return interp.run("main");
  }
  motion::Simulator sim;
  std::ostringstream out;
  interpreter::Interpreter interp;
};

const motion::CellEvent* find(const motion::CellRuntime& c, const std::string& kind, const std::string& subject) {
  for (const auto& e : c.clock().events())
    if (e.kind == kind && e.subject == subject) return &e;
  return nullptr;
}
}  // namespace

TEST_CASE("WAIT SIG(input) ends when the conveyor brings the part to the sensor") {
  CellFixture f;
  const auto r = f.run(".PROGRAM main()\n  SIGNAL 1\n  WAIT SIG(1001)\n  TYPE \"seen\"\n.END\n");
  REQUIRE(r.status == interpreter::RunStatus::completed);
  CHECK(f.out.str() == "seen\n");
  const auto* cell = f.interp.cell_state();
  REQUIRE(cell);
  const auto* on = find(*cell, "signal", "1001");
  REQUIRE(on);
  CHECK(on->time_s == Approx(4.75).margin(1e-12));  // origin at x = -25 after 475 mm at 100 mm/s
  CHECK(f.sim.time_s() >= 4.75);
  CHECK(f.sim.time_s() < 4.75 + f.interp.limits().tick_s + 1e-12);
  const auto* out = find(*cell, "signal", "1");
  REQUIRE(out);
  CHECK(out->line == 2);
}

TEST_CASE("a WAIT no device can satisfy names the undriven signal") {
  CellFixture f;
  f.interp.limits().max_wait_s = 0.5;
  const auto r = f.run(".PROGRAM main()\n  WAIT SIG(1002)\n.END\n");
  REQUIRE(r.status == interpreter::RunStatus::error);
  CHECK(r.error.message == "*Wait limit exceeded*");
  CHECK(r.error.detail == "still false after 0.5 s; no device in the cell drives signal 1002");
}

TEST_CASE("CLOSEI grasps the part in the zone, OPENI puts it on the table, HAND.TIME passes") {
  CellFixture f;
  const auto r = f.run(".PROGRAM main()\n  PARAMETER HAND.TIME = 0.25\n  CLOSEI\n  DRIVE 1, 20, 50\n  OPENI\n.END\n");
  REQUIRE(r.status == interpreter::RunStatus::completed);
  const auto* cell = f.interp.cell_state();
  REQUIRE(cell);
  const auto* grasp = find(*cell, "grasp", "held");
  REQUIRE(grasp);
  CHECK(grasp->line == 3);
  CHECK(grasp->time_s == 0);
  const auto* rel = find(*cell, "release", "held");
  REQUIRE(rel);
  CHECK(rel->line == 5);
  // The part lies on the table (top face 280 mm below the flange height at READY).
  const motion::Location flange0 = robots::flange_pose(f.sim.robot(), f.sim.cell().start_joints);
  const double top = flange0.translation().z() - 280;
  std::size_t held = 1;
  CHECK(cell->clock().parts()[held].holder == motion::Holder::world);
  CHECK(cell->clock().part_pose(held).translation().z() == Approx(top + 10).margin(1e-9));
  CHECK(f.sim.time_s() > 0.5);  // two hand times and the drive
}

TEST_CASE("CLOSEI on air is reported, or an error when the cell says so, OPENI over nothing stops") {
  SECTION("reported") {
    CellFixture f;
    REQUIRE(f.run(".PROGRAM main()\n  DRIVE 1, 90, 50\n  CLOSEI\n.END\n").status == interpreter::RunStatus::completed);
    CHECK(find(*f.interp.cell_state(), "close_on_air", ""));
  }
  SECTION("an error") {
    CellFixture f(true);
    const auto r = f.run(".PROGRAM main()\n  DRIVE 1, 90, 50\n  CLOSEI\n.END\n");
    REQUIRE(r.status == interpreter::RunStatus::error);
    CHECK(r.error.message == "*Nothing in the gripper*");
  }
  SECTION("no support below") {
    CellFixture f;
    const auto r = f.run(".PROGRAM main()\n  CLOSEI\n  DRIVE 2, 60, 50\n  OPENI\n.END\n");
    REQUIRE(r.status == interpreter::RunStatus::error);
    CHECK(r.error.message == "*No support below the part*");
    CHECK(r.error.detail.find("no support below part held") == 0);
  }
}

// A program run to its end on `cell` (max_wait_s > 0: the wait limit).
struct CellRun {
  CellRun(motion::Cell cell, const std::string& text, double max_wait_s = 0) : sim(std::move(cell)), interp(sim, out) {
    if (max_wait_s > 0) interp.limits().max_wait_s = max_wait_s;
    for (const auto& d : interp.load_source(text, "test.v2")) REQUIRE(d.warning);
    r = interp.run("main");
  }
  motion::Simulator sim;
  std::ostringstream out;
  interpreter::Interpreter interp;
  interpreter::RunResult r;
};

// A post standing over the belt, 770 mm ahead of the riding cube's leading face (cube x in
// [-510, -490], post x from 280): with the belt on, the cube reaches it after 7.7 s, while the
// program waits and the arm stands still (Walker::dwell). Touching is a resting contact: the
// collision is the instant the cube has pushed its resting tolerance into the post, 7.7 s plus
// that depth over the belt speed (docs/collision.md §15).
namespace {
double sink_s() { return motion::resting_tolerance(collision::make_box({20, 20, 20})) / 100; }
}  // namespace
TEST_CASE("a part the belt carries into a post while the program waits is a collision at the WAIT") {
  const auto post_cell = [](double post_y, bool continuous, motion::Stepping stepping) {
    motion::Cell cell = reacting_cell();
    cell.collision.enabled = true;
    cell.collision.continuous = continuous;
    cell.collision.stepping = stepping;
    cell.objects.erase(cell.objects.end() - 1);  // the table under the flange (it stands in the arm)
    cell.workcell.parts.pop_back();             // and the cube on it
    cell.objects.push_back({"post", collision::make_box({40, 40, 40}), at(300, post_y, 30)});  // z in [10, 50]
    return cell;
  };
  const std::string wait_event = ".PROGRAM main()\n  SIGNAL 1\n  WAIT.EVENT , 20\n  TYPE \"done\"\n.END\n";
  const std::string wait_sig = ".PROGRAM main()\n  SIGNAL 1\n  TYPE \"waiting\"\n  WAIT SIG(2001)\n.END\n";
  for (const bool continuous : {false, true})
    for (const auto stepping : {motion::Stepping::fixed, motion::Stepping::gap}) {
      CAPTURE(continuous, static_cast<int>(stepping));
      {
        CellRun run(post_cell(-3000, continuous, stepping), wait_event);
        const auto& r = run.r;
        REQUIRE(r.status == interpreter::RunStatus::collision);
        CHECK(r.collision.body_a + " / " + r.collision.body_b == "post / part:riding");
        const double tol = run.sim.cell().collision.toc_tolerance_s >= 0 ? run.sim.cell().collision.toc_tolerance_s : 1e-6;
        CHECK(std::abs(r.collision.time_s - (7.7 + sink_s())) <= tol + 1e-9);
        CHECK(r.collision.time_free_s <= 7.7 + sink_s() + 1e-9);
        CHECK(r.collision.time_free_s > 7.7);
        CHECK(r.error.line == 3);  // the WAIT.EVENT
        CHECK(run.out.str().empty());
        CHECK(run.sim.time_s() == Approx(r.collision.time_s).margin(1e-12));
        // The cube is reported where it touched the post (its leading face at x = 280, 100 mm/s
        // from x = -500 at 0 s), not at the checked pose after the contact.
        REQUIRE(run.interp.cell_state());
        const auto& clock = run.interp.cell_state()->clock();
        CHECK(clock.time_s() == r.collision.time_s);
        for (std::size_t i = 0; i < clock.parts().size(); ++i)
          if (clock.parts()[i].def->name == "riding")
            CHECK(clock.part_pose(i).translation().x() == Approx(-500 + 100 * r.collision.time_s).margin(1e-9));
      }
      {  // a polling WAIT (tick by tick) finds it the same way
        const CellRun run(post_cell(-3000, continuous, stepping), wait_sig, 30);
        REQUIRE(run.r.status == interpreter::RunStatus::collision);
        CHECK(std::abs(run.r.collision.time_s - (7.7 + sink_s())) <= 1e-6 + 1e-9);
        CHECK(run.r.error.line == 4);
      }
      {  // the post beside the belt: the wait ends, the cube rides on past it
        const CellRun run(post_cell(-2800, continuous, stepping), wait_event);
        REQUIRE(run.r.status == interpreter::RunStatus::completed);
        CHECK(run.out.str() == "done\n");
        CHECK(run.sim.time_s() == Approx(20).margin(1e-9));
      }
    }
}

// The contact comes between two checked poses and a sensor switches in between (after the
// contact, before the pose that found it): the run halts at the contact instant, and the switch
// never happened. Post x from 280.5: the cube's leading face touches at 7.705 s; sensor 1002's
// box from x = 270.75: the origin enters at 7.7075 s (fixed stepping checks at 7.71 s).
TEST_CASE("a sensor that would switch after the contact instant does not, the part stays where it touched") {
  for (const bool continuous : {false, true})
    for (const auto stepping : {motion::Stepping::fixed, motion::Stepping::gap}) {
      CAPTURE(continuous, static_cast<int>(stepping));
      motion::Cell cell = reacting_cell();
      cell.collision.enabled = true;
      cell.collision.continuous = continuous;
      cell.collision.stepping = stepping;
      cell.objects.erase(cell.objects.end() - 1);  // the table under the flange
      cell.workcell.parts.pop_back();             // and the cube on it
      cell.objects.push_back({"post", collision::make_box({40, 40, 40}), at(300.5, -3000, 30)});
      cell.workcell.sensors.push_back({"late", 1002, {at(335.375, -3000, 10), {129.25, 200, 100}}, "", ""});
      CellRun run(std::move(cell), ".PROGRAM main()\n  SIGNAL 1\n  WAIT.EVENT , 20\n.END\n");
      REQUIRE(run.r.status == interpreter::RunStatus::collision);
      CHECK(std::abs(run.r.collision.time_s - (7.705 + sink_s())) <= 1e-6 + 1e-9);
      REQUIRE(run.interp.cell_state());
      const auto& clock = run.interp.cell_state()->clock();
      CHECK_FALSE(clock.signal(1002));
      for (const auto& e : clock.events()) CHECK_FALSE((e.kind == "signal" && e.subject == "1002"));
      CHECK(clock.signal(1001) == false);  // eye: on from 4.75 s to 5.25 s, off again
      CHECK(clock.part_pose(0).translation().x() == Approx(-500 + 100 * run.r.collision.time_s).margin(1e-9));
    }
}

// A fast belt (3 m/s) carries the cube into a 4 mm post while the arm makes a short, slow
// joint move (two grid poses in all): the belt-borne part's motion limits the stretches too
// (Walk::part_cap), so sampled checking (continuous off), fixed or gap, finds the contact as
// continuous checking does. The eye sensor switches during the move (a device change). The
// leading face reaches the post's face at (-2 + 490) / 3000 s.
TEST_CASE("a part on a fast belt cannot pass a thin post between the checked poses of an arm motion") {
  for (const bool continuous : {false, true})
    for (const auto stepping : {motion::Stepping::fixed, motion::Stepping::gap}) {
      CAPTURE(continuous, static_cast<int>(stepping));
      motion::Cell cell = reacting_cell();
      cell.collision.enabled = true;
      cell.collision.continuous = continuous;
      cell.collision.stepping = stepping;
      cell.objects.erase(cell.objects.end() - 1);  // the table under the flange
      cell.workcell.parts.pop_back();             // and the cube on it
      cell.workcell.conveyors[0].speed_mm_s = 3000;
      cell.objects.push_back({"post", collision::make_box({4, 40, 40}), at(0, -3000, 20)});
      CellRun run(std::move(cell), ".PROGRAM main()\n  SIGNAL 1\n  SPEED 2 ALWAYS\n  DRIVE 1, 3, 100\n  BREAK\n.END\n");
      REQUIRE(run.r.status == interpreter::RunStatus::collision);
      CHECK(run.r.collision.body_a + " / " + run.r.collision.body_b == "post / part:riding");
      CHECK(std::abs(run.r.collision.time_s - 488.0 / 3000) <= 2e-6);
      CHECK(run.r.error.line == 4);
    }
}

TEST_CASE("waiting with nothing moving queries nothing") {
  motion::Cell cell = reacting_cell();
  cell.collision.enabled = true;
  cell.objects.erase(cell.objects.end() - 1);
  cell.workcell.parts.pop_back();
  // The belt is off: neither the wait nor the hand time checks a pose.
  const CellRun run(std::move(cell), ".PROGRAM main()\n  WAIT.EVENT , 5\n  PARAMETER HAND.TIME = 2\n  CLOSEI\n.END\n");
  REQUIRE(run.r.status == interpreter::RunStatus::completed);
  CHECK(run.sim.time_s() == Approx(7).margin(1e-12));
  CHECK(run.sim.recorders().counts.poses == 0);
}
