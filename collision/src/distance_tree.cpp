#include "distance_tree.hpp"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cfloat>
#include <numeric>

namespace asimov::collision {
namespace {

float round_up(double v) {
  float f = static_cast<float>(v);
  if (static_cast<double>(f) < v) f = std::nextafter(f, INFINITY);
  return f;
}

// The stored float axes and centre, read back from the node: GCC 12 at -O2 was seen to carry
// the unrounded doubles past the float stores when all was inlined, and the ranges measured along
// them missed the stored box by a float rounding (tests/collision/test_distance_tree.cpp).
[[gnu::noinline]] Vec3 axis_of(const DistanceNode& node, int k) {
  return Vec3(node.axis[k][0], node.axis[k][1], node.axis[k][2]);
}
[[gnu::noinline]] Vec3 centre_of(const DistanceNode& node) { return Vec3(node.c[0], node.c[1], node.c[2]); }

// Each vertex once per pass over a node's faces (a vertex is shared by about six faces): `stamp`
// holds, per vertex, the last pass that visited it; `proj` the vertex's coordinate along the
// node's first axis, for the split keys.
struct Scratch {
  std::vector<std::uint32_t> stamp;
  std::vector<double> proj;
  std::uint32_t pass = 0;
  explicit Scratch(std::size_t vertices) : stamp(vertices, 0), proj(vertices, 0) {}
  std::uint32_t next() { return ++pass; }
};

// Centre and half sides along the node's float axes: the ranges of its faces' vertices, padded
// for the rounding; when `key` is given, each face's centroid (times 3) along the first axis,
// the split's key.
void measure(const Polyhedron& mesh, const std::uint32_t* faces, std::size_t count, DistanceNode& node, double* key,
             Scratch& scratch) {
  const Vec3 a[3] = {axis_of(node, 0), axis_of(node, 1), axis_of(node, 2)};
  Vec3 lo = Vec3::Constant(INFINITY), hi = Vec3::Constant(-INFINITY);
  double mag = 0;  // largest |coordinate| in play, for the rounding pad
  const std::uint32_t pass = scratch.next();
  for (std::size_t i = 0; i < count; ++i)
    for (const std::uint32_t v : mesh.triangles[faces[i]]) {
      if (scratch.stamp[v] == pass) continue;
      scratch.stamp[v] = pass;
      const Vec3& p = mesh.vertices[v];
      mag = std::max(mag, p.cwiseAbs().maxCoeff());
      for (int k = 0; k < 3; ++k) {
        const double s = a[k].dot(p);
        lo[k] = std::min(lo[k], s);
        hi[k] = std::max(hi[k], s);
        if (k == 0) scratch.proj[v] = s;
      }
    }
  if (key)
    for (std::size_t i = 0; i < count; ++i) {
      const auto& t = mesh.triangles[faces[i]];
      key[i] = scratch.proj[t[0]] + scratch.proj[t[1]] + scratch.proj[t[2]];
    }
  // Centre: the middle of each range along its axis (the axes nearly orthonormal), in float.
  const Vec3 c = 0.5 * ((lo[0] + hi[0]) * a[0] + (lo[1] + hi[1]) * a[1] + (lo[2] + hi[2]) * a[2]);
  for (int j = 0; j < 3; ++j) node.c[j] = static_cast<float>(c[j]);
  const Vec3 cf = centre_of(node);
  for (int k = 0; k < 3; ++k) {
    const double pc = a[k].dot(cf);
    // a_k . (v - c) = a_k . v - a_k . c, each rounded within a few ulps of 3 |a| mag: padded.
    const double pad = 1e-14 * (3 * mag + std::fabs(pc) + 1e-300);
    node.h[k] = round_up(std::max(hi[k] - pc, pc - lo[k]) + pad);
  }
}

// The node's box: PCA axes of its faces' vertices (largest spread first, each vertex weighted by
// the faces it is in), rounded to float, then the centre and half sides measured along those
// float axes, so the box holds every vertex. Two passes: the moments over the faces' vertices
// (relative to the first vertex, so the covariance does not cancel far from the origin), then
// the ranges over each vertex once; when `key` is given, each face's centroid (times 3) along
// the first axis follows, the split's key.
void fit(const Polyhedron& mesh, const std::uint32_t* faces, std::size_t count, DistanceNode& node, double* key,
         Scratch& scratch) {
  const Vec3 ref = mesh.vertices[mesh.triangles[faces[0]][0]];
  // The six distinct second moments only (the matrix is symmetric).
  double s[3] = {0, 0, 0}, xx = 0, xy = 0, xz = 0, yy = 0, yz = 0, zz = 0;
  for (std::size_t i = 0; i < count; ++i)
    for (const std::uint32_t v : mesh.triangles[faces[i]]) {
      const Vec3& p = mesh.vertices[v];
      const double dx = p[0] - ref[0], dy = p[1] - ref[1], dz = p[2] - ref[2];
      s[0] += dx, s[1] += dy, s[2] += dz;
      xx += dx * dx, xy += dx * dy, xz += dx * dz;
      yy += dy * dy, yz += dy * dz, zz += dz * dz;
    }
  const Vec3 sum(s[0], s[1], s[2]);
  Mat3 sum2;
  sum2 << xx, xy, xz, xy, yy, yz, xz, yz, zz;
  const double nv = static_cast<double>(3 * count);
  const Vec3 mean = sum / nv;
  const Mat3 cov = sum2 / nv - mean * mean.transpose();
  Mat3 axes = Mat3::Identity();  // rows
  if (cov.allFinite()) {
    Eigen::SelfAdjointEigenSolver<Mat3> es;
    es.computeDirect(cov);
    const Mat3& e = es.eigenvectors();  // columns, eigenvalues ascending
    if (es.info() == Eigen::Success && e.allFinite()) {
      axes.row(0) = e.col(2).transpose();
      axes.row(1) = e.col(1).transpose();
      axes.row(2) = axes.row(0).cross(axes.row(1));  // orthonormal even when eigenvalues repeat
      if (!axes.allFinite() || std::fabs(axes.determinant() - 1) > 1e-6) axes = Mat3::Identity();
    }
  }
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < 3; ++j) node.axis[k][j] = static_cast<float>(axes(k, j));
  measure(mesh, faces, count, node, key, scratch);
}

}  // namespace

