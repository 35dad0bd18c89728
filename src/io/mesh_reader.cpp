// Mesh files through Assimp (io/mesh_reader.h): which files are meshes, and their
// triangles in metres, z up.

#include "uavip/io/mesh_reader.h"

#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <Eigen/Core>
#include <algorithm>
#include <assimp/Importer.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>

#include "cloud_formats.h"
#include "uavip/core/error.h"
#include "uavip/core/text.h"

namespace uavip::io {
namespace {

/// The cloud formats io reads itself (cloud_io.cpp); never handed to Assimp.
bool isCloudExtension(const std::string& ext) {
  return ext == ".pcd" || ext == ".ply" || ext == ".xyz" || ext == ".txt" || ext == ".csv" ||
         ext == ".las" || ext == ".laz";
}

/// True when a PLY header declares `element face N` with N > 0. A header that cannot
/// be read is left to the cloud reader (false), which names what is wrong.
bool plyDeclaresFaces(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string line;
  if (!in || !std::getline(in, line) || line.rfind("ply", 0) != 0) return false;
  for (int lines = 0; lines < 256 && std::getline(in, line); ++lines) {
    const std::vector<std::string> w = headerWords(line);
    if (w.empty()) continue;
    if (w[0] == "end_header") return false;
    if (w[0] == "element" && w.size() == 3 && w[1] == "face")
      return w[2].find_first_not_of("0123456789") == std::string::npos &&
             w[2].find_first_not_of('0') != std::string::npos;
  }
  return false;
}

/// Formats whose coordinates are y up once Assimp has read them: glTF by its
/// specification, COLLADA and 3DS because Assimp turns them to its own y-up frame.
bool yUpOnceRead(const std::string& ext) {
  return ext == ".gltf" || ext == ".glb" || ext == ".dae" || ext == ".3ds";
}

/// A node's placement: x' = linear x + shift, in double.
struct Placement {
  Eigen::Matrix3d linear{Eigen::Matrix3d::Identity()};
  Vec3 shift{Vec3::Zero()};
};

Placement operator*(const Placement& parent, const aiMatrix4x4& m) {
  Placement local;
  local.linear << m.a1, m.a2, m.a3, m.b1, m.b2, m.b3, m.c1, m.c2, m.c3;
  local.shift = Vec3(m.a4, m.b4, m.c4);
  return {parent.linear * local.linear, parent.linear * local.shift + parent.shift};
}

/// Appends the triangles of `m` placed by `at` (indices shifted past the vertices
/// already held).
void appendMesh(const aiMesh& m, const Placement& at, bool y_up, double scale, TriangleMesh& out) {
  const std::size_t base = out.vertices.size();
  out.vertices.reserve(base + m.mNumVertices);
  out.triangles.reserve(out.triangles.size() + m.mNumFaces);
  for (unsigned v = 0; v < m.mNumVertices; ++v) {
    const aiVector3D& p = m.mVertices[v];
    const Vec3 q = at.linear * Vec3(p.x, p.y, p.z) + at.shift;
    out.vertices.push_back(scale * (y_up ? Vec3(q.x(), -q.z(), q.y()) : q));
  }
  for (unsigned f = 0; f < m.mNumFaces; ++f) {
    const aiFace& face = m.mFaces[f];
    if (face.mNumIndices != 3) continue;  // points and lines: no surface
    out.triangles.push_back({static_cast<std::uint32_t>(base + face.mIndices[0]),
                             static_cast<std::uint32_t>(base + face.mIndices[1]),
                             static_cast<std::uint32_t>(base + face.mIndices[2])});
  }
}

/// Appends every mesh `node` and its children show, each placed by the product of
/// its nodes' transforms (what aiProcess_PreTransformVertices does, without copying
/// the scene).
void appendNode(const aiScene& scene, const aiNode& node, const Placement& parent, bool y_up,
                double scale, const std::string& path, TriangleMesh& out) {
  const Placement at = parent * node.mTransformation;
  for (unsigned k = 0; k < node.mNumMeshes; ++k) {
    const aiMesh* m = node.mMeshes[k] < scene.mNumMeshes ? scene.mMeshes[node.mMeshes[k]] : nullptr;
    if (m == nullptr) continue;
    if (out.vertices.size() + m->mNumVertices > std::numeric_limits<std::uint32_t>::max())
      throw InputError(path + ": the mesh has more than 4e9 vertices; split it");
    appendMesh(*m, at, y_up, scale, out);
  }
  for (unsigned c = 0; c < node.mNumChildren; ++c) {
    if (node.mChildren[c] != nullptr)
      appendNode(scene, *node.mChildren[c], at, y_up, scale, path, out);
  }
}

/// Assimp holds coordinates as float: a mesh far from its file's origin (UTM) is
/// rounded by |x| 2^-24; beyond kMaxMeshRoundingM it is refused, naming the fix.
void requireSinglePrecisionFits(const std::string& path, const TriangleMesh& mesh) {
  double far = 0.0;
  for (const Vec3& p : mesh.vertices) far = std::max(far, p.cwiseAbs().maxCoeff());
  const double rounding = far * 0x1.0p-24;  // half a float's step at the farthest coordinate
  if (rounding > kMaxMeshRoundingM)
    throw InputError(path + ": the mesh reaches " + formatNumber(far / 1e3, 4) +
                     " km from its file's origin; read in single precision (Assimp) its corners "
                     "move by up to " +
                     formatNumber(rounding * 1e3, 3) +
                     " mm: export it in a local frame (an offset near the structure)");
}

}  // namespace

bool isMeshFile(const std::string& path) {
  const std::string ext = lowerExtension(path);
  if (ext == ".ply") return plyDeclaresFaces(path);
  if (ext.empty() || isCloudExtension(ext)) return false;
  return Assimp::Importer().IsExtensionSupported(ext);
}

TriangleMesh readMesh(const std::string& path, double scale, MeshReadInfo* info) {
  const std::string ext = lowerExtension(path);
  Assimp::Importer importer;
  // Points and lines are dropped at import: only faces carry a surface.
  importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE,
                              aiPrimitiveType_POINT | aiPrimitiveType_LINE);
  const aiScene* scene = importer.ReadFile(
      path, aiProcess_Triangulate | aiProcess_SortByPType | aiProcess_ValidateDataStructure);
  if (scene == nullptr) {
    std::string why = importer.GetErrorString();
    std::replace(why.begin(), why.end(), '\n', ' ');
    // Assimp's validation of a file without faces (an empty STL, vertices only).
    if (why.find("contains no faces") != std::string::npos ||
        why.find("contains no vertices") != std::string::npos)
      throwNoFaces(path);
    if (why.size() > 160) why = why.substr(0, 160) + "…";
    throw InputError(path + ": cannot read the mesh (" + why + ")");
  }
  const bool y_up = yUpOnceRead(ext);
  TriangleMesh mesh;
  if (scene->mRootNode != nullptr)
    appendNode(*scene, *scene->mRootNode, Placement{}, y_up, scale, path, mesh);
  requireSinglePrecisionFits(path, mesh);
  if (mesh.triangles.empty()) throwNoFaces(path);
  if (info != nullptr) {
    info->present = true;
    info->format = ext.substr(1);
    info->triangles = mesh.triangles.size();
    info->scale = scale;
    info->axes = y_up ? "y up turned to z up" : "z up as in the file";
  }
  return mesh;
}

}  // namespace uavip::io
