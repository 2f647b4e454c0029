// A triangle mesh over plain data: the part's tessellation in millimetres.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace art2part {

using Vec3 = Eigen::Vector3d;
using Triangle = std::array<int, 3>;  // vertex indices, counter-clockwise seen from outside

// An error in what the caller gave us (a file, a request): one line that says what and where.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct Box {
  Vec3 min{Vec3::Constant(std::numeric_limits<double>::infinity())};
  Vec3 max{Vec3::Constant(-std::numeric_limits<double>::infinity())};
  bool empty() const { return (max.array() < min.array()).any(); }
  Vec3 size() const { return empty() ? Vec3::Zero() : Vec3(max - min); }
  Vec3 center() const { return 0.5 * (min + max); }
  double diagonal() const { return size().norm(); }
  void extend(const Vec3& p) {
    min = min.cwiseMin(p);
    max = max.cwiseMax(p);
  }
};

struct Mesh {
  std::vector<Vec3> vertices;
  std::vector<Triangle> triangles;

  int triangleCount() const { return static_cast<int>(triangles.size()); }
  const Vec3& corner(int t, int i) const { return vertices[triangles[t][i]]; }
};

// Geometry of one triangle.
Vec3 triangleNormal(const Mesh& mesh, int t);  // unit normal (zero for a degenerate triangle)
double triangleArea(const Mesh& mesh, int t);
Vec3 triangleCentroid(const Mesh& mesh, int t);

Box boundingBox(const Mesh& mesh);
double surfaceArea(const Mesh& mesh);
// Signed volume by the divergence theorem: positive for a closed mesh oriented outwards.
double signedVolume(const Mesh& mesh);

// Scales every vertex (unit conversion).
void scaleMesh(Mesh& mesh, double factor);

}  // namespace art2part
