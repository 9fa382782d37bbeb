// The collision scene of a cell, built in one place for the simulator and `asimov pairs`: the
// bodies in engine order (robot link bodies, "tool", then the objects), their rigid groups,
// static flags, the joined (adjacent) pairs and the user's ignore list, and the body poses at
// given joints.
#pragma once
#include "asimov/collision/auto_pairs.hpp"
#include "asimov/motion/cell.hpp"

#include <string>
#include <vector>

namespace asimov::motion {

constexpr int kStaticGroup = 1000;  // link0 and every cell object: never tested together

struct SceneBody {
  std::string name;             // "link3", "tool", "table"
  collision::Polyhedron mesh;   // local frame
  int group = -1;               // rigid group (robot: its link; static parts: kStaticGroup)
  bool is_static = false;       // link 0 and objects
  bool robot = false;           // a robot part (link body or tool): its self-pairs may be sampled
  int link = -1;                // robot bodies: frame index (the tool: joint_count()); objects: -1
  int hand = -1;                // a gripper finger's body: its robots::HandJoint (posed open)
  int object = -1;              // objects: index into cell.objects
};

struct Scene {
  std::vector<SceneBody> bodies;                // engine order: robot bodies, "tool", objects
  std::vector<collision::BodyPair> adjacent;    // joined: links k and k +/- 1, the tool and link n-1
  std::vector<collision::BodyPair> ignored;     // cell.collision.ignore resolved by name
  std::vector<collision::BodyPair> srdf;        // cell.collision.srdf_disabled resolved by name
  std::vector<collision::BodyPair> start_contacts;  // cell.collision.start_contacts resolved by name
  std::vector<std::string> unknown_ignored;     // ignore entries naming no body (for warnings)
};

// Bodies, groups and joined pairs of the cell. The tool is rigid with the last link (group
// joint_count()) and joined to link n-1 (the J5 body of a 6-axis arm), adjacent links touch at
// their joint.
// `object_meshes` false leaves the objects' SceneBody::mesh empty (their meshes stay in
// cell.objects: World borrows them, and a copy of a 10M-face object was 240 MB).
Scene scene_bodies(const Cell& cell, bool object_meshes = true);

// The robot's self-pairs (link bodies and tool) that touch, or come within `clearance_mm`, at
// the start joints and that nothing else disables yet (rigid, joined, SRDF, ignore): the pairs
// the default policy leaves untested (source DEFAULT), so an arm never collides with itself at
// t = 0. Exact (the engine's face test), in (a, b) order, a < b.
std::vector<collision::BodyPair> start_contacts(const Cell& cell, const Scene& scene, double clearance_mm);

// The joints a cell starts at: cell.start_joints, or READY when they do not fit the robot.
robots::JointVector start_joints(const Cell& cell);

// World pose of every scene body at display joints q (robot bodies cell.base . frames[link],
// objects their pose). `frames` is scratch space.
void scene_poses(const Cell& cell, const Scene& scene, const robots::JointVector& q, std::vector<collision::Pose>& frames,
                 std::vector<collision::Pose>& poses);

// Input of collision::generate_pairs for the cell: robot bodies and tool sampled, objects not;
// default pose = start_joints(cell), random poses uniform within the joint limits; pose_source
// holds the kinematics, limits, base and start joints as text. `samples`: N for NEVER. The
// callbacks refer to `cell` and `scene`, which must outlive the result.
collision::AutoPairsInput auto_pairs_input(const Cell& cell, const Scene& scene, int samples = 10000);

}  // namespace asimov::motion
