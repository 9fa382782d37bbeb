// Hostile mesh files (issue 17): a binary STL whose header lies about its face count, binary
// garbage, NaN, huge indices and more faces than a mesh may have end with an Error.
#include "support/scratch.hpp"
#include "asimov/collision/mesh_io.hpp"
#include "support/result.hpp"

#include <catch2/catch.hpp>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

using namespace asimov::collision;
using asimov::test::error_message;
namespace fs = std::filesystem;

namespace {

std::string mesh_error(const std::string& data, bool obj) {
  const auto r = obj ? parse_obj(data, "bad.obj") : parse_stl(data, "bad.stl");
  return r ? "no error" : r.error().message;
}

std::string binary_stl(std::uint32_t claimed, std::uint32_t actual) {
  std::string s(80, ' ');
  s.append(reinterpret_cast<const char*>(&claimed), 4);
  for (std::uint32_t f = 0; f < actual; ++f) {
    float v[12] = {0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0};
    s.append(reinterpret_cast<const char*>(v), sizeof v);
    s.append(2, '\0');
  }
  return s;
}

}  // namespace

TEST_CASE("binary STL whose header lies about the face count", "[mesh][hostile]") {
  CHECK(mesh_error(binary_stl(4000000000u, 1), false) ==
        "bad.stl: neither binary STL (size does not match the triangle count) nor ASCII STL");
  CHECK(mesh_error(binary_stl(0, 3), false) ==
        "bad.stl: neither binary STL (size does not match the triangle count) nor ASCII STL");
}

TEST_CASE("binary STL files past the face limit or truncated are refused before the faces are read",
          "[mesh][hostile]") {
  REQUIRE(kMaxMeshFaces == 10000000);  // docs/limits.md
  const fs::path dir = asimov::test::scratch_dir("hostile_mesh");
  // A sparse file (no disk written): the count matches the size, one face past the limit. The
  // streamed reader refuses it from the header.
  const std::string huge = (dir / "huge.stl").string();
  {
    std::ofstream(huge, std::ios::binary) << binary_stl(kMaxMeshFaces + 1, 0);
    fs::resize_file(huge, 84 + 50 * (kMaxMeshFaces + 1));
  }
  CHECK(error_message(read_stl(huge)) == huge + ": 10000001 faces; a mesh has at most 10000000");
  // A header claiming a face more than the file holds (truncated): not binary, and not ASCII.
  const std::string cut = (dir / "cut.stl").string();
  std::ofstream(cut, std::ios::binary) << binary_stl(3, 2);
  CHECK(error_message(read_stl(cut)) == cut + ": neither binary STL (size does not match the triangle count) nor ASCII STL");
  fs::remove_all(dir);  // the sparse file: 500 MB if copied
}

TEST_CASE("a flood of zero-area faces names the first 100 and counts the rest", "[mesh][hostile]") {
  std::string s(80, ' ');
  const std::uint32_t n = 1001;
  s.append(reinterpret_cast<const char*>(&n), 4);
  for (std::uint32_t f = 0; f < n; ++f) {  // 1000 faces of three equal vertices, then a real one
    const float x = static_cast<float>(f);
    const float dot[12] = {0, 0, 1, x, 0, 0, x, 0, 0, x, 0, 0};
    const float real[12] = {0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0};
    s.append(reinterpret_cast<const char*>(f + 1 < n ? dot : real), sizeof dot);
    s.append(2, '\0');
  }
  const auto r = parse_stl(s, "bad.stl");
  REQUIRE(r);
  REQUIRE(r->warnings.size() == 102);  // 100 faces, the count, the open mesh
  CHECK(r->warnings[0] == "bad.stl: face 1: zero area, dropped");
  CHECK(r->warnings[99] == "bad.stl: face 100: zero area, dropped");
  CHECK(r->warnings[100] == "bad.stl: 900 more faces of zero area dropped (only the first 100 are listed)");
  CHECK(r->warnings[101].starts_with("bad.stl: face 1001: an edge on one face only"));
  CHECK(r->mesh.triangles.size() == 1);
}

TEST_CASE("mesh garbage, NaN and huge references", "[mesh][hostile]") {
  CHECK(mesh_error(std::string("\0\xff\x01garbage", 10), false) ==
        "bad.stl: neither binary STL (size does not match the triangle count) nor ASCII STL");
  CHECK(mesh_error("solid x\nfacet\nvertex nan 0 0\nvertex 1 0 0\nvertex 0 1 0\nendfacet\n", false) ==
        "bad.stl: face 1: non-finite coordinate");
  CHECK(mesh_error("solid x\nfacet\nvertex 1e999 0 0\n", false) == "bad.stl: face 1: coordinate out of range");
  CHECK(mesh_error("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99999999999999999999999\n", true) ==
        "bad.obj:4: face 1: bad vertex reference '99999999999999999999999'");
  CHECK(mesh_error("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -9223372036854775807\n", true) ==
        "bad.obj:4: face 1: vertex -9223372036854775807 out of range");
  CHECK(mesh_error("v inf 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", true) == "bad.obj: face 1: non-finite coordinate");
  CHECK(mesh_error(std::string(1000, '\0'), true) == "bad.obj: no faces");
}

TEST_CASE("an OBJ polygon fanning past the face limit is refused", "[mesh][hostile]") {
  std::string obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1";
  obj.reserve(obj.size() + 2 * (kMaxMeshFaces + 10));
  for (std::size_t i = 0; i < kMaxMeshFaces + 2; ++i) obj += i % 2 ? " 2" : " 3";
  obj += "\n";
  CHECK(mesh_error(obj, true) == "bad.obj: face 1: more than 10000000 triangles; a mesh has at most that many");
}
