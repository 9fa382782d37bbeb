// A UR-style description as shipped: joint limits and speeds from a joint_limits.yaml whose
// angles are tagged !degrees (ros/xacro turns them into radians). J1 keeps +-360 deg and
// 180 deg/s: a 180 deg turn takes at least a second, 400 deg is refused.
#include "asimov/motion/simulator.hpp"
#include "asimov/robots/urdf_loader.hpp"

#include "support/joints.hpp"
#include "support/result.hpp"
#include "support/scratch.hpp"

#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>

using namespace asimov;
using namespace asimov::motion;
using asimov::test::jv;

TEST_CASE("UR-style xacro: !degrees limits keep J1 within 360 deg and 180 deg/s", "[urdf][xacro][simulator]") {
  const std::filesystem::path dir = asimov::test::scratch_dir("ur_limits");
  std::ofstream(dir / "joint_limits.yaml")
      << "joint_limits:\n  shoulder_pan_joint:\n    max_position: !degrees  360.0\n    min_position: !degrees -360.0\n"
         "    max_velocity: !degrees  180.0\n  shoulder_lift_joint:\n    max_position: !degrees  360.0\n"
         "    min_position: !degrees -360.0\n    max_velocity: !degrees  180.0\n";
  std::ofstream(dir / "ur.urdf.xacro")
      << "<robot xmlns:xacro=\"http://wiki.ros.org/xacro\" name=\"ur_like\">\n"
         "<xacro:property name=\"limits\" value=\"${xacro.load_yaml('joint_limits.yaml')['joint_limits']}\"/>\n"
         "<xacro:macro name=\"j\" params=\"name parent child xyz axis\"><xacro:property name=\"l\" value=\"${limits[name]}\"/>"
         "<joint name=\"${name}\" type=\"revolute\"><parent link=\"${parent}\"/><child link=\"${child}\"/><origin xyz=\"${xyz}\"/>"
         "<axis xyz=\"${axis}\"/><limit lower=\"${l.min_position}\" upper=\"${l.max_position}\" velocity=\"${l.max_velocity}\" effort=\"150\"/></joint>"
         "</xacro:macro>\n"
         "<link name=\"base_link\"><collision><origin xyz=\"0 0 0.04\"/><geometry><cylinder radius=\"0.07\" length=\"0.08\"/></geometry></collision></link>"
         "<link name=\"shoulder_link\"/><link name=\"upper_arm_link\"><collision><origin xyz=\"0.2 0 0\"/><geometry><box size=\"0.3 0.08 0.08\"/></geometry></collision></link>"
         "<link name=\"tool0\"/>"
         "<xacro:j name=\"shoulder_pan_joint\" parent=\"base_link\" child=\"shoulder_link\" xyz=\"0 0 0.1625\" axis=\"0 0 1\"/>"
         "<xacro:j name=\"shoulder_lift_joint\" parent=\"shoulder_link\" child=\"upper_arm_link\" xyz=\"0 0.14 0\" axis=\"0 1 0\"/>"
         "<joint name=\"flange\" type=\"fixed\"><parent link=\"upper_arm_link\"/><child link=\"tool0\"/><origin xyz=\"0.425 0 0\"/></joint>\n"
         "</robot>\n";
  Cell c;
  c.robot = asimov::test::must(robots::load_urdf((dir / "ur.urdf.xacro").string()));
  REQUIRE(c.robot.joint_count() == 2);
  CHECK(c.robot.upper[0] == Approx(360));
  CHECK(c.robot.max_velocity[0] == Approx(180));
  c.start_joints = jv({0, 0});
  Simulator sim(c);
  REQUIRE(sim.start_joint_move(jv({180, 0}), {}, 1).status == MotionStatus::ok);
  REQUIRE(sim.finish_motion().status == MotionStatus::ok);
  CHECK(sim.time_s() >= 1.0);  // read as radians it took 0.132 s
  const MotionResult past = sim.start_joint_move(jv({400, 0}), {}, 2);
  CHECK(past.error.message == "*Joint limit exceeded*");
  CHECK(past.error.detail == "J1 = 400.000 > 360.000");
}
