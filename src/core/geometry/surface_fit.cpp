#include "art2part/geometry/surface_fit.h"

#include <Eigen/Dense>
#include <algorithm>
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

// A point seen from an axis (cylinder or cone): how far along it and across it, and which way across.
struct AxialPosition {
  Vec3 offset;    // the point minus the axis origin
  double along;   // signed distance along the axis from its origin
  double across;  // distance from the axis line
  Vec3 outwards;  // unit, from the axis towards the point; zero on the axis
};

AxialPosition axialPosition(const Vec3& p, const Vec3& origin, const Vec3& axis) {
  AxialPosition a;
  a.offset = p - origin;
  a.along = a.offset.dot(axis);
  const Vec3 radial = a.offset - a.along * axis;
  a.across = radial.norm();
  a.outwards = a.across > 0.0 ? Vec3(radial / a.across) : Vec3::Zero();
  return a;
}

Vec3 centroidOf(const std::vector<Vec3>& points) {
  Vec3 sum = Vec3::Zero();
  for (const Vec3& p : points) sum += p;
  return sum / static_cast<double>(points.size());
}

// The damped normal equations of one Gauss-Newton step over N parameters: add a row (the residual's derivatives)
// and its residual per point, then solve with Levenberg-Marquardt damping of the diagonal.
template <int N>
struct NormalEquations {
  using Vector = Eigen::Matrix<double, N, 1>;
  Eigen::Matrix<double, N, N> matrix = Eigen::Matrix<double, N, N>::Zero();  // sum of row row^T
  Vector gradient = Vector::Zero();                                          // sum of row * residual

  void add(const Vector& row, double residual) {
    matrix += row * row.transpose();
    gradient += row * residual;
  }

  Vector step(double damping) const {
    Eigen::Matrix<double, N, N> damped = matrix;
    for (int i = 0; i < N; ++i) damped(i, i) *= 1.0 + damping;
    return damped.ldlt().solve(-gradient);
  }
};

// Damped Gauss-Newton (Levenberg-Marquardt) from `start`: a step that lowers the cost and gives a proper surface
// (`proper`) is taken and the damping relaxed; otherwise the damping grows tenfold, towards gradient descent, until it
// passes 1e6. Stops when a step gains less than 1e-8 of the cost or after max_iterations.
template <class Surface, class StepFn, class CostFn, class ProperFn>
Surface dampedGaussNewton(const Surface& start, int max_iterations, StepFn step, CostFn cost_of, ProperFn proper) {
  Surface current = start;
  double cost = cost_of(current);
  double damping = 1e-6;
  for (int iteration = 0; iteration < max_iterations && cost > 0.0; ++iteration) {
    const Surface next = step(current, damping);
    const double next_cost = cost_of(next);
    if (!(next_cost < cost) || !proper(next)) {
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
  return current;
}

// The cost a fit minimises: the sum over the points of distance(p)^2.
template <class Distance>
double sumOfSquares(const std::vector<Vec3>& points, Distance distance) {
  double sum = 0.0;
  for (const Vec3& p : points) {
    const double d = distance(p);
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
  NormalEquations<5> equations;
  for (const Vec3& p : points) {
    const AxialPosition a = axialPosition(p, c.point, c.axis);
    if (a.across <= 0.0) continue;
    const double du = a.outwards.dot(u), dw = a.outwards.dot(w);
    Eigen::Matrix<double, 5, 1> row;
    row << -du, -dw, -a.along * du, -a.along * dw, -1.0;
    equations.add(row, a.across - c.radius);
  }
  const Eigen::Matrix<double, 5, 1> step = equations.step(damping);
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
  const AxialPosition a = axialPosition(p, c.apex, c.axis);
  return a.across * std::cos(c.half_angle) - a.along * std::sin(c.half_angle);
}

// One damped Gauss-Newton step on apex (3), axis tilt (2, along u and w across the axis) and half angle (1). The
// residual is across cos(a) - along sin(a); the rows below are its derivatives.
ConeSurface coneStep(const std::vector<Vec3>& points, const ConeSurface& c, double damping) {
  Vec3 u, w;
  perpendicularBasis(c.axis, u, w);
  const double cos_a = std::cos(c.half_angle), sin_a = std::sin(c.half_angle);
  NormalEquations<6> equations;
  for (const Vec3& p : points) {
    const AxialPosition a = axialPosition(p, c.apex, c.axis);
    if (a.across <= 0.0) continue;
    const Vec3 by_apex = -cos_a * a.outwards + sin_a * c.axis;
    Eigen::Matrix<double, 6, 1> row;
    row << by_apex.x(), by_apex.y(), by_apex.z(),
        -cos_a * a.along * a.outwards.dot(u) - sin_a * a.offset.dot(u),
        -cos_a * a.along * a.outwards.dot(w) - sin_a * a.offset.dot(w),
        -a.across * sin_a - a.along * cos_a;
    equations.add(row, a.across * cos_a - a.along * sin_a);
  }
  const Eigen::Matrix<double, 6, 1> step = equations.step(damping);
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
  const auto proper = [](const ConeSurface& c) { return c.half_angle > 0.0 && c.half_angle < kHalfPi; };
  const ConeSurface fitted = dampedGaussNewton(
      guess, kMaxConeIterations,
      [&](const ConeSurface& c, double damping) { return coneStep(points, c, damping); },
      [&](const ConeSurface& c) {
        return sumOfSquares(points, [&](const Vec3& p) { return signedConeDistance(c, p); });
      },
      proper);
  if (!proper(fitted) || !fitted.apex.allFinite()) return false;
  cone = fitted;
  return true;
}

double distanceToCylinder(const CylinderSurface& cylinder, const Vec3& p) {
  return std::abs(axialPosition(p, cylinder.point, cylinder.axis).across - cylinder.radius);
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
  CylinderSurface start;
  if (!fitCylinderAroundAxis(points, axis_guess, start)) return false;
  cylinder = dampedGaussNewton(
      start, kMaxCylinderIterations,
      [&](const CylinderSurface& c, double damping) {
        CylinderSurface next = gaussNewtonStep(points, c, damping);
        centreAxisPoint(points, next);
        return next;
      },
      [&](const CylinderSurface& c) {
        return sumOfSquares(points, [&](const Vec3& p) { return distanceToCylinder(c, p); });
      },
      [](const CylinderSurface& c) { return c.radius > 0.0; });
  return true;
}

}  // namespace art2part
