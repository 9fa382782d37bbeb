// The exact face-face test (Guigue & Devillers 2003) on exact orientation signs, and a
// contact point for reports. Triangles are closed: touching counts as intersecting.
#pragma once
#include "asimov/collision/types.hpp"

namespace asimov::collision {

using TriangleVerts = std::array<Vec3, 3>;

// True when the closed triangles share at least one point. Zero-area triangles act as the
// segment or point they are. Symmetric in its arguments and in the vertex order of each.
bool triangles_intersect(const TriangleVerts& t1, const TriangleVerts& t2);

// Closed segment [s0, s1] (possibly a point) against a closed triangle (possibly degenerate).
bool segment_intersects_triangle(const Vec3& s0, const Vec3& s1, const TriangleVerts& t);

// Two closed segments in space (either may be a point).
bool segments_intersect(const Vec3& p0, const Vec3& p1, const Vec3& q0, const Vec3& q1);

// A point on both triangles, for reports only (computed in double, not exact).
// Precondition: triangles_intersect(t1, t2).
Vec3 contact_point(const TriangleVerts& t1, const TriangleVerts& t2);

}  // namespace asimov::collision
