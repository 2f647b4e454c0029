#include "art2part/geometry/mesh_io.h"

#include <assimp/cimport.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <sys/stat.h>

namespace art2part {

bool hasExtension(const std::string& path, const std::string& ext) {
  const auto dot = path.find_last_of('.');
  if (dot == std::string::npos) return false;
  std::string e = path.substr(dot + 1);
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return std::tolower(c); });
  std::string want = ext;
  std::transform(want.begin(), want.end(), want.begin(), [](unsigned char c) { return std::tolower(c); });
  return e == want;
}

namespace {

void requireReadableFile(const std::string& path) {
  struct stat st {};
  if (stat(path.c_str(), &st) != 0) throw InputError("'" + path + "': no such file");
  if (S_ISDIR(st.st_mode)) throw InputError("'" + path + "': is a folder, not a part file");
  if (st.st_size == 0) throw InputError("'" + path + "': empty file");
  std::ifstream probe(path, std::ios::binary);
  if (!probe) throw InputError("'" + path + "': cannot open for reading");
}

// Appends the triangles of one assimp mesh, transformed by the node's matrix, in the file's order.
void appendMesh(const aiMesh& in, const aiMatrix4x4& transform, Mesh& out) {
  const int base = static_cast<int>(out.vertices.size());
  for (unsigned i = 0; i < in.mNumVertices; ++i) {
    const aiVector3D p = transform * in.mVertices[i];
    out.vertices.emplace_back(p.x, p.y, p.z);
  }
  for (unsigned f = 0; f < in.mNumFaces; ++f) {
    const aiFace& face = in.mFaces[f];
    // aiProcess_Triangulate has split polygons; points and lines have fewer than three corners.
    if (face.mNumIndices != 3) continue;
    out.triangles.push_back({base + static_cast<int>(face.mIndices[0]), base + static_cast<int>(face.mIndices[1]),
                             base + static_cast<int>(face.mIndices[2])});
  }
}

void appendNode(const aiScene& scene, const aiNode& node, const aiMatrix4x4& parent, Mesh& out) {
  const aiMatrix4x4 transform = parent * node.mTransformation;
  for (unsigned i = 0; i < node.mNumMeshes; ++i) appendMesh(*scene.mMeshes[node.mMeshes[i]], transform, out);
  for (unsigned i = 0; i < node.mNumChildren; ++i) appendNode(scene, *node.mChildren[i], transform, out);
}

}  // namespace

Mesh readMeshFile(const std::string& path) {
  requireReadableFile(path);
  // No vertex joining or reordering here: triangle order must stay that of the file.
  const aiScene* scene = aiImportFile(path.c_str(), aiProcess_Triangulate);
  if (!scene || !scene->mRootNode) {
    std::string reason = aiGetErrorString();
    if (reason.empty()) reason = "unknown format";
    std::replace(reason.begin(), reason.end(), '\n', ' ');
    throw InputError("'" + path + "': not a mesh file assimp can read (" + reason + ")");
  }
  Mesh mesh;
  appendNode(*scene, *scene->mRootNode, aiMatrix4x4(), mesh);
  aiReleaseImport(scene);
  if (mesh.triangles.empty()) throw InputError("'" + path + "': holds no triangles");
  return mesh;
}

void writeBinaryStl(const Mesh& mesh, const std::string& path, const std::string& header) {
  std::ofstream out(path, std::ios::binary);
  if (!out) throw InputError("cannot write '" + path + "'");
  char head[80] = {0};
  // A binary STL header must not start with "solid" or readers take it for ASCII.
  std::strncpy(head, header.rfind("solid", 0) == 0 ? ("binary " + header).c_str() : header.c_str(), 79);
  out.write(head, 80);
  const std::uint32_t count = static_cast<std::uint32_t>(mesh.triangles.size());
  out.write(reinterpret_cast<const char*>(&count), 4);
  for (int t = 0; t < mesh.triangleCount(); ++t) {
    float record[12];
    const Vec3 n = triangleNormal(mesh, t);
    for (int k = 0; k < 3; ++k) record[k] = static_cast<float>(n[k]);
    for (int c = 0; c < 3; ++c)
      for (int k = 0; k < 3; ++k) record[3 + 3 * c + k] = static_cast<float>(mesh.corner(t, c)[k]);
    out.write(reinterpret_cast<const char*>(record), sizeof(record));
    const std::uint16_t attribute = 0;
    out.write(reinterpret_cast<const char*>(&attribute), 2);
  }
  if (!out) throw InputError("writing '" + path + "' failed");
}

}  // namespace art2part
