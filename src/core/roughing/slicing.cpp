// Slicing (thesis 4.1.1). Every triangle that straddles the plane is cut along a segment from the crossing of its
// "down" edge (a corner above the plane to one below, in the triangle's counter-clockwise order) to the crossing of
// its "up" edge. With outward triangles this puts the material on the left of the segment seen from +z, and the up
// edge of one triangle is the down edge of the triangle across it, so contours are chained through the adjacency.
#include "art2part/roughing/slicing.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>

namespace art2part {

namespace {

// A corner is above the plane when its signed height is >= 0: a vertex on the plane counts as a hair above it, the
// same for every triangle, so a straddling triangle always has exactly two crossing edges.
constexpr std::uint8_t kVisited = 8;  // triangle state: bits 0-2 = corners above, bit 3 = already in a contour

int next(int corner) { return corner == 2 ? 0 : corner + 1; }

// The down edge (above -> below) of a triangle whose corners above are `mask` (not 0 and not 7).
int downEdge(int mask) {
  for (int e = 0; e < 3; ++e)
    if ((mask >> e & 1) && !(mask >> next(e) & 1)) return e;
  return 0;  // not reached: asked only of straddling triangles (mask 1..6), which have one of each
}

// The up edge (below -> above).
int upEdge(int mask) {
  for (int e = 0; e < 3; ++e)
    if (!(mask >> e & 1) && (mask >> next(e) & 1)) return e;
  return 0;  // not reached, as above
}

std::uint64_t directedEdgeKey(int from, int to) {
  return static_cast<std::uint64_t>(static_cast<std::uint32_t>(from)) << 32 | static_cast<std::uint32_t>(to);
}

// Cuts a mesh by one plane into chains of crossing points.
class Slicer {
 public:
  Slicer(const Mesh& mesh, const Adjacency& adjacency, const Eigen::Vector3d& origin, const Eigen::Vector3d& x_axis,
         const Eigen::Vector3d& y_axis, const Eigen::Vector3d& z_axis, double z)
      : mesh_(mesh), adjacency_(adjacency), origin_(origin), x_axis_(x_axis), y_axis_(y_axis) {
    height_.resize(mesh.vertices.size());
    for (std::size_t v = 0; v < mesh.vertices.size(); ++v) height_[v] = (mesh.vertices[v] - origin).dot(z_axis) - z;
    classifyTriangles();
  }

  void traceContours(Slice& slice) {
    for (int t : straddling_) {
      if (state_[t] & kVisited) continue;
      SliceContour contour = traceChain(t);
      if (!contour.closed) ++slice.open_chains;
      if (contour.points.size() >= (contour.closed ? 3u : 2u)) slice.contours.push_back(std::move(contour));
    }
  }

 private:
  int mask(int t) const { return state_[t] & 7; }
  bool straddles(int t) const { return mask(t) != 0; }
  bool visited(int t) const { return state_[t] & kVisited; }
  int vertex(int t, int corner) const { return mesh_.triangles[t][corner]; }

  void classifyTriangles() {
    state_.assign(mesh_.triangles.size(), 0);
    for (int t = 0; t < mesh_.triangleCount(); ++t) {
      int above = 0;
      for (int k = 0; k < 3; ++k) above |= (height_[vertex(t, k)] >= 0) << k;
      if (above == 0 || above == 7) continue;
      state_[t] = static_cast<std::uint8_t>(above);
      straddling_.push_back(t);
      for (int e : {downEdge(above), upEdge(above)})
        if (adjacency_.neighbour[t][e] == Adjacency::kNonManifold)
          nonmanifold_uses_.emplace_back(directedEdgeKey(vertex(t, e), vertex(t, next(e))), t);
    }
    std::sort(nonmanifold_uses_.begin(), nonmanifold_uses_.end());
  }

  // Where edge a-b crosses the plane, in the slice frame. The edge is taken from its lower vertex index to the
  // higher, so the two triangles sharing it get the same bits; a vertex on the plane is returned exactly.
  Point2 crossingPoint(int a, int b) const {
    if (a > b) std::swap(a, b);
    const double sa = height_[a], sb = height_[b];
    Vec3 p;
    if (sa == 0) {
      p = mesh_.vertices[a];
    } else if (sb == 0) {
      p = mesh_.vertices[b];
    } else {
      const double t = sa / (sa - sb);
      p = mesh_.vertices[a] + t * (mesh_.vertices[b] - mesh_.vertices[a]);
    }
    const Vec3 d = p - origin_;
    return Point2(d.dot(x_axis_), d.dot(y_axis_));
  }

