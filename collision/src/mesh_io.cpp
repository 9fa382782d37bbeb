#include "asimov/collision/mesh_io.hpp"

#include "containment.hpp"
#include "predicates.hpp"

#include "asimov/collision/text_file.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <memory>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <sys/stat.h>

namespace asimov::collision {
static LoadedMesh validate_mesh_x(Polyhedron mesh, const std::string& source, const std::vector<std::size_t>& face_numbers);
static LoadedMesh parse_stl_x(const std::string& data, const std::string& path, const Vec3& scale);
static LoadedMesh parse_obj_x(const std::string& data, const std::string& path, const Vec3& scale);
namespace {
// Thrown deep inside the readers and caught at this file's public functions, which return it
// as an Error (docs/design.md "Errors"): the readers stay free of a status test per face.
struct MeshError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

std::string read_file(const std::string& path) {
  Result<std::string> text = read_file_bounded(path, kMaxMeshFileBytes);
  if (!text) throw MeshError(path + ": " + text.error().message);
  return std::move(*text);
}

// Face `face` of `path` would make more than kMaxMeshFaces triangles.
std::string past_face_limit(const std::string& path, std::size_t face) {
  return fmt::format("{}: face {}: more than {} triangles; a mesh has at most that many", path, face, kMaxMeshFaces);
}

// Collects triangles with bit-identical vertices merged; checks finiteness.
struct Builder {
  std::string path{};
  Vec3 scale = Vec3::Ones();
  Polyhedron mesh{};
  // 1-based source face number per triangle; empty while triangle i is face i + 1 (every STL,
  // and OBJ files of triangles only): 8 bytes per face saved where it says nothing.
  std::vector<std::size_t> numbers{};
  // Welding: open addressing over indices into mesh.vertices, keyed by the coordinates' bits
  // (a std::map of coordinates took some 70 bytes per vertex at 1M faces). A slot holds the
  // index and 32 bits of the hash, so a probe past another vertex does not load that vertex
  // (a cache miss in a vertex list of megabytes); 8 bytes a slot, at most half of them full.
  struct Slot {
    std::uint32_t index, tag;
  };
  std::vector<Slot> slots = std::vector<Slot>(1024, Slot{kEmpty, 0});
  static constexpr std::uint32_t kEmpty = 0xffffffffu;

