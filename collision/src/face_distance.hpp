// Closest points between triangles in double precision: the clearance test (c > 0) and the
// in-plane contact point. Not exact; the exact intersection decision is face_test.hpp.
#pragma once
#include "face_test.hpp"

namespace asimov::collision {

// Closest points of two closed segments (either may be a point); returns the squared distance.
double segment_closest_points(const Vec3& p0, const Vec3& p1, const Vec3& q0, const Vec3& q1,
                              Vec3& on_p, Vec3& on_q);

// Closest point of a closed triangle (possibly of zero area) to p.
Vec3 triangle_closest_point(const Vec3& p, const TriangleVerts& t);

// Minimum over the 9 edge-edge and 6 vertex-triangle pairs; returns the squared distance.
// This is the distance between the triangles when they do not intersect.
double triangle_closest_points(const TriangleVerts& t1, const TriangleVerts& t2, Vec3& on1, Vec3& on2);

// The same squared distance for two triangles known not to intersect (triangles_intersect false),
// faster (distance query, docs/collision.md §11): the 9 edge pairs, stopping at one whose closest
// points bound a slab that holds each whole triangle on its side (then no other pair is nearer),
// then only the nearest vertex of a triangle lying wholly on one side of the other's plane
// against that face (the only vertex-face pair that can be the closest one). Degenerate
// triangles fall through to the edge pairs, which then hold the answer.
double disjoint_triangle_distance2(const TriangleVerts& t1, const TriangleVerts& t2, Vec3& on1, Vec3& on2);

// The clearance test of step 4 (used by the engine and by brute force alike): true when the
// closest points found above are within `clearance`; bounding boxes farther apart than the
// clearance on some axis are rejected first. Fills the distance and the closest points.
bool triangles_within(const TriangleVerts& t1, const TriangleVerts& t2, double clearance, double& distance,
                      Vec3& on1, Vec3& on2);

}  // namespace asimov::collision
