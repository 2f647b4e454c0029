// The solid a machinist makes of an open mesh. A relief, a scanned or sculpted surface, a skin a repair could not close
// bounds no solid: a planner would cut on both sides of it and a simulation could not tell part from stock. Its closure
// here is the solid between the surface and a floor square to the side it is open towards: the mesh S, its boundary
// swept along the direction d down to the floor (the skirt) and S projected onto the floor, reversed (the cap). By the
// prism formula, boundary(prism S) = cap - S - skirt up to signs, so S + skirt + cap is a closed 2-chain whatever S is
// (non-manifold, in many pieces, holed): every edge is used as often forwards as backwards, and the winding number
// of the sum is an integer everywhere. For a closed mesh the cap's pieces cancel and the solid is the mesh's own.
// The cap's triangles overlap (each triangle of S gives one): right for what winds and projects (shadows, dexels,
// sections), not a tessellation to show or to analyse for visibility.
#pragma once

#include <vector>

#include "art2part/geometry/mesh.h"
#include "art2part/geometry/part.h"

namespace art2part {

struct SolidClosure {
  Mesh mesh;                    // the mesh's triangles first (same indices), then skirt, then cap
  int boundary_edges = 0;       // edges of the mesh's boundary chain (used more often one way than the other)
  int skirt_triangles = 0, cap_triangles = 0;
  Vec3 direction = -Vec3::UnitZ();  // towards the floor: the axis nearest to minus the mesh's vector area
  double floor = 0;             // the floor plane: {p : p . direction = floor}, through the farthest vertex
  bool closed() const { return boundary_edges == 0; }
};

// Edges (undirected) whose uses by triangles do not cancel: the mesh's algebraic boundary. Zero for a closed mesh,
// also a non-manifold one whose sheets pair up.
int boundaryChainEdges(const Mesh& mesh);

// The closure above; the mesh unchanged when its boundary chain is empty.
SolidClosure closeOpenMesh(const Mesh& mesh);

// The part as a solid for roughing and simulation: the part itself when its mesh is closed, else with the mesh
// closed (added triangles in face -1, adjacency and check rebuilt). `closure`, if given, says what was added.
Part machiningSolid(const Part& part, SolidClosure* closure = nullptr);

}  // namespace art2part