  static Vec3 key_of(const Vec3& v) { return {v.x() == 0 ? 0.0 : v.x(), v.y() == 0 ? 0.0 : v.y(), v.z() == 0 ? 0.0 : v.z()}; }  // -0 is 0
  static std::uint64_t hash(const Vec3& v) {
    std::uint64_t h = 0x9E3779B97F4A7C15ull;
    for (int k = 0; k < 3; ++k) {
      std::uint64_t bits;
      std::memcpy(&bits, &v[k], sizeof bits);
      h = (h ^ bits) * 0xff51afd7ed558ccdull;
      h ^= h >> 33;
    }
    // A float's coordinates as doubles end in 29 zero bits: finish with a full avalanche
    // (murmur3's), or the slots the low bits pick cluster and the probes run long.
    h *= 0xc4ceb9fe1a85ec53ull;
    h ^= h >> 33;
    return h;
  }
  static std::uint32_t tag_of(std::uint64_t h) { return static_cast<std::uint32_t>(h >> 32); }
  void rehash(std::size_t size) {
    std::vector<Slot> bigger(size, Slot{kEmpty, 0});
    const std::size_t mask = bigger.size() - 1;
    for (std::uint32_t i = 0; i < mesh.vertices.size(); ++i) {
      const std::uint64_t h = hash(mesh.vertices[i]);
      std::size_t s = h & mask;
      while (bigger[s].index != kEmpty) s = (s + 1) & mask;
      bigger[s] = {i, tag_of(h)};
    }
    slots = std::move(bigger);
  }
  // Room for `faces` triangles and the vertices of a closed mesh of that many (about half):
  // the vectors never double past what they hold (a doubling held up to three times a vector
  // while copying), the welding table is not rebuilt on the way.
  void reserve(std::size_t faces) {
    mesh.triangles.reserve(faces);
    const std::size_t vertices = faces / 2 + 2;
    mesh.vertices.reserve(vertices);
    if (slots.size() < 2 * vertices) rehash(std::bit_ceil(2 * vertices));
  }
  // Loads the welding slot of a vertex to come into the cache: the slot is where its hash
  // lands, a miss in a table of megabytes.
  void prefetch(const float* xyz) const {
    const Vec3 key = key_of(Vec3(xyz[0], xyz[1], xyz[2]).cwiseProduct(scale));
    __builtin_prefetch(slots.data() + (hash(key) & (slots.size() - 1)));
  }
  std::uint32_t vertex(const Vec3& raw, std::size_t face) {
    if (!raw.allFinite()) throw MeshError(path + ": face " + std::to_string(face) + ": non-finite coordinate");
    const Vec3 v = raw.cwiseProduct(scale);
    if (!v.allFinite()) throw MeshError(path + ": face " + std::to_string(face) + ": coordinate overflows after scaling");
    const Vec3 key = key_of(v);
    if (2 * (mesh.vertices.size() + 1) > slots.size()) rehash(2 * slots.size());
    const std::size_t mask = slots.size() - 1;
    const std::uint64_t h = hash(key);
    const std::uint32_t tag = tag_of(h);
    auto same = [&](std::uint32_t i) {  // bit-identical (no NaN, -0 folded)
      const Vec3& w = mesh.vertices[i];
      return w.x() == key.x() && w.y() == key.y() && w.z() == key.z();
    };
    for (std::size_t s = h & mask;; s = (s + 1) & mask) {
      const Slot slot = slots[s];
      if (slot.index == kEmpty) {
        slots[s] = {static_cast<std::uint32_t>(mesh.vertices.size()), tag};
        mesh.vertices.push_back(key);
        return slots[s].index;
      }
      if (slot.tag == tag && same(slot.index)) return slot.index;
    }
  }
  void triangle(const Vec3& a, const Vec3& b, const Vec3& c, std::size_t face) {
    const std::size_t n = mesh.triangles.size();
    if (n == kMaxMeshFaces) throw MeshError(past_face_limit(path, face));
    if (numbers.empty() && face != n + 1) {  // the first triangle not numbered by its index
      numbers.resize(n);
      for (std::size_t i = 0; i < n; ++i) numbers[i] = i + 1;
    }
    mesh.triangles.push_back({vertex(a, face), vertex(b, face), vertex(c, face)});
    if (!numbers.empty() || face != n + 1) numbers.push_back(face);
  }
  LoadedMesh finish() {
    if (mesh.triangles.empty()) throw MeshError(path + ": no faces");
    std::vector<Slot>().swap(slots);  // freed before the checks
    return validate_mesh_x(std::move(mesh), path, numbers);
  }
};

// Binary STL records (50 bytes: normal, three vertices, attribute) of faces first + 1 ...
void binary_faces(Builder& b, const char* records, std::size_t first, std::size_t count) {
  constexpr std::size_t kAhead = 8;  // faces between a slot's prefetch and its use
  for (std::size_t f = 0; f < count; ++f) {
    if (f + kAhead < count)
      for (int k = 0; k < 3; ++k) {
        float xyz[3];
        std::memcpy(xyz, records + 50 * (f + kAhead) + 12 + 12 * k, 12);
        b.prefetch(xyz);
      }
    const char* p = records + 50 * f + 12;  // skip the normal
    Vec3 v[3];
    for (int k = 0; k < 3; ++k) {
      float xyz[3];
      std::memcpy(xyz, p + 12 * k, 12);
      v[k] = Vec3(xyz[0], xyz[1], xyz[2]);
    }
    b.triangle(v[0], v[1], v[2], first + f + 1);
  }
}

// Zero-area faces named one warning each, then one line counting the rest: ten million of them
// would be ten million lines and a gigabyte of messages.
constexpr std::size_t kZeroAreaWarnings = 100;

std::string too_many_faces(const std::string& path, std::uint32_t n) {
  return fmt::format("{}: {} faces; a mesh has at most {}", path, n, kMaxMeshFaces);
}

bool zero_area(const Vec3& a, const Vec3& b, const Vec3& c) {
  // Collinear (or repeated) exactly: every axis projection has zero signed area.
  return orient2d(a.x(), a.y(), b.x(), b.y(), c.x(), c.y()) == 0 &&
         orient2d(a.y(), a.z(), b.y(), b.z(), c.y(), c.z()) == 0 &&
         orient2d(a.z(), a.x(), b.z(), b.x(), c.z(), c.x()) == 0;
}

std::string lower_extension(const std::string& path) {
  const auto dot = path.find_last_of('.');
  std::string e = dot == std::string::npos ? "" : path.substr(dot + 1);
  for (char& ch : e) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  return e;
}

}  // namespace

static LoadedMesh validate_mesh_x(Polyhedron mesh, const std::string& source, const std::vector<std::size_t>& face_numbers) {
  LoadedMesh out;
  auto number = [&](std::size_t i) { return face_numbers.empty() ? i + 1 : face_numbers[i]; };
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i)
    if (!mesh.vertices[i].allFinite()) throw MeshError(source + ": vertex " + std::to_string(i + 1) + ": non-finite coordinate");
  // Zero-area faces dropped in place (no second triangle list); `dropped` (input indices,
  // increasing) maps a kept triangle back to its face number for the closedness message.
  std::vector<std::size_t> dropped;
  std::size_t kept = 0;
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    const Triangle t = mesh.triangles[i];
    for (const std::uint32_t v : t)
      if (v >= mesh.vertices.size())
        throw MeshError(source + ": face " + std::to_string(number(i)) + ": vertex index out of range");
    if (zero_area(mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]])) {
      if (dropped.size() < kZeroAreaWarnings)
        out.warnings.push_back(source + ": face " + std::to_string(number(i)) + ": zero area, dropped");
      dropped.push_back(i);
      continue;
    }
    mesh.triangles[kept++] = t;
  }
  if (kept == 0) throw MeshError(source + ": every face has zero area");
  if (dropped.size() > kZeroAreaWarnings)
    out.warnings.push_back(fmt::format("{}: {} more faces of zero area dropped (only the first {} are listed)", source,
                                       dropped.size() - kZeroAreaWarnings, kZeroAreaWarnings));
  mesh.triangles.resize(kept);
  auto input_index = [&](std::size_t k) {  // kept triangle k was input triangle i
    std::size_t i = k;
    for (const std::size_t d : dropped) {
      if (d > i) break;
      ++i;
    }
    return i;
  };
  // Closed: each directed edge once, and its reverse once (containment.hpp: per-vertex edge
  // lists; a std::map of edges took some 190 bytes per face at 1M faces, sorted 64-bit keys 24
  // bytes and a fifth of the load). The first bad edge in (from, to) order is reported with the
  // first face using it.
  out.closed = true;
  if (const std::optional<EdgeFault> e = first_edge_fault(mesh.triangles, mesh.vertices.size())) {
    const std::uint32_t from = e->from, to = e->to;
    const char* why = e->kind == EdgeFault::twice_one_way
                          ? "an edge used twice in one direction (non-manifold or inconsistent orientation)"
                      : e->kind == EdgeFault::one_face ? "an edge on one face only (open mesh)"
                      : e->kind == EdgeFault::many_faces ? "an edge shared by more than two faces (non-manifold)"
                                                         : "an edge from a vertex to itself";
    std::size_t first = 0;  // the first face using the edge
    for (; first < mesh.triangles.size(); ++first) {
      const Triangle& t = mesh.triangles[first];
      if ((t[0] == from && t[1] == to) || (t[1] == from && t[2] == to) || (t[2] == from && t[0] == to)) break;
    }
    out.closed = false;
    out.warnings.push_back(source + ": face " + std::to_string(number(input_index(first))) + ": " + why +
                           "; the mesh has no inside, containment is not tested for it");
  }
  out.mesh = std::move(mesh);
  return out;
}

