// Triangle adjacency across edges, built once and shared by slicing, side visibility and finishing.
#pragma once

#include <array>
#include <vector>

#include "art2part/geometry/mesh.h"

namespace art2part {

// How the surface bends across an edge. Convex: the outward normals turn away from each other (an outside corner);
// concave: an inside corner. Smooth: the dihedral is below the sharp angle.
enum class EdgeClass { Smooth, Convex, Concave, Boundary, NonManifold };

const char* edgeClassName(EdgeClass c);

// Edge e of triangle t runs from corner e to corner (e + 1) % 3.
struct Adjacency {
  static constexpr int kBoundary = -1;
  static constexpr int kNonManifold = -2;

  // neighbour[t][e]: the one triangle across edge e, or kBoundary / kNonManifold.
  std::vector<std::array<int, 3>> neighbour;
  // dihedral[t][e]: angle in radians between the two outward normals across edge e (0 = flat), signed: positive when
  // the edge is convex, negative when concave; 0 for boundary and non-manifold edges.
  std::vector<std::array<double, 3>> dihedral;
  // klass[t][e]: the class of edge e of t with the sharp angle given at build time.
  std::vector<std::array<EdgeClass, 3>> klass;

  int boundary_edges = 0;      // edges with a single triangle
  int nonmanifold_edges = 0;   // edges with three or more triangles, or two with the same winding
  int edges = 0;               // distinct undirected edges
  double sharp_angle = 0.0;    // radians

  bool closed() const { return boundary_edges == 0; }
  bool manifold() const { return nonmanifold_edges == 0; }
};

// Builds the adjacency on shared vertex indices (merge duplicate vertices first). An edge shared by two triangles
// with opposite winding is manifold; two triangles with the same winding across an edge count as non-manifold here
// (orient the mesh first to fix that).
Adjacency buildAdjacency(const Mesh& mesh, double sharp_angle_rad = 30.0 * 3.14159265358979323846 / 180.0);

// Connected components over manifold edges: component id per triangle, and the count.
std::vector<int> connectedComponents(const Adjacency& adjacency, int* count = nullptr);

}  // namespace art2part
