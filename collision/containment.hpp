// Containment (four-step.md §6.1): closed meshes, their shells, and an exact point-in-solid
// test. A body inside another has no crossing faces, so the face steps alone would miss it.
#pragma once
#include "collision/polyhedron.hpp"

#include <cstdint>
#include <vector>

namespace asimov::collision {

// Every directed edge appears exactly once and its reverse exactly once.
bool is_closed(const Polyhedron& mesh);

// One vertex index per connected component (shell) of the triangles, in increasing order.
std::vector<std::uint32_t> shell_vertices(const Polyhedron& mesh);

enum class PointClass { outside, on_surface, inside };

// Parity of crossings of a ray from p, decided with exact orientation signs; a ray that
// touches an edge or a vertex is discarded and another direction drawn (deterministic
// sequence). `vertices` are the mesh vertices in the frame of p.
PointClass point_in_solid(const Vec3& p, const std::vector<Vec3>& vertices, const std::vector<Triangle>& triangles);

}  // namespace asimov::collision