// A binary STL in a regular file is read in blocks of faces (the file is never held whole: 500 MB
// at 10M faces); anything else (ASCII, a size that does not match the count, a device or pipe)
// as the file's bytes.
static LoadedMesh read_stl_x(const std::string& path, const Vec3& scale) {
  struct stat st {};
  if (::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode) && st.st_size >= 84 &&
      static_cast<std::size_t>(st.st_size) <= kMaxMeshFileBytes) {
    const std::unique_ptr<std::FILE, int (*)(std::FILE*)> f(std::fopen(path.c_str(), "rb"), &std::fclose);
    char head[84];
    if (f && std::fread(head, 1, 84, f.get()) == 84) {
      std::uint32_t n = 0;
      std::memcpy(&n, head + 80, 4);
      if (static_cast<std::size_t>(st.st_size) == 84 + 50 * static_cast<std::size_t>(n)) {
        if (n > kMaxMeshFaces) throw MeshError(too_many_faces(path, n));
        Builder b{.path = path, .scale = scale};
        b.reserve(n);
        constexpr std::size_t kBlock = 1 << 16;  // faces per read: 3.2 MB
        std::vector<char> block(50 * std::min<std::size_t>(kBlock, n));
        for (std::size_t done = 0; done < n;) {
          const std::size_t count = std::min<std::size_t>(kBlock, n - done);
          if (std::fread(block.data(), 50, count, f.get()) != count)
            throw MeshError(fmt::format("{}: face {}: the file ended before its {} faces (it changed while being read)",
                                        path, done + 1, n));
          binary_faces(b, block.data(), done, count);
          done += count;
        }
        return b.finish();
      }
    }
  }
  return parse_stl_x(read_file(path), path, scale);
}

