// The stock model: tri-dexel, in the part frame.
//
// Why tri-dexel and not voxels: a span end is an exact coordinate along its ray, so a flat floor or a wall along a
// family's axis is exact rather than rounded to a cell, volumes converge with the square of the resolution instead of
// its cube's worth of cells (a 100 mm part at 0.2 mm is 0.75 M rays, against 125 M voxels), and cutting a ray is one
// interval subtraction. Three families (rather than one height field) keep walls, undercuts and 5-axis cuts as
// accurate as floors, and let gouge and thickness measures take the best-aligned ray.
#pragma once

#include <array>
#include <vector>

#include "art2part/geometry/mesh.h"
#include "art2part/simulation/dexel.h"
#include "art2part/simulation/mesh_dexels.h"

namespace art2part {

struct Stock {
  DexelLattice lattice;
  std::array<std::vector<SpanList>, 3> dexels;  // by family, by ray index: the material left

  SpanList& ray(int axis, int index) { return dexels[axis][index]; }
  const SpanList& ray(int axis, int index) const { return dexels[axis][index]; }
  double volume() const;  // mean over the three families, mm^3
};

// A block filling the lattice's box.
Stock boxStock(const DexelLattice& lattice);
// The material of a closed mesh (raw stock, a casting, a previous stage's result).
Stock meshStock(const MeshDexels& solid);
// Adds a solid's material (the part is always stock: a stock mesh that misses some of it still holds it).
void addSolid(Stock& stock, const MeshDexels& solid);

// The part's box grown by `margin` on every side (the default stock).
Box stockBox(const Box& part_box, double margin);

}  // namespace art2part
