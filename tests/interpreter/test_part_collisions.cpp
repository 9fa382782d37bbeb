// Parts as collision bodies (motion/world.hpp, docs/cell-format.md "Parts and devices"): the
// carried part against the cell and other parts, resting parts against the arm, the contacts
// of a grasp and a release excused until the bodies part, the carried part in the trace.
#include "interpreter_fixture.hpp"

#include "asimov/robots/robot.hpp"

#include <algorithm>
#include <random>

using namespace asimov;

namespace {
motion::Location at(double x, double y, double z) { return motion::trans(x, y, z, 0, 0, 0); }

// programs/cells/carried_crash_cell.yaml in code: a 300 x 40 x 20 plate on the table at
// (500, -200), gripped at its centre; a post at x 580..620, y -20..20, z -400..-300.
motion::Cell plate_cell(bool with_plate) {
  motion::Cell cell = test::empty_puma_cell();
  cell.tool = at(0, 0, 200);
  cell.tool_shape = collision::make_box({50, 80, 100});
  for (auto& v : cell.tool_shape->vertices) v.z() += 90;
  cell.objects.push_back({"table", collision::make_box({700, 1200, 40}), at(750, 0, -420)});
  cell.objects.push_back({"post", collision::make_box({40, 40, 100}), at(600, 0, -350)});
  auto& w = cell.workcell;
  w.gripper.declared = true;
  w.gripper.zone = {at(0, 0, 200), {30, 30, 30}};
  if (with_plate) w.parts.push_back({"plate", "", collision::make_box({300, 40, 20}), at(500, -200, -390)});
  return cell;
}

// Down to the plate and grip it.
const std::string kPick =
    ".PROGRAM main()\n"
    "  SPEED 50 ALWAYS\n"
    "  SET down = TRANS(0, 0, 0, 0, 180, 0)\n"
    "  SET pick = TRANS(500, -200, -390):down\n"
    "  APPRO pick, 100\n"
    "  MOVES pick\n"
    "  CLOSEI\n";
const std::string kSlide = kPick +
    "  DEPARTS 30\n"
    "  MOVES TRANS(500, 200, -360):down\n"
    ".END\n";

struct Run {
  explicit Run(motion::Cell cell) : sim(std::move(cell)), interp(sim, out) {}
  interpreter::RunResult run(const std::string& text) {
    for (const auto& d : interp.load_source(text, "test.v2")) REQUIRE(d.warning);
    return interp.run("main");
  }
  motion::Simulator sim;
  std::ostringstream out;
  interpreter::Interpreter interp;
};
}  // namespace

TEST_CASE("the carried part, not the arm, hits the post: the report names it, the point lies on both") {
  SECTION("without the plate the same motions pass the post") {
    Run r(plate_cell(false));
    CHECK(r.run(kSlide).status == interpreter::RunStatus::completed);
  }
  SECTION("with the plate in the gripper") {
    Run r(plate_cell(true));
    const auto res = r.run(kSlide);
    REQUIRE(res.status == interpreter::RunStatus::collision);
    CHECK(res.collision.body_a == "post");
    CHECK(res.collision.body_b == "carried part:plate");
    CHECK(res.line == 9);
    // The plate's +Y face (centre y + 20) meets the post's -Y face y = -20, between the post's
    // x 580..620 and the plate's z -370..-350.
    const collision::Vec3 p = res.collision.point;
    CHECK(p.y() == Approx(-20).margin(0.01));
    CHECK(p.x() >= 580 - 0.01);
    CHECK(p.x() <= 620 + 0.01);
    CHECK(p.z() >= -370 - 0.01);
    CHECK(p.z() <= -350 + 0.01);
    // Lifted off the table it lay on: that contact of the grasp was excused, not reported.
    CHECK(res.collision.time_s > 0);
  }
}

