#include "art2part/geometry/mesh.h"

namespace art2part {

namespace {
Vec3 crossOf(const Mesh& mesh, int t) {
  const Vec3& a = mesh.corner(t, 0);
  return (mesh.corner(t, 1) - a).cross(mesh.corner(t, 2) - a);
}
}  // namespace

Vec3 triangleNormal(const Mesh& mesh, int t) {
  const Vec3 n = crossOf(mesh, t);
  const double length = n.norm();
  return length > 0.0 ? Vec3(n / length) : Vec3::Zero();
}

double triangleArea(const Mesh& mesh, int t) { return 0.5 * crossOf(mesh, t).norm(); }

Vec3 triangleCentroid(const Mesh& mesh, int t) {
  return (mesh.corner(t, 0) + mesh.corner(t, 1) + mesh.corner(t, 2)) / 3.0;
}

Box boundingBox(const Mesh& mesh) {
  Box box;
  for (const Triangle& tri : mesh.triangles)
    for (int i : tri) box.extend(mesh.vertices[i]);
  return box;
}

double surfaceArea(const Mesh& mesh) {
  double area = 0.0;
  for (int t = 0; t < mesh.triangleCount(); ++t) area += triangleArea(mesh, t);
  return area;
}

double signedVolume(const Mesh& mesh) {
  // Relative to the box centre, so large coordinates do not cost precision.
  const Vec3 origin = boundingBox(mesh).center();
  double six_volume = 0.0;
  for (int t = 0; t < mesh.triangleCount(); ++t) {
    const Vec3 a = mesh.corner(t, 0) - origin, b = mesh.corner(t, 1) - origin, c = mesh.corner(t, 2) - origin;
    six_volume += a.dot(b.cross(c));
  }
  return six_volume / 6.0;
}

void scaleMesh(Mesh& mesh, double factor) {
  for (Vec3& v : mesh.vertices) v *= factor;
}

}  // namespace art2part
