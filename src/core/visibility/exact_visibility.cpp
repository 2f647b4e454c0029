// The visibility oracle of exact_visibility.h: per pair, t's projection minus the projections of what lies in front
// of t's plane, by Clipper (Debian's libpolyclipping, as roughing uses it) in integer units fitted to t.
#include "art2part/visibility/exact_visibility.h"

#include <polyclipping/clipper.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <utility>

namespace art2part {

namespace {

using ClipperLib::cInt;
using ClipperLib::IntPoint;
using ClipperLib::Path;
using ClipperLib::Paths;

// Integer units across the larger side of t's projected box: coordinates of the clipped occluders stay within
// Clipper's fast range (2^30).
constexpr double kUnits = 268435456.0;  // 2^28

// Heights off t's plane at or below this fraction of the mesh's size count as on the plane: a coplanar neighbour is
// not in front of t.
constexpr double kPlaneTolerance = 1e-12;

// A point of the view plane with its height in front of t's plane.
struct Lifted {
  double x, y, h;
};
using Polygon = std::vector<Lifted>;

struct ViewFrame {
  Vec3 right, up;  // right x up = d: front-facing triangles project counter-clockwise
};

ViewFrame frameAlong(const Vec3& d) {
  Eigen::Index least = 0;
  d.cwiseAbs().minCoeff(&least);
  const Vec3 right = Vec3::Unit(least).cross(d).normalized();
  return {right, d.cross(right)};
}

// Keeps the part of the polygon with h > 0 (Sutherland-Hodgman against t's plane).
Polygon inFront(const Polygon& in) {
  Polygon out;
  for (std::size_t i = 0; i < in.size(); ++i) {
    const Lifted& p = in[i];
    const Lifted& q = in[(i + 1) % in.size()];
    if (p.h > 0) out.push_back(p);
    if ((p.h > 0) != (q.h > 0) && p.h != q.h) {
      const double s = p.h / (p.h - q.h);
      out.push_back({p.x + s * (q.x - p.x), p.y + s * (q.y - p.y), 0.0});
    }
  }
  return out;
}

// Keeps the part of the polygon on the side of the line x[axis] = bound given by `below` (one side of a box).
Polygon clipSide(const Polygon& in, int axis, double bound, bool below) {
  Polygon out;
  auto coordinate = [axis](const Lifted& p) { return axis == 0 ? p.x : p.y; };
  auto inside = [&](const Lifted& p) { return below ? coordinate(p) <= bound : coordinate(p) >= bound; };
  for (std::size_t i = 0; i < in.size(); ++i) {
    const Lifted& p = in[i];
    const Lifted& q = in[(i + 1) % in.size()];
    if (inside(p)) out.push_back(p);
    if (inside(p) != inside(q)) {
      const double s = (bound - coordinate(p)) / (coordinate(q) - coordinate(p));
      out.push_back({p.x + s * (q.x - p.x), p.y + s * (q.y - p.y), p.h + s * (q.h - p.h)});
    }
  }
  return out;
}

// The pair's setting: t, its plane and projected box, and the integer frame fitted to it.
struct Target {
  int t = -1;
  Vec3 a, n;
  double lo[2], hi[2];  // projected box of t
  double scale = 1;     // integer units per length
  double tolerance = 0; // kPlaneTolerance times the mesh size
};

IntPoint toUnits(const Target& target, double x, double y) {
  return IntPoint(static_cast<cInt>(std::llround((x - target.lo[0]) * target.scale)),
                  static_cast<cInt>(std::llround((y - target.lo[1]) * target.scale)));
}

// The projection of the part of triangle u in front of t's plane, within t's box (slightly enlarged), counter-
// clockwise in integer units; empty when none.
Path occluderPath(const Mesh& mesh, const std::vector<Eigen::Vector2d>& xy, const Target& target, int u) {
  Polygon polygon(3);
  double top = -1;
  for (int k = 0; k < 3; ++k) {
    const int v = mesh.triangles[u][k];
    double h = (mesh.vertices[v] - target.a).dot(target.n);
    if (std::abs(h) <= target.tolerance) h = 0;
    polygon[k] = {xy[v].x(), xy[v].y(), h};
    top = std::max(top, h);
  }
  if (!(top > 0)) return {};
  const double x_lo = std::min({polygon[0].x, polygon[1].x, polygon[2].x});
  const double x_hi = std::max({polygon[0].x, polygon[1].x, polygon[2].x});
  const double y_lo = std::min({polygon[0].y, polygon[1].y, polygon[2].y});
  const double y_hi = std::max({polygon[0].y, polygon[1].y, polygon[2].y});
  if (x_hi < target.lo[0] || x_lo > target.hi[0] || y_hi < target.lo[1] || y_lo > target.hi[1]) return {};
  polygon = inFront(polygon);
  const double margin = 0.01 * std::max(target.hi[0] - target.lo[0], target.hi[1] - target.lo[1]);
  for (int axis = 0; axis < 2 && polygon.size() >= 3; ++axis) {
    polygon = clipSide(polygon, axis, target.lo[axis] - margin, false);
    if (polygon.size() >= 3) polygon = clipSide(polygon, axis, target.hi[axis] + margin, true);
  }
  if (polygon.size() < 3) return {};
  Path path;
  for (const Lifted& p : polygon) path.push_back(toUnits(target, p.x, p.y));
  if (!ClipperLib::Orientation(path)) ClipperLib::ReversePath(path);
  return path;
}

// The point of t whose projection is (x, y).
Vec3 pointOfTriangle(const Mesh& mesh, int t, const std::vector<Eigen::Vector2d>& xy, const Eigen::Vector2d& p) {
  const Eigen::Vector2d a = xy[mesh.triangles[t][0]], b = xy[mesh.triangles[t][1]], c = xy[mesh.triangles[t][2]];
  const double area = (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
  const double wb = ((p - a).x() * (c - a).y() - (p - a).y() * (c - a).x()) / area;
  const double wc = ((b - a).x() * (p - a).y() - (b - a).y() * (p - a).x()) / area;
  return (1 - wb - wc) * mesh.corner(t, 0) + wb * mesh.corner(t, 1) + wc * mesh.corner(t, 2);
}

std::vector<Eigen::Vector2d> projectVertices(const Mesh& mesh, const Vec3& d) {
  const ViewFrame frame = frameAlong(d);
  std::vector<Eigen::Vector2d> xy;
  xy.reserve(mesh.vertices.size());
  for (const Vec3& v : mesh.vertices) xy.emplace_back(v.dot(frame.right), v.dot(frame.up));
  return xy;
}

double planeTolerance(const Mesh& mesh) { return kPlaneTolerance * std::max(boundingBox(mesh).diagonal(), 1e-300); }

// One direction's view of the mesh: every vertex projected, and a uniform grid over the view plane listing the
// triangles whose projected box meets each cell, so that a pair clips only against triangles whose shadow can reach
// it (a few dozen on a real part instead of all of them).
class ExactView {
 public:
  ExactView(const Mesh& mesh, const std::vector<Vec3>& normals, const Vec3& d, double tolerance)
      : mesh_(mesh), normals_(normals), d_(d), tolerance_(tolerance), xy_(projectVertices(mesh, d)),
        stamp_(mesh.triangleCount(), -1) {
    const int count = mesh.triangleCount();
    for (int t = 0; t < count; ++t) {
      if (normals_[t].isZero()) continue;  // degenerate: hides nothing
      for (int v : mesh.triangles[t]) lo_ = lo_.cwiseMin(xy_[v]), hi_ = hi_.cwiseMax(xy_[v]);
    }
    // About one cell per triangle: a cell then holds a few triangles where the surface is one layer deep.
    const Eigen::Vector2d size = (hi_ - lo_).cwiseMax(1e-300);
    const double cell = std::sqrt(size.x() * size.y() / std::max(count, 1));
    for (int k = 0; k < 2; ++k) cells_[k] = std::clamp(static_cast<int>(size[k] / std::max(cell, 1e-300)), 1, 4096);
    std::vector<int> counts(std::size_t(cells_[0]) * cells_[1] + 1, 0);
    forEachTriangleCell([&](int, std::size_t c) { ++counts[c + 1]; });
    for (std::size_t c = 1; c < counts.size(); ++c) counts[c] += counts[c - 1];
    first_ = counts;
    members_.resize(counts.back());
    forEachTriangleCell([&](int t, std::size_t c) { members_[counts[c]++] = t; });
  }

  ExactPair pair(int t) {
    ExactPair result;
    Target target;
    target.t = t;
    target.n = normals_[t];
    target.a = mesh_.corner(t, 0);
    target.tolerance = tolerance_;
    if (!(target.n.dot(d_) > 0)) return result;
    for (int axis = 0; axis < 2; ++axis) {
      target.lo[axis] = std::min({xy_[mesh_.triangles[t][0]][axis], xy_[mesh_.triangles[t][1]][axis],
                                  xy_[mesh_.triangles[t][2]][axis]});
      target.hi[axis] = std::max({xy_[mesh_.triangles[t][0]][axis], xy_[mesh_.triangles[t][1]][axis],
                                  xy_[mesh_.triangles[t][2]][axis]});
    }
    const double extent = std::max(target.hi[0] - target.lo[0], target.hi[1] - target.lo[1]);
    if (!(extent > 0)) return result;
    target.scale = kUnits / extent;
    Path subject;
    for (int v : mesh_.triangles[t]) subject.push_back(toUnits(target, xy_[v].x(), xy_[v].y()));
    const double full = ClipperLib::Area(subject);
    if (!(full > 0)) return result;

    ++query_;
    stamp_[t] = query_;
    Paths occluders;
    int cell_lo[2], cell_hi[2];
    for (int k = 0; k < 2; ++k) cell_lo[k] = cellOf(target.lo[k], k), cell_hi[k] = cellOf(target.hi[k], k);
    for (int cy = cell_lo[1]; cy <= cell_hi[1]; ++cy)
      for (int cx = cell_lo[0]; cx <= cell_hi[0]; ++cx) {
        const std::size_t c = std::size_t(cy) * cells_[0] + cx;
        for (int m = first_[c]; m < first_[c + 1]; ++m) {
          const int u = members_[m];
          if (stamp_[u] == query_) continue;
          stamp_[u] = query_;
          Path path = occluderPath(mesh_, xy_, target, u);
          if (!path.empty()) occluders.push_back(std::move(path));
        }
      }
    ClipperLib::Clipper clipper;
    clipper.AddPath(subject, ClipperLib::ptSubject, true);
    clipper.AddPaths(occluders, ClipperLib::ptClip, true);
    Paths visible;
    clipper.Execute(ClipperLib::ctDifference, visible, ClipperLib::pftNonZero, ClipperLib::pftNonZero);
    double area = 0, largest = 0;
    const Path* biggest = nullptr;
    for (const Path& path : visible) {
      const double a = ClipperLib::Area(path);
      area += a;
      if (a > largest) largest = a, biggest = &path;
    }
    result.uncovered = std::max(area, 0.0) / full;
    result.visible = result.uncovered > kExactMinUncovered;
    if (result.visible && biggest) {
      Eigen::Vector2d mean = Eigen::Vector2d::Zero();
      for (const IntPoint& p : *biggest) mean += Eigen::Vector2d(double(p.X), double(p.Y));
      mean = mean / double(biggest->size()) / target.scale + Eigen::Vector2d(target.lo[0], target.lo[1]);
      result.witness = pointOfTriangle(mesh_, t, xy_, mean);
    }
    return result;
  }

 private:
  int cellOf(double coordinate, int k) const {
    const double f = (coordinate - lo_[k]) / std::max(hi_[k] - lo_[k], 1e-300) * cells_[k];
    return std::clamp(static_cast<int>(std::floor(f)), 0, cells_[k] - 1);
  }

  // Calls visit(t, cell) for every non-degenerate triangle and every cell its projected box meets.
  template <typename Visit>
  void forEachTriangleCell(Visit visit) const {
    for (int t = 0; t < mesh_.triangleCount(); ++t) {
      if (normals_[t].isZero()) continue;
      int lo[2], hi[2];
      for (int k = 0; k < 2; ++k) {
        const double a = xy_[mesh_.triangles[t][0]][k], b = xy_[mesh_.triangles[t][1]][k],
                     c = xy_[mesh_.triangles[t][2]][k];
        lo[k] = cellOf(std::min({a, b, c}), k);
        hi[k] = cellOf(std::max({a, b, c}), k);
      }
      for (int cy = lo[1]; cy <= hi[1]; ++cy)
        for (int cx = lo[0]; cx <= hi[0]; ++cx) visit(t, std::size_t(cy) * cells_[0] + cx);
    }
  }

  const Mesh& mesh_;
  const std::vector<Vec3>& normals_;
  const Vec3 d_;
  const double tolerance_;
  const std::vector<Eigen::Vector2d> xy_;
  Eigen::Vector2d lo_ = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector2d hi_ = -lo_;
  int cells_[2] = {1, 1};
  std::vector<int> first_, members_;  // the triangles of cell c: members_[first_[c] .. first_[c + 1])
  std::vector<int> stamp_;            // the last query that met each triangle, so each is clipped once
  int query_ = 0;
};

std::vector<Vec3> normalsOf(const Mesh& mesh) {
  std::vector<Vec3> normals(mesh.triangleCount());
  for (int t = 0; t < mesh.triangleCount(); ++t) normals[t] = triangleNormal(mesh, t);
  return normals;
}

}  // namespace

ExactPair exactVisibility(const Mesh& mesh, int t, const Vec3& d) {
  if (!(d.norm() > 0)) return {};
  const std::vector<Vec3> normals = normalsOf(mesh);
  ExactView view(mesh, normals, d.normalized(), planeTolerance(mesh));
  return view.pair(t);
}

std::vector<ExactPair> exactVisibility(const Mesh& mesh, const std::vector<Vec3>& directions,
                                       const std::vector<std::pair<int, int>>& pairs) {
  std::vector<ExactPair> out(pairs.size());
  if (mesh.triangles.empty()) return out;
  std::vector<std::vector<std::size_t>> by_direction(directions.size());
  for (std::size_t i = 0; i < pairs.size(); ++i) by_direction.at(pairs[i].second).push_back(i);
  const std::vector<Vec3> normals = normalsOf(mesh);
  const double tolerance = planeTolerance(mesh);
  for (std::size_t d = 0; d < directions.size(); ++d) {
    if (by_direction[d].empty() || !(directions[d].norm() > 0)) continue;
    ExactView view(mesh, normals, directions[d].normalized(), tolerance);
    for (std::size_t i : by_direction[d]) out[i] = view.pair(pairs[i].first);
  }
  return out;
}

VisibilityMap exactVisibility(const Mesh& mesh, const std::vector<Vec3>& directions) {
  VisibilityMap map{BitMatrix(mesh.triangleCount(), static_cast<int>(directions.size()))};
  if (mesh.triangles.empty()) return map;
  const std::vector<Vec3> normals = normalsOf(mesh);
  const double tolerance = planeTolerance(mesh);
  for (int d = 0; d < static_cast<int>(directions.size()); ++d) {
    if (!(directions[d].norm() > 0)) continue;
    ExactView view(mesh, normals, directions[d].normalized(), tolerance);
    for (int t = 0; t < mesh.triangleCount(); ++t)
      if (view.pair(t).visible) map.bits.set(t, d);
  }
  return map;
}

}  // namespace art2part
