// The collision scene of a cell (motion/scene.hpp): body order, groups, joined pairs, poses,
// the generated pair matrix, and the simulator running on that matrix.
#include "support/scratch.hpp"
#include "asimov/motion/scene.hpp"
#include "asimov/motion/simulator.hpp"
#include "asimov/robots/puma560.hpp"

#include "support/joints.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <unistd.h>

using namespace asimov;
using namespace asimov::motion;
using robots::JointVector;

using asimov::test::jv;

namespace {
Cell puma_cell() {
  Cell c;
  c.robot = robots::puma560();
  c.start_joints = jv({0, -90, 90, 0, 0, 0});
  c.tool_shape = collision::transformed(collision::make_box({40, 40, 80}), collision::Pose(Eigen::Translation3d(0, 0, 60)));
  CellObject block;
  block.name = "block";
  block.mesh = collision::make_box({100, 200, 100});
  block.pose.translation() = collision::Vec3(220, -150, 660);
  c.objects.push_back(block);
  CellObject table = block;
  table.name = "table";
  table.mesh = collision::make_box({700, 1200, 40});
  table.pose.translation() = collision::Vec3(750, 0, -420);
  c.objects.push_back(table);
  c.collision.ignore = {{"link1", "table"}, {"nobody", "table"}};
  return c;
}
}  // namespace

TEST_CASE("scene: bodies in engine order, groups, joined and ignored pairs", "[scene]") {
  const Cell cell = puma_cell();
  const Scene s = scene_bodies(cell);
  REQUIRE(s.bodies.size() == 10);
  const char* names[] = {"link0", "link1", "link2", "link3", "link4", "link5", "link6", "tool", "block", "table"};
  for (std::size_t i = 0; i < 10; ++i) CHECK(s.bodies[i].name == names[i]);
  CHECK(s.bodies[0].group == kStaticGroup);
  CHECK(s.bodies[0].is_static);
  CHECK(s.bodies[3].group == 3);
  CHECK(s.bodies[7].group == 6);  // the tool is rigid with link6
  CHECK(s.bodies[7].robot);
  CHECK(s.bodies[8].group == kStaticGroup);
  CHECK_FALSE(s.bodies[8].robot);
  const std::vector<collision::BodyPair> joined = {{0, 1}, {1, 2}, {2, 3}, {3, 4}, {4, 5}, {5, 6}, {5, 7}, {6, 7}};
  CHECK(s.adjacent == joined);
  CHECK(s.ignored == std::vector<collision::BodyPair>{{1, 9}});
  CHECK(s.unknown_ignored == std::vector<std::string>{"nobody"});

  std::vector<collision::Pose> frames, poses;
  const JointVector q = jv({10, -60, 150, 20, 40, 30});
  scene_poses(cell, s, q, frames, poses);
  REQUIRE(poses.size() == 10);
  CHECK(poses[3].isApprox(frames[3]));
  CHECK(poses[7].isApprox(frames[6]));
  CHECK(poses[9].isApprox(cell.objects[1].pose));
}

TEST_CASE("scene: the generated matrix keeps joined pairs ADJACENT and robot-object pairs tested", "[scene]") {
  const Cell cell = puma_cell();
  const Scene s = scene_bodies(cell);
  const collision::AutoPairs p = collision::generate_pairs(auto_pairs_input(cell, s, 400));
  for (const auto& j : s.adjacent)
    CHECK(p.entry(j.a, j.b).reason == (j == collision::BodyPair{6, 7} ? collision::PairReason::rigid
                                                                       : collision::PairReason::adjacent));
  CHECK(p.entry(1, 9).reason == collision::PairReason::user_ignore);
  for (std::uint32_t k = 1; k <= 7; ++k) CHECK(p.tested(k, 8));  // every moving body vs block
  CHECK(p.entry(8, 9).reason == collision::PairReason::rigid);
}

TEST_CASE("scene: the simulator on the generated matrix halts on the block as before, with fewer pairs", "[scene][simulator]") {
  Cell cell = puma_cell();
  cell.tool_shape.reset();
  const auto cache = asimov::test::scratch_dir() / "scene_pairs";
  std::filesystem::remove(cache);
  MotionResult results[2];
  collision::StepCounts counts[2];
  for (int generated = 0; generated < 2; ++generated) {
    Cell c = cell;
    c.collision.generated_pairs = generated == 1;
    c.collision.pair_samples = 400;
    c.collision.pairs_cache = cache.string();
    Simulator sim(c);
    REQUIRE(sim.start_joint_move(jv({0, -90, 180, 0, 0, 0}), {}, 42).status == MotionStatus::ok);
    results[generated] = sim.finish_motion();
    counts[generated] = sim.recorders().counts.counts;
  }
  CHECK(std::filesystem::exists(cache));  // the generated matrix was cached
  REQUIRE(results[0].status == MotionStatus::collision);
  REQUIRE(results[1].status == MotionStatus::collision);
  CHECK(results[1].collision.body_a == results[0].collision.body_a);
  CHECK(results[1].collision.body_b == results[0].collision.body_b);
  // Fewer moving pairs also mean fewer sampled poses (the step rule): other brackets, both
  // within toc_tolerance_s after the contact.
  CHECK(std::abs(results[1].collision.time_s - results[0].collision.time_s) <= cell.collision.toc_tolerance_s);
  CHECK(counts[1].pairs_enabled < counts[0].pairs_enabled);  // NEVER self pairs are skipped
}
