#include "art2part/geometry/surface_fit.h"

#include <Eigen/Dense>
#include <cmath>

namespace art2part {

namespace {

constexpr double kHalfPi = 1.57079632679489661923;
// Damped Gauss-Newton from a start near the surface converges in a handful of steps; a start that needs more is
// rarely a surface at all (the callers check the result against their tolerance). A cone starts further off: its
// axis comes from three close normals.
constexpr int kMaxCylinderIterations = 15;
constexpr int kMaxConeIterations = 50;

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

// Signed distance from the cone (positive outside, away from the axis), along the normal of the nearest ruling.
double signedConeDistance(const ConeSurface& c, const Vec3& p) {
  const Vec3 d = p - c.apex;
  const double along = d.dot(c.axis);
  const double across = (d - along * c.axis).norm();
  return across * std::cos(c.half_angle) - along * std::sin(c.half_angle);
}

double sumOfSquaredConeDistances(const std::vector<Vec3>& points, const ConeSurface& cone) {
  const double cos_a = std::cos(cone.half_angle), sin_a = std::sin(cone.half_angle);
  double sum = 0.0;
  for (const Vec3& p : points) {
    const Vec3 d = p - cone.apex;
    const double along = d.dot(cone.axis);
    const double residual = (d - along * cone.axis).norm() * cos_a - along * sin_a;
    sum += residual * residual;
  }
  return sum;
}

// One damped Gauss-Newton step on apex (3), axis tilt (2, along u and w across the axis) and half angle (1). The
// residual is across cos(a) - along sin(a); the rows below are its derivatives.
ConeSurface coneStep(const std::vector<Vec3>& points, const ConeSurface& c, double damping) {
  Vec3 u, w;
  perpendicularBasis(c.axis, u, w);
  const double cos_a = std::cos(c.half_angle), sin_a = std::sin(c.half_angle);
  Eigen::Matrix<double, 6, 6> normal_matrix = Eigen::Matrix<double, 6, 6>::Zero();
  Eigen::Matrix<double, 6, 1> gradient = Eigen::Matrix<double, 6, 1>::Zero();
  for (const Vec3& p : points) {
    const Vec3 d = p - c.apex;
    const double along = d.dot(c.axis);
    const Vec3 radial = d - along * c.axis;
    const double across = radial.norm();
    if (across <= 0.0) continue;
    const Vec3 outwards = radial / across;
    const Vec3 by_apex = -cos_a * outwards + sin_a * c.axis;
    Eigen::Matrix<double, 6, 1> row;
    row << by_apex.x(), by_apex.y(), by_apex.z(),
        -cos_a * along * outwards.dot(u) - sin_a * d.dot(u),
        -cos_a * along * outwards.dot(w) - sin_a * d.dot(w),
        -across * sin_a - along * cos_a;
    normal_matrix += row * row.transpose();
    gradient += row * (across * cos_a - along * sin_a);
  }
  for (int i = 0; i < 6; ++i) normal_matrix(i, i) *= 1.0 + damping;
  const Eigen::Matrix<double, 6, 1> step = normal_matrix.ldlt().solve(-gradient);
  ConeSurface next = c;
  next.apex = c.apex + step.head<3>();
  next.axis = (c.axis + step(3) * u + step(4) * w).normalized();
  next.half_angle = c.half_angle + step(5);
  return next;
}

}  // namespace

double distanceToCone(const ConeSurface& cone, const Vec3& p) { return std::abs(signedConeDistance(cone, p)); }

bool nearestPointToLines(const std::vector<Vec3>& points, const std::vector<Vec3>& directions, Vec3& nearest) {
  Eigen::Matrix3d matrix = Eigen::Matrix3d::Zero();
  Vec3 rhs = Vec3::Zero();
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Eigen::Matrix3d across = Eigen::Matrix3d::Identity() - directions[i] * directions[i].transpose();
    matrix += across;
    rhs += across * points[i];
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> spectrum(matrix);
  if (spectrum.eigenvalues()(0) <= 1e-9 * spectrum.eigenvalues()(2)) return false;
  nearest = matrix.ldlt().solve(rhs);
  return nearest.allFinite();
}

bool fitCone(const std::vector<Vec3>& points, const ConeSurface& guess, ConeSurface& cone) {
  if (points.size() < 6) return false;
  ConeSurface current = guess;
  double cost = sumOfSquaredConeDistances(points, current);
  double damping = 1e-6;
  for (int iteration = 0; iteration < kMaxConeIterations && cost > 0.0; ++iteration) {
    const ConeSurface next = coneStep(points, current, damping);
    const double next_cost = sumOfSquaredConeDistances(points, next);
    if (!(next_cost < cost) || !(next.half_angle > 0.0) || !(next.half_angle < kHalfPi)) {
      damping *= 10.0;
      if (damping > 1e6) break;
      continue;
    }
    const bool converged = cost - next_cost <= 1e-8 * cost;
    current = next;
    cost = next_cost;
    damping = std::max(damping * 0.1, 1e-9);
    if (converged) break;
  }
  if (!(current.half_angle > 0.0 && current.half_angle < kHalfPi) || !current.apex.allFinite()) return false;
  cone = current;
  return true;
}

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

bool fitCylinderAroundAxis(const std::vector<Vec3>& points, const Vec3& axis, CylinderSurface& cylinder) {
  if (points.size() < 3 || axis.norm() <= 0.0 || !initialCylinder(points, axis.normalized(), cylinder)) return false;
  centreAxisPoint(points, cylinder);
  return true;
}

bool fitCylinder(const std::vector<Vec3>& points, const Vec3& axis_guess, CylinderSurface& cylinder) {
  if (points.size() < 5) return false;
  CylinderSurface current;
  if (!fitCylinderAroundAxis(points, axis_guess, current)) return false;
  double cost = sumOfSquaredDistances(points, current);
  double damping = 1e-6;
  for (int iteration = 0; iteration < kMaxCylinderIterations && cost > 0.0; ++iteration) {
    CylinderSurface next = gaussNewtonStep(points, current, damping);
    centreAxisPoint(points, next);
    const double next_cost = sumOfSquaredDistances(points, next);
    if (!(next_cost < cost) || !(next.radius > 0.0)) {
      damping *= 10.0;  // overshoot: lean towards gradient descent
      if (damping > 1e6) break;
      continue;
    }
    const bool converged = cost - next_cost <= 1e-8 * cost;
    current = next;
    cost = next_cost;
    damping = std::max(damping * 0.1, 1e-9);
    if (converged) break;
  }
  cylinder = current;
  return true;
}

}  // namespace art2part
