// Hostile mesh files (issue 17): a binary STL whose header lies about its face count, binary
// garbage, NaN, huge indices and more faces than a mesh may have end with an Error.
#include "asimov/collision/mesh_io.hpp"
#include "support/result.hpp"

#include <catch2/catch.hpp>

#include <cstdint>
#include <cstring>
#include <string>

using namespace asimov::collision;

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
  // The count matches the size but exceeds the limit: refused before any face is read.
  std::string huge(80, ' ');
  const std::uint32_t n = 3000000;
  huge.append(reinterpret_cast<const char*>(&n), 4);
  huge.resize(84 + 50 * std::size_t{n}, '\0');
  CHECK(mesh_error(huge, false) == "bad.stl: 3000000 faces; a mesh has at most 2000000");
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
  CHECK(mesh_error(obj, true) == "bad.obj: face 1: more than 2000000 triangles; a mesh has at most that many");
}