static LoadedMesh parse_stl_x(const std::string& data, const std::string& path, const Vec3& scale) {
  Builder b{.path = path, .scale = scale};
  // Binary when the size matches the triangle count, whatever the header says ("solid" too).
  if (data.size() >= 84) {
    std::uint32_t n = 0;
    std::memcpy(&n, data.data() + 80, 4);
    if (data.size() == 84 + 50 * static_cast<std::size_t>(n)) {
      if (n > kMaxMeshFaces) throw MeshError(too_many_faces(path, n));
      b.reserve(n);
      binary_faces(b, data.data() + 84, 0, n);
      return b.finish();
    }
  }
  if (data.compare(0, 5, "solid") != 0)
    throw MeshError(path + ": neither binary STL (size does not match the triangle count) nor ASCII STL");
  std::istringstream in(data);
  std::string word;
  std::size_t face = 0, line_vertices = 0;
  Vec3 v[3];
  while (in >> word) {
    if (word == "facet") {
      ++face;
      line_vertices = 0;
    } else if (word == "vertex") {
      std::string xs, ys, zs;
      if (!(in >> xs >> ys >> zs)) throw MeshError(path + ": face " + std::to_string(face) + ": truncated vertex");
      if (line_vertices >= 3) throw MeshError(path + ": face " + std::to_string(face) + ": more than three vertices");
      try {
        v[line_vertices++] = Vec3(std::stod(xs), std::stod(ys), std::stod(zs));
      } catch (const std::out_of_range&) {
        throw MeshError(path + ": face " + std::to_string(face) + ": coordinate out of range");
      } catch (const std::invalid_argument&) {
        throw MeshError(path + ": face " + std::to_string(face) + ": bad number in '" + xs + " " + ys + " " + zs + "'");
      }
    } else if (word == "endfacet") {
      if (line_vertices != 3) throw MeshError(path + ": face " + std::to_string(face) + ": not three vertices");
      b.triangle(v[0], v[1], v[2], face);
    }
  }
  return b.finish();
}

static LoadedMesh read_obj_x(const std::string& path, const Vec3& scale) { return parse_obj_x(read_file(path), path, scale); }

