// The order to visit points in with the least travel between them, near enough: an open path (no return to the
// start) by nearest neighbour from the first point, then 2-opt (reverse the stretch between two edges wherever that
// shortens the path) until no reversal shortens it by more than a micrometre. Quadratic per 2-opt sweep: for the
// hundreds of points a drilling run has, not for a mesh's vertices.
// Why not the optimum: an open travelling-salesman path is NP-hard; 2-opt removes every crossing (two crossing edges
// are always longer than the pair that uncrosses them), which is what a machinist sees as a wasteful order.
#pragma once

#include <vector>

#include "art2part/geometry/mesh.h"

namespace art2part {

// Indices into `points` in visiting order, `points[0]` first; straight-line distances in the plane square to `axis`
// (the travel of a tool that moves across at one height along it). Empty for no points.
std::vector<int> travelOrder(const std::vector<Vec3>& points, const Vec3& axis);

}  // namespace art2part
