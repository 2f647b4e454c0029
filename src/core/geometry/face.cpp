#include "art2part/geometry/face.h"

namespace art2part {

const char* surfaceTypeName(SurfaceType type) {
  switch (type) {
    case SurfaceType::Plane: return "plane";
    case SurfaceType::Cylinder: return "cylinder";
    case SurfaceType::Cone: return "cone";
    case SurfaceType::Sphere: return "sphere";
    case SurfaceType::Torus: return "torus";
    case SurfaceType::Other: return "other";
  }
  return "other";
}

FaceCounts countFaces(const std::vector<Face>& faces) {
  FaceCounts counts;
  for (const Face& f : faces) {
    switch (f.type) {
      case SurfaceType::Plane: ++counts.plane; break;
      case SurfaceType::Cylinder: ++counts.cylinder; break;
      case SurfaceType::Cone: ++counts.cone; break;
      case SurfaceType::Sphere: ++counts.sphere; break;
      case SurfaceType::Torus: ++counts.torus; break;
      case SurfaceType::Other: ++counts.other; break;
    }
  }
  return counts;
}

void updateFaceAreas(const Mesh& mesh, const std::vector<int>& triangle_face, std::vector<Face>& faces) {
  for (Face& f : faces) {
    f.area = 0.0;
    f.triangle_count = 0;
  }
  for (int t = 0; t < mesh.triangleCount(); ++t) {
    const int f = triangle_face[t];
    if (f < 0 || f >= static_cast<int>(faces.size())) continue;
    faces[f].area += triangleArea(mesh, t);
    ++faces[f].triangle_count;
  }
}

}  // namespace art2part
