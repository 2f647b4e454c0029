// Directions on the Gaussian sphere (thesis 3.2.2): an even sampling by recursive subdivision of a tetrahedron
// (Algorithm 1) or an icosahedron, the cells' neighbourhood graph, and the special directions of a part.
#pragma once

#include <array>
#include <vector>

#include "art2part/geometry/mesh.h"

namespace art2part {

// A direction d means "seen from d": the eye (or the tool's spindle) lies at +infinity along d, so a face is
// visible along d when its outward normal has a positive component along d and nothing lies in front of it.
// This is also the tool axis convention (tip towards spindle).
struct DirectionSet {
  int level = 0;
  // The Gaussian triangles: corners on the unit sphere, counter-clockwise seen from outside.
  std::vector<Vec3> corners;
  std::vector<std::array<int, 3>> cells;
  std::vector<double> cell_area;  // steradians; they sum to 4 pi

  // The sampled directions (unit). The first cells.size() are one per cell (the cell's centroid projected on the
  // sphere, or the special direction that replaced it); further entries are special directions that fell into a
  // cell that already had one.
  std::vector<Vec3> directions;
  std::vector<int> cell_of;     // cell of each direction
  std::vector<char> special;    // 1 when the direction is a special direction of the part

  // Neighbourhood of each cell: cells sharing an edge (3) and cells sharing only a corner (about 9 on a
  // subdivided sphere; the thesis counts the three nearest, 3.2.2).
  std::vector<std::vector<int>> edge_neighbours;
  std::vector<std::vector<int>> vertex_neighbours;

  int size() const { return static_cast<int>(directions.size()); }
  int cellCount() const { return static_cast<int>(cells.size()); }
  // Directions whose cells touch direction d's cell (edge or vertex), plus the other directions of its own cell.
  std::vector<int> neighbours(int d) const;
};

enum class SphereBase { Tetrahedron, Icosahedron };

// Algorithm 1: level L gives 4 * 4^L cells from a tetrahedron (L = 4: 1024) or 20 * 4^L from an icosahedron.
DirectionSet sampleSphere(int level, SphereBase base = SphereBase::Tetrahedron);

// The cell whose spherical triangle contains the unit direction d.
int cellContaining(const DirectionSet& set, const Vec3& d);

// Largest over smallest cell area: how even the sampling is.
double cellAreaRatio(const DirectionSet& set);

}  // namespace art2part
