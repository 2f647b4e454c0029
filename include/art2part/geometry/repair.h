// Validation and safe repair of a triangle mesh. Triangle order is kept: triangles only ever get dropped, never moved.
#pragma once

#include <string>
#include <vector>

#include "art2part/geometry/mesh.h"

namespace art2part {

struct RepairOptions {
  // Vertices closer than this are merged (mm). 0 = exact duplicates only (the default: safe, since a CAD export
  // writes a shared corner with the same bits each time; merging near vertices can collapse small triangles);
  // negative = 1e-6 of the box diagonal.
  double merge_tolerance = 0.0;
  // A triangle whose height over its longest edge is below this (mm) is a sliver: its middle corner lies on the
  // long edge. Negative = 1e-8 of the box diagonal. Slivers are removed by splitting the neighbour across the long
  // edge at the middle corner (the mesh stays closed); triangles with a repeated corner are dropped.
  double sliver_height = -1.0;
  bool orient = true;  // make winding consistent across edges and outward per closed component
};

struct RepairReport {
  int merged_vertices = 0;      // vertices removed as duplicates
  int dropped_degenerate = 0;   // triangles removed (zero area or repeated corner)
  int dropped_duplicate = 0;    // triangles removed as exact duplicates of an earlier one
  int split_neighbours = 0;     // triangles split in two to absorb a sliver (both halves keep the input index)
  int flipped = 0;              // triangles whose winding was reversed
  std::vector<std::string> notes;  // one line per repair, for the user
  bool any() const { return merged_vertices || dropped_degenerate || dropped_duplicate || split_neighbours || flipped; }
};

struct MeshCheck {
  int triangles = 0;
  int vertices = 0;
  int boundary_edges = 0;
  int nonmanifold_edges = 0;
  int components = 0;
  bool closed = false;
  bool manifold = false;
  double volume = 0.0;  // mm^3 (meaningful when closed)
  double area = 0.0;    // mm^2
  Box box;
};

// Rejects what cannot be repaired: an empty mesh, NaN or infinite coordinates, indices out of range. Throws InputError.
void validateMesh(const Mesh& mesh, const std::string& where);

// Repairs in place. kept[i] is the input index of output triangle i: input order is preserved, and the two halves of
// a triangle split to absorb a sliver both carry its index.
RepairReport repairMesh(Mesh& mesh, std::vector<int>* kept = nullptr, const RepairOptions& options = {});

MeshCheck checkMesh(const Mesh& mesh);

// Whether p lies inside the closed set of triangles `tris` (or the whole closed mesh): the parity of a ray's crossings.
bool insideTriangles(const Mesh& mesh, const std::vector<int>& tris, const Vec3& p);
bool insideClosedMesh(const Mesh& mesh, const Vec3& p);

// Orients triangles consistently across manifold edges, and each closed component outwards (positive volume).
// Returns how many triangles were flipped.
int orientConsistently(Mesh& mesh);

}  // namespace art2part