static LoadedMesh parse_obj_x(const std::string& data, const std::string& path, const Vec3& scale) {
  Builder b{.path = path, .scale = scale};
  std::vector<Vec3> v;
  std::istringstream in(data);
  std::string line;
  std::size_t line_no = 0, face = 0;
  while (std::getline(in, line)) {
    ++line_no;
    std::istringstream ls(line);
    std::string tag;
    if (!(ls >> tag) || tag[0] == '#') continue;
    const std::string where = path + ":" + std::to_string(line_no);
    if (tag == "v") {
      std::string xs, ys, zs;
      if (!(ls >> xs >> ys >> zs)) throw MeshError(where + ": a vertex needs x y z");
      try {
        v.emplace_back(std::stod(xs), std::stod(ys), std::stod(zs));
      } catch (const std::exception&) {
        throw MeshError(where + ": bad number in vertex");
      }
    } else if (tag == "f") {
      ++face;
      std::vector<Vec3> poly;
      std::string item;
      while (ls >> item) {
        long idx = 0;
        try {
          idx = std::stol(item.substr(0, item.find('/')));
        } catch (const std::exception&) {
          throw MeshError(where + ": face " + std::to_string(face) + ": bad vertex reference '" + item + "'");
        }
        const long n = static_cast<long>(v.size());
        const long i = idx < 0 ? n + idx : idx - 1;  // negative: relative to the last vertex
        if (idx == 0 || i < 0 || i >= n)
          throw MeshError(where + ": face " + std::to_string(face) + ": vertex " + item + " out of range");
        poly.push_back(v[static_cast<std::size_t>(i)]);
        // A polygon fanning past the face limit is refused as it is read (its vertices alone
        // would take 24 bytes per triangle).
        if (poly.size() >= 3 && b.mesh.triangles.size() + poly.size() - 2 > kMaxMeshFaces)
          throw MeshError(past_face_limit(path, face));
      }
      if (poly.size() < 3) throw MeshError(where + ": face " + std::to_string(face) + ": fewer than three vertices");
      for (std::size_t k = 1; k + 1 < poly.size(); ++k) b.triangle(poly[0], poly[k], poly[k + 1], face);  // fan
    }
    // vn, vt, g, o, s, usemtl, mtllib, l, p: not geometry we use.
  }
  return b.finish();
}

static LoadedMesh read_mesh_x(const std::string& path, const Vec3& scale) {
  const std::string e = lower_extension(path);
  if (e == "stl") return read_stl_x(path, scale);
  if (e == "obj") return read_obj_x(path, scale);
  throw MeshError(path + ": unknown mesh format (expected .stl or .obj)");
}

int segments_for_tolerance(double radius, double tolerance, int min_segments) {
  if (!(radius > 0) || !(tolerance > 0) || tolerance >= radius) return std::max(min_segments, 3);
  // r (1 - cos(pi / n)) <= tol  <=>  n >= pi / acos(1 - tol / r)
  // Clamped as a double: a tolerance below radius * 1e-16 makes acos 0 and n infinite, which
  // converted to int is undefined (UBSan float-cast-overflow).
  const double n = std::ceil(std::numbers::pi / std::acos(1 - tolerance / radius));
  return static_cast<int>(std::min(std::max(n, static_cast<double>(std::max(min_segments, 3))), 4096.0));
}

namespace {
Polyhedron uv_sphere(double radius, int segments, int rings) {
  Polyhedron p;
  p.vertices.emplace_back(0, 0, -radius);
  for (int r = 1; r < rings; ++r) {
    const double phi = std::numbers::pi * r / rings - std::numbers::pi / 2;
    for (int s = 0; s < segments; ++s) {
      const double th = 2 * std::numbers::pi * s / segments;
      p.vertices.emplace_back(radius * std::cos(phi) * std::cos(th), radius * std::cos(phi) * std::sin(th),
                              radius * std::sin(phi));
    }
  }
  p.vertices.emplace_back(0, 0, radius);
  const auto top = static_cast<std::uint32_t>(p.vertices.size() - 1);
  auto at = [&](int r, int s) { return static_cast<std::uint32_t>(1 + (r - 1) * segments + (s % segments)); };
  for (int s = 0; s < segments; ++s) p.triangles.push_back({0, at(1, s + 1), at(1, s)});
  for (int r = 1; r + 1 < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      p.triangles.push_back({at(r, s), at(r, s + 1), at(r + 1, s + 1)});
      p.triangles.push_back({at(r, s), at(r + 1, s + 1), at(r + 1, s)});
    }
  for (int s = 0; s < segments; ++s) p.triangles.push_back({at(rings - 1, s), at(rings - 1, s + 1), top});
  return p;
}
}  // namespace

