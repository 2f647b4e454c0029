// Cone thinning (thesis 4.1.3.1): the access direction of a voxel is the "centre" of its visibility cone in the
// sense of a skeleton on the triangulated Gaussian sphere, not its centre of mass (which may lie outside the cone).
// Thinning peels the region's boundary one layer at a time and stops just before the region would vanish: what
// remains, the last layer, is the skeleton. Restricted thinning (machine limits) peels the primary cone the same way
// but stops just before the region's intersection with a secondary cone (the machine's reach) vanishes.
//
// Layers are measured as angles, not as steps through the cells' neighbour graph: on the tetrahedron's sphere the
// cells differ in area by 6.5x (level 4; neighbour spacing 2.3 to 9.9 degrees), and graph peeling of a 40-degree cap
// ends up to 28 degrees (13 on average) off its axis. A direction's depth is its angle to the nearest sampled
// direction outside the cone, and the last layer is the directions within one cell width (sqrt(4 pi / cells), 6.3
// degrees at level 4) of the deepest: isotropic peeling, with the layers aligned on the deepest direction.
//
// Cones are bitsets over the set's directions (cones.h); bits at or beyond set.size() are ignored. None of these
// functions keeps state: they are safe to call from several threads.
#pragma once

#include "art2part/sphere/direction_set.h"
#include "art2part/visibility/cones.h"

namespace art2part {

// The skeleton of `cone`, a subset of it: empty only when the cone is. A cone with no boundary (every direction) has
// nothing to peel and is its own skeleton.
Cone thinCone(const DirectionSet& set, const Cone& cone);

// Peels `primary` (depths within the primary) and keeps the last layer of its intersection with `secondary`: the
// directions of primary and secondary within a cell width of the deepest such direction. Empty when they do not
// meet; the whole intersection when the primary is every direction.
Cone restrictedThinning(const DirectionSet& set, const Cone& primary, const Cone& secondary);

// Directions within max_tilt_deg of `axis` (any length but zero): the reach of a machine tilting that far around a
// setup direction. Throws std::invalid_argument for a zero axis.
Cone reachCone(const DirectionSet& set, const Vec3& axis, double max_tilt_deg);

// One access direction: of the skeleton (restricted to `reach` when given), the direction nearest the skeleton's
// mean direction (weighted by depth), so a ring- or crescent-shaped skeleton still gives one of its own directions,
// never one outside the cone. -1 when the cone (and reach) is empty. Note that restricted thinning goes as deep into the cone as the reach
// allows: a cone open almost everywhere but on one side tilts the axis to the far edge of the reach.
int accessDirection(const DirectionSet& set, const Cone& cone, const Cone* reach = nullptr);

// Solid angle (steradians) of the directions two cones share, counted by cells like coneSolidAngle (voxel-to-voxel
// transitions, 4.1.4).
double intersectionSolidAngle(const DirectionSet& set, const Cone& a, const Cone& b);

}  // namespace art2part