TEST_CASE("a part carried into a resting part, the arm into a resting part") {
  SECTION("carried into another part") {
    motion::Cell cell = plate_cell(true);
    cell.objects.pop_back();  // no post: a block lying in its place
    cell.workcell.parts.push_back({"block", "", collision::make_box({40, 40, 100}), at(600, 0, -350)});
    Run r(std::move(cell));
    const auto res = r.run(kSlide);
    REQUIRE(res.status == interpreter::RunStatus::collision);
    CHECK(res.collision.body_a == "carried part:plate");  // the first declared part: the lower id
    CHECK(res.collision.body_b == "part:block");
    CHECK(res.collision.point.y() == Approx(-20).margin(0.01));
  }
  SECTION("the tool into a resting part (named part:NAME)") {
    motion::Cell cell = plate_cell(true);
    cell.objects.pop_back();
    // A tall block under the path of the tool down to the plate.
    cell.workcell.parts.push_back({"tower", "", collision::make_box({60, 60, 200}), at(500, -200, -200)});
    cell.workcell.parts.front().pose = at(500, -200, -390);
    Run r(std::move(cell));
    const auto res = r.run(kSlide);
    REQUIRE(res.status == interpreter::RunStatus::collision);
    CHECK(res.collision.body_b == "part:tower");  // against an arm body (lower ids)
    CHECK(res.collision.body_a.find("part:") == std::string::npos);
  }
}

TEST_CASE("the trace holds the carried part's pose, a grasp and a release leave the support free") {
  motion::Cell cell = plate_cell(true);
  cell.objects.pop_back();  // no post: the slide completes
  Run r(std::move(cell));
  r.sim.recorders().trace.on = true;
  const std::string program =
      ".PROGRAM main()\n"
      "  SET down = TRANS(0, 0, 0, 0, 180, 0)\n"
      "  SET pick = TRANS(500, -200, -390):down\n"
      "  APPRO pick, 100\n"
      "  MOVES pick\n"
      "  CLOSEI\n"
      "  DEPARTS 30\n"
      "  MOVES TRANS(500, 200, -360):down\n"
      "  MOVES TRANS(500, 200, -388):down\n"
      "  OPENI\n"
      "  DEPARTS 100\n"
      ".END\n";
  REQUIRE(r.run(program).status == interpreter::RunStatus::completed);
  std::size_t carried = 0;
  for (const auto& s : r.sim.recorders().trace.samples) {
    if (s.part.empty()) continue;
    ++carried;
    CHECK(s.part == "plate");
    // Gripped at its centre: the part's origin is the tool point.
    CHECK((s.part_pose.translation() - s.tool.translation()).norm() < 1e-6);
  }
  CHECK(carried > 10);
  const auto* cell_state = r.interp.cell_state();
  REQUIRE(cell_state);
  CHECK(cell_state->clock().parts()[0].holder == motion::Holder::world);
  CHECK(cell_state->clock().part_pose(0).translation().isApprox(collision::Vec3(500, 200, -390), 1e-9));
}

namespace {
// Continuous path with a part in the gripper (docs/blending.md): the plate, lifted 150 mm, is
// carried along +Y over where the post was and then down; the corner at (500, 60, -240) is
// rounded. A small peg sits inside that corner: 3 mm below and beside the sharp corner's swept
// plate (y 27..37 against the plate's edge at y 40 on the way down, z -263..-253 against its
// underside at -250 on the way across), where the rounded corner (at SPEED 100 the plate's
// centre passes about 15 mm inside the corner in y and in z) cuts. At x 610..630 it is under
// the plate's end only: the gripper (x 475..525) sweeps down beside it.
const std::string kCorner = kPick +
    "  DEPARTS 150\n"
    "  SPEED 100 ALWAYS\n"
    "  MOVES TRANS(500, 60, -240):down\n"
    "%"
    "  MOVES TRANS(500, 60, -360):down\n"
    ".END\n";

motion::Cell peg_cell(bool with_plate, double step_mm = 1.0) {
  motion::Cell cell = plate_cell(with_plate);
  cell.objects.pop_back();  // no post
  cell.objects.push_back({"peg", collision::make_box({20, 10, 10}), at(620, 32, -258)});
  cell.collision.step_mm = step_mm;
  return cell;
}

std::string corner_program(const char* between) {
  std::string p = kCorner;
  p.replace(p.find('%'), 1, between);
  return p;
}
}  // namespace

