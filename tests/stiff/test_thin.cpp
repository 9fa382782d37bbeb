// Fast motions against thin things (docs/collision-method.md §6.3, docs/stiff-cases.md "Thin things"):
// the PUMA sweeps a 0.5 mm tool blade about J1 through a thin vertical plate (1 mm or
// 0.1 mm) at SPEED 100. Checked poses are spaced by distance (step_mm), so whether a contact
// is seen depends on where the samples fall relative to the plate: each setting is run with
// the plate shifted across one sample spacing in `kPhases` positions and the contacts counted.
// - clearance 0 with step_mm larger than plate + blade: some phases miss (the blind spot);
// - clearance 0 with step_mm <= plate + blade: the blade cannot pass between two samples;
// - the documented safe setting, clearance c > 0 with step_mm <= c: no phase ever misses, for
//   any thickness (a pair farther than c at one pose cannot touch before the next).
#include "asimov/motion/simulator.hpp"
#include "asimov/robots/puma560.hpp"

#include "support/cell_bodies.hpp"

#include <catch2/catch.hpp>

#include <cmath>

using namespace asimov;
using namespace asimov::motion;

namespace {

constexpr int kPhases = 12;
constexpr double kBlade = 0.5;  // tool blade thickness along the sweep [mm]

struct Setting {
  double plate_mm, step_mm, clearance_mm;
  double blade_mm = kBlade;
  bool continuous = false;  // continuous checking between checked poses (docs/collision.md §12)
};

struct Outcome {
  int contacts = 0;           // phases in which the sweep halted on the plate
  int other = 0;              // phases halted by anything else (must stay 0)
  double max_tool_step = 0;   // largest tool-vertex displacement between two checked poses [mm]
  std::uint64_t poses = 0;    // checked poses of the sweep (first phase)
};

Cell base_cell(double blade_mm = kBlade) {
  Cell c;
  c.robot = robots::puma560();
  c.tool = trans(0, 0, 200, 0, 0, 0);
  // The blade: 60 mm wide (flange X), 0.5 mm thin (flange Y), 100 mm long (flange Z).
  collision::Pose at = collision::Pose::Identity();
  at.translation() = collision::Vec3(0, 0, 150);
  c.tool_shape = collision::transformed(collision::make_box({60, blade_mm, 100}), at);
  return c;
}

// Joints with the tool pointing down at (600, -100, -180): the sweep's start.
robots::JointVector sweep_start() {
  static const robots::JointVector q = [] {
    Simulator sim(base_cell());
    REQUIRE(sim.start_move(trans(600, -100, -180, 0, 180, 0), false, {}, 1).status == MotionStatus::ok);
    REQUIRE(sim.finish_motion().status == MotionStatus::ok);
    return sim.joints();
  }();
  return q;
}

// The plate lies in the blade's plane at the middle of the sweep (J1 + 10 degrees), moved
// `offset` mm along the blade's normal, and reaches up to the blade's middle: the blade
// crosses it edge-first over its lower 50 mm, its thin side leading (rotating about J1, the
// blade's far end sets the sample spacing, its near end the time inside the plate).
Cell thin_cell(const Setting& s, double offset, Stepping stepping) {
  Cell c = base_cell(s.blade_mm);
  robots::JointVector mid = sweep_start();
  mid[0] += 10;
  std::vector<collision::Pose> frames;
  robots::link_frames(c.robot, mid, frames);
  collision::Pose local = collision::Pose::Identity();
  local.translation() = collision::Vec3(0, offset, 150 + 75);
  CellObject plate = test::box_object("plate", {200, s.plate_mm, 150}, {0, 0, 0});
  plate.pose = frames.back() * local;
  c.objects.push_back(plate);
  c.collision.step_mm = s.step_mm;
  c.collision.clearance_mm = s.clearance_mm;
  c.collision.stepping = stepping;
  c.collision.continuous = s.continuous;
  c.start_joints = sweep_start();
  return c;
}

// Fixed stepping unless told: the spacing rules below are about the step_mm grid; gap stepping
// (the default in cells) checks a subset of that grid and must see the same contacts.
Outcome sweep(const Setting& s, double speed = 100, Stepping stepping = Stepping::fixed) {
  Outcome out;
  const robots::JointVector start = sweep_start();
  robots::JointVector target = start;
  target[0] += 20;
  // Phases: the plate shifted along its normal across the largest spacing the step rule allows.
  for (int k = 0; k < kPhases; ++k) {
    const Cell cell = thin_cell(s, std::max(s.step_mm, s.clearance_mm) * k / kPhases, stepping);
    Simulator sim(cell);
    sim.recorders().trace.on = true;
    SpeedSettings speed_settings;
    speed_settings.program = speed;
    REQUIRE(sim.start_joint_move(target, speed_settings, 1).status == MotionStatus::ok);
    const MotionResult r = sim.finish_motion();
    if (r.status == MotionStatus::collision) {
      if (r.collision.body_a == "tool" && r.collision.body_b == "plate") ++out.contacts;
      else ++out.other;
    }
    if (k == 0) {  // spacing measured on the first phase
      out.poses = sim.recorders().counts.poses;
      const auto& tr = sim.recorders().trace.samples;
      std::vector<collision::Pose> fa, fb;
      for (std::size_t i = 1; i < tr.size(); ++i) {
        robots::link_frames(cell.robot, tr[i - 1].joints, fa);
        robots::link_frames(cell.robot, tr[i].joints, fb);
        for (const auto& v : cell.tool_shape->vertices)
          out.max_tool_step = std::max(out.max_tool_step, (fb.back() * v - fa.back() * v).norm());
      }
    }
  }
  return out;
}

}  // namespace

