// Exact orientation signs (Shewchuk 1997 static filter, exact expansion fallback).
// Every geometric decision of the face test is built on these two functions only.
#pragma once
#include "asimov/collision/types.hpp"

namespace asimov::collision {

// Sign of det[b-a; c-a] : +1 when a, b, c turn counter-clockwise, 0 when collinear.
int orient2d(double ax, double ay, double bx, double by, double cx, double cy);

// Sign of det[b-a; c-a; d-a] = ((b-a) x (c-a)) . (d-a): +1 when d lies on the side the
// normal of the counter-clockwise triangle a, b, c points to, 0 when the four are coplanar.
int orient3d(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

// The exact fallbacks alone (no filter), exposed so tests can compare them with the filter.
int orient2d_exact(double ax, double ay, double bx, double by, double cx, double cy);
int orient3d_exact(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

}  // namespace asimov::collision
