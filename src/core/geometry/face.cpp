#include "art2part/geometry/face.h"

#include <algorithm>
#include <cmath>

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

namespace {

// How far p lies inside the true concave surface (towards the space it bounds), or 0.
double inward(const Face& f, const Vec3& p) {
  switch (f.type) {
    case SurfaceType::Cylinder: {
      const Vec3 a = f.axis.normalized();
      const Vec3 d = p - f.point;
      return f.radius - (d - d.dot(a) * a).norm();
    }
    case SurfaceType::Sphere:
      return f.radius - (p - f.point).norm();
    case SurfaceType::Torus: {
      const Vec3 a = f.axis.normalized();
      const Vec3 d = p - f.point;
      const Vec3 radial = d - d.dot(a) * a;
      if (radial.norm() < 1e-12) return 0;
      const Vec3 tube = f.point + radial.normalized() * f.radius;  // the tube's centre circle, nearest p
      return f.minor_radius - (p - tube).norm();
    }
    case SurfaceType::Cone: {
      // Distance from the cone's surface, positive inside (towards its axis).
      const Vec3 a = f.axis.normalized();
      const Vec3 d = p - f.point;
      const double h = d.dot(a), r = (d - h * a).norm();
      return (h * std::tan(f.half_angle) - r) * std::cos(f.half_angle);
    }
    default:
      return 0;
  }
}

}  // namespace

std::vector<double> concaveSag(const Mesh& mesh, const std::vector<int>& triangle_face, const std::vector<Face>& faces) {
  std::vector<double> sag(faces.size(), 0.0);
  for (int t = 0; t < mesh.triangleCount() && t < static_cast<int>(triangle_face.size()); ++t) {
    const int f = triangle_face[t];
    if (f < 0 || f >= static_cast<int>(faces.size()) || !faces[f].concave) continue;
    const Vec3 &a = mesh.corner(t, 0), &b = mesh.corner(t, 1), &c = mesh.corner(t, 2);
    for (const Vec3& p : {Vec3((a + b + c) / 3), Vec3((a + b) / 2), Vec3((b + c) / 2), Vec3((c + a) / 2)})
      sag[f] = std::max(sag[f], inward(faces[f], p));
  }
  return sag;
}

}  // namespace art2part