static Polyhedron make_sphere_x(double radius, double tolerance) {
  // A face's plane is sqrt(r^2 - rho^2) from the centre (rho: its circumradius), so a face
  // deviates more than the chord of one direction: refine until every face is within tolerance,
  // but never past the face budget (a radius of 1e8 mm within 1e-6 mm would need ~10^14 faces).
  int segments = segments_for_tolerance(radius, tolerance, 8);  // around the z axis
  const auto rings_for = [](int s) { return std::max(2, (s + 1) / 2); };
  const auto faces_for = [&](int s) { return 2 * static_cast<std::size_t>(s) * static_cast<std::size_t>(rings_for(s) - 1); };
  const auto over_budget = [&] {
    return MeshError(fmt::format("a sphere of radius {:g} mm within {:g} mm needs more than {} faces, the limit "
                                 "for one primitive; use a larger tolerance_mm",
                                 radius, tolerance, kMaxPrimitiveFaces));
  };
  if (faces_for(segments) > kMaxPrimitiveFaces) throw over_budget();
  for (;;) {
    Polyhedron p = uv_sphere(radius, segments, rings_for(segments));
    double worst = 0;
    for (const Triangle& t : p.triangles) {
      const Vec3 &a = p.vertices[t[0]], &b = p.vertices[t[1]], &c = p.vertices[t[2]];
      const Vec3 n = (b - a).cross(c - a);
      if (n.norm() > 0) worst = std::max(worst, radius - n.normalized().dot(a));
    }
    if (worst <= tolerance || !(tolerance > 0)) return p;
    segments += std::max(1, segments / 16);
    if (faces_for(segments) > kMaxPrimitiveFaces) throw over_budget();
  }
}

Polyhedron make_cylinder_tol(double radius, double height, double tolerance) {
  return make_cylinder(radius, height, segments_for_tolerance(radius, tolerance));
}

// The public face: the same functions returning their MeshError as an Error.
namespace {
template <class F>
auto as_result(const std::string& file, F&& f) -> Result<decltype(f())> {
  try {
    return f();
  } catch (const MeshError& e) {
    return Error{e.what(), "", file};
  }
}
}  // namespace

Result<LoadedMesh> validate_mesh(Polyhedron mesh, const std::string& source, const std::vector<std::size_t>& face_numbers) {
  return as_result("", [&] { return validate_mesh_x(std::move(mesh), source, face_numbers); });
}
Result<LoadedMesh> read_stl(const std::string& path, const Vec3& scale) {
  return as_result(path, [&] { return read_stl_x(path, scale); });
}
Result<LoadedMesh> read_obj(const std::string& path, const Vec3& scale) {
  return as_result(path, [&] { return read_obj_x(path, scale); });
}
Result<LoadedMesh> parse_stl(const std::string& data, const std::string& path, const Vec3& scale) {
  return as_result(path, [&] { return parse_stl_x(data, path, scale); });
}
Result<LoadedMesh> parse_obj(const std::string& data, const std::string& path, const Vec3& scale) {
  return as_result(path, [&] { return parse_obj_x(data, path, scale); });
}
Result<LoadedMesh> read_mesh(const std::string& path, const Vec3& scale) {
  return as_result(path, [&] { return read_mesh_x(path, scale); });
}
Result<Polyhedron> make_sphere(double radius, double tolerance) {
  return as_result("", [&] { return make_sphere_x(radius, tolerance); });
}

}  // namespace asimov::collision
