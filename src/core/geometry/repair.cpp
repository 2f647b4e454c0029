#include "art2part/geometry/repair.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <sstream>
#include <unordered_map>

#include "art2part/geometry/adjacency.h"

namespace art2part {

namespace {

std::string formatNote(const char* what, int count) {
  std::ostringstream out;
  out << what << ": " << count;
  return out.str();
}

// Hash of a grid cell of vertex positions.
struct CellHash {
  std::size_t operator()(const Eigen::Vector3i& c) const {
    return (static_cast<std::size_t>(c.x()) * 73856093u) ^ (static_cast<std::size_t>(c.y()) * 19349663u) ^
           (static_cast<std::size_t>(c.z()) * 83492791u);
  }
};
struct CellEqual {
  bool operator()(const Eigen::Vector3i& a, const Eigen::Vector3i& b) const { return a == b; }
};

// Maps every vertex to the first earlier vertex within `tolerance` (or bitwise equal when tolerance is 0).
std::vector<int> findVertexRepresentatives(const std::vector<Vec3>& vertices, double tolerance) {
  std::vector<int> representative(vertices.size());
  if (tolerance <= 0.0) {
    std::unordered_map<std::string, int> seen;
    seen.reserve(vertices.size());
    for (std::size_t i = 0; i < vertices.size(); ++i) {
      std::string key(reinterpret_cast<const char*>(vertices[i].data()), 3 * sizeof(double));
      representative[i] = seen.emplace(key, static_cast<int>(i)).first->second;
    }
    return representative;
  }
  std::unordered_map<Eigen::Vector3i, std::vector<int>, CellHash, CellEqual> grid;
  grid.reserve(vertices.size());
  const double tol2 = tolerance * tolerance;
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    const Eigen::Vector3i cell = (vertices[i] / tolerance).array().floor().cast<int>();
    int found = -1;
    for (int dx = -1; dx <= 1 && found < 0; ++dx)
      for (int dy = -1; dy <= 1 && found < 0; ++dy)
        for (int dz = -1; dz <= 1 && found < 0; ++dz) {
          auto it = grid.find(cell + Eigen::Vector3i(dx, dy, dz));
          if (it == grid.end()) continue;
          for (int j : it->second)
            if ((vertices[j] - vertices[i]).squaredNorm() <= tol2) {
              found = j;
              break;
            }
        }
    if (found < 0) {
      found = static_cast<int>(i);
      grid[cell].push_back(found);
    }
    representative[i] = found;
  }
  return representative;
}

// Merges vertices and drops vertices no triangle uses; returns how many vertices went.
int mergeVertices(Mesh& mesh, double tolerance) {
  const std::vector<int> rep = findVertexRepresentatives(mesh.vertices, tolerance);
  std::vector<char> used(mesh.vertices.size(), 0);
  for (Triangle& tri : mesh.triangles)
    for (int& v : tri) used[v = rep[v]] = 1;
  std::vector<int> new_index(mesh.vertices.size(), -1);
  std::vector<Vec3> kept;
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i)
    if (used[i]) {
      new_index[i] = static_cast<int>(kept.size());
      kept.push_back(mesh.vertices[i]);
    }
  for (Triangle& tri : mesh.triangles)
    for (int& v : tri) v = new_index[v];
  const int removed = static_cast<int>(mesh.vertices.size() - kept.size());
  mesh.vertices.swap(kept);
  return removed;
}

std::uint64_t sortedTriangleKey(const Triangle& tri, std::size_t vertex_count) {
  std::array<std::uint64_t, 3> v = {static_cast<std::uint64_t>(tri[0]), static_cast<std::uint64_t>(tri[1]),
                                    static_cast<std::uint64_t>(tri[2])};
  std::sort(v.begin(), v.end());
  const std::uint64_t n = vertex_count + 1;
  return (v[0] * n + v[1]) * n + v[2];
}

// The corner of a sliver that lies on its longest edge, and that edge's ends, in the sliver's winding order:
// the sliver runs from -> middle -> to (and back along its long edge to -> from).
struct Sliver {
  int from, middle, to;
};

