// Discrete visibility cones (thesis 3.2.3): the set of sampled directions along which a triangle or a face is
// visible, and its solid angle on the Gaussian sphere.
#pragma once

#include <cstdint>
#include <vector>

#include "art2part/sphere/direction_set.h"
#include "art2part/visibility/visibility_map.h"

namespace art2part {

// A cone as a bitset over directions (the row layout of BitMatrix).
using Cone = std::vector<std::uint64_t>;

Cone triangleCone(const VisibilityMap& map, int t);
// Directions along which every triangle of the set is visible (the face can be finished from there in one go) ...
Cone commonCone(const VisibilityMap& map, const std::vector<int>& triangles);
// ... and along which at least one is.
Cone unionCone(const VisibilityMap& map, const std::vector<int>& triangles);

int coneSize(const Cone& cone);
bool coneHas(const Cone& cone, int d);
// Solid angle in steradians: the area of the cells with at least one visible direction.
double coneSolidAngle(const Cone& cone, const DirectionSet& directions);

// Per triangle: the solid angle of its cone (for colouring and reports).
std::vector<double> coneSolidAngles(const VisibilityMap& map, const DirectionSet& directions);
// Triangles visible along no direction at all.
std::vector<int> invisibleTriangles(const VisibilityMap& map);
// Per direction: how many triangles it sees.
std::vector<int> trianglesSeenPerDirection(const VisibilityMap& map);

}  // namespace art2part
