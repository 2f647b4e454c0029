// After pass 3 of face segmentation: free-form segments that are a sphere or a torus. Pass 2 drops the bands such
// surfaces are tessellated in (they end in unfitted facets at both ends), so they come out of pass 3 as free-form
// groups; a fit of the whole group tells which are in fact surfaces of revolution of these two kinds.
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "segmentation_internal.h"

namespace art2part {
namespace segmentation {

namespace {

constexpr int kMinTriangles = 8;       // fewer: too few to tell a sphere or a torus from free-form
constexpr double kMinSpreadRatio = 1e-9;

std::vector<Vec3> distinctCorners(const Mesh& mesh, const std::vector<int>& triangles) {
  std::vector<int> ids;
  for (int t : triangles) ids.insert(ids.end(), mesh.triangles[t].begin(), mesh.triangles[t].end());
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  std::vector<Vec3> points;
  for (int v : ids) points.push_back(mesh.vertices[v]);
  return points;
}

// Concave when the outward normals point towards the given centre of curvature of each triangle.
bool concaveTowards(const Mesh& mesh, const std::vector<int>& triangles, const std::vector<Vec3>& centres) {
  double outwardness = 0.0;
  for (std::size_t i = 0; i < triangles.size(); ++i) {
    const int t = triangles[i];
    outwardness += triangleArea(mesh, t) * triangleNormal(mesh, t).dot(triangleCentroid(mesh, t) - centres[i]);
  }
  return outwardness < 0.0;
}

// Sphere through the points: algebraic fit |p|^2 + d.p + e = 0 (centred for conditioning), checked by distance.
bool fitSphere(const std::vector<Vec3>& points, double tolerance, Vec3& centre, double& radius) {
  Vec3 mean = Vec3::Zero();
  for (const Vec3& p : points) mean += p / static_cast<double>(points.size());
  Eigen::Matrix4d normal_matrix = Eigen::Matrix4d::Zero();
  Eigen::Vector4d rhs = Eigen::Vector4d::Zero();
  for (const Vec3& p : points) {
    const Vec3 q = p - mean;
    const Eigen::Vector4d row(q.x(), q.y(), q.z(), 1.0);
    normal_matrix += row * row.transpose();
    rhs -= row * q.squaredNorm();
  }
  const Eigen::Vector4d solution = normal_matrix.ldlt().solve(rhs);
  centre = -0.5 * solution.head<3>();
  const double r2 = centre.squaredNorm() - solution(3);
  if (!(r2 > 0.0) || !centre.allFinite()) return false;
  radius = std::sqrt(r2);
  centre += mean;
  for (const Vec3& p : points)
    if (std::abs((p - centre).norm() - radius) > tolerance) return false;
  return true;
}

// The axis of a surface of revolution: every normal line meets it. A line (p, n) meets the axis (a, c) when
// a.(p x n) + n.(c x a) = 0, linear in (a, c x a): the solution is the eigenvector of least eigenvalue.
bool axisOfRevolution(const Mesh& mesh, const std::vector<int>& triangles, const Vec3& origin, Vec3& axis,
                      Vec3& point) {
  // Positions in units of their spread, so that both halves of the unknown weigh alike.
  double scale = 0.0;
  for (int t : triangles) scale = std::max(scale, (triangleCentroid(mesh, t) - origin).norm());
  if (!(scale > 0.0)) return false;
  Eigen::Matrix<double, 6, 6> scatter = Eigen::Matrix<double, 6, 6>::Zero();
  for (int t : triangles) {
    const Vec3 p = (triangleCentroid(mesh, t) - origin) / scale, n = triangleNormal(mesh, t);
    Eigen::Matrix<double, 6, 1> row;
    row << p.cross(n), n;
    scatter += triangleArea(mesh, t) * row * row.transpose();
  }
  // A singular value decomposition of the symmetric scatter: its eigenvectors, least last (and no gcc warnings, which
  // the 6x6 self-adjoint solver raises).
  const Eigen::JacobiSVD<Eigen::Matrix<double, 6, 6>> spectrum(scatter, Eigen::ComputeFullV);
  const auto& values = spectrum.singularValues();
  if (values(4) <= kMinSpreadRatio * values(0)) return false;  // no single axis (a sphere, a cylinder)
  const Eigen::Matrix<double, 6, 1> x = spectrum.matrixV().col(5);
  const double length = x.head<3>().norm();
  if (!(length > 0.0)) return false;
  axis = x.head<3>() / length;
  const Vec3 moment = x.tail<3>() / length;  // c x a, c in units of the spread
  point = origin + scale * axis.cross(moment);
  return axis.allFinite() && point.allFinite();
}

struct Torus {
  Vec3 axis = Vec3::UnitZ(), centre = Vec3::Zero();
  double major = 0.0, minor = 0.0;
};

double torusDistance(const Torus& torus, const Vec3& p) {
  const Vec3 d = p - torus.centre;
  const double z = d.dot(torus.axis);
  const double rho = (d - z * torus.axis).norm();
  return std::abs(std::hypot(rho - torus.major, z) - torus.minor);
}

// Torus around the axis: a circle fit of the points in the half plane (distance from the axis, height along it).
bool fitTorus(const Mesh& mesh, const std::vector<int>& triangles, const std::vector<Vec3>& points,
              const Tolerances& tol, Torus& torus) {
  Vec3 mean = Vec3::Zero();
  for (const Vec3& p : points) mean += p / static_cast<double>(points.size());
  Vec3 axis, point;
  if (!axisOfRevolution(mesh, triangles, mean, axis, point)) return false;
  std::vector<Eigen::Vector2d> meridian;
  for (const Vec3& p : points) {
    const Vec3 d = p - point;
    const double z = d.dot(axis);
    meridian.emplace_back((d - z * axis).norm(), z);
  }
  Eigen::Vector2d centre;
  double minor = 0.0;
  if (!fitCircle(meridian, centre, minor)) return false;
  torus = Torus{axis, point + centre.y() * axis, centre.x(), minor};
  if (!(torus.major > 0.0) || torus.major > tol.max_radius) return false;
  double worst = 0.0;
  for (const Vec3& p : points) worst = std::max(worst, torusDistance(torus, p));
  return worst <= tol.distance;
}

// Centre of the tube circle nearest each triangle: where its normal points from or to.
std::vector<Vec3> tubeCentres(const Mesh& mesh, const std::vector<int>& triangles, const Torus& torus) {
  std::vector<Vec3> centres;
  for (int t : triangles) {
    const Vec3 d = triangleCentroid(mesh, t) - torus.centre;
    const Vec3 radial = d - torus.axis * d.dot(torus.axis);
    centres.push_back(torus.centre + (radial.norm() > 0.0 ? Vec3(radial.normalized()) : Vec3::Zero()) * torus.major);
  }
  return centres;
}

}  // namespace

void fitDoublyCurved(const Mesh& mesh, const std::vector<int>& triangles, const Tolerances& tol, Face& face) {
  if (static_cast<int>(triangles.size()) < kMinTriangles) return;
  const std::vector<Vec3> points = distinctCorners(mesh, triangles);
  Vec3 centre;
  double radius = 0.0;
  if (fitSphere(points, tol.distance, centre, radius) && radius <= tol.max_radius) {
    face.type = SurfaceType::Sphere;
    face.point = centre;
    face.radius = radius;
    face.concave = concaveTowards(mesh, triangles, std::vector<Vec3>(triangles.size(), centre));
    return;
  }
  Torus torus;
  if (!fitTorus(mesh, triangles, points, tol, torus)) return;
  face.type = SurfaceType::Torus;
  face.axis = torus.axis;
  face.point = torus.centre;
  face.radius = torus.major;
  face.minor_radius = torus.minor;
  face.concave = concaveTowards(mesh, triangles, tubeCentres(mesh, triangles, torus));
}

}  // namespace segmentation
}  // namespace art2part
