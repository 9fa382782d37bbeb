// Mesh input: STL (ASCII, binary), OBJ (polygons, negative indices), scale, tessellated
// primitives, and validation messages naming file and face. Files are written to a temp dir.
#include "support/scratch.hpp"
#include "collision/src/containment.hpp"
#include "asimov/collision/engine.hpp"
#include "asimov/collision/mesh_io.hpp"
#include "support/result.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <numbers>

using namespace asimov::collision;
using asimov::test::must;
using asimov::test::error_message;
namespace fs = std::filesystem;

namespace {

fs::path temp_dir() { return asimov::test::scratch_dir("mesh_io"); }

std::string write(const std::string& name, const std::string& text) {
  const fs::path p = temp_dir() / name;
  std::ofstream(p, std::ios::binary) << text;
  return p.string();
}

// The 12 faces of a unit cube [0,1]^3 as vertex triples, outward.
std::vector<std::array<Vec3, 3>> cube_faces() {
  const Polyhedron b = make_box(Vec3(1, 1, 1));
  std::vector<std::array<Vec3, 3>> f;
  for (const Triangle& t : b.triangles)
    f.push_back({b.vertices[t[0]] + Vec3::Constant(0.5), b.vertices[t[1]] + Vec3::Constant(0.5),
                 b.vertices[t[2]] + Vec3::Constant(0.5)});
  return f;
}

std::string ascii_stl(const std::vector<std::array<Vec3, 3>>& faces) {
  std::string s = "solid cube\n";
  for (const auto& f : faces) {
    s += "  facet normal 0 0 0\n    outer loop\n";
    for (const Vec3& v : f)
      s += "      vertex " + std::to_string(v.x()) + " " + std::to_string(v.y()) + " " + std::to_string(v.z()) + "\n";
    s += "    endloop\n  endfacet\n";
  }
  return s + "endsolid cube\n";
}

std::string binary_stl(const std::vector<std::array<Vec3, 3>>& faces) {
  std::string s(80, ' ');
  s.replace(0, 5, "solid");  // a binary file whose header starts like ASCII
  const auto n = static_cast<std::uint32_t>(faces.size());
  s.append(reinterpret_cast<const char*>(&n), 4);
  for (const auto& f : faces) {
    float rec[12] = {0, 0, 0};
    for (int k = 0; k < 3; ++k)
      for (int c = 0; c < 3; ++c) rec[3 + 3 * k + c] = static_cast<float>(f[static_cast<std::size_t>(k)][c]);
    s.append(reinterpret_cast<const char*>(rec), sizeof rec);
    s.append(2, '\0');
  }
  return s;
}

}  // namespace

TEST_CASE("STL ASCII and binary give the same welded closed cube and scale applies", "[mesh_io]") {
  const std::string a = write("cube_ascii.stl", ascii_stl(cube_faces()));
  const std::string b = write("cube_binary.STL", binary_stl(cube_faces()));
  const LoadedMesh ma = must(read_stl(a)), mb = must(read_mesh(b));
  CHECK(ma.mesh.triangles.size() == 12);
  CHECK(ma.mesh.vertices.size() == 8);  // welded
  CHECK(mb.mesh.vertices.size() == 8);
  CHECK(ma.closed);
  CHECK(mb.closed);
  CHECK(ma.warnings.empty());
  CHECK(is_closed(ma.mesh));
  const LoadedMesh ms = must(read_stl(a, Vec3::Constant(1000)));  // metres -> mm
  Vec3 hi = Vec3::Zero();
  for (const Vec3& v : ms.mesh.vertices) hi = hi.cwiseMax(v);
  CHECK(hi == Vec3(1000, 1000, 1000));
}

TEST_CASE("OBJ: quads fan-triangulated, negative indices, v/vt/vn forms, scale", "[mesh_io]") {
  const std::string obj = write("cube.obj",
                                "# cube\no cube\n"
                                "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
                                "vn 0 0 1\nvt 0 0\n"
                                "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2/1 3/1 7/1 6/1\n"
                                "f 3//1 4//1 8//1 7//1\nf -4 -1 -5 -8\n");  // last: 5 8 4 1, relative
  const LoadedMesh m = must(read_obj(obj, Vec3(2, 2, 2)));
  CHECK(m.mesh.triangles.size() == 12);
  CHECK(m.mesh.vertices.size() == 8);
  CHECK(m.closed);
  Engine e;
  const BodyId big = e.add_body({.name = "cube", .mesh = m.mesh});
  const BodyId small = e.add_body({.name = "dot", .mesh = make_box(Vec3(0.1, 0.1, 0.1))});
  Pose p = Pose::Identity();
  p.translation() = Vec3(1, 1, 1);  // inside the scaled cube [0, 2]^3: containment
  e.set_pose(big, Pose::Identity());
  e.set_pose(small, p);
  CHECK(e.check().contact.kind == ContactKind::containment);
}

