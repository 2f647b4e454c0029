// Sampling the Gaussian sphere (thesis 3.2.2, Algorithm 1): a tetrahedron or an icosahedron whose spherical
// triangles are split into four, level times, by edge midpoints pushed out to the unit sphere.
//
// Two layout choices make the rest cheap and exact:
//  - corners are shared between cells (a midpoint map per edge), so neighbours are found by corner index, never by
//    comparing coordinates;
//  - the four children of cell i of one level are cells 4i .. 4i+3 of the next (child j < 3 keeps corner j of its
//    parent, child 3 is the middle one), so the final cell array still encodes the whole hierarchy and
//    cellContaining can descend it without storing anything more.
#include "art2part/sphere/direction_set.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <unordered_map>

namespace art2part {
namespace {

constexpr int kMaxLevel = 10;  // 4 * 4^10 = 4M cells; beyond that an int index and memory both run out

using Cell = std::array<int, 3>;

struct Tessellation {
  std::vector<Vec3> corners;
  std::vector<Cell> cells;
};

uint64_t edgeKey(int a, int b) {
  const auto lo = static_cast<uint64_t>(std::min(a, b)), hi = static_cast<uint64_t>(std::max(a, b));
  return (hi << 32) | lo;
}

// Flips the cells that are clockwise seen from outside: det(a, b, c) > 0 means counter-clockwise for a triangle
// of a convex polyhedron around the origin.
void orientOutwards(Tessellation& t) {
  for (Cell& c : t.cells)
    if (t.corners[c[0]].cross(t.corners[c[1]]).dot(t.corners[c[2]]) < 0) std::swap(c[1], c[2]);
}

Tessellation tetrahedron() {
  Tessellation t;
  for (const Vec3& v : {Vec3(1, 1, 1), Vec3(1, -1, -1), Vec3(-1, 1, -1), Vec3(-1, -1, 1)})
    t.corners.push_back(v.normalized());
  t.cells = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
  orientOutwards(t);
  return t;
}

// The 12 corners (0, +-1, +-phi) and cyclic permutations; the faces are found as the triples of corners at mutual
// distance 2 (the edge length), which is less error-prone than a typed face table.
Tessellation icosahedron() {
  const double phi = 0.5 * (1.0 + std::sqrt(5.0));
  std::vector<Vec3> raw;
  for (double s1 : {-1.0, 1.0})
    for (double s2 : {-1.0, 1.0}) {
      raw.emplace_back(0, s1, s2 * phi);
      raw.emplace_back(s1, s2 * phi, 0);
      raw.emplace_back(s2 * phi, 0, s1);
    }
  auto isEdge = [&](int i, int j) { return std::abs((raw[i] - raw[j]).squaredNorm() - 4.0) < 1e-9; };
  Tessellation t;
  for (const Vec3& v : raw) t.corners.push_back(v.normalized());
  const int n = static_cast<int>(raw.size());
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j)
      for (int k = j + 1; k < n; ++k)
        if (isEdge(i, j) && isEdge(j, k) && isEdge(i, k)) t.cells.push_back({i, j, k});
  orientOutwards(t);
  return t;
}

// One step of Algorithm 1. Children of cell i go to 4i .. 4i+3 in the order (a, ab, ca), (ab, b, bc), (ca, bc, c),
// (ab, bc, ca): all counter-clockwise like their parent, and child j keeps the parent's corner j.
void subdivide(Tessellation& t) {
  std::unordered_map<uint64_t, int> midpoint;
  midpoint.reserve(t.cells.size() * 3 / 2 + 1);
  auto mid = [&](int a, int b) {
    auto [it, added] = midpoint.try_emplace(edgeKey(a, b), static_cast<int>(t.corners.size()));
    if (added) t.corners.push_back((t.corners[a] + t.corners[b]).normalized());
    return it->second;
  };
  std::vector<Cell> next;
  next.reserve(t.cells.size() * 4);
  for (const Cell& c : t.cells) {
    const int ab = mid(c[0], c[1]), bc = mid(c[1], c[2]), ca = mid(c[2], c[0]);
    next.push_back({c[0], ab, ca});
    next.push_back({ab, c[1], bc});
    next.push_back({ca, bc, c[2]});
    next.push_back({ab, bc, ca});
  }
  t.cells = std::move(next);
}

// Solid angle of the spherical triangle (a, b, c) by Van Oosterom and Strackee (1983): tan(omega / 2) =
// det(a, b, c) / (1 + a.b + b.c + c.a). atan2 keeps it accurate for the tiny cells of high levels.
double sphericalTriangleArea(const Vec3& a, const Vec3& b, const Vec3& c) {
  const double det = a.cross(b).dot(c);
  return 2.0 * std::atan2(det, 1.0 + a.dot(b) + b.dot(c) + c.dot(a));
}

// Smallest of the three edge-plane tests of d against the counter-clockwise triangle (a, b, c): >= 0 when d is
// inside. Each edge is tested as a x b in its own order, so the two cells of an edge get exactly opposite values
// (IEEE products commute and fl(x - y) = -fl(y - x)): a direction on an edge is inside at least one of them.
double insideness(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  return std::min({a.cross(b).dot(d), b.cross(c).dot(d), c.cross(a).dot(d)});
}

double insideness(const DirectionSet& set, int cell, const Vec3& d) {
  const Cell& c = set.cells[cell];
  return insideness(set.corners[c[0]], set.corners[c[1]], set.corners[c[2]], d);
}

// The cells around each corner, as one flat array (CSR): offsets[k] .. offsets[k + 1] index into cells.
struct CornerCells {
  std::vector<int> offsets, cells;
  const int* begin(int k) const { return cells.data() + offsets[k]; }
  const int* end(int k) const { return cells.data() + offsets[k + 1]; }
};

CornerCells cellsAroundCorners(const DirectionSet& set) {
  CornerCells out;
  out.offsets.assign(set.corners.size() + 1, 0);
  for (const Cell& c : set.cells)
    for (int k : c) ++out.offsets[k + 1];
  for (size_t k = 1; k < out.offsets.size(); ++k) out.offsets[k] += out.offsets[k - 1];
  out.cells.resize(set.cells.size() * 3);
  std::vector<int> fill(out.offsets.begin(), out.offsets.end() - 1);
  for (int c = 0; c < set.cellCount(); ++c)
    for (int k : set.cells[c]) out.cells[fill[k]++] = c;
  return out;
}

bool hasCorner(const Cell& c, int k) { return c[0] == k || c[1] == k || c[2] == k; }

// Corners are shared, so the cell across edge (a, b) is the other cell around a that also has b; the vertex
// neighbours are the remaining cells around the three corners. A corner has at most 6 cells (5 or 3 at the base
// corners), so this is a few comparisons per cell and needs no hash map.
void buildNeighbours(DirectionSet& set) {
  const CornerCells around = cellsAroundCorners(set);
  set.edge_neighbours.assign(set.cells.size(), {});
  set.vertex_neighbours.assign(set.cells.size(), {});
  for (int c = 0; c < set.cellCount(); ++c) {
    const Cell& cell = set.cells[c];
    std::vector<int>& edge = set.edge_neighbours[c];
    std::vector<int>& vertex = set.vertex_neighbours[c];
    edge.reserve(3);
    for (int e = 0; e < 3; ++e) {
      const int a = cell[e], b = cell[(e + 1) % 3];
      for (const int* x = around.begin(a); x != around.end(a); ++x)
        if (*x != c && hasCorner(set.cells[*x], b)) edge.push_back(*x);
    }
    if (edge.size() != 3) throw std::logic_error("sampleSphere: a cell without three edge neighbours");
    for (int k : cell)
      for (const int* x = around.begin(k); x != around.end(k); ++x)
        if (*x != c && std::find(edge.begin(), edge.end(), *x) == edge.end()) vertex.push_back(*x);
    std::sort(vertex.begin(), vertex.end());
    vertex.erase(std::unique(vertex.begin(), vertex.end()), vertex.end());
  }
}

// How many base cells the set was built from, or 0 when its cell array is not the layout of sampleSphere.
int baseCellCount(const DirectionSet& set) {
  if (set.level < 0 || set.level > kMaxLevel) return 0;
  const long long per_base = 1LL << (2 * set.level);
  for (int base : {4, 20})
    if (base * per_base == set.cellCount()) return base;
  return 0;
}

// Corner j of cell k of hierarchy level l is corner j of the finest cell reached by always taking child j, whose
// index is k * 4^m + j * (4^(m-1) + ... + 1) with m = level - l.
const Vec3& hierarchyCorner(const DirectionSet& set, int l, long long k, int j) {
  const long long span = 1LL << (2 * (set.level - l));
  return set.corners[set.cells[k * span + j * (span - 1) / 3][j]];
}

double hierarchyInsideness(const DirectionSet& set, int l, long long k, const Vec3& d) {
  return insideness(hierarchyCorner(set, l, k, 0), hierarchyCorner(set, l, k, 1), hierarchyCorner(set, l, k, 2), d);
}

// Best child at each level (largest insideness, so a direction lost to rounding on a coarse edge still goes to the
// nearer side). The result contains d or touches the cell that does.
int descend(const DirectionSet& set, int base_count, const Vec3& d) {
  long long best = 0;
  double best_value = -HUGE_VAL;
  for (int k = 0; k < base_count; ++k) {
    const double v = hierarchyInsideness(set, 0, k, d);
    if (v > best_value) best_value = v, best = k;
  }
  for (int l = 1; l <= set.level; ++l) {
    const long long parent = best;
    best_value = -HUGE_VAL;
    for (int j = 0; j < 4; ++j) {
      const double v = hierarchyInsideness(set, l, 4 * parent + j, d);
      if (v > best_value) best_value = v, best = 4 * parent + j;
    }
  }
  return static_cast<int>(best);
}

int bruteForceCell(const DirectionSet& set, const Vec3& d) {
  int best = -1;
  double best_value = -HUGE_VAL;
  for (int c = 0; c < set.cellCount(); ++c) {
    const double v = insideness(set, c, d);
    if (v > best_value) best_value = v, best = c;
  }
  return best;
}

}  // namespace

