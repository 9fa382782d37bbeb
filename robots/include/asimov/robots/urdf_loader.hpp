// Robots from URDF files (tinyxml2): revolute, continuous, prismatic and fixed joints with
// origins, axes and limits; collision geometry from box / cylinder / sphere (tessellated) and
// STL meshes. Units are converted once, here: metres -> mm, radians -> display degrees.
//
// The arm is the path from the root link to options.tip, or without a tip the one chain of
// independent movable joints (an ambiguous tree is an error listing the candidate leaves).
// Fixed joints are folded into the next movable joint's origin (or into Robot::flange_offset
// after the last one), and the geometry of every link is expressed in the frame of the movable
// joint that carries it. Off the chain: fixed joints are rigid, prismatic joints and their
// <mimic> followers become Robot::hand joints (OPEN = upper limit, CLOSE = lower), any other
// movable joint is an error naming it.
#pragma once
#include "asimov/robots/package_path.hpp"
#include "asimov/robots/robot.hpp"
#include <map>
#include "asimov/core/result.hpp"
#include <string>

namespace asimov::robots {

// How a description's files are found: package://NAME/... through `packages` (package_path.hpp).
struct UrdfOptions {
  PackagePath packages;
  std::map<std::string, std::string> xacro_args;  // $(arg NAME) values of a .xacro description
  std::string tip;  // the arm's last link (the cell's `tip:`, or the SRDF end effector's parent); empty: chosen
};

// Loads `path`. Mesh file names: package://NAME/... (options.packages), file://..., or relative
// to the URDF file's folder; STL and OBJ as collision::read_mesh, COLLADA and the other formats
// assimp reads with the units and up axis a COLLADA file declares (mesh_files.hpp). Joint values of the result are display values: degrees, mm.
// Velocity limits come from <limit velocity>; accelerations are 4x the velocity per second
// (docs/kinematics.md §3 ratio); READY is the zero pose clamped into the limits.
// A path ending in .xacro is expanded first, in process (docs/robots.md: what xacro covers);
// errors in the expanded URDF name the .xacro file and the line of the expanded text.
// A problem is an Error: message "file:line: what" (line 0: none known), file and line set.
Result<Robot> load_urdf(const std::string& path, const UrdfOptions& options = {});

// Same from text; `source_name` names it in errors, `base_dir` resolves relative mesh files.
Result<Robot> load_urdf_text(const std::string& xml, const std::string& source_name, const std::string& base_dir = ".",
                     const UrdfOptions& options = {});

}  // namespace asimov::robots
