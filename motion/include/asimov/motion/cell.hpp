// The work cell as plain data: robot, BASE/TOOL, tool body, static objects, collision settings.
// Loaded from YAML by app/; the built-in default cell is an embedded YAML document there.
#pragma once
#include "asimov/motion/devices.hpp"
#include "asimov/motion/location.hpp"
#include "asimov/robots/robot.hpp"
#include <algorithm>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace asimov::motion {

struct CellObject {
  std::string name;
  collision::Polyhedron mesh;  // local frame
  Location pose = Location::Identity();  // object frame in the robot (world) frame
};

// How checked poses are spaced (docs/collision-method.md §6.3; docs/collision.md "Stepping"). fixed: no body
// point moves more than step_mm between checked poses. gap: a pair whose step-2 containers are g
// apart allows delta_A + delta_B <= max(c, step_mm, g - c); the poses are a subset of fixed's
// (while parts ride a running belt, a stretch may also end between grid poses: Walk::part_cap).
enum class Stepping { fixed, gap };

// The finest step the simulator takes (a zero or negative step_mm is raised to it); cell files
// below it are refused.
inline constexpr double kMinStepMm = 1e-3;

// What a clearance contact (distance <= clearance_mm, no touching) does: halt the program as a
// contact, or only be reported (the run's clearance report lists the pairs that came that near).
enum class OnClearance { halt, warn };

struct CollisionSettings {
  int halvings = 9;            // M for every body unless a body says otherwise
  double step_mm = 1.0;        // no body point moves more than this between checked poses
  double clearance_mm = 0.0;   // contact when distance <= clearance
  double toc_tolerance_s = 1e-6;  // contact time: bisect until t_hit - t_free <= this (docs/collision-method.md §6.4)
  std::vector<std::pair<std::string, std::string>> ignore;  // user-disabled pairs (body names)
  // Robot self-pairs that are not tested whatever `pairs` says (body names): the SRDF's
  // <disable_collisions> (matrix source SRDF), and the pairs in contact at the start joints
  // (source DEFAULT; the cell loader finds them with motion::start_contacts and warns once).
  std::vector<std::pair<std::string, std::string>> srdf_disabled;
  std::vector<std::pair<std::string, std::string>> start_contacts;
  bool enabled = true;
  // Step 1. false: joined pairs (adjacent links, tool-link n-1), `srdf_disabled`,
  // `start_contacts` and `ignore` are disabled, every other pair is tested. true: the generated matrix of `asimov pairs` (collision/auto_pairs.hpp:
  // robot self-pairs touching at the start joints, in >= 95 % or in none of `pair_samples`
  // random poses are disabled too; robot-object pairs stay tested).
  bool generated_pairs = false;
  int pair_samples = 10000;    // N of the generated matrix
  std::string pairs_cache;     // its cache file (collision::generate_pairs_cached); empty: none
  Stepping stepping = Stepping::gap;  // gap: 50x fewer checked poses than fixed on the demos, same contacts
  // Continuous checking between checked poses (docs/collision.md §12): every window proven free
  // or its earliest contact found, at any thickness. false: the checked poses alone.
  bool continuous = true;
  double report_within_mm = 10;  // clearance report: pairs that came nearer than this [mm]
  OnClearance on_clearance = OnClearance::halt;
  // The broad phase over the bodies that do not move (docs/collision.md §14): used when a cell has
  // enough pairs of an arm body and an object or resting part for it to pay. false: every pair at
  // every checked pose (the reference the tests compare with; not a cell-file key).
  bool broad_phase = true;
};

// The distance within which pairs are watched and reported (the clearance report, the broad
// phase's kept pairs, continuous checking's report windows): report_within_mm, never below the
// clearance (a pair that halts is always reported). The one rule; every layer asks it.
inline double report_distance_mm(const CollisionSettings& s) { return std::max(s.report_within_mm, s.clearance_mm); }

struct Cell {
  robots::Robot robot;
  Location base = Location::Identity();  // robot base in the world (the cell's frame)
  Location tool = Location::Identity();  // initial TOOL transformation
  std::optional<collision::Polyhedron> tool_shape;  // in the flange frame; body name "tool"
  std::vector<CellObject> objects;
  CollisionSettings collision;
  robots::JointVector start_joints;      // display [deg]; READY unless the cell says otherwise
  std::vector<std::string> warnings;     // load-time notes on the cell's data (e.g. open meshes)
  std::vector<std::string> notes;        // load-time information (the SRDF's groups and end effectors)
  Workcell workcell;                     // parts, gripper, devices, logic; empty for a static cell
};

}  // namespace asimov::motion