  Point2 entryPoint(int t) const {
    const int e = downEdge(mask(t));
    return crossingPoint(vertex(t, e), vertex(t, next(e)));
  }

  Point2 exitPoint(int t) const {
    const int e = upEdge(mask(t));
    return crossingPoint(vertex(t, e), vertex(t, next(e)));
  }

  // The triangle across edge e of t that crosses the plane on the same edge, run the other way (so its role, down or
  // up, is the opposite of the edge's role in t), or -1. Prefers `closing` (the start of the chain) among the
  // candidates of a non-manifold edge, then any triangle not yet in a contour.
  int across(int t, int e, int closing) const {
    const int from = vertex(t, e), to = vertex(t, next(e));
    const int n = adjacency_.neighbour[t][e];
    if (n >= 0) return straddles(n) && sharesEdgeReversed(n, from, to) ? n : -1;
    if (n != Adjacency::kNonManifold) return -1;
    const auto key = directedEdgeKey(to, from);
    auto it = std::lower_bound(nonmanifold_uses_.begin(), nonmanifold_uses_.end(), std::make_pair(key, -1));
    int found = -1;
    for (; it != nonmanifold_uses_.end() && it->first == key; ++it) {
      if (it->second == closing) return closing;
      if (found < 0 && !visited(it->second)) found = it->second;
    }
    return found;
  }

  bool sharesEdgeReversed(int n, int from, int to) const {
    for (int k = 0; k < 3; ++k)
      if (vertex(n, k) == to && vertex(n, next(k)) == from) return true;
    return false;
  }

  int successor(int t, int start) const { return across(t, upEdge(mask(t)), start); }
  int predecessor(int t) const { return across(t, downEdge(mask(t)), -1); }

  // Follows the chain through `start` forwards until it closes; if it runs into an edge with no usable neighbour,
  // also backwards, and marks it open.
  SliceContour traceChain(int start) {
    SliceContour contour;
    Ring& points = contour.points;
    state_[start] |= kVisited;
    points.push_back(entryPoint(start));
    int t = start;
    for (;;) {
      const int n = successor(t, start);
      if (n == start) break;
      if (n < 0 || visited(n)) {
        contour.closed = false;
        points.push_back(exitPoint(t));
        break;
      }
      state_[n] |= kVisited;
      points.push_back(entryPoint(n));
      t = n;
    }
    if (!contour.closed) prependBackwards(start, points);
    dropRepeatedPoints(points, contour.closed);
    return contour;
  }

  void prependBackwards(int start, Ring& points) {
    Ring before;
    for (int t = predecessor(start); t >= 0 && !visited(t); t = predecessor(t)) {
      state_[t] |= kVisited;
      before.push_back(entryPoint(t));
    }
    if (before.empty()) return;
    std::reverse(before.begin(), before.end());
    points.insert(points.begin(), before.begin(), before.end());
  }

  // Consecutive equal points come from vertices on the plane (every triangle around one ends there).
  static void dropRepeatedPoints(Ring& points, bool closed) {
    points.erase(std::unique(points.begin(), points.end()), points.end());
    while (closed && points.size() > 1 && points.back() == points.front()) points.pop_back();
  }