bool findSliver(const Mesh& mesh, const Triangle& tri, double max_height, Sliver& out) {
  int longest = 0;
  double longest_length = -1.0;
  for (int e = 0; e < 3; ++e) {
    const double l = (mesh.vertices[tri[(e + 1) % 3]] - mesh.vertices[tri[e]]).norm();
    if (l > longest_length) longest_length = l, longest = e;
  }
  const Vec3& a = mesh.vertices[tri[0]];
  const double twice_area = (mesh.vertices[tri[1]] - a).cross(mesh.vertices[tri[2]] - a).norm();
  if (longest_length <= 0.0 || twice_area / longest_length > max_height) return false;
  // The long edge runs tri[longest] -> tri[longest + 1]; the middle corner is the third.
  out = {tri[(longest + 1) % 3], tri[(longest + 2) % 3], tri[longest]};
  return true;
}

std::uint64_t directedKey(int a, int b) { return (static_cast<std::uint64_t>(a) << 32) | static_cast<std::uint32_t>(b); }

// Removes slivers (a corner on the opposite edge, as CAD meshers leave at seams) without opening the mesh: the
// neighbour across the long edge is split at the middle corner, and the sliver dropped. Triangles with a repeated
// corner are dropped. Each input triangle becomes zero, one or two output triangles, in input order.
std::vector<std::vector<Triangle>> absorbSlivers(const Mesh& mesh, double max_height, RepairReport& report) {
  const int n = mesh.triangleCount();
  std::vector<std::vector<Triangle>> pieces(n);
  std::unordered_map<std::uint64_t, std::pair<int, int>> owner;  // directed edge -> (input triangle, piece)
  owner.reserve(3 * n);
  auto addPiece = [&](int t, const Triangle& tri) {
    pieces[t].push_back(tri);
    for (int e = 0; e < 3; ++e)
      owner[directedKey(tri[e], tri[(e + 1) % 3])] = {t, static_cast<int>(pieces[t].size()) - 1};
  };
  for (int t = 0; t < n; ++t) {
    const Triangle& tri = mesh.triangles[t];
    if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2]) {
      ++report.dropped_degenerate;
      continue;
    }
    addPiece(t, tri);
  }
  for (int t = 0; t < n; ++t) {
    if (pieces[t].size() != 1) continue;
    Sliver s;
    if (!findSliver(mesh, pieces[t][0], max_height, s)) continue;
    auto drop = [&]() {
      for (int e = 0; e < 3; ++e) owner.erase(directedKey(pieces[t][0][e], pieces[t][0][(e + 1) % 3]));
      pieces[t].clear();
      ++report.dropped_degenerate;
    };
    // Nothing on the other side of its short edges: the sliver fills no gap, dropping it opens nothing.
    if (!owner.count(directedKey(s.middle, s.from)) && !owner.count(directedKey(s.to, s.middle))) {
      drop();
      continue;
    }
    // The neighbour runs the long edge the other way round than the sliver: from -> to.
    auto it = owner.find(directedKey(s.from, s.to));
    if (it == owner.end() || it->second.first == t) continue;  // open edge: keep the sliver rather than a hole
    const int u = it->second.first, piece = it->second.second;
    Triangle nb = pieces[u][piece];
    while (nb[0] != s.from) std::rotate(nb.begin(), nb.begin() + 1, nb.end());
    const int apex = nb[2];
    if (apex == s.middle) continue;  // the neighbour is the sliver's mirror image; leave both
    drop();
    // The halves take over the sliver's short edges, so its neighbours there find a partner.
    pieces[u][piece] = {s.from, s.middle, apex};
    owner[directedKey(s.from, s.middle)] = {u, piece};
    owner[directedKey(s.middle, apex)] = {u, piece};
    owner[directedKey(apex, s.from)] = {u, piece};
    addPiece(u, {s.middle, s.to, apex});
    ++report.split_neighbours;
  }
  return pieces;
}

