#include "art2part/geometry/adjacency.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>

namespace art2part {

const char* edgeClassName(EdgeClass c) {
  switch (c) {
    case EdgeClass::Smooth: return "smooth";
    case EdgeClass::Convex: return "convex";
    case EdgeClass::Concave: return "concave";
    case EdgeClass::Boundary: return "boundary";
    case EdgeClass::NonManifold: return "non-manifold";
  }
  return "?";
}

namespace {

std::uint64_t edgeKey(int a, int b) {
  if (a > b) std::swap(a, b);
  return (static_cast<std::uint64_t>(a) << 32) | static_cast<std::uint32_t>(b);
}

// The half-edges (triangle, edge) of every undirected edge.
struct HalfEdge {
  int triangle;
  int edge;
};

std::unordered_map<std::uint64_t, std::vector<HalfEdge>> collectEdges(const Mesh& mesh) {
  std::unordered_map<std::uint64_t, std::vector<HalfEdge>> edges;
  edges.reserve(mesh.triangles.size() * 2);
  for (int t = 0; t < mesh.triangleCount(); ++t)
    for (int e = 0; e < 3; ++e)
      edges[edgeKey(mesh.triangles[t][e], mesh.triangles[t][(e + 1) % 3])].push_back({t, e});
  return edges;
}

// Signed angle between the outward normals of t and u across their shared edge a->b (a->b as seen in t):
// positive when the edge is convex.
double signedDihedral(const Mesh& mesh, int t, int u, int a, int b) {
  const Vec3 nt = triangleNormal(mesh, t), nu = triangleNormal(mesh, u);
  const Vec3 edge = (mesh.vertices[b] - mesh.vertices[a]).normalized();
  const double angle = std::atan2(nt.cross(nu).dot(edge), nt.dot(nu));
  return angle;  // for outward normals turning away across a convex edge, nt x nu points along a->b
}

}  // namespace

Adjacency buildAdjacency(const Mesh& mesh, double sharp_angle_rad) {
  Adjacency adj;
  const int n = mesh.triangleCount();
  adj.sharp_angle = sharp_angle_rad;
  adj.neighbour.assign(n, {Adjacency::kBoundary, Adjacency::kBoundary, Adjacency::kBoundary});
  adj.dihedral.assign(n, {0.0, 0.0, 0.0});
  adj.klass.assign(n, {EdgeClass::Boundary, EdgeClass::Boundary, EdgeClass::Boundary});

  const auto edges = collectEdges(mesh);
  adj.edges = static_cast<int>(edges.size());
  for (const auto& entry : edges) {
    const std::vector<HalfEdge>& halves = entry.second;
    if (halves.size() == 1) {
      ++adj.boundary_edges;
      continue;
    }
    const HalfEdge& h0 = halves[0];
    bool manifold = halves.size() == 2;
    if (manifold) {
      // Opposite winding: the second triangle runs the edge the other way.
      const HalfEdge& h1 = halves[1];
      manifold = mesh.triangles[h0.triangle][h0.edge] == mesh.triangles[h1.triangle][(h1.edge + 1) % 3];
    }
    if (!manifold) {
      ++adj.nonmanifold_edges;
      for (const HalfEdge& h : halves) {
        adj.neighbour[h.triangle][h.edge] = Adjacency::kNonManifold;
        adj.klass[h.triangle][h.edge] = EdgeClass::NonManifold;
      }
      continue;
    }
    const HalfEdge& h1 = halves[1];
    const int a = mesh.triangles[h0.triangle][h0.edge], b = mesh.triangles[h0.triangle][(h0.edge + 1) % 3];
    const double angle = signedDihedral(mesh, h0.triangle, h1.triangle, a, b);
    EdgeClass c = EdgeClass::Smooth;
    if (std::abs(angle) >= sharp_angle_rad) c = angle > 0 ? EdgeClass::Convex : EdgeClass::Concave;
    for (int k = 0; k < 2; ++k) {
      const HalfEdge& h = halves[k];
      adj.neighbour[h.triangle][h.edge] = halves[1 - k].triangle;
      adj.dihedral[h.triangle][h.edge] = angle;  // symmetric: the same edge seen from either side
      adj.klass[h.triangle][h.edge] = c;
    }
  }
  return adj;
}

std::vector<int> connectedComponents(const Adjacency& adjacency, int* count) {
  const int n = static_cast<int>(adjacency.neighbour.size());
  std::vector<int> component(n, -1);
  std::vector<int> stack;
  int next = 0;
  for (int seed = 0; seed < n; ++seed) {
    if (component[seed] >= 0) continue;
    component[seed] = next;
    stack.push_back(seed);
    while (!stack.empty()) {
      const int t = stack.back();
      stack.pop_back();
      for (int u : adjacency.neighbour[t])
        if (u >= 0 && component[u] < 0) {
          component[u] = next;
          stack.push_back(u);
        }
    }
    ++next;
  }
  if (count) *count = next;
  return component;
}

}  // namespace art2part