  const Mesh& mesh_;
  const Adjacency& adjacency_;
  const Vec3 origin_, x_axis_, y_axis_;
  std::vector<double> height_;        // signed height of each vertex above the plane
  std::vector<std::uint8_t> state_;   // per triangle: corners above, visited
  std::vector<int> straddling_;       // triangles with corners on both sides
  std::vector<std::pair<std::uint64_t, int>> nonmanifold_uses_;  // (directed crossing edge, triangle), sorted
};

double signedArea(const Ring& ring) {
  if (ring.size() < 3) return 0;
  double twice = 0;
  const Point2& o = ring.front();
  for (std::size_t i = 1; i + 1 < ring.size(); ++i) {
    const Point2 a = ring[i] - o, b = ring[i + 1] - o;
    twice += a.x() * b.y() - a.y() * b.x();
  }
  return 0.5 * twice;
}

struct Bounds {
  Point2 min, max;
  bool contains(const Bounds& b) const {
    return min.x() <= b.min.x() && min.y() <= b.min.y() && max.x() >= b.max.x() && max.y() >= b.max.y();
  }
};

Bounds ringBounds(const Ring& ring) {
  Bounds b{ring.front(), ring.front()};
  for (const Point2& p : ring) {
    b.min = b.min.cwiseMin(p);
    b.max = b.max.cwiseMax(p);
  }
  return b;
}

enum class Side { Inside, Outside, OnBoundary };

bool onSegment(const Point2& p, const Point2& a, const Point2& b) {
  const Point2 ab = b - a, ap = p - a;
  if (ab.x() * ap.y() - ab.y() * ap.x() != 0) return false;
  return ap.dot(ab) >= 0 && ap.dot(ab) <= ab.squaredNorm();
}

// Crossing-number test of p against a closed ring.
Side sideOf(const Point2& p, const Ring& ring) {
  bool inside = false;
  for (std::size_t i = 0, j = ring.size() - 1; i < ring.size(); j = i++) {
    const Point2& a = ring[j];
    const Point2& b = ring[i];
    if (onSegment(p, a, b)) return Side::OnBoundary;
    if ((a.y() > p.y()) != (b.y() > p.y()) && p.x() < a.x() + (p.y() - a.y()) * (b.x() - a.x()) / (b.y() - a.y()))
      inside = !inside;
  }
  return inside ? Side::Inside : Side::Outside;
}

// Contours of a closed mesh do not cross, so the first vertex of `inner` off the boundary of `outer` decides.
bool encloses(const Ring& outer, const Ring& inner) {
  for (const Point2& p : inner) {
    const Side side = sideOf(p, outer);
    if (side != Side::OnBoundary) return side == Side::Inside;
  }
  return false;
}

// Parent = the smallest closed contour enclosing it; depth from the parents. Open chains stay at the top.
void nestContours(std::vector<SliceContour>& contours) {
  std::vector<int> order;
  std::vector<Bounds> bounds(contours.size());
  for (std::size_t i = 0; i < contours.size(); ++i) {
    contours[i].area_mm2 = signedArea(contours[i].points);
    if (!contours[i].closed) continue;
    bounds[i] = ringBounds(contours[i].points);
    order.push_back(static_cast<int>(i));
  }
  // Largest first: every possible parent of a contour comes before it.
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return std::abs(contours[a].area_mm2) > std::abs(contours[b].area_mm2); });
  for (std::size_t k = 0; k < order.size(); ++k) {
    SliceContour& child = contours[order[k]];
    for (std::size_t j = k; j-- > 0;) {
      const SliceContour& candidate = contours[order[j]];
      if (!bounds[order[j]].contains(bounds[order[k]]) || !encloses(candidate.points, child.points)) continue;
      child.parent = order[j];
      child.depth = candidate.depth + 1;
      break;
    }
  }
}

}  // namespace

Slice sliceMesh(const Mesh& mesh, const Adjacency& adjacency, const Eigen::Vector3d& origin,
                const Eigen::Vector3d& x_axis, const Eigen::Vector3d& y_axis, const Eigen::Vector3d& z_axis,
                double z) {
  Slice slice;
  slice.z = z;
  Slicer slicer(mesh, adjacency, origin, x_axis, y_axis, z_axis, z);
  slicer.traceContours(slice);
  nestContours(slice.contours);
  return slice;
}

Region sliceRegion(const Slice& slice) {
  // Rings keep their orientation (outer counter-clockwise, holes clockwise): the non-zero winding rule then fills
  // outer contours minus their holes, plus islands inside holes.
  Region rings;
  for (const SliceContour& contour : slice.contours) {
    if (!contour.closed || contour.points.size() < 3) continue;
    ClipperLib::Path path;
    path.reserve(contour.points.size());
    for (const Point2& p : contour.points) path.push_back(toRegionPoint(p));
    rings.push_back(std::move(path));
  }
  ClipperLib::Clipper clipper;
  clipper.AddPaths(rings, ClipperLib::ptSubject, true);
  Region out;
  clipper.Execute(ClipperLib::ctUnion, out, ClipperLib::pftNonZero, ClipperLib::pftNonZero);
  return out;
}

Region machinableRegion(const Region& stock_section, const Slice& part_slice) {
  return subtract(stock_section, sliceRegion(part_slice));
}

}  // namespace art2part