std::vector<int> DirectionSet::neighbours(int d) const {
  const int own = cell_of.at(d);
  std::vector<int> touching{own};
  touching.insert(touching.end(), edge_neighbours[own].begin(), edge_neighbours[own].end());
  touching.insert(touching.end(), vertex_neighbours[own].begin(), vertex_neighbours[own].end());
  // The first cellCount() directions are the cells' own representatives; later ones are extra special directions.
  std::vector<int> out;
  for (int c : touching)
    if (c != d) out.push_back(c);
  for (int i = cellCount(); i < size(); ++i)
    if (i != d && std::find(touching.begin(), touching.end(), cell_of[i]) != touching.end()) out.push_back(i);
  std::sort(out.begin(), out.end());
  return out;
}

DirectionSet sampleSphere(int level, SphereBase base) {
  if (level < 0 || level > kMaxLevel)
    throw std::invalid_argument("sampleSphere: level " + std::to_string(level) + " is outside 0.." +
                                std::to_string(kMaxLevel));
  Tessellation t = base == SphereBase::Tetrahedron ? tetrahedron() : icosahedron();
  for (int i = 0; i < level; ++i) subdivide(t);

  DirectionSet set;
  set.level = level;
  set.corners = std::move(t.corners);
  set.cells = std::move(t.cells);
  const int n = set.cellCount();
  set.cell_area.resize(n);
  set.directions.resize(n);
  set.cell_of.resize(n);
  set.special.assign(n, 0);
  for (int c = 0; c < n; ++c) {
    const Vec3 &a = set.corners[set.cells[c][0]], &b = set.corners[set.cells[c][1]], &cc = set.corners[set.cells[c][2]];
    set.cell_area[c] = sphericalTriangleArea(a, b, cc);
    set.directions[c] = (a + b + cc).normalized();
    set.cell_of[c] = c;
  }
  buildNeighbours(set);
  return set;
}

int cellContaining(const DirectionSet& set, const Vec3& d) {
  if (set.cells.empty()) throw std::invalid_argument("cellContaining: empty direction set");
  const int base_count = baseCellCount(set);
  if (base_count == 0) return bruteForceCell(set, d);  // not the layout of sampleSphere: no hierarchy to descend
  const int guess = descend(set, base_count, d);
  if (insideness(set, guess, d) >= 0) return guess;
  // Rounding on a coarse edge can land one cell off: the true cell touches the guess. On a fine edge the exact
  // antisymmetry of the edge test makes one side non-negative; exactly on a corner the best is within rounding.
  int best = guess;
  double best_value = insideness(set, guess, d);
  for (const auto* list : {&set.edge_neighbours[guess], &set.vertex_neighbours[guess]})
    for (int c : *list) {
      const double v = insideness(set, c, d);
      if (v > best_value) best_value = v, best = c;
    }
  return best;
}

double cellAreaRatio(const DirectionSet& set) {
  if (set.cell_area.empty()) return 0.0;
  const auto [lo, hi] = std::minmax_element(set.cell_area.begin(), set.cell_area.end());
  return *hi / *lo;
}

}  // namespace art2part
