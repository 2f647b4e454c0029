// Slicing a part perpendicular to a setup direction (thesis 4.1.1): triangle/plane intersections chained into closed
// contours through the triangle adjacency, nested into outer contours and islands. The machinable contours of a
// slice are the stock's section minus the part's (machinableRegion).
#pragma once

#include <vector>

#include "art2part/geometry/adjacency.h"
#include "art2part/geometry/mesh.h"
#include "art2part/roughing/region.h"

namespace art2part {

struct SliceContour {
  Ring points;          // mm in the slice frame (x, y); closed, last point not repeated
  bool closed = true;   // false when the chain ran into a boundary or non-manifold edge (open mesh)
  int parent = -1;      // the contour directly enclosing this one, -1 for none
  int depth = 0;        // nesting depth: even = outer boundary of material, odd = a hole in it
  double area_mm2 = 0;  // signed: material on the left (CCW outer > 0, hole < 0)
};

struct Slice {
  double z = 0;
  std::vector<SliceContour> contours;
  int open_chains = 0;
};

// The section of `mesh` by the plane {p : (p - origin).z_axis = z}, expressed in the frame (x_axis, y_axis) (a
// right-handed orthonormal frame, so outer contours come out counter-clockwise). Robust to vertices exactly on the
// plane: they are treated as lying a hair above it, consistently for every triangle, so every crossing edge is cut
// once and contours close on a closed mesh. In effect the plane lies a hair below z: at the height of an upward flat
// face the section is the material just under it, at the height of a downward flat face it no longer includes it.
// Contours are chained through `adjacency` (built on `mesh`); across non-manifold edges by matching the crossed edge,
// and a chain that runs into a boundary edge (an open mesh) is kept as an open polyline (closed = false, counted in
// open_chains). Nesting (parent, depth) is over the closed contours; open ones stay at depth 0 with no parent.
// O(triangles) per call; nothing is cached across calls.
Slice sliceMesh(const Mesh& mesh, const Adjacency& adjacency, const Eigen::Vector3d& origin,
                const Eigen::Vector3d& x_axis, const Eigen::Vector3d& y_axis, const Eigen::Vector3d& z_axis,
                double z);

// The material of a slice as a region: the closed contours with their orientation kept, filled by the non-zero rule
// (outer contours minus their holes, plus islands in holes); open chains are skipped. The machinable region of a
// slice is the stock's section minus the part's.
Region sliceRegion(const Slice& slice);
Region machinableRegion(const Region& stock_section, const Slice& part_slice);

}  // namespace art2part
