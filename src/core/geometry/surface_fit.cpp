#include "art2part/geometry/surface_fit.h"

#include <Eigen/Dense>
#include <cmath>

namespace art2part {

namespace {

// Two unit vectors completing a unit axis to a right-handed orthonormal frame.
void perpendicularBasis(const Vec3& axis, Vec3& u, Vec3& w) {
  const Vec3 helper = std::abs(axis.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  u = axis.cross(helper).normalized();
  w = axis.cross(u);
}

Vec3 centroidOf(const std::vector<Vec3>& points) {
  Vec3 sum = Vec3::Zero();
  for (const Vec3& p : points) sum += p;
  return sum / static_cast<double>(points.size());
}

double sumOfSquaredDistances(const std::vector<Vec3>& points, const CylinderSurface& cylinder) {
  double sum = 0.0;
  for (const Vec3& p : points) {
    const double d = distanceToCylinder(cylinder, p);
    sum += d * d;
  }
  return sum;
}

// The circle fit of the points projected along the axis gives the starting position and radius.
bool initialCylinder(const std::vector<Vec3>& points, const Vec3& axis, CylinderSurface& cylinder) {
  Vec3 u, w;
  perpendicularBasis(axis, u, w);
  const Vec3 origin = centroidOf(points);
  std::vector<Eigen::Vector2d> projected;
  projected.reserve(points.size());
  for (const Vec3& p : points) projected.emplace_back((p - origin).dot(u), (p - origin).dot(w));
  Eigen::Vector2d centre;
  double radius = 0.0;
  if (!fitCircle(projected, centre, radius)) return false;
  cylinder.axis = axis;
  cylinder.point = origin + centre.x() * u + centre.y() * w;
  cylinder.radius = radius;
  return true;
}

// One damped Gauss-Newton step on (position across the axis: 2, axis tilt: 2, radius: 1). The residual of a point is
// its distance from the axis minus the radius; the derivatives below are those of that distance.
CylinderSurface gaussNewtonStep(const std::vector<Vec3>& points, const CylinderSurface& c, double damping) {
  Vec3 u, w;
  perpendicularBasis(c.axis, u, w);
  Eigen::Matrix<double, 5, 5> normal_matrix = Eigen::Matrix<double, 5, 5>::Zero();
  Eigen::Matrix<double, 5, 1> gradient = Eigen::Matrix<double, 5, 1>::Zero();
  for (const Vec3& p : points) {
    const Vec3 d = p - c.point;
    const double along = d.dot(c.axis);
    const Vec3 radial = d - along * c.axis;
    const double distance = radial.norm();
    if (distance <= 0.0) continue;
    const Vec3 direction = radial / distance;
    const double du = direction.dot(u), dw = direction.dot(w);
    Eigen::Matrix<double, 5, 1> row;
    row << -du, -dw, -along * du, -along * dw, -1.0;
    normal_matrix += row * row.transpose();
    gradient += row * (distance - c.radius);
  }
  for (int i = 0; i < 5; ++i) normal_matrix(i, i) *= 1.0 + damping;
  const Eigen::Matrix<double, 5, 1> step = normal_matrix.ldlt().solve(-gradient);
  CylinderSurface next = c;
  next.point = c.point + step(0) * u + step(1) * w;
  next.axis = (c.axis + step(2) * u + step(3) * w).normalized();
  next.radius = c.radius + step(4);
  return next;
}

// Keeps the axis point level with the middle of the points, so the tilt derivatives stay well conditioned.
void centreAxisPoint(const std::vector<Vec3>& points, CylinderSurface& c) {
  const Vec3 middle = centroidOf(points);
  c.point += c.axis * c.axis.dot(middle - c.point);
}

}  // namespace

double distanceToCylinder(const CylinderSurface& cylinder, const Vec3& p) {
  const Vec3 d = p - cylinder.point;
  const Vec3 radial = d - cylinder.axis * cylinder.axis.dot(d);
  return std::abs(radial.norm() - cylinder.radius);
}

Vec3 leastAlignedDirection(const std::vector<Vec3>& normals, const std::vector<double>& weights) {
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (std::size_t i = 0; i < normals.size(); ++i) scatter += weights[i] * normals[i] * normals[i].transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(scatter);
  return solver.eigenvectors().col(0).normalized();  // eigenvalues come in increasing order
}

bool fitCircle(const std::vector<Eigen::Vector2d>& points, Eigen::Vector2d& centre, double& radius) {
  if (points.size() < 3) return false;
  // Centre and scale the points first: the algebraic fit squares coordinates.
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const auto& p : points) mean += p;
  mean /= static_cast<double>(points.size());
  double scale = 0.0;
  for (const auto& p : points) scale = std::max(scale, (p - mean).norm());
  if (scale <= 0.0) return false;
  // Minimise sum (x^2 + y^2 + D x + E y + F)^2 over D, E, F.
  Eigen::Matrix3d normal_matrix = Eigen::Matrix3d::Zero();
  Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
  for (const auto& p : points) {
    const Eigen::Vector2d q = (p - mean) / scale;
    const Eigen::Vector3d row(q.x(), q.y(), 1.0);
    normal_matrix += row * row.transpose();
    rhs -= row * q.squaredNorm();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> spectrum(normal_matrix);
  // Collinear points (a single planar strip seen end-on) leave the system singular: no circle.
  if (spectrum.eigenvalues()(0) <= 1e-12 * spectrum.eigenvalues()(2)) return false;
  const Eigen::Vector3d def = normal_matrix.ldlt().solve(rhs);
  const double r2 = 0.25 * (def(0) * def(0) + def(1) * def(1)) - def(2);
  if (!(r2 > 0.0) || !std::isfinite(r2)) return false;
  centre = mean + scale * Eigen::Vector2d(-0.5 * def(0), -0.5 * def(1));
  radius = scale * std::sqrt(r2);
  return true;
}

bool fitCylinder(const std::vector<Vec3>& points, const Vec3& axis_guess, CylinderSurface& cylinder) {
  if (points.size() < 5 || axis_guess.norm() <= 0.0) return false;
  CylinderSurface current;
  if (!initialCylinder(points, axis_guess.normalized(), current)) return false;
  centreAxisPoint(points, current);
  double cost = sumOfSquaredDistances(points, current);
  double damping = 1e-6;
  for (int iteration = 0; iteration < 30 && cost > 0.0; ++iteration) {
    CylinderSurface next = gaussNewtonStep(points, current, damping);
    centreAxisPoint(points, next);
    const double next_cost = sumOfSquaredDistances(points, next);
    if (!(next_cost < cost) || !(next.radius > 0.0)) {
      damping *= 10.0;  // overshoot: lean towards gradient descent
      if (damping > 1e6) break;
      continue;
    }
    const bool converged = cost - next_cost <= 1e-12 * cost;
    current = next;
    cost = next_cost;
    damping = std::max(damping * 0.1, 1e-9);
    if (converged) break;
  }
  cylinder = current;
  return true;
}

}  // namespace art2part
