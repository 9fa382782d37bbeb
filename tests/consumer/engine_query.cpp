#include "examples.hpp"

#include "asimov/collision/engine.hpp"

using namespace asimov::collision;

// Two 100 mm cubes side by side, `gap_mm` apart (negative: overlapping).
bool cubes_touch(double gap_mm) {
  Engine engine;
  const BodyId a = engine.add_body({.name = "a", .mesh = make_box(Vec3(100, 100, 100))});
  const BodyId b = engine.add_body({.name = "b", .mesh = make_box(Vec3(100, 100, 100))});
  engine.set_pose(a, Pose::Identity());
  engine.set_pose(b, Pose(Eigen::Translation3d(100 + gap_mm, 0, 0)));
  const QueryResult r = engine.check();  // the four steps over every enabled pair
  return r.collided;                     // r.contact: bodies, faces, world point
}