TEST_CASE("validation: non-finite rejected, zero-area dropped, open meshes warned", "[mesh_io]") {
  auto faces = cube_faces();
  SECTION("NaN and infinity are rejected with file and face") {
    std::string s = ascii_stl(faces);
    const auto at = s.find("vertex", s.find("facet", s.find("facet") + 1));  // face 2
    s.replace(at, 6, "vertex nan 0 0 #");
    const std::string path = write("nan.stl", s);
    const auto nan = read_stl(path);
    REQUIRE_FALSE(nan.ok());
    CHECK(nan.error().file == path);
    CHECK_THAT(nan.error().message, Catch::Contains("nan.stl") && Catch::Contains("face 2") && Catch::Contains("non-finite"));
    faces[4][1].x() = INFINITY;
    CHECK_THAT(error_message(read_stl(write("inf.stl", binary_stl(faces)))), Catch::Contains("face 5"));
    CHECK_THAT(error_message(read_obj(write("inf.obj", "v 0 0 0\nv 1 0 0\nv 0 inf 0\nf 1 2 3\n"))),
               Catch::Contains("inf.obj") && Catch::Contains("non-finite"));
  }
  SECTION("zero-area faces are dropped with a warning naming them") {
    faces.push_back({Vec3(0, 0, 0), Vec3(0.5, 0.5, 0.5), Vec3(1, 1, 1)});  // collinear: face 13
    faces.push_back({Vec3(0, 0, 0), Vec3(0, 0, 0), Vec3(1, 0, 0)});        // repeated: face 14
    const LoadedMesh m = must(read_stl(write("degenerate.stl", binary_stl(faces))));
    CHECK(m.mesh.triangles.size() == 12);
    REQUIRE(m.warnings.size() == 2);
    CHECK_THAT(m.warnings[0], Catch::Contains("degenerate.stl: face 13: zero area"));
    CHECK_THAT(m.warnings[1], Catch::Contains("face 14: zero area"));
    CHECK(m.closed);
  }
  SECTION("an open mesh is accepted, warned, and has no inside") {
    faces.pop_back();  // face 12 gone: a hole
    const LoadedMesh m = must(read_stl(write("open.stl", ascii_stl(faces))));
    CHECK_FALSE(m.closed);
    REQUIRE(m.warnings.size() == 1);
    CHECK_THAT(m.warnings[0], Catch::Contains("open.stl: face") && Catch::Contains("open mesh") &&
                                  Catch::Contains("containment"));
    Engine e;
    const BodyId id = e.add_body({.name = "open", .mesh = m.mesh});
    CHECK_FALSE(e.body_closed(id));
  }
  SECTION("non-manifold: an edge shared by four faces") {
    Polyhedron two = merged(make_box(Vec3(1, 1, 1)), transformed(make_box(Vec3(1, 1, 1)), Pose(Eigen::Translation3d(1, 1, 0))));
    const LoadedMesh m = must(validate_mesh(two, "object 'pair'"));  // boxes touch along an edge, not welded here
    CHECK(m.closed);  // two separate closed shells: still closed
    Polyhedron welded = two;  // weld the shared edge's vertices: now four faces meet there
    for (Triangle& t : welded.triangles)
      for (std::uint32_t& v : t)
        for (std::uint32_t u = 0; u < 8; ++u)
          if (v >= 8 && welded.vertices[v] == welded.vertices[u]) v = u;
    const LoadedMesh w = must(validate_mesh(welded, "object 'pair'"));
    CHECK_FALSE(w.closed);
    REQUIRE_FALSE(w.warnings.empty());
    CHECK_THAT(w.warnings[0], Catch::Contains("object 'pair': face"));
  }
  SECTION("unreadable and unknown") {
    CHECK_THAT(error_message(read_mesh((temp_dir() / "missing.stl").string())), Catch::Contains("cannot open the file"));
    CHECK_THAT(error_message(read_mesh(write("x.ply", "ply\n"))), Catch::Contains("unknown mesh format"));
    CHECK_THAT(error_message(read_obj(write("bad.obj", "v 0 0 0\nf 1 2 3\n"))),
               Catch::Contains("bad.obj:2") && Catch::Contains("out of range"));
    CHECK_THAT(error_message(read_stl(write("junk.stl", "hello"))), Catch::Contains("junk.stl"));
  }
}

