// The remaining stock as a triangle mesh, coloured by its deviation from the part.
//
// Contouring is the dual form of marching cubes (surface nets): occupancy is sampled at lattice points (every `step`-th
// one, so the mesh stays a few hundred cells across whatever the resolution), one vertex per cell the surface passes
// through, placed at the mean of the cell's edge crossings, one quad per crossed edge. The crossings are not
// interpolated but exact: a lattice edge lies on a dexel ray, whose span ends say where the material stops. Dual
// contouring needs no 256-case table and gives half the triangles of marching cubes on the same grid, with flat floors
// and walls flat. The mesh is closed (cells outside the box count as empty) and faces outwards.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "art2part/geometry/mesh.h"
#include "art2part/simulation/mesh_dexels.h"
#include "art2part/simulation/part_distance.h"
#include "art2part/simulation/stock.h"

namespace art2part {

struct StockMesh {
  Mesh mesh;
  std::vector<double> deviation;  // per triangle, mm: + stock left above the part, - a gouge into it
};

// `max_cells`: cells along the longest side of the box (the sampling step is chosen from it).
StockMesh remainingStockMesh(const Stock& stock, const MeshDexels& part, const PartDistance& part_distance,
                             int max_cells = 200);

// Deviation colours: the ramp from 0 (on the part, within the tolerance) to `scale` mm of stock left, red for gouges
// deeper than the tolerance.
std::vector<std::array<unsigned char, 3>> deviationColours(const std::vector<double>& deviation, double scale,
                                                           double tolerance);
// A PNG of the mesh so coloured (OSMesa), with `title` above it and the colour scale (mm) beside it. Throws InputError
// when the file cannot be written.
void writeDeviationPicture(const StockMesh& stock_mesh, double scale, double tolerance, const std::string& path,
                           const std::string& title = "stock left");

}  // namespace art2part