TEST_CASE("thin plates at clearance 0: samples farther apart than plate plus blade miss contacts", "[stiff][thin]") {
  // docs/stiff-cases.md, table "Thin things"; counts are of kPhases plate positions.
  for (const Setting s : {Setting{0.1, 5, 0}, Setting{0.1, 20, 0}, Setting{1, 20, 0}}) {
    const Outcome o = sweep(s);
    INFO("plate " << s.plate_mm << " mm, step_mm " << s.step_mm << ": contacts " << o.contacts << " of " << kPhases
                  << ", max tool step " << o.max_tool_step << " mm, poses " << o.poses);
    CHECK(o.other == 0);
    CHECK(o.max_tool_step > s.plate_mm + s.blade_mm);  // the blade can pass between two samples ...
    CHECK(o.contacts < kPhases);                   // ... and does for some plate positions
    CHECK(o.contacts > 0);                         // (not all: it depends on where samples fall)
  }
}

TEST_CASE("thin plates at clearance 0: samples closer than plate plus blade never miss", "[stiff][thin]") {
  // step_mm bounds the real spacing from above (here it is about 0.28 step_mm): step_mm <=
  // plate + blade is the documented guarantee; the bound's slack makes coarser steps safe too.
  for (const Setting s : {Setting{1, 1, 0}, Setting{0.1, 0.5, 0}, Setting{0.1, 1, 0}, Setting{0.1, 2, 0},
                          Setting{1, 5, 0}}) {
    const Outcome o = sweep(s);
    INFO("plate " << s.plate_mm << " mm, step_mm " << s.step_mm << ": contacts " << o.contacts << " of " << kPhases
                  << ", max tool step " << o.max_tool_step << " mm, poses " << o.poses);
    CHECK(o.other == 0);
    CHECK(o.max_tool_step <= s.step_mm);
    CHECK(o.max_tool_step <= s.plate_mm + s.blade_mm);
    CHECK(o.contacts == kPhases);
    const Outcome gap = sweep(s, 100, Stepping::gap);
    CHECK(gap.other == 0);
    CHECK(gap.contacts == kPhases);
    CHECK(gap.poses < o.poses);  // far from the plate, gap stepping skips grid poses
  }
}

TEST_CASE("thin plates: clearance c > 0 with step_mm <= c never misses, even with coarse steps", "[stiff][thin]") {
  // (With c = 20 mm other pairs, e.g. the wrist and the plate, come within c first.)
  for (const Setting s : {Setting{0.1, 1, 1}, Setting{1, 1, 1}, Setting{0.1, 0.5, 0.5}, Setting{0.1, 0.2, 2},
                          Setting{0.1, 5, 5}, Setting{1, 5, 5}}) {
    const Outcome o = sweep(s);
    INFO("plate " << s.plate_mm << " mm, step_mm " << s.step_mm << ", clearance " << s.clearance_mm << ": contacts "
                  << o.contacts << " of " << kPhases << ", max tool step " << o.max_tool_step);
    CHECK(o.other == 0);
    CHECK(o.contacts == kPhases);
    const Outcome gap = sweep(s, 100, Stepping::gap);
    CHECK(gap.other == 0);
    CHECK(gap.contacts == kPhases);
  }
}

TEST_CASE("thin plates: SPEED does not change which contacts are seen (samples are spaced by distance)",
          "[stiff][thin]") {
  for (const Setting s : {Setting{0.1, 20, 0}, Setting{0.1, 1, 1}}) {
    const Outcome fast = sweep(s, 100), slow = sweep(s, 10);
    CHECK(fast.contacts == slow.contacts);
    CHECK(fast.poses == slow.poses);
  }
}

TEST_CASE("thin plates at the default settings: continuous checking misses no contact at any thickness",
          "[stiff][thin][continuous]") {
  // docs/stiff-cases.md, table "Thin things, continuous": plates 0.01-1 mm, blades 0.05-1 mm,
  // step_mm 1 (default), 5 and 20, clearance 0, SPEED 100, 12 plate positions each; gap
  // stepping (the default) with continuous checking (the default).
  int runs = 0, misses = 0;
  for (const double plate : {0.01, 0.1, 1.0})
    for (const double blade : {0.05, 0.5, 1.0})
      for (const double step : {1.0, 5.0, 20.0}) {
        const Setting s{plate, step, 0, blade, true};
        const Outcome o = sweep(s, 100, Stepping::gap);
        INFO("plate " << plate << " blade " << blade << " step_mm " << step << ": contacts " << o.contacts);
        CHECK(o.other == 0);
        CHECK(o.contacts == kPhases);
        runs += kPhases;
        misses += kPhases - o.contacts;
      }
  WARN("thin plates, continuous: " << runs << " runs, " << misses << " misses");
}
