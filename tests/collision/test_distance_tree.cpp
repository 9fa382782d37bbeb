// The distance query's face tree (collision/src/distance_tree.hpp, docs/collision.md §11):
// every face in exactly one leaf, every node's float box holding its faces' vertices, and the
// node-pair bound never above the true distance of the two nodes' faces.
#include "collision/src/distance_tree.hpp"
#include "collision/src/face_distance.hpp"
#include "collision/src/minimax.hpp"
#include "scenes.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <random>
#include <vector>

using namespace asimov::collision;

namespace {

// Faces under node i (leaves' runs of DistanceTree::faces).
void faces_under(const DistanceTree& t, std::uint32_t i, std::vector<std::uint32_t>& out) {
  const DistanceNode& n = t.nodes[i];
  if (n.leaf()) {
    for (std::uint32_t k = 0; k < n.count(); ++k) out.push_back(t.faces[n.first + k]);
    return;
  }
  faces_under(t, n.first, out);
  faces_under(t, n.second, out);
}

std::vector<Polyhedron> meshes() {
  std::vector<Polyhedron> m{make_box({10, 20, 30}), make_cylinder(5, 40, 24), test::make_l_prism(40, 10, 20),
                            test::make_merged_part()};
  Pose far = Pose::Identity();  // far from the origin: the float centres round
  far.translation() = Vec3(12345.678, -9876.5, 4321.25);
  far.linear() = Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  m.push_back(transformed(test::make_merged_part(), far));
  m.push_back(transformed(make_cylinder(0.001, 0.002, 64), far));  // tiny faces far out
  return m;
}

}  // namespace

TEST_CASE("distance tree: each face in one leaf, each box holds its faces", "[distance][tree]") {
  for (const Polyhedron& m : meshes())
    for (const std::uint32_t leaf : {1u, 3u, kDistanceLeafFaces}) {
      const DistanceTree t = build_distance_tree(m, leaf);
      REQUIRE(!t.nodes.empty());
      std::vector<int> seen(m.triangles.size(), 0);
      for (std::uint32_t i = 0; i < t.nodes.size(); ++i) {
        const DistanceNode& n = t.nodes[i];
        if (n.leaf()) {
          CHECK(n.count() >= 1);
          CHECK(n.count() <= leaf);
          for (std::uint32_t k = 0; k < n.count(); ++k) ++seen[t.faces[n.first + k]];
        } else {
          CHECK(n.first > i);  // children after their parent
          CHECK(n.second > i);
        }
        std::vector<std::uint32_t> fs;
        faces_under(t, i, fs);
        bool holds = true;
        for (const std::uint32_t f : fs)
          for (const std::uint32_t v : m.triangles[f])
            for (int k = 0; k < 3; ++k) {
              const Vec3 a(n.axis[k][0], n.axis[k][1], n.axis[k][2]);
              const Vec3 c(n.c[0], n.c[1], n.c[2]);
              holds = holds && std::fabs(a.dot(m.vertices[v] - c)) <= n.h[k];
            }
        CHECK(holds);
      }
      for (const int s : seen) CHECK(s == 1);
    }
  CHECK(build_distance_tree(Polyhedron{}).nodes.empty());
}

TEST_CASE("distance tree: a node pair's bound is never above its faces' distance", "[distance][tree]") {
  std::mt19937_64 rng(1414);
  const std::vector<Polyhedron> ms = meshes();
  int checked = 0, positive = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const Polyhedron& ma = ms[static_cast<std::size_t>(trial) % ms.size()];
    const Polyhedron& mb = ms[static_cast<std::size_t>(trial / 7) % ms.size()];
    const DistanceTree ta = build_distance_tree(ma), tb = build_distance_tree(mb);
    Pose pa = test::random_pose(rng, 60), pb = test::random_pose(rng, 60);
    // Bodies far out: their boxes are mapped from where they are.
    if (trial % 3 == 0) pa = Pose(Eigen::Translation3d(Vec3(5000, 0, 0))) * pa;
    if (trial % 3 == 0) pb = Pose(Eigen::Translation3d(Vec3(5000, 0, 0))) * pb;
    const Pose a_from_b = relative_pose(pa, pb);
    const DistanceBound bound(a_from_b, 0.0);  // no slack for the pose's rounding: exact poses here
    std::uniform_int_distribution<std::uint32_t> na(0, static_cast<std::uint32_t>(ta.nodes.size() - 1)),
        nb(0, static_cast<std::uint32_t>(tb.nodes.size() - 1));
    for (int k = 0; k < 20; ++k) {
      const std::uint32_t x = na(rng), y = nb(rng);
      std::vector<std::uint32_t> fa, fb;
      faces_under(ta, x, fa);
      faces_under(tb, y, fb);
      // The faces in A's frame, B's mapped by the relative pose, as the bound sees them.
      double best = INFINITY;
      for (const std::uint32_t f : fa)
        for (const std::uint32_t g : fb) {
          const Triangle& s = ma.triangles[f];
          const Triangle& t = mb.triangles[g];
          const TriangleVerts u{ma.vertices[s[0]], ma.vertices[s[1]], ma.vertices[s[2]]};
          const TriangleVerts w{a_from_b * mb.vertices[t[0]], a_from_b * mb.vertices[t[1]], a_from_b * mb.vertices[t[2]]};
          Vec3 p, q;
          best = std::min(best, std::sqrt(triangle_closest_points(u, w, p, q)));
        }
      const double lb = bound(ta.nodes[x], tb.nodes[y]);
      // Room for the rounding of mapping B's vertices here (a few ulps of the coordinates).
      CHECK(lb <= best + 1e-9 * (1 + a_from_b.translation().norm()));
      ++checked;
      positive += lb > 0;
    }
  }
  CHECK(checked == 6000);
  CHECK(positive > 500);  // the bound is not trivially 0
}
