// Mesh input for robot descriptions: STL files (binary and ASCII) and a tessellated sphere.
// (Lives in robots/ for now; a natural home later is collision/.)
#pragma once
#include "collision/polyhedron.hpp"
#include <stdexcept>
#include <string>

namespace asimov::robots {

// A mesh file that cannot be read: missing, truncated, malformed, non-finite coordinates.
class MeshError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Reads an STL file (binary, or ASCII starting with "solid" and containing "facet"), scales
// every coordinate by `scale` (e.g. 1000 for metres -> mm) and welds bit-identical vertices.
// Throws MeshError with the file name (and the line for ASCII) on bad input.
collision::Polyhedron read_stl(const std::string& path, const collision::Vec3& scale);

// UV sphere of radius r centred at the origin: `rings` >= 2 latitude bands, `segments` >= 3.
collision::Polyhedron make_sphere(double radius, int rings = 8, int segments = 16);

}  // namespace asimov::robots