TEST_CASE("blending: the carried part is checked along the rounded corner, not the sharp one", "[blend]") {
  SECTION("blended: the plate cuts the corner into the peg, inside the overlap") {
    Run r(peg_cell(true));
    const auto res = r.run(corner_program(""));
    REQUIRE(res.status == interpreter::RunStatus::collision);
    CHECK(res.collision.body_a == "peg");
    CHECK(res.collision.body_b == "carried part:plate");
    CHECK(res.line == 11);  // the overlap is walked with the motion that blends in: the second MOVES
    REQUIRE(res.motion_times.size() == 5);
    const interpreter::MotionTime &across = res.motion_times[3], &down = res.motion_times[4];
    CHECK(down.blended);
    CHECK(res.collision.time_s > down.start_s);
    CHECK(res.collision.time_s < across.start_s + across.duration_s);
    // The plate's underside (z <= -253 there) against the peg's top, or its edge against the peg's side.
    CHECK(res.collision.point.z() <= -253 + 0.01);
    CHECK(res.collision.point.y() <= 37 + 0.01);
  }
  SECTION("stopped at the corner (BREAK) the plate passes the peg") {
    Run r(peg_cell(true));
    const auto res = r.run(corner_program("  BREAK\n"));
    CHECK(res.status == interpreter::RunStatus::completed);
  }
  SECTION("without the plate the arm and the gripper pass the peg on the rounded corner") {
    Run r(peg_cell(false));
    const auto res = r.run(corner_program(""));
    CHECK(res.status == interpreter::RunStatus::completed);
  }
  SECTION("with a coarse step continuous checking still finds it on the overlap") {
    Run r(peg_cell(true, 100.0));
    const auto res = r.run(corner_program(""));
    REQUIRE(res.status == interpreter::RunStatus::collision);
    CHECK(res.collision.body_a == "peg");
    CHECK(res.collision.body_b == "carried part:plate");
  }
}

TEST_CASE("blending: a deferred CLOSE with a part to grasp stops the arm first", "[blend]") {
  motion::Cell cell = plate_cell(true);
  cell.objects.pop_back();
  Run r(std::move(cell));
  const auto res = r.run(".PROGRAM main()\n"
                         "  SET down = TRANS(0, 0, 0, 0, 180, 0)\n"
                         "  SET pick = TRANS(500, -200, -390):down\n"
                         "  APPRO pick, 100\n"
                         "  MOVES pick\n"
                         "  CLOSE\n"
                         "  DEPARTS 30\n"
                         "  MOVES TRANS(500, 0, -360):down\n"
                         ".END\n");
  REQUIRE(res.status == interpreter::RunStatus::completed);
  REQUIRE(res.motion_times.size() == 4);
  CHECK(res.motion_times[1].blended);         // MOVES pick into APPRO: no hand change between
  CHECK_FALSE(res.motion_times[2].blended);   // the grasp at pick: DEPARTS starts at rest
  CHECK(res.motion_times[2].start_s == Approx(res.motion_times[1].start_s + res.motion_times[1].duration_s));
  CHECK(res.motion_times[3].blended);         // carrying the plate, DEPARTS and MOVES blend again
  const auto* cell_state = r.interp.cell_state();
  REQUIRE(cell_state);
  CHECK(cell_state->clock().parts()[0].holder == motion::Holder::carried);
}

// World::sleep_far (docs/cell-format.md "Speed"): pairs of the arm and resting parts that cannot
// come near during a walk or a rest leave the tested pairs. Thirty parts stacked behind the
// robot (over a metre from every path) sleep; a tower at the end of the slide, 400 mm from the
// tool when the slide starts, must not: the same contact is found with and without the decoys,
// with continuous checking and with sampled poses only.
TEST_CASE("far resting parts sleep through the motions without hiding or moving a contact") {
  for (const bool continuous : {true, false}) {
    CAPTURE(continuous);
    const auto make = [&](bool decoys) {
      motion::Cell cell = plate_cell(true);
      cell.objects.pop_back();  // no post
      cell.collision.continuous = continuous;
      cell.workcell.parts.push_back({"tower", "", collision::make_box({60, 60, 200}), at(500, 200, -200)});
      if (decoys)
        for (int i = 0; i < 30; ++i)
          cell.workcell.parts.push_back(
              {"decoy" + std::to_string(i), "", collision::make_box({40, 40, 40}), at(-700 + 60 * (i % 6), -150 + 60 * (i / 6), -380)});
      return cell;
    };
    Run plain(make(false)), decoys(make(true));
    const auto a = plain.run(kSlide);
    const auto b = decoys.run(kSlide);
    REQUIRE(a.status == interpreter::RunStatus::collision);
    REQUIRE(b.status == interpreter::RunStatus::collision);
    CHECK(a.collision.body_a + " / " + a.collision.body_b == b.collision.body_a + " / " + b.collision.body_b);
    CHECK((a.collision.body_a + a.collision.body_b).find("tower") != std::string::npos);
    CHECK(a.error.line == b.error.line);
    const double tol = plain.sim.cell().collision.toc_tolerance_s >= 0 ? plain.sim.cell().collision.toc_tolerance_s : 1e-6;
    CHECK(std::abs(a.collision.time_s - b.collision.time_s) <= 2 * tol + 1e-12);
    // The decoys never moved and were never reported.
    REQUIRE(decoys.interp.cell_state());
    const auto& clock = decoys.interp.cell_state()->clock();
    for (std::size_t i = 0; i < clock.parts().size(); ++i)
      if (clock.parts()[i].def->name.rfind("decoy", 0) == 0) CHECK(clock.parts()[i].holder == motion::Holder::world);
  }
}

