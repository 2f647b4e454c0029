// Special directions of a part (thesis 3.2.2): the directions a machinist would pick first.
#pragma once

#include <vector>

#include "art2part/geometry/part.h"
#include "art2part/sphere/direction_set.h"

namespace art2part {

struct SpecialDirectionOptions {
  bool plane_normals = true;      // the outward normal of every plane face
  bool cylinder_axes = true;      // both senses of every cylinder (and cone) axis
  bool linear_edges = true;       // both senses of long straight sharp edges
  double min_edge_fraction = 0.1; // an edge is long when it is at least this fraction of the box diagonal
  double min_face_fraction = 1e-4;// faces smaller than this fraction of the part's area add no direction
  double merge_angle = 0.5 * 3.14159265358979323846 / 180.0;  // directions closer than this are one
};

struct SpecialDirection {
  Vec3 direction;
  double weight = 0.0;  // area of the faces (mm^2) or length of the edges (mm) that asked for it
};

// Deduplicated within merge_angle, heaviest first.
std::vector<SpecialDirection> specialDirections(const Part& part, const SpecialDirectionOptions& options = {});

// Each special direction replaces its cell's centroid as the cell's representative (heaviest first); one that
// falls into a cell already taken is appended as an extra direction of that cell.
void insertSpecialDirections(DirectionSet& set, const std::vector<SpecialDirection>& special);

}  // namespace art2part
