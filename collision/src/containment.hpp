// Containment (docs/collision-method.md §6.1): closed meshes, their shells, and an exact point-in-solid
// test. A body inside another has no crossing faces, so the face steps alone would miss it.
#pragma once
#include "asimov/collision/polyhedron.hpp"

#include <cstdint>
#include <optional>
#include <vector>

namespace asimov::collision {

// Every directed edge appears exactly once and its reverse exactly once (and no edge joins a
// vertex to itself).
bool is_closed(const Polyhedron& mesh);

// The first directed edge, in (from, to) order, that keeps `triangles` (indices below
// `vertex_count`) from being closed, or nothing when they are closed. Per-vertex lists of
// outgoing edges (CSR, 4 bytes per directed edge and per vertex): a sort of every edge took a
// fifth of the set-up of a 1M-face mesh and 24 bytes per face.
struct EdgeFault {
  enum Kind { self, twice_one_way, one_face, many_faces };
  std::uint32_t from = 0, to = 0;
  Kind kind = self;
};
std::optional<EdgeFault> first_edge_fault(const std::vector<Triangle>& triangles, std::size_t vertex_count);

// One vertex index per connected component (shell) of the triangles, in increasing order.
std::vector<std::uint32_t> shell_vertices(const Polyhedron& mesh);

// Per shell (in the order of shell_vertices), every vertex of its faces, the shell_vertices one
// first.
std::vector<std::vector<std::uint32_t>> shell_members(const Polyhedron& mesh);

// Per shell (in the order of shell_vertices), up to `per_shell` of its vertices spread over its
// vertex list, the shell_vertices one first. Any of them stands for the whole shell once no
// face of the shell meets the other body's surface (a connected set that does not cross a
// closed surface lies on one side of it), so the engine may use whichever is cheapest to decide.
std::vector<std::vector<std::uint32_t>> shell_samples(const Polyhedron& mesh, std::size_t per_shell);

enum class PointClass { outside, on_surface, inside };

// Parity of crossings of a ray from p, decided with exact orientation signs; a ray that
// touches an edge or a vertex is discarded and another direction drawn (deterministic
// sequence). `vertices` are the mesh vertices in the frame of p.
PointClass point_in_solid(const Vec3& p, const std::vector<Vec3>& vertices, const std::vector<Triangle>& triangles);

}  // namespace asimov::collision
