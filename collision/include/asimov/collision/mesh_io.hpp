// Mesh input for cell objects, link and tool bodies: STL (ASCII and binary) and OBJ files,
// primitives tessellated to a stated chordal tolerance, and the validation every loaded mesh
// goes through. Load time only: a problem comes back as an Error (Result) naming file and face.
//
// Validation policy (docs/collision.md):
// - NaN or infinite coordinate, index out of range, unreadable file: rejected (an Error).
// - Zero-area face (repeated or exactly collinear vertices, exact test): dropped, one warning
//   each naming the face.
// - Open or non-manifold mesh (an edge not shared by exactly two faces in opposite
//   directions): accepted with a warning naming an offending face; such a body has no inside,
//   so the engine skips it in the containment test (Engine::body_closed is false).
#pragma once
#include "asimov/collision/polyhedron.hpp"
#include "asimov/core/result.hpp"

#include <cstddef>
#include <string>
#include <vector>

namespace asimov::collision {

struct LoadedMesh {
  Polyhedron mesh;                    // welded (bit-identical vertices merged), scaled, valid faces
  bool closed = false;                // every edge shared by two faces in opposite directions
  std::vector<std::string> warnings;  // "file: face N: ..." lines for the user
};

// Faces are numbered from 1 in messages, in file order (STL facet, OBJ polygon).
// `scale` multiplies every coordinate (e.g. 1000 for a file in metres).
Result<LoadedMesh> read_stl(const std::string& path, const Vec3& scale = Vec3::Ones());
Result<LoadedMesh> read_obj(const std::string& path, const Vec3& scale = Vec3::Ones());
// The same from the file's bytes; `path` names it in messages (fuzz/ feeds these directly).
Result<LoadedMesh> parse_stl(const std::string& data, const std::string& path, const Vec3& scale = Vec3::Ones());
Result<LoadedMesh> parse_obj(const std::string& data, const std::string& path, const Vec3& scale = Vec3::Ones());
// Triangles one mesh file may give (docs/limits.md): 10 million, a 500 MB binary STL (the 512 MiB
// file limit lets 10.7 million through); loading and the engine's set-up of that many take
// seconds and about a gigabyte (docs/collision.md §13), so more is refused.
inline constexpr std::size_t kMaxMeshFaces = 10000000;
// By extension (.stl / .obj, any case); an Error for anything else.
Result<LoadedMesh> read_mesh(const std::string& path, const Vec3& scale = Vec3::Ones());

// Checks a mesh as above; `source` names it in messages ("file.stl", "object 'table'").
// `face_numbers[i]` is the 1-based number shown for triangle i (empty: i + 1).
Result<LoadedMesh> validate_mesh(Polyhedron mesh, const std::string& source, const std::vector<std::size_t>& face_numbers = {});

// Segments per full turn so that a circle of `radius` is within `tolerance` of its inscribed
// polygon (chord sagitta r (1 - cos(pi / n)) <= tolerance); at least `min_segments`.
int segments_for_tolerance(double radius, double tolerance, int min_segments = 3);

// Most faces one tessellated primitive may have: far above what a cell needs (a sphere within
// 0.1 % of its radius has ~5,000) and small enough that building the cell stays well under a
// second. A sphere that needs more is an Error (docs/limits.md).
inline constexpr std::size_t kMaxPrimitiveFaces = 100000;
// UV sphere centred at the origin, every point of the sphere within `tolerance` of the mesh
// and the mesh inside the sphere (vertices on it); closed, outward faces. An Error
// when that takes more than kMaxPrimitiveFaces faces.
Result<Polyhedron> make_sphere(double radius, double tolerance);
// make_cylinder with the segment count from the tolerance.
Polyhedron make_cylinder_tol(double radius, double height, double tolerance);

}  // namespace asimov::collision
