// Reading and writing mesh files. Triangle order of the file is preserved.
#pragma once

#include <string>

#include "art2part/geometry/mesh.h"

namespace art2part {

// Reads any mesh format assimp knows (STL ascii/binary, OBJ, PLY, OFF, ...). Faces with more than three corners are
// triangulated in place; points and lines are ignored. Vertices are not merged here (see repairMesh).
// Throws InputError for a missing or unreadable file or one with no triangles.
Mesh readMeshFile(const std::string& path);

// Binary STL, float32, as the file contracts require. Throws InputError when the file cannot be written.
void writeBinaryStl(const Mesh& mesh, const std::string& path, const std::string& header = "art2part");

bool hasExtension(const std::string& path, const std::string& ext);  // case-insensitive, ext without the dot

}  // namespace art2part
