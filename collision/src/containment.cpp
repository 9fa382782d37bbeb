#include "containment.hpp"

#include "face_test.hpp"
#include "predicates.hpp"

#include <algorithm>
#include <cassert>
#include <numeric>
#include <utility>

namespace asimov::collision {

std::optional<EdgeFault> first_edge_fault(const std::vector<Triangle>& triangles, std::size_t vertex_count) {
  // offsets[v] .. offsets[v + 1]: the `to` ends of the edges leaving v, sorted.
  std::vector<std::uint32_t> offsets(vertex_count + 1, 0);
  for (const Triangle& t : triangles)
    for (int k = 0; k < 3; ++k) ++offsets[t[k] + 1];
  for (std::size_t v = 0; v < vertex_count; ++v) offsets[v + 1] += offsets[v];
  std::vector<std::uint32_t> to(3 * triangles.size());
  {
    std::vector<std::uint32_t> fill(offsets.begin(), offsets.end() - 1);
    for (const Triangle& t : triangles)
      for (int k = 0; k < 3; ++k) to[fill[t[k]]++] = t[(k + 1) % 3];
  }
  for (std::size_t v = 0; v < vertex_count; ++v) std::sort(to.begin() + offsets[v], to.begin() + offsets[v + 1]);
  auto count = [&](std::uint32_t from, std::uint32_t target) {
    const auto r = std::equal_range(to.begin() + offsets[from], to.begin() + offsets[from + 1], target);
    return r.second - r.first;
  };
  for (std::uint32_t from = 0; from < vertex_count; ++from)
    for (std::uint32_t i = offsets[from]; i < offsets[from + 1];) {
      std::uint32_t j = i + 1;
      while (j < offsets[from + 1] && to[j] == to[i]) ++j;
      const std::uint32_t t = to[i];
      const auto reverse = count(t, from);
      const std::optional<EdgeFault::Kind> kind = from == t    ? std::optional(EdgeFault::self)
                                                  : j - i > 1  ? std::optional(EdgeFault::twice_one_way)
                                                  : reverse == 0 ? std::optional(EdgeFault::one_face)
                                                  : reverse != 1 ? std::optional(EdgeFault::many_faces)
                                                                 : std::nullopt;
      if (kind) return EdgeFault{.from = from, .to = t, .kind = *kind};
      i = j;
    }
  return std::nullopt;
}

bool is_closed(const Polyhedron& mesh) {
  return !mesh.triangles.empty() && !first_edge_fault(mesh.triangles, mesh.vertices.size());
}

namespace {

// Shell root of every used vertex (the smallest vertex index of its shell), unused ones -1.
std::vector<std::int64_t> shell_roots(const Polyhedron& mesh) {
  std::vector<std::uint32_t> parent(mesh.vertices.size());
  std::iota(parent.begin(), parent.end(), 0u);
  auto find = [&](std::uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  std::vector<bool> used(mesh.vertices.size(), false);
  for (const Triangle& t : mesh.triangles)
    for (int i = 0; i < 3; ++i) {
      used[t[i]] = true;
      const std::uint32_t a = find(t[i]), b = find(t[(i + 1) % 3]);
      if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
  std::vector<std::int64_t> root(mesh.vertices.size(), -1);
  for (std::uint32_t v = 0; v < parent.size(); ++v)
    if (used[v]) root[v] = find(v);
  return root;
}

}  // namespace

std::vector<std::uint32_t> shell_vertices(const Polyhedron& mesh) {
  const std::vector<std::int64_t> root = shell_roots(mesh);
  std::vector<std::uint32_t> roots;
  for (std::uint32_t v = 0; v < root.size(); ++v)
    if (root[v] == v) roots.push_back(v);
  return roots;
}

std::vector<std::vector<std::uint32_t>> shell_members(const Polyhedron& mesh) {
  const std::vector<std::int64_t> root = shell_roots(mesh);
  std::vector<std::uint32_t> shell_of(root.size(), 0);
  std::vector<std::vector<std::uint32_t>> members;
  for (std::uint32_t v = 0; v < root.size(); ++v) {
    if (root[v] < 0) continue;
    if (root[v] == v) {
      shell_of[v] = static_cast<std::uint32_t>(members.size());
      members.emplace_back();
    }
    members[shell_of[static_cast<std::size_t>(root[v])]].push_back(v);  // the root comes first
  }
  return members;
}

std::vector<std::vector<std::uint32_t>> shell_samples(const Polyhedron& mesh, std::size_t per_shell) {
  const std::vector<std::vector<std::uint32_t>> members = shell_members(mesh);
  std::vector<std::vector<std::uint32_t>> out(members.size());
  for (std::size_t s = 0; s < members.size(); ++s) {
    const auto& m = members[s];
    const std::size_t k = std::min(std::max<std::size_t>(per_shell, 1), m.size());
    for (std::size_t i = 0; i < k; ++i) out[s].push_back(m[i * m.size() / k]);
  }
  return out;
}

PointClass point_in_solid(const Vec3& p, const std::vector<Vec3>& vertices, const std::vector<Triangle>& triangles) {
  if (vertices.empty()) return PointClass::outside;
  Vec3 lo = vertices.front(), hi = vertices.front();
  for (const Vec3& v : vertices) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  // The far end q is outside the bounding box whatever the direction.
  const double reach = 2 * ((hi - lo).norm() + (p - 0.5 * (lo + hi)).norm()) + 1;
  std::uint64_t state = 0x9E3779B97F4A7C15ull;
  auto next = [&state] {  // splitmix64: a fixed sequence of directions, same on every run
    std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return static_cast<double>((z ^ (z >> 31)) >> 11) * 0x1p-53 * 2 - 1;
  };
  for (int attempt = 0; attempt < 64; ++attempt) {
    Vec3 dir(next(), next(), next());
    if (dir.norm() < 0.1) continue;
    const Vec3 q = p + reach * dir.normalized();
    bool degenerate = false;
    int crossings = 0;
    for (const Triangle& tri : triangles) {
      const TriangleVerts t{vertices[tri[0]], vertices[tri[1]], vertices[tri[2]]};
      const int op = orient3d(t[0], t[1], t[2], p);
      if (op == 0) {
        if (segment_intersects_triangle(p, p, t)) return PointClass::on_surface;
        continue;  // the ray leaves the plane at p, outside this triangle
      }
      const int oq = orient3d(t[0], t[1], t[2], q);
      if (oq == 0) {
        degenerate = true;
        break;
      }
      if (op == oq) continue;
      const int e0 = orient3d(p, q, t[0], t[1]), e1 = orient3d(p, q, t[1], t[2]), e2 = orient3d(p, q, t[2], t[0]);
      if ((e0 > 0 && e1 > 0 && e2 > 0) || (e0 < 0 && e1 < 0 && e2 < 0)) {
        ++crossings;
      } else if (!((e0 > 0 || e1 > 0 || e2 > 0) && (e0 < 0 || e1 < 0 || e2 < 0))) {
        degenerate = true;  // through an edge or a vertex: parity undefined, draw again
        break;
      }
    }
    if (!degenerate) return crossings % 2 ? PointClass::inside : PointClass::outside;
  }
  assert(false && "no non-degenerate ray in 64 directions");
  return PointClass::outside;
}

}  // namespace asimov::collision
