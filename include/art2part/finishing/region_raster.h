// Roughing's regions (region.h) on a regular grid of nodes, grown there: what a clearance map needs of the stock a
// tool's shank and holder must keep clear of. Growing the regions in Clipper instead (an offset per slab and radius)
// costs in the regions' rings, and the stock roughing leaves has thousands of them (17,465 rings over mount_rush's
// slabs, 11 % of its whole plan in those offsets); on the grid the cost is the nodes times the disc's rows, whatever
// the rings.
#pragma once

#include <vector>

#include "art2part/roughing/region.h"

namespace art2part {

// A regular x-y grid: node (i, j) at (x0 + i pitch, y0 + j pitch), numbered j nx + i.
struct NodeGrid {
  double x0 = 0, y0 = 0, pitch = 1;
  int nx = 0, ny = 0;
  double x(int i) const { return x0 + i * pitch; }
  double y(int j) const { return y0 + j * pitch; }
  int node(int i, int j) const { return j * nx + i; }
  std::size_t size() const { return static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny); }
  int nearestI(double x) const;  // clamped into the grid
  int nearestJ(double y) const;
  int nearest(double x, double y) const { return node(nearestI(x), nearestJ(y)); }
};

// Material that may reach `height` anywhere in `region` (mm; a slab of stock and its top).
struct RegionAtHeight {
  const Region* region = nullptr;
  double height = 0;
};

// Per radius of `radii`, a height per node of `grid`: the highest of the levels whose region comes near the node,
// -inf where none does. Near: every level whose region comes within the radius of a node counts at that node, and no
// level whose region stays farther than the radius + q sqrt 2 does, q the grid's pitch divided by the least whole
// number that brings it to `cell` or under (the regions are taken as the cells, q square, that they touch, and a node
// counts every cell whose square lies within the radius of it: a sliding maximum along the rows of cells, one per row
// the radius spans; the cost grows as the radius over q times the grid's nodes times the grid's pitch over q).
// Regions may reach past the grid. Throws InputError for a pitch or cell that is not positive, or a negative radius.
std::vector<std::vector<double>> highestNear(const NodeGrid& grid, const std::vector<RegionAtHeight>& levels,
                                             const std::vector<double>& radii, double cell);

}  // namespace art2part
