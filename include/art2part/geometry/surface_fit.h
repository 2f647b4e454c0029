// Least-squares fits of analytic surfaces to points of a mesh: the geometry behind face segmentation.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "art2part/geometry/mesh.h"

namespace art2part {

struct CylinderSurface {
  Vec3 axis = Vec3::UnitZ();  // unit
  Vec3 point = Vec3::Zero();  // on the axis
  double radius = 0.0;
};

// A cone: the apex, the unit axis from the apex into the cone, and the half angle between axis and rulings.
struct ConeSurface {
  Vec3 apex = Vec3::Zero();
  Vec3 axis = Vec3::UnitZ();
  double half_angle = 0.0;  // rad, in (0, pi/2)
};

// Distance of p from the cylinder's surface (not from its axis), always >= 0.
double distanceToCylinder(const CylinderSurface& cylinder, const Vec3& p);

// Distance of p from the cone's surface (its nappe on the axis side), always >= 0.
double distanceToCone(const ConeSurface& cone, const Vec3& p);

// The point nearest to all the lines (least squares), each given by a point and a unit direction: where the rulings
// of a cone meet. False when the lines are (nearly) parallel.
bool nearestPointToLines(const std::vector<Vec3>& points, const std::vector<Vec3>& directions, Vec3& nearest);

// The direction least aligned with the given normals: the eigenvector of sum w n n^T with the smallest eigenvalue.
// For the facets of a tessellated cylinder every normal is perpendicular to the axis, so this is the axis.
Vec3 leastAlignedDirection(const std::vector<Vec3>& normals, const std::vector<double>& weights);

// Circle through 2D points: algebraic (Kasa) fit. False when the points are (nearly) collinear or too few.
bool fitCircle(const std::vector<Eigen::Vector2d>& points, Eigen::Vector2d& centre, double& radius);

// Cylinder through points around a given axis direction: a circle fit of the points projected onto the plane
// perpendicular to the axis. Cheap; false when no circle fits.
bool fitCylinderAroundAxis(const std::vector<Vec3>& points, const Vec3& axis, CylinderSurface& cylinder);

// Cylinder through points, starting from an axis direction: a circle fit of the points projected onto the plane
// perpendicular to the axis, then Gauss-Newton on axis, position and radius together (geometric distances), so a
// rough axis (say from triangles whose normals are not exactly radial) still ends on the true surface.
// False when no circle fits (too few points, or collinear in projection).
bool fitCylinder(const std::vector<Vec3>& points, const Vec3& axis_guess, CylinderSurface& cylinder);

// Cone through points from a starting cone: damped Gauss-Newton on apex, axis and half angle (geometric distances).
// False when it does not converge to a proper cone (half angle outside (0, pi/2)).
bool fitCone(const std::vector<Vec3>& points, const ConeSurface& guess, ConeSurface& cone);

}  // namespace art2part
