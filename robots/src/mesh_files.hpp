// Mesh files of robot descriptions: STL and OBJ through collision::read_mesh, every other format
// assimp reads (COLLADA .dae, .ply, .3ds, glTF, ...) through assimp. A COLLADA file's
// <unit meter> scales it and its <up_axis> (Y_UP, X_UP) is turned onto Z, the URDF convention
// (Z_UP files are taken as they are). Validation as collision::validate_mesh.
#pragma once
#include "asimov/collision/mesh_io.hpp"

#include <string>

namespace asimov::robots {

// `scale` multiplies the coordinates after the file's own units (1000: metres -> mm).
Result<collision::LoadedMesh> read_mesh_file(const std::string& path, const collision::Vec3& scale);

}  // namespace asimov::robots
