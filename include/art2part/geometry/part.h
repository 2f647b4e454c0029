// The part: its tessellation, its faces, and what loading it found and repaired.
#pragma once

#include <string>
#include <vector>

#include "art2part/geometry/adjacency.h"
#include "art2part/geometry/face.h"
#include "art2part/geometry/mesh.h"
#include "art2part/geometry/repair.h"

namespace art2part {

enum class LengthUnit { Auto, Millimetre, Inch, Metre };

struct LoadOptions {
  // STEP tessellation: chordal deviation in mm (<= 0: 0.05% of the box diagonal, at least 0.005 mm) and angular
  // deflection in radians.
  double chordal_tolerance = 0.0;
  double angular_tolerance = 0.2;
  // Mesh files carry no unit: Auto takes millimetres. STEP files carry their own and are converted to mm.
  LengthUnit unit = LengthUnit::Auto;
  bool segment_mesh = true;  // recover faces of a mesh file by segmentation
  bool repair = true;
};

struct Part {
  std::string source;  // the file it came from
  Mesh mesh;           // mm, part frame
  std::vector<int> triangle_face;  // face id of each triangle
  std::vector<Face> faces;
  FaceSource face_source = FaceSource::Segmentation;
  RepairReport repairs;
  MeshCheck check;
  Adjacency adjacency;  // built once, on the final mesh
};

// Loads STEP (.step/.stp) through OpenCASCADE and everything else assimp reads (STL, OBJ, PLY, OFF, ...), repairs
// what is safe to repair, recovers faces, builds adjacency and checks the result. Throws InputError with one line
// that says what and where for a file that is not a part (missing, unreadable, empty, NaN, zero size, a size that
// looks like the wrong unit).
Part loadPart(const std::string& path, const LoadOptions& options = {});

// Builds a part from a mesh already in memory (same repair, segmentation and checks). `source` names it in errors.
Part partFromMesh(Mesh mesh, const std::string& source, const LoadOptions& options = {});

// Rejects sizes that are not a machinable part in mm: zero size, below 0.5 mm (likely metres) or above 20 m
// (likely micrometres). Throws InputError naming the size and the likely unit.
void checkPartSize(const Box& box, const std::string& where);

// What a user should know about a loaded part: an open or non-manifold mesh, several bodies. One line each.
std::vector<std::string> partWarnings(const Part& part);

// The triangles of each face (part.faces order), ascending; triangles whose face id is out of range belong to none.
std::vector<std::vector<int>> faceTriangles(const Part& part);

double lengthUnitToMm(LengthUnit unit);
LengthUnit parseLengthUnit(const std::string& text);  // mm, in|inch, m, auto; throws InputError

}  // namespace art2part
