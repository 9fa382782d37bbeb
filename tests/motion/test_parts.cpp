// Gripping geometry (motion/parts.hpp): the part CLOSE takes, and where a released part rests.
#include "asimov/motion/cell_runtime.hpp"
#include "asimov/motion/parts.hpp"

#include <catch2/catch.hpp>

#include <cmath>

using namespace asimov;
using collision::Vec3;
using motion::DeviceClock;
using motion::Support;

namespace {
motion::Location at(double x, double y, double z, double o = 0) { return motion::trans(x, y, z, o, 0, 0); }
motion::PartDef cube(const std::string& name, double x, double y, double z) {
  return {name, "", collision::make_box({20, 20, 20}), at(x, y, z)};
}
}  // namespace

TEST_CASE("grasp: nothing in the zone is a close on air") {
  motion::Workcell w;
  w.parts.push_back(cube("far", 500, 0, 10));
  const DeviceClock clock(w);
  CHECK_FALSE(motion::grasp_candidate(clock, {at(0, 0, 10), {30, 30, 30}}).has_value());
}

TEST_CASE("grasp: of two overlapping candidates the one nearest the zone centre, ties to the first") {
  motion::Workcell w;
  w.parts.push_back(cube("a", 8, 0, 10));
  w.parts.push_back(cube("b", -3, 0, 10));  // overlaps a: both origins in the zone
  w.parts.push_back(cube("c", 3, 0, 10));   // as near as b, declared later
  DeviceClock clock(w);
  const motion::Region zone{at(0, 0, 10), {30, 30, 30}};
  REQUIRE(motion::grasp_candidate(clock, zone) == 1u);
  clock.carry(1, 1);  // carried parts are not candidates
  CHECK(motion::grasp_candidate(clock, zone) == 2u);
}

TEST_CASE("release: the part drops onto the highest support directly below") {
  const auto table = collision::make_box({1000, 1000, 40});   // top at z = 0 when posed at -20
  const auto pallet = collision::make_box({200, 200, 30});    // top at z = 30 posed at 15
  const auto part = collision::make_box({20, 20, 20});
  const std::vector<Support> both{{&table, at(0, 0, -20)}, {&pallet, at(300, 0, 15)}};
  CHECK(*motion::drop_distance(part, at(0, 0, 40.5), both) == Approx(30.5).margin(1e-12));   // on the table
  CHECK(*motion::drop_distance(part, at(300, 0, 52), both) == Approx(12).margin(1e-12));     // on the pallet
  CHECK(*motion::drop_distance(part, at(405, 0, 52), both) == Approx(12).margin(1e-12));     // overhanging its edge
  CHECK(*motion::drop_distance(part, at(0, 0, 10), both) == 0);                             // resting already
  CHECK_FALSE(motion::drop_distance(part, at(5000, 0, 10), both).has_value());              // nothing below
  CHECK_FALSE(motion::drop_distance(part, at(0, 0, -100), both).has_value());               // under the table
}

TEST_CASE("release: crossed bars meet edge to edge (no vertex lies over a face)") {
  const auto bar = collision::make_box({200, 10, 10});
  const std::vector<Support> below{{&bar, at(0, 0, 0)}};
  CHECK(*motion::drop_distance(bar, at(0, 0, 37, 90), below) == Approx(27).margin(1e-9));
}

TEST_CASE("release: a cylinder onto a sloped wedge mesh") {
  // A wedge: the support's highest point under the part is a face, not a vertex of either.
  collision::Polyhedron wedge;
  wedge.vertices = {{-100, -100, 0}, {100, -100, 0}, {100, 100, 0}, {-100, 100, 0}, {100, -100, 100}, {100, 100, 100}};
  wedge.triangles = {{0, 2, 1}, {0, 3, 2}, {0, 1, 4}, {3, 5, 2}, {1, 2, 5}, {1, 5, 4}, {0, 4, 5}, {0, 5, 3}};
  const auto post = collision::make_box({10, 10, 10});
  const std::vector<Support> below{{&wedge, at(0, 0, 0)}};
  // Slope z = (x + 100) / 2: under a 10 mm block at x = 0 the highest point is at x = 5, z = 52.5.
  CHECK(*motion::drop_distance(post, at(0, 0, 100), below) == Approx(100 - 5 - 52.5).margin(1e-9));
}

TEST_CASE("cell runtime: grasp, carry, release onto a moving conveyor, no support is an error") {
  motion::Cell cell;
  cell.objects.push_back({"table", collision::make_box({400, 400, 40}), at(0, 0, -20)});  // top z = 0
  auto& w = cell.workcell;
  w.gripper.declared = true;
  w.gripper.zone = {at(0, 0, 50), {30, 30, 30}};  // 50 mm out along the flange Z
  motion::Conveyor belt{"belt", {at(1000, 0, -20), {1000, 200, 40}}, Vec3::UnitX(), 100, 0};
  cell.objects.push_back({"belt", collision::make_box(belt.body.size), belt.body.pose});
  w.conveyors.push_back(belt);
  w.parts.push_back(cube("p", 0, 0, 10));
  motion::CellRuntime rt(cell);
  // Flange pointing down (tool Z = -world Z) 60 mm above the part's origin: the zone centre is
  // 10 mm above it.
  const motion::Location down = at(0, 0, 60) * motion::Location(Eigen::AngleAxisd(M_PI, Vec3::UnitX()));
  CHECK_FALSE(rt.close(at(900, 0, 60), 1).has_value());  // air
  CHECK(rt.clock().events().back().kind == "close_on_air");
  REQUIRE(rt.close(down, 2) == 0u);
  CHECK(rt.clock().parts()[0].holder == motion::Holder::carried);
  // Carried to 30 mm above the belt (part origin at z = 40, bottom at 30) and released.
  const motion::Location over_belt = at(800, 0, 90) * motion::Location(Eigen::AngleAxisd(M_PI, Vec3::UnitX()));
  CHECK(rt.carried_pose(over_belt).translation().isApprox(Vec3(800, 0, 40)));
  rt.clock().advance_to(1);
  CHECK_FALSE(rt.open(over_belt, 3).has_value());
  CHECK(rt.clock().parts()[0].holder == motion::Holder::conveyor);
  CHECK(rt.clock().part_pose(0).translation().isApprox(Vec3(800, 0, 10)));
  rt.clock().advance_to(2);
  CHECK(rt.clock().part_pose(0).translation().x() == Approx(900).margin(1e-9));
  // Grasp it off the moving belt and release it over nothing.
  const motion::Location over_part = at(900, 0, 60) * motion::Location(Eigen::AngleAxisd(M_PI, Vec3::UnitX()));
  REQUIRE(rt.close(over_part, 4) == 0u);
  const motion::Location outside = at(5000, 0, 60) * motion::Location(Eigen::AngleAxisd(M_PI, Vec3::UnitX()));
  const auto err = rt.open(outside, 5);
  REQUIRE(err.has_value());
  CHECK(*err == "no support below part p released at [5000.000, 0.000, 10.000]");
  CHECK(rt.carried() == 0u);  // still held
}
