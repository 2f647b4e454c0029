// A visibility result handed from one process to another in the file contract's layout (docs/contracts.md:
// directions.csv's directions, visibility.bits' rows, the special flags), as analyse_visibility's result carries it,
// rebuilt on the part for the planners: the sphere's cells from the directions (sampleSphere of the level whose cells
// they are), the special flags given or found by matching the part's special directions, the bit matrix, the
// triangles no direction sees.
#pragma once

#include <cstdint>
#include <vector>

#include "art2part/geometry/part.h"
#include "art2part/visibility/analysis.h"

namespace art2part {

// Throws InputError for no directions, a direction that is not a unit vector, bits of another size than the part's
// triangles x ceil(D / 8) (a result of another part or level), special flags not one per direction. Empty `special`:
// found on the part. Directions are kept as given (to the bit) when they are unit to rounding.
VisibilityResult visibilityFromBits(const Part& part, const std::vector<Vec3>& directions,
                                    const std::vector<std::uint8_t>& bits, const std::vector<std::uint8_t>& special);

}  // namespace art2part
