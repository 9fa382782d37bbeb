#include "mesh_files.hpp"

#include <assimp/Importer.hpp>
#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <tinyxml2.h>

#include "asimov/collision/text_file.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <functional>
#include <stdexcept>

namespace asimov::robots {
namespace {
using collision::Vec3;
// A problem inside the assimp path; returned as an Error by read_mesh_file.
struct MeshError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

std::string lower_extension(const std::string& path) {
  std::string e = std::filesystem::path(path).extension().string();
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return e;
}

// COLLADA <asset>: metres per unit and the up axis ('X', 'Y' or 'Z').
void collada_asset(const std::string& path, double& metres, char& up) {
  metres = 1, up = 'Y';  // the COLLADA defaults
  tinyxml2::XMLDocument doc;
  if (doc.LoadFile(path.c_str()) != tinyxml2::XML_SUCCESS) return;  // assimp reports the real error
  const tinyxml2::XMLElement* asset = doc.RootElement() ? doc.RootElement()->FirstChildElement("asset") : nullptr;
  if (!asset) return;
  if (const tinyxml2::XMLElement* unit = asset->FirstChildElement("unit")) {
    const double m = unit->DoubleAttribute("meter", 1.0);
    if (std::isfinite(m) && m > 0) metres = m;
  }
  if (const tinyxml2::XMLElement* u = asset->FirstChildElement("up_axis"); u && u->GetText()) {
    const std::string t = u->GetText();
    if (t.find('X') != std::string::npos) up = 'X';
    else if (t.find('Z') != std::string::npos) up = 'Z';
  }
}

collision::Polyhedron read_with_assimp(const std::string& path, const std::string& ext, const Vec3& scale,
                                       std::vector<std::size_t>& faces) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw MeshError(path + ": cannot open the mesh file");
  // The limits of STL / OBJ (docs/limits.md), before assimp reads anything.
  const auto bytes = std::filesystem::file_size(path, ec);
  if (ec || bytes > collision::kMaxMeshFileBytes)
    throw MeshError(path + ": larger than " + std::to_string(collision::kMaxMeshFileBytes >> 20) + " MiB");
  Assimp::Importer importer;
  // The file's own coordinates: its units and up axis are applied below, the same way for
  // every assimp version (assimp folds them into the root node otherwise).
  importer.SetPropertyBool(AI_CONFIG_IMPORT_COLLADA_IGNORE_UP_DIRECTION, true);
  const aiScene* scene = importer.ReadFile(path, aiProcess_Triangulate | aiProcess_JoinIdenticalVertices |
                                                     aiProcess_SortByPType);
  if (!scene || !scene->mRootNode) throw MeshError(path + ": " + importer.GetErrorString());
  Eigen::Matrix4d file = Eigen::Matrix4d::Identity();
  bool skip_root = false;
  if (ext == ".dae") {
    double metres;
    char up;
    collada_asset(path, metres, up);
    Eigen::Matrix3d r = Eigen::Matrix3d::Identity();
    if (up == 'Y') r << 1, 0, 0, 0, 0, -1, 0, 1, 0;       // file Y -> Z, file Z -> -Y
    else if (up == 'X') r << 0, -1, 0, 0, 0, -1, 1, 0, 0;  // file X -> Z, -Y -> X, Z -> -Y (COLLADA axes)
    file.topLeftCorner<3, 3>() = r * metres;
    skip_root = true;  // the root holds assimp's own unit factor
  }
  collision::Polyhedron mesh;
  std::size_t face_number = 0;
  std::function<void(const aiNode*, const Eigen::Matrix4d&)> walk = [&](const aiNode* node, const Eigen::Matrix4d& parent) {
    Eigen::Matrix4d local;
    const aiMatrix4x4& m = node->mTransformation;
    local << m.a1, m.a2, m.a3, m.a4, m.b1, m.b2, m.b3, m.b4, m.c1, m.c2, m.c3, m.c4, m.d1, m.d2, m.d3, m.d4;
    const Eigen::Matrix4d t = (skip_root && node == scene->mRootNode) ? parent : Eigen::Matrix4d(parent * local);
    for (unsigned k = 0; k < node->mNumMeshes; ++k) {
      const aiMesh* am = scene->mMeshes[node->mMeshes[k]];
      const auto base = static_cast<std::uint32_t>(mesh.vertices.size());
      for (unsigned v = 0; v < am->mNumVertices; ++v) {
        const Eigen::Vector4d p = t * Eigen::Vector4d(am->mVertices[v].x, am->mVertices[v].y, am->mVertices[v].z, 1);
        mesh.vertices.push_back(p.head<3>().cwiseProduct(scale));
      }
      if (mesh.triangles.size() + am->mNumFaces > collision::kMaxMeshFaces)
        throw MeshError(path + ": more than " + std::to_string(collision::kMaxMeshFaces) + " faces; a mesh has at most " +
                        std::to_string(collision::kMaxMeshFaces));
      for (unsigned f = 0; f < am->mNumFaces; ++f) {
        ++face_number;
        const aiFace& face = am->mFaces[f];
        if (face.mNumIndices != 3) continue;  // points and lines (aiProcess_SortByPType keeps them apart)
        mesh.triangles.push_back({base + face.mIndices[0], base + face.mIndices[1], base + face.mIndices[2]});
        faces.push_back(face_number);
      }
    }
    for (unsigned c = 0; c < node->mNumChildren; ++c) walk(node->mChildren[c], t);
  };
  walk(scene->mRootNode, file);
  if (mesh.triangles.empty()) throw MeshError(path + ": no triangle in the mesh");
  return mesh;
}
}  // namespace

Result<collision::LoadedMesh> read_mesh_file(const std::string& path, const Vec3& scale) {
  const std::string ext = lower_extension(path);
  if (ext == ".stl" || ext == ".obj") return collision::read_mesh(path, scale);
  std::vector<std::size_t> faces;
  try {
    collision::Polyhedron mesh = read_with_assimp(path, ext, scale, faces);
    return collision::validate_mesh(std::move(mesh), path, faces);
  } catch (const MeshError& e) {
    return Error{e.what(), "", path};
  }
}

}  // namespace asimov::robots