// The broad phase (docs/collision.md §14) against every pair at every pose (broad_phase off, the
// reference): random cells of resting parts and small objects around the pick and the slide,
// some near the path, continuous and sampled. The outcome, the contact (bodies, time), the
// checked poses' verdicts and the clearance report (pairs within report_within_mm and their least
// distances) must agree; fails when the broad phase leaves out a pair that comes near.
TEST_CASE("the broad phase finds the same contacts and clearance report as every pair, random cells") {
  std::mt19937 rng(1217);
  std::uniform_real_distribution<double> ux(150, 850), uy(-600, 600), uz(-395, -150), us(10, 60);
  int contacts = 0, reported = 0, runs = 0;
  double worst = 0;
  for (int cell_i = 0; cell_i < 16; ++cell_i) {
    const bool continuous = cell_i % 2 == 0;
    motion::Cell base = plate_cell(true);
    base.collision.continuous = continuous;
    if (cell_i % 4 < 2) base.objects.pop_back();  // no post
    for (int i = 0; i < 30; ++i) {
      const double s = us(rng);
      // Cells 8..15: most bodies behind the robot (far from every path), a few in front.
      // One draw per statement: the order of a call's arguments is unspecified (gcc and clang
      // differ), and the cells must be the same whichever compiler builds the test.
      const double x = cell_i >= 8 && i % 4 != 0 ? ux(rng) - 1100 : ux(rng);
      const double y = uy(rng);
      const double z = uz(rng) + s / 2;
      const motion::Location p = at(x, y, z);
      if (i % 3 == 0) base.objects.push_back({"o" + std::to_string(i), collision::make_box({s, s, s}), p});
      else base.workcell.parts.push_back({"r" + std::to_string(i), "", collision::make_box({s, s, s}), p});
    }
    motion::Cell off = base;
    off.collision.broad_phase = false;
    CAPTURE(cell_i, continuous);
    Run a(base), b(off);
    const auto ra = a.run(kSlide);
    const auto rb = b.run(kSlide);
    ++runs;
    REQUIRE(ra.status == rb.status);
    if (ra.status == interpreter::RunStatus::collision) {
      ++contacts;
      CHECK(ra.collision.body_a + " / " + ra.collision.body_b == rb.collision.body_a + " / " + rb.collision.body_b);
      CHECK(std::abs(ra.collision.time_s - rb.collision.time_s) <= 2e-6 + 1e-12);
    }
    const auto& pa = a.sim.recorders().clearance.pairs;
    const auto& pb = b.sim.recorders().clearance.pairs;
    CHECK(pa.size() == pb.size());
    // Each least distance is one the checker measured at an evaluated pose (checked pose or
    // probe), and the broad phase may place the checked poses differently (a mover's room limits
    // a stretch). Between two evaluated poses a pair moves at most A <= max(step_mm, d) (gap
    // stepping's allowance at distance d, clearance 0), so each run's least distance m is within
    // A/2 of the continuous minimum d* and d* >= m/2: two runs agree within max(step_mm, m)/2.
    // A pair the broad phase left out while it came near is missing or far off.
    const double step = base.collision.step_mm;
    for (const auto& x : pb) {
      const auto it = std::find_if(pa.begin(), pa.end(), [&](const auto& y) { return y.pair == x.pair; });
      REQUIRE(it != pa.end());
      const double diff = std::abs(it->distance_mm - x.distance_mm);
      CHECK(diff <= std::max(step, std::max(it->distance_mm, x.distance_mm)) / 2 + 1e-9);
      worst = std::max(worst, diff);
      ++reported;
    }
  }
  CHECK(runs == 16);
  CHECK(contacts > 0);
  CHECK(contacts < runs);
  CHECK(reported > 0);
  WARN(contacts << " contacts, " << reported << " clearance-report pairs compared, largest difference " << worst << " mm");
}
