// A rigid triangle mesh in its own local frame, and primitive builders.
#pragma once
#include "asimov/collision/types.hpp"
#include <vector>

namespace asimov::collision {

struct Polyhedron {
  std::vector<Vec3> vertices;       // local coordinates [mm]
  std::vector<Triangle> triangles;  // outward orientation (right-hand rule)
};

// Axis-aligned box of full side lengths `size`, centred at the origin.
Polyhedron make_box(const Vec3& size);
// Cylinder about local Z, centred at the origin, `segments` sides (>= 3).
Polyhedron make_cylinder(double radius, double height, int segments = 24);
// The mesh with every vertex mapped by `pose` (used to place primitives inside a body).
Polyhedron transformed(const Polyhedron& mesh, const Pose& pose);
// Concatenation of two meshes (vertex indices of `b` are shifted).
Polyhedron merged(const Polyhedron& a, const Polyhedron& b);
// out[i] = pose * vertices[i]. The one place local vertices become world vertices, so the
// engine and the brute-force reference test bit-identical coordinates.
void transform_vertices(const std::vector<Vec3>& vertices, const Pose& pose, std::vector<Vec3>& out);
// pose * v, bit-identical to the elements transform_vertices writes (the engine maps only the
// vertices step 4 touches, one at a time, and must agree with brute force to the bit).
Vec3 transform_vertex(const Pose& pose, const Vec3& v);

}  // namespace asimov::collision
