// STEP through OpenCASCADE: a tessellation in mm in which every triangle keeps the id of its B-rep face, and every
// face knows its surface.
#pragma once

#include <string>
#include <vector>

#include "art2part/geometry/face.h"
#include "art2part/geometry/mesh.h"

namespace art2part {

struct StepTessellation {
  Mesh mesh;                       // mm, vertices shared along face boundaries are NOT yet merged
  std::vector<int> triangle_face;  // B-rep face index of each triangle
  std::vector<Face> faces;         // one per B-rep face, in the order TopExp_Explorer visits them
  double unit_to_mm = 1.0;         // what the file's length unit was, in mm
};

// chordal_tolerance in mm (> 0), angular_tolerance in radians. Throws InputError when the file cannot be read or
// holds no faces.
StepTessellation readStep(const std::string& path, double chordal_tolerance, double angular_tolerance);

// The box of the shape in the file, in mm, without tessellating (to pick a chordal tolerance).
Box stepBoundingBox(const std::string& path);

}  // namespace art2part
