// Sideways visibility (thesis 3.2.4, Algorithm 2): a face parallel to a direction is not seen from it, yet an end
// mill's flank cuts it from there. If a neighbouring direction sees such a face, it is visible from the direction
// sideways too.
#pragma once

#include "art2part/geometry/mesh.h"
#include "art2part/sphere/direction_set.h"
#include "art2part/visibility/visibility_map.h"

namespace art2part {

// For every direction o and triangle t not visible along o: when t is parallel to o (|n . o| <= sin r_o, where r_o is
// the angle from o to the farthest corner of its cell, so o's cell holds a direction exactly in the face's plane) and
// some neighbour o' of o sees t in the direct analysis, t becomes visible along o. Only the neighbours' direct
// visibility counts (no propagation), as in the thesis. Returns how many (triangle, direction) pairs were added.
long long sideCorrection(VisibilityMap& map, const Mesh& mesh, const DirectionSet& directions);

// The angular radius of each direction's cell: the largest angle between the direction and a corner of its cell.
std::vector<double> cellRadii(const DirectionSet& directions);

}  // namespace art2part
