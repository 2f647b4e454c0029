// The part's material round a hole's axis, in bands: above the mouth (what a tool's flutes, shank and holder must
// clear at full depth) and beyond a through hole's far end (how far a drill's point may break through).
#include <algorithm>
#include <cmath>

#include "art2part/geometry/repair.h"  // insideClosedMesh
#include "hole_internal.h"

namespace art2part::hole_detail {

namespace {

constexpr double kBeyondStep = 0.05;  // mm: the bands of free_beyond (what a drill's point may pass into)
constexpr double kSolidProbe = 0.05;   // mm past a through hole's far end where it must be out of the solid
constexpr double kBandSlack = 1e-3;   // mm: material this close above the mouth (or beyond the far end) is the face the
                                      // hole opens in, not an obstacle

struct Point2 {
  double h, x, y;  // height along the bands' direction, position across it
};

// The part of a convex polygon with h in [lo, hi].
std::vector<Point2> clipSlab(const std::vector<Point2>& polygon, double lo, double hi) {
  std::vector<Point2> out = polygon;
  for (int side = 0; side < 2; ++side) {
    std::vector<Point2> in;
    in.swap(out);
    const size_t n = in.size();
    for (size_t i = 0; i < n; ++i) {
      const Point2& a = in[i];
      const Point2& b = in[(i + 1) % n];
      const double da = side == 0 ? a.h - lo : hi - a.h, db = side == 0 ? b.h - lo : hi - b.h;
      if (da >= 0) out.push_back(a);
      if ((da >= 0) != (db >= 0)) {
        const double f = da / (da - db);
        out.push_back({a.h + f * (b.h - a.h), a.x + f * (b.x - a.x), a.y + f * (b.y - a.y)});
      }
    }
    if (out.empty()) break;
  }
  return out;
}

// Distance from the origin of the projection (x, y) of a convex polygon (0 when it covers the origin).
double distanceToOrigin(const std::vector<Point2>& polygon) {
  const size_t n = polygon.size();
  if (n == 0) return kInfinity;
  double best = kInfinity;
  int positive = 0, negative = 0;
  for (size_t i = 0; i < n; ++i) {
    const Point2& a = polygon[i];
    const Point2& b = polygon[(i + 1) % n];
    const double ex = b.x - a.x, ey = b.y - a.y, length2 = ex * ex + ey * ey;
    const double f = length2 > 0 ? std::clamp(-(a.x * ex + a.y * ey) / length2, 0.0, 1.0) : 0.0;
    best = std::min(best, std::hypot(a.x + f * ex, a.y + f * ey));
    const double cross = ex * (-a.y) - ey * (-a.x);
    if (cross > 0) ++positive;
    if (cross < 0) ++negative;
  }
  if (n >= 3 && (positive == 0 || negative == 0) && positive + negative > 0) return 0.0;  // inside (or on) it
  return best;
}

}  // namespace

void orthonormalPair(const Vec3& axis, Vec3& u, Vec3& v) {
  const Vec3 seed = std::abs(axis.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  u = axis.cross(seed).normalized();
  v = axis.cross(u);
}

std::vector<double> radialBands(const Mesh& mesh, const Vec3& start, const Vec3& dir, double step, int count,
                                double cap, double slack) {
  std::vector<double> bands(std::max(0, count), kInfinity);
  Vec3 u, v;
  orthonormalPair(dir, u, v);
  const double top = count * step;
  for (int t = 0; t < mesh.triangleCount(); ++t) {
    std::vector<Point2> polygon(3);
    double h_min = kInfinity, h_max = -kInfinity, x_min = kInfinity, x_max = -kInfinity, y_min = kInfinity,
           y_max = -kInfinity;
    for (int c = 0; c < 3; ++c) {
      const Vec3 d = mesh.corner(t, c) - start;
      polygon[c] = {d.dot(dir), d.dot(u), d.dot(v)};
      h_min = std::min(h_min, polygon[c].h);
      h_max = std::max(h_max, polygon[c].h);
      x_min = std::min(x_min, polygon[c].x);
      x_max = std::max(x_max, polygon[c].x);
      y_min = std::min(y_min, polygon[c].y);
      y_max = std::max(y_max, polygon[c].y);
    }
    if (h_max <= slack || h_min >= top) continue;
    const double gap_x = std::max({0.0, x_min, -x_max}), gap_y = std::max({0.0, y_min, -y_max});
    if (std::hypot(gap_x, gap_y) > cap) continue;  // the triangle's box is farther than the cap
    const int first = std::max(0, static_cast<int>(std::floor(std::max(h_min, slack) / step)));
    const int last = std::min(count - 1, static_cast<int>(std::floor(h_max / step)));
    for (int k = first; k <= last; ++k) {
      const std::vector<Point2> piece = clipSlab(polygon, std::max(k * step, slack), (k + 1) * step);
      if (piece.empty()) continue;
      const double distance = distanceToOrigin(piece);
      if (distance <= cap) bands[k] = std::min(bands[k], distance);
    }
  }
  return bands;
}

void measureSurroundings(const Part& part, Hole& hole, const HoleOptions& options) {
  hole.clearance_step = options.clearance_step;
  const int count = static_cast<int>(std::ceil(options.clearance_height / options.clearance_step));
  hole.free_radius = radialBands(part.mesh, hole.mouth, hole.axis, options.clearance_step, count,
                                 options.clearance_radius, kBandSlack);
  hole.free_beyond = 0;
  if (hole.bottom != HoleBottom::Through) return;
  const Vec3 far_end = hole.mouth - hole.total_depth * hole.axis;
  const int beyond = static_cast<int>(std::ceil(options.clearance_height / kBeyondStep));
  const std::vector<double> below =
      radialBands(part.mesh, far_end, -hole.axis, kBeyondStep, beyond, 0.5 * hole.diameter, kBandSlack);
  hole.free_beyond = kInfinity;
  for (int k = 0; k < beyond; ++k)
    if (below[k] < 0.5 * hole.diameter) {
      hole.free_beyond = k * kBeyondStep;
      break;
    }
  // The bands see surfaces only: a far end closed by a face that is no surface of the hole (a floor belonging to a
  // larger face, as segmentation can leave it) has solid behind it and no triangle near, so a through hole must also
  // leave the solid just past its far end.
  if (insideClosedMesh(part.mesh, far_end - kSolidProbe * hole.axis)) hole.free_beyond = 0;
}

double holeRadiusAt(const Hole& hole, double depth) {
  double radius = 0;
  for (const HoleSegment& s : hole.segments) {
    if (depth < s.from - 1e-9 || depth > s.to + 1e-9) continue;
    if (s.kind == HoleSegmentKind::Flat) {
      radius = std::max(radius, 0.5 * s.diameter_from);
      continue;
    }
    const double f = s.to > s.from ? std::clamp((depth - s.from) / (s.to - s.from), 0.0, 1.0) : 0.0;
    radius = std::max(radius, 0.5 * (s.diameter_from + f * (s.diameter_to - s.diameter_from)));
  }
  return radius;
}

double pointLength(const Tool& drill) {
  return 0.5 * drill.diameter / std::tan(0.5 * drill.point_angle_deg * kDegree);
}

}  // namespace art2part::hole_detail
