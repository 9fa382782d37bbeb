// STL reading (binary / ASCII, vertex welding) and sphere tessellation.
#include "robots/mesh_io.hpp"

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <map>
#include <numbers>
#include <sstream>

namespace asimov::robots {
namespace {
using collision::Polyhedron;
using collision::Vec3;

struct Welder {
  Polyhedron mesh;
  std::map<std::array<double, 3>, std::uint32_t> index;
  std::uint32_t add(const Vec3& v) {
    const auto [it, inserted] = index.try_emplace({v.x(), v.y(), v.z()}, static_cast<std::uint32_t>(mesh.vertices.size()));
    if (inserted) mesh.vertices.push_back(v);
    return it->second;
  }
  void triangle(const Vec3& a, const Vec3& b, const Vec3& c) {
    const std::uint32_t i = add(a), j = add(b), k = add(c);
    if (i != j && j != k && i != k) mesh.triangles.push_back({i, j, k});  // drop degenerate facets
  }
};

bool looks_ascii(const std::string& data) {
  if (data.compare(0, 5, "solid") != 0) return false;
  return data.find("facet", 5) != std::string::npos && data.find("vertex") != std::string::npos;
}

Polyhedron read_ascii(const std::string& data, const std::string& path, const Vec3& scale) {
  Welder w;
  std::istringstream in(data);
  std::string line;
  int line_no = 0;
  std::array<Vec3, 3> v;
  int n = 0;
  while (std::getline(in, line)) {
    ++line_no;
    std::istringstream ls(line);
    std::string word;
    if (!(ls >> word) || word != "vertex") {
      if (word == "endloop" && n != 3)
        throw MeshError(path + ":" + std::to_string(line_no) + ": a facet needs exactly 3 vertices");
      if (word == "outer") n = 0;
      continue;
    }
    double x, y, z;
    if (!(ls >> x >> y >> z) || !std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z))
      throw MeshError(path + ":" + std::to_string(line_no) + ": bad vertex (three finite numbers expected)");
    if (n >= 3) throw MeshError(path + ":" + std::to_string(line_no) + ": a facet needs exactly 3 vertices");
    v[static_cast<std::size_t>(n++)] = Vec3(x, y, z).cwiseProduct(scale);
    if (n == 3) w.triangle(v[0], v[1], v[2]);
  }
  if (w.mesh.triangles.empty()) throw MeshError(path + ": no facets");
  return std::move(w.mesh);
}

Polyhedron read_binary(const std::string& data, const std::string& path, const Vec3& scale) {
  if (data.size() < 84) throw MeshError(path + ": truncated binary STL (no header)");
  std::uint32_t count = 0;
  std::memcpy(&count, data.data() + 80, 4);
  if (data.size() < 84 + 50ull * count)
    throw MeshError(path + ": truncated binary STL (" + std::to_string(count) + " facets announced)");
  Welder w;
  for (std::uint32_t f = 0; f < count; ++f) {
    const char* p = data.data() + 84 + 50ull * f + 12;  // skip the normal
    std::array<Vec3, 3> v;
    for (int k = 0; k < 3; ++k) {
      float c[3];
      std::memcpy(c, p + 12 * k, 12);
      for (float x : c)
        if (!std::isfinite(x)) throw MeshError(path + ": facet " + std::to_string(f) + " has a non-finite coordinate");
      v[static_cast<std::size_t>(k)] = Vec3(c[0], c[1], c[2]).cwiseProduct(scale);
    }
    w.triangle(v[0], v[1], v[2]);
  }
  if (w.mesh.triangles.empty()) throw MeshError(path + ": no facets");
  return std::move(w.mesh);
}
}  // namespace

Polyhedron read_stl(const std::string& path, const Vec3& scale) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw MeshError(path + ": cannot open mesh file");
  const std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  return looks_ascii(data) ? read_ascii(data, path, scale) : read_binary(data, path, scale);
}

Polyhedron make_sphere(double radius, int rings, int segments) {
  rings = std::max(rings, 2);
  segments = std::max(segments, 3);
  Polyhedron p;
  p.vertices.emplace_back(0, 0, -radius);
  for (int i = 1; i < rings; ++i) {
    const double phi = std::numbers::pi * i / rings - std::numbers::pi / 2;
    for (int j = 0; j < segments; ++j) {
      const double th = 2 * std::numbers::pi * j / segments;
      p.vertices.emplace_back(radius * std::cos(phi) * std::cos(th), radius * std::cos(phi) * std::sin(th),
                              radius * std::sin(phi));
    }
  }
  p.vertices.emplace_back(0, 0, radius);
  const auto top = static_cast<std::uint32_t>(p.vertices.size() - 1);
  const auto at = [segments](int ring, int j) {  // ring 1..rings-1
    return static_cast<std::uint32_t>(1 + (ring - 1) * segments + (j % segments));
  };
  for (int j = 0; j < segments; ++j) {
    p.triangles.push_back({0, at(1, j + 1), at(1, j)});
    for (int i = 1; i + 1 < rings; ++i) {
      p.triangles.push_back({at(i, j), at(i, j + 1), at(i + 1, j + 1)});
      p.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i + 1, j)});
    }
    p.triangles.push_back({top, at(rings - 1, j), at(rings - 1, j + 1)});
  }
  return p;
}

}  // namespace asimov::robots
