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

// Distance of p from the cylinder's surface (not from its axis), always >= 0.
double distanceToCylinder(const CylinderSurface& cylinder, const Vec3& p);

// The direction least aligned with the given normals: the eigenvector of sum w n n^T with the smallest eigenvalue.
// For the facets of a tessellated cylinder every normal is perpendicular to the axis, so this is the axis.
Vec3 leastAlignedDirection(const std::vector<Vec3>& normals, const std::vector<double>& weights);

// Circle through 2D points: algebraic (Kasa) fit. False when the points are (nearly) collinear or too few.
bool fitCircle(const std::vector<Eigen::Vector2d>& points, Eigen::Vector2d& centre, double& radius);

// Cylinder through points, starting from an axis direction: a circle fit of the points projected onto the plane
// perpendicular to the axis, then Gauss-Newton on axis, position and radius together (geometric distances), so a
// rough axis (say from triangles whose normals are not exactly radial) still ends on the true surface.
// False when no circle fits (too few points, or collinear in projection).
bool fitCylinder(const std::vector<Vec3>& points, const Vec3& axis_guess, CylinderSurface& cylinder);

}  // namespace art2part