// Removes slivers and degenerate triangles, then exact duplicates (same corners), keeping input order;
// `kept` maps output to input index.
void dropBadTriangles(Mesh& mesh, double max_sliver_height, std::vector<int>& kept, RepairReport& report) {
  const auto pieces = absorbSlivers(mesh, max_sliver_height, report);
  std::vector<Triangle> out;
  std::vector<int> out_kept;
  std::unordered_map<std::uint64_t, int> seen;
  for (int t = 0; t < mesh.triangleCount(); ++t)
    for (const Triangle& tri : pieces[t]) {
      if (!seen.emplace(sortedTriangleKey(tri, mesh.vertices.size()), t).second) {
        ++report.dropped_duplicate;
        continue;
      }
      out.push_back(tri);
      out_kept.push_back(kept[t]);
    }
  mesh.triangles.swap(out);
  kept.swap(out_kept);
}

}  // namespace

void validateMesh(const Mesh& mesh, const std::string& where) {
  if (mesh.triangles.empty()) throw InputError(where + ": no triangles");
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i)
    if (!mesh.vertices[i].allFinite()) {
      std::ostringstream out;
      out << where << ": vertex " << i << " has a coordinate that is not a finite number (" << mesh.vertices[i].x()
          << ", " << mesh.vertices[i].y() << ", " << mesh.vertices[i].z() << ")";
      throw InputError(out.str());
    }
  const int n = static_cast<int>(mesh.vertices.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    for (int v : mesh.triangles[t])
      if (v < 0 || v >= n)
        throw InputError(where + ": triangle " + std::to_string(t) + " refers to vertex " + std::to_string(v) +
                         " of " + std::to_string(n));
}

RepairReport repairMesh(Mesh& mesh, std::vector<int>* kept_out, const RepairOptions& options) {
  RepairReport report;
  const double diagonal = boundingBox(mesh).diagonal();
  const double merge_tol = options.merge_tolerance < 0 ? 1e-6 * diagonal : options.merge_tolerance;
  const double sliver_height = options.sliver_height < 0 ? 1e-8 * diagonal : options.sliver_height;

  const int vertices_before = static_cast<int>(mesh.vertices.size());
  report.merged_vertices = mergeVertices(mesh, merge_tol);
  std::vector<int> kept(mesh.triangles.size());
  for (std::size_t i = 0; i < kept.size(); ++i) kept[i] = static_cast<int>(i);
  dropBadTriangles(mesh, sliver_height, kept, report);
  if (report.dropped_degenerate || report.dropped_duplicate) mergeVertices(mesh, 0.0);  // drop orphans
  if (options.orient) report.flipped = orientConsistently(mesh);

  if (report.merged_vertices)
    report.notes.push_back(formatNote("merged duplicate vertices", report.merged_vertices) + " of " +
                           std::to_string(vertices_before));
  if (report.dropped_degenerate)
    report.notes.push_back(formatNote("dropped degenerate triangles", report.dropped_degenerate) +
                           (report.split_neighbours ? " (" + std::to_string(report.split_neighbours) +
                                                          " slivers among them, their neighbours split to stay closed)"
                                                    : std::string()));
  if (report.dropped_duplicate)
    report.notes.push_back(formatNote("dropped duplicate triangles", report.dropped_duplicate));
  if (report.flipped) report.notes.push_back(formatNote("flipped triangles to orient outward", report.flipped));
  if (kept_out) kept_out->swap(kept);
  return report;
}

MeshCheck checkMesh(const Mesh& mesh) {
  MeshCheck check;
  const Adjacency adj = buildAdjacency(mesh);
  check.triangles = mesh.triangleCount();
  check.vertices = static_cast<int>(mesh.vertices.size());
  check.boundary_edges = adj.boundary_edges;
  check.nonmanifold_edges = adj.nonmanifold_edges;
  connectedComponents(adj, &check.components);
  check.closed = adj.closed() && adj.manifold();
  check.manifold = adj.manifold();
  check.volume = signedVolume(mesh);
  check.area = surfaceArea(mesh);
  check.box = boundingBox(mesh);
  return check;
}

}  // namespace art2part
