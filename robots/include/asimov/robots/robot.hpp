// A serial arm: a standard DH chain (the built-in PUMA) or a chain of URDF-style joints (fixed
// origin transform + axis, revolute or prismatic), display-angle mapping, limits, link bodies.
// Joint values crossing this interface are DISPLAY values (VAL convention, degrees; mm for
// prismatic joints); the internal values (DH angles [rad], or radians / mm for a joint chain)
// are converted in exactly one place.
#pragma once
#include "asimov/collision/polyhedron.hpp"
#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

namespace asimov::robots {

using collision::Pose;
using collision::Vec3;

constexpr int kMaxJoints = 8;
// Fixed capacity, no heap: joint vectors live in the per-pose hot path.
using JointVector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxJoints, 1>;

struct DhLink {
  double d = 0, a = 0, alpha = 0;  // [mm], [mm], [rad]; A = Rz(theta) Tz(d) Tx(a) Rx(alpha)
};

// theta_dh [rad] = sign * display [deg] * pi/180 + offset [rad]
struct JointMapping {
  double sign = 1;
  double offset = 0;
};

enum class JointType { revolute, prismatic };

// A joint of the arm chain that follows the movable joint before it (a URDF <mimic> on the
// chain, as IRB 5400's joint5b follows joint5): after that joint's motion come `origin` and a
// motion by multiplier * q + offset (internal units: rad, mm) about / along `axis`.
struct CoupledJoint {
  std::string name;
  Pose origin = Pose::Identity();  // [mm], fixed joints before it folded in
  Vec3 axis = Vec3::UnitZ();
  JointType type = JointType::revolute;
  double multiplier = 1, offset = 0;
};
constexpr int kMaxCoupled = 4;  // followers of one joint

// One movable joint of a URDF-style chain: frame k+1 = frame k . origin . motion(q) [. each
// coupled joint's origin . motion], where motion is a rotation by q [rad] about `axis`
// (revolute) or a translation by q [mm] along it.
struct ChainJoint {
  std::string name;
  Pose origin = Pose::Identity();  // [mm]; fixed joints before this one are folded in
  Vec3 axis = Vec3::UnitZ();       // unit vector in the joint frame
  JointType type = JointType::revolute;
  std::vector<CoupledJoint> coupled;  // at most kMaxCoupled
};

// The directions joint k moves the flange by, at internal joints q, in the base frame: its own
// axis (rate 1) and those of its coupled joints (rate = multiplier): the Jacobian column of joint
// k is the sum of rate * [a x (p_flange - point); a] (revolute) or rate * [a; 0] (prismatic).
struct JointScrew {
  Vec3 axis = Vec3::UnitZ(), point = Vec3::Zero();
  double rate = 1;
  JointType type = JointType::revolute;
};
struct JointScrews {
  std::array<JointScrew, 1 + kMaxCoupled> screw;
  int count = 0;
};


struct LinkBody {
  int link = 0;                  // 0 = base column (fixed), k = moves with DH frame k
  std::string name;              // "link0" ... "link6"
  collision::Polyhedron mesh;    // in frame `link` (DH frame, or chain frame); a finger: at its joint's 0
  int hand = -1;                 // the hand joint (Robot::hand) that moves it, or -1: rigid in frame `link`
};

// A joint off the arm chain (docs/robots.md "Grippers and side branches"): a prismatic finger
// the hand drives, a <mimic> follower of one, or a follower of an arm joint (a parallel-link
// lever: it moves with that joint, not with the hand). Its bodies are stored at joint value 0;
// at value v their pose in frame `frame` is hand_offset(): the parent's offset . origin .
// motion(v) . origin^-1.
struct HandJoint {
  std::string name;
  int frame = 0;                   // the arm frame it hangs on
  int parent = -1;                 // the hand joint it hangs on (a finger on a finger), or -1
  Pose origin = Pose::Identity();  // its joint frame in frame `frame` [mm], parents at 0
  Vec3 axis = Vec3::UnitZ();       // unit, in its joint frame
  JointType type = JointType::prismatic;
  double open = 0, closed = 0;     // display values (mm; deg for a revolute follower) at OPEN, CLOSE
  double lower = 0, upper = 0;     // its limits (display)
  int leader = -1;                 // a <mimic> follower: value = multiplier * leader's + offset (display)
  int arm_joint = -1;              // a follower of arm joint j (0-based): value = multiplier * q_j + offset
  double multiplier = 1, offset = 0;
};

struct Robot {
  std::string name;
  std::vector<DhLink> dh;        // standard DH chain (used when `chain` is empty)
  std::vector<ChainJoint> chain; // URDF-style chain (when not empty, `dh` is unused)
  Pose flange_offset = Pose::Identity();  // chain only: fixed joints after the last movable one
  JointVector ready;             // READY pose (display); empty: (0, -90, 90, 0, 0, 0)
  std::vector<JointMapping> mapping;
  JointVector lower, upper;      // display limits [deg]
  // Per joint: the precision its limits were written with (display units; empty or 0: exact).
  // A URDF limit of 1.04719755 rad is 60 deg to 2.9e-7 deg: J3 = 60 is within it (limit_low/high).
  JointVector limit_tolerance;
  JointVector max_velocity;      // [deg/s] at SPEED 100
  JointVector max_acceleration;  // [deg/s^2]
  double max_tool_speed = 500;   // straight-line translation [mm/s]
  double max_tool_accel = 2000;  // [mm/s^2]
  double max_tool_rot_speed = 90;   // straight-line rotation [deg/s]
  double max_tool_rot_accel = 360;  // [deg/s^2]
  std::vector<LinkBody> bodies;
  std::vector<HandJoint> hand;        // fingers and their followers, parents first
  std::vector<std::string> links;     // every link of the description (URDF), bodies or not; built-in: empty
  std::vector<std::string> warnings;  // load-time warnings (URDF mesh problems), for the user
  int joint_count() const { return static_cast<int>(chain.empty() ? dh.size() : chain.size()); }
  bool is_chain() const { return !chain.empty(); }
  bool prismatic(int j) const { return is_chain() && chain[static_cast<std::size_t>(j)].type == JointType::prismatic; }
};

// `frame_k` is the pose of frame k; returns frame k+1 (frame_k . joint_transform(robot, k, q)).
Pose joint_screws(const Robot& robot, int k, double q, const Pose& frame_k, JointScrews& out);
// True when a chain joint has coupled followers (the closed forms then do not apply).
bool has_coupled_joints(const Robot& robot);

// The READY joints of the robot (robot.ready, or (0, -90, 90, 0, 0, 0) for a 6-axis arm).
JointVector ready_joints(const Robot& robot);

// True when the robot is a standard-DH 6R arm of the PUMA type (docs/kinematics.md §5: alpha =
// (90, 0, -90, 90, -90, 0) deg, d1 = d2 = a1 = a4 = a5 = d5 = 0): the closed-form IK applies.
bool is_puma_type(const Robot& robot);

// Converts display joint values [deg] to DH angles [rad] and back (the only place that does).
JointVector display_to_dh(const Robot& robot, const JointVector& display);
JointVector dh_to_display(const Robot& robot, const JointVector& dh);

// frames[0] = robot base (identity), frames[k] = frame of link k, k = 1..n; flange = frames[n]
// (for a chain, frames[n] includes flange_offset).
void link_frames(const Robot& robot, const JointVector& display, std::vector<Pose>& frames);
Pose flange_pose(const Robot& robot, const JointVector& display);

// Index of the first joint outside its limits (widened by limit_tolerance), or -1.
int first_limit_violation(const Robot& robot, const JointVector& display);
// Joint j's limits widened by its limit_tolerance: the bounds every limit comparison uses.
double limit_low(const Robot& robot, int j);
double limit_high(const Robot& robot, int j);

// Bound [mm] of the distance between the origins of frames k and k+1 (0-based k) over all
// joint values: sqrt(a^2 + d^2) for DH; |origin| (+ prismatic travel, + flange offset on the
// last joint) for a chain.
double link_offset_bound(const Robot& robot, int k);

// Transform of joint k (0-based) at internal value q: A_k for DH, origin . motion(q) for a chain
// (the last one with flange_offset appended).
Pose joint_transform(const Robot& robot, int k, double q);

// One standard DH link transform A = Rz(theta) Tz(d) Tx(a) Rx(alpha), theta in radians.
Pose dh_transform(const DhLink& link, double theta);
// Flange pose from internal values (DH angles [rad]; chain: rad / mm), no display mapping.
Pose flange_pose_dh(const Robot& robot, const JointVector& dh);

// Sets each follower's open and closed values from its leader's (leaders first; followers of
// followers resolved in turn).
void update_hand_followers(Robot& robot);

// Pose of hand joint k's bodies in its frame `frame` with the hand closed or open and the arm
// at display joints q (followers of arm joints; an empty q counts as all 0), the joints above
// it too; identity for k < 0.
Pose hand_offset(const Robot& robot, int k, bool closed, const JointVector& q = JointVector());
// True when hand joint k (or one above it) follows an arm joint: its pose changes with q.
bool hand_follows_arm(const Robot& robot, int k);

// Angle helpers [deg]: wrap into (-180, 180].
double wrap_deg(double deg);

}  // namespace asimov::robots