DistanceTree build_distance_tree(const Polyhedron& mesh, std::uint32_t leaf_faces) {
  DistanceTree tree;
  const std::size_t n = mesh.triangles.size();
  if (n == 0) return tree;
  leaf_faces = std::max<std::uint32_t>(1, leaf_faces);
  tree.faces.resize(n);
  std::iota(tree.faces.begin(), tree.faces.end(), 0u);
  // About 2 n / leaf_faces nodes (fewer faces per leaf where the mean splits unevenly); the
  // vector is shrunk to its size at the end.
  tree.nodes.reserve(2 * ((n + leaf_faces - 1) / leaf_faces));
  std::vector<double> key(n);  // centroid along the split axis, per position in tree.faces
  Scratch scratch(mesh.vertices.size());
  struct Work {
    std::uint32_t node, begin, end;
  };
  std::vector<Work> work{{0, 0, static_cast<std::uint32_t>(n)}};
  tree.nodes.emplace_back();
  while (!work.empty()) {
    const Work w = work.back();
    work.pop_back();
    const std::size_t count = w.end - w.begin;
    std::uint32_t* f = tree.faces.data() + w.begin;
    {
      DistanceNode node{};
      fit(mesh, f, count, node, count <= leaf_faces ? nullptr : key.data() + w.begin, scratch);
      tree.nodes[w.node] = node;
    }
    DistanceNode& node = tree.nodes[w.node];
    if (count <= leaf_faces) {
      node.first = w.begin;
      node.second = DistanceNode::kLeaf | static_cast<std::uint32_t>(count);
      continue;
    }
    // Split along the widest axis at the centroids' mean.
    double mean = 0;
    for (std::size_t i = 0; i < count; ++i) mean += key[w.begin + i];
    mean /= static_cast<double>(count);
    std::size_t mid = 0;
    for (std::size_t i = 0; i < count; ++i)
      if (key[w.begin + i] < mean) {
        std::swap(f[i], f[mid]);
        std::swap(key[w.begin + i], key[w.begin + mid]);
        ++mid;
      }
    if (mid == 0 || mid == count) {  // all centroids on one side (equal keys): split the run in half
      mid = count / 2;
      std::vector<std::pair<double, std::uint32_t>> order(count);
      for (std::size_t i = 0; i < count; ++i) order[i] = {key[w.begin + i], f[i]};
      std::nth_element(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(mid), order.end());
      for (std::size_t i = 0; i < count; ++i) f[i] = order[i].second;
    }
    const auto left = static_cast<std::uint32_t>(tree.nodes.size());
    node.first = left;
    node.second = left + 1;
    tree.nodes.emplace_back();  // may reallocate: `node` is not used past here
    tree.nodes.emplace_back();
    const auto m = static_cast<std::uint32_t>(w.begin + mid);
    work.push_back({left + 1, m, w.end});
    work.push_back({left, w.begin, m});
  }
  tree.nodes.shrink_to_fit();
  return tree;
}

}  // namespace asimov::collision