TEST_CASE("a tolerance too small for doubles gives the most segments, not an undefined cast", "[mesh_io]") {
  // 1 - 1e-302 is 1: acos gives 0 and the segment count infinity (UBSan float-cast-overflow).
  CHECK(segments_for_tolerance(100, 1e-300) == 4096);
  CHECK(segments_for_tolerance(100, 1e-300, 5000) == 4096);
  CHECK(segments_for_tolerance(100, 10, 5000) == 4096);
  CHECK(segments_for_tolerance(1e8, 1e-6) == 4096);
}

TEST_CASE("primitives tessellated to a chordal tolerance", "[mesh_io]") {
  for (const double tol : {1.0, 0.1, 0.01}) {
    const double r = 50;
    const int n = segments_for_tolerance(r, tol);
    CHECK(r * (1 - std::cos(std::numbers::pi / n)) <= tol);
    CHECK(r * (1 - std::cos(std::numbers::pi / (n - 1))) > tol);  // the fewest that do
    const Polyhedron s = must(make_sphere(r, tol));
    CHECK(must(validate_mesh(s, "sphere")).closed);
    CHECK(must(validate_mesh(s, "sphere")).warnings.empty());
    for (const Vec3& v : s.vertices) CHECK(std::fabs(v.norm() - r) < 1e-9);
    // Every face lies within tol of the sphere: its plane is at least r - tol from the centre.
    for (const Triangle& t : s.triangles) {
      const Vec3 a = s.vertices[t[0]], b = s.vertices[t[1]], c = s.vertices[t[2]];
      const Vec3 nrm = (b - a).cross(c - a).normalized();
      CHECK(nrm.dot(a) >= r - tol - 1e-9);  // also outward
    }
    CHECK(must(validate_mesh(make_cylinder_tol(r, 10, tol), "cylinder")).closed);
  }
}

TEST_CASE("a binary STL above the old 2,000,000-face limit loads, streamed", "[mesh][big]") {
  // A torus of 1500 x 700 quads (2.1M faces, 105 MB), written row by row: every vertex is the
  // same float bits wherever it appears, so the loader welds a closed mesh.
  const int nu = 1500, nv = 700;
  const std::uint32_t n = 2u * nu * nv;
  const std::string path = (temp_dir() / "big.stl").string();
  {
    std::ofstream out(path, std::ios::binary);
    out << std::string(80, ' ');
    out.write(reinterpret_cast<const char*>(&n), 4);
    auto at = [&](int i, int j, float* p) {
      const double u = 2 * std::numbers::pi * (i % nu) / nu, v = 2 * std::numbers::pi * (j % nv) / nv;
      p[0] = static_cast<float>((1000 + 300 * std::cos(v)) * std::cos(u));
      p[1] = static_cast<float>((1000 + 300 * std::cos(v)) * std::sin(u));
      p[2] = static_cast<float>(300 * std::sin(v));
    };
    std::vector<char> row;
    auto put = [&](const float* p, const float* q, const float* r) {
      char record[50] = {};  // normal (zero), three vertices, attribute
      std::memcpy(record + 12, p, 12);
      std::memcpy(record + 24, q, 12);
      std::memcpy(record + 36, r, 12);
      row.insert(row.end(), record, record + 50);
    };
    for (int i = 0; i < nu; ++i) {
      row.clear();
      for (int j = 0; j < nv; ++j) {
        float a[3], b[3], c[3], d[3];
        at(i, j, a), at(i + 1, j, b), at(i + 1, j + 1, c), at(i, j + 1, d);
        put(a, b, c);
        put(a, c, d);
      }
      out.write(row.data(), static_cast<std::streamsize>(row.size()));
    }
  }
  REQUIRE(fs::file_size(path) == 84 + 50 * std::size_t{n});
  const LoadedMesh m = must(read_stl(path));
  CHECK(m.mesh.triangles.size() == n);
  CHECK(m.mesh.vertices.size() == std::size_t{nu} * nv);
  CHECK(m.closed);
  CHECK(m.warnings.empty());
  // The same file cut in the middle of its last face: the size no longer matches the count.
  fs::resize_file(path, 84 + 50 * std::size_t{n} - 7);
  CHECK(error_message(read_stl(path)) == path + ": neither binary STL (size does not match the triangle count) nor ASCII STL");
  fs::remove(path);
}
