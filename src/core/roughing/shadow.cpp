#include "art2part/roughing/shadow.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <functional>
#include <numeric>
#include <stdexcept>
#include <utility>

namespace art2part {

std::vector<Vec3> toFrame(const std::vector<Vec3>& points, const SetupFrame& frame) {
  std::vector<Vec3> out;
  out.reserve(points.size());
  for (const Vec3& p : points) {
    const Vec3 d = p - frame.origin;
    out.emplace_back(d.dot(frame.x), d.dot(frame.y), d.dot(frame.z));
  }
  return out;
}

Vec3 fromFrame(const Vec3& p, const SetupFrame& frame) {
  return frame.origin + p.x() * frame.x + p.y() * frame.y + p.z() * frame.z;
}

namespace {

// Rings of no area to speak of (under 1 um2: edges of up- and down-facing triangles projected onto each other) are
// dropped: hundreds of them in a shadow made Clipper take the shadow's outline for a hole (CTC-01, +z, 68 mm down).
Region dropDegenerateRings(Region region) {
  region.erase(std::remove_if(region.begin(), region.end(),
                              [](const ClipperLib::Path& p) { return std::abs(ClipperLib::Area(p)) < 1e-6 * kRegionScale * kRegionScale; }),
               region.end());
  return region;
}

// The point of edge a-b at height z, computed from the lower-indexed end so that two triangles sharing the edge get
// the same point.
Point2 edgeAt(const std::vector<Vec3>& v, int a, int b, double z) {
  if (a > b) std::swap(a, b);
  const Vec3& p = v[a];
  const Vec3& q = v[b];
  const double t = (z - p.z()) / (q.z() - p.z());
  return Point2(p.x() + t * (q.x() - p.x()), p.y() + t * (q.y() - p.y()));
}

// Triangle `tri` clipped to lo <= z <= hi, projected: up to five points (Sutherland-Hodgman on two planes).
Ring clipToSlab(const std::vector<Vec3>& v, const Triangle& tri, double lo, double hi) {
  Ring out;
  for (int i = 0; i < 3; ++i) {
    const int a = tri[i], b = tri[(i + 1) % 3];
    const double za = v[a].z(), zb = v[b].z();
    const bool a_in = za >= lo && za <= hi;
    if (a_in) out.emplace_back(v[a].x(), v[a].y());
    // Crossings of the open edge a-b with the two planes, in order along the edge.
    double ts[2];
    double zs[2];
    int n = 0;
    for (double plane : {lo, hi}) {
      if ((za < plane && zb > plane) || (za > plane && zb < plane)) {
        ts[n] = (plane - za) / (zb - za);
        zs[n] = plane;
        ++n;
      }
    }
    if (n == 2 && ts[0] > ts[1]) {
      std::swap(ts[0], ts[1]);
      std::swap(zs[0], zs[1]);
    }
    for (int k = 0; k < n; ++k) out.push_back(edgeAt(v, a, b, zs[k]));
  }
  return out;
}

}  // namespace

SetupShadows::SetupShadows(std::vector<Vec3> vertices, const std::vector<Triangle>& triangles)
    : vertices_(std::move(vertices)), part_top_(-std::numeric_limits<double>::infinity()) {
  for (const Vec3& p : vertices_) part_top_ = std::max(part_top_, p.z());
  for (const Triangle& t : triangles) {
    const Vec3 &a = vertices_[t[0]], &b = vertices_[t[1]], &c = vertices_[t[2]];
    if ((b - a).cross(c - a).z() != 0) up_.push_back(t);  // twice the projected area: vertical ones cast none
  }
  auto top = [&](const Triangle& t) {
    return std::max({vertices_[t[0]].z(), vertices_[t[1]].z(), vertices_[t[2]].z()});
  };
  std::sort(up_.begin(), up_.end(), [&](const Triangle& p, const Triangle& q) { return top(p) > top(q); });
  for (const Triangle& t : up_) {
    top_.push_back(top(t));
    bottom_.push_back(std::min({vertices_[t[0]].z(), vertices_[t[1]].z(), vertices_[t[2]].z()}));
  }
}

const SetupShadows::Kept& SetupShadows::keep(double z) {
  const auto below = kept_.lower_bound(z);  // the first kept height at or below z
  if (below != kept_.end() && below->first == z) return below->second;
  const bool any_above = below != kept_.begin();
  const double hi = any_above ? std::prev(below)->first : std::numeric_limits<double>::infinity();
  Kept kept;
  if (any_above) kept.shadow = std::prev(below)->second.shadow;
  // The triangles reaching into [z, hi]: top at or above z (a prefix, highest top first), bottom at or below hi.
  const std::size_t reaching = static_cast<std::size_t>(
      std::upper_bound(top_.begin(), top_.end(), z, std::greater<double>()) - top_.begin());
  std::vector<Ring> pieces;
  for (std::size_t i = 0; i < reaching; ++i) {
    if (bottom_[i] > hi) continue;  // wholly above the kept height: in its shadow already
    Ring piece = clipToSlab(vertices_, up_[i], z, hi);
    if (piece.size() >= 3) pieces.push_back(std::move(piece));
  }
  if (!pieces.empty()) {
    kept.gain = dropDegenerateRings(subtract(regionFromPolygons(pieces), kept.shadow));
    if (!kept.gain.empty()) kept.shadow = dropDegenerateRings(unite(kept.shadow, kept.gain));
    kept.gain = dropThinPieces(kept.gain, kThinGain);
  }
  return kept_.emplace_hint(below, z, std::move(kept))->second;
}

ShadowStack SetupShadows::stack(std::vector<double> heights) {
  std::sort(heights.begin(), heights.end(), std::greater<double>());
  heights.erase(std::unique(heights.begin(), heights.end()), heights.end());
  for (const double z : heights) keep(z);
  ShadowStack stack;
  stack.part_top_ = part_top_;
  auto kept = kept_.begin();
  for (const double z : heights) {
    Region gain;
    for (; kept != kept_.end() && kept->first >= z; ++kept)
      gain.insert(gain.end(), kept->second.gain.begin(), kept->second.gain.end());
    stack.heights_.push_back(z);
    stack.shadows_.push_back(std::prev(kept)->second.shadow);
    stack.gains_.push_back(std::move(gain));
  }
  return stack;
}

ShadowStack::ShadowStack(const std::vector<Vec3>& vertices, const std::vector<Triangle>& triangles,
                         std::vector<double> heights)
    : ShadowStack(SetupShadows(vertices, triangles).stack(std::move(heights))) {}

int ShadowStack::indexAt(double z) const {
  if (z > part_top_) return -1;
  const auto it = std::lower_bound(heights_.begin(), heights_.end(), z, std::greater<double>());  // first <= z
  if (it == heights_.end()) throw std::out_of_range("ShadowStack: a height below every stored one");
  return static_cast<int>(it - heights_.begin());
}

const Region& ShadowStack::at(double z) const {
  const int i = indexAt(z);
  return i < 0 ? empty_ : shadows_[i];
}

namespace {

double cross2(const Point2& o, const Point2& a, const Point2& b) {
  return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
}

// Andrew's monotone chain; counter-clockwise.
Ring convexHull(std::vector<Point2> points) {
  std::sort(points.begin(), points.end(),
            [](const Point2& a, const Point2& b) { return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y()); });
  if (points.size() < 3) return points;
  Ring hull(2 * points.size());
  std::size_t k = 0;
  for (const Point2& p : points) {
    while (k >= 2 && cross2(hull[k - 2], hull[k - 1], p) <= 0) --k;
    hull[k++] = p;
  }
  for (std::size_t i = points.size() - 1, lower = k + 1; i-- > 0;) {
    while (k >= lower && cross2(hull[k - 2], hull[k - 1], points[i]) <= 0) --k;
    hull[k++] = points[i];
  }
  hull.resize(k - 1);
  return hull;
}

}  // namespace

Region stockSlabRegion(const std::vector<Vec3>& vertices, const std::vector<Triangle>& triangles, double lo,
                       double hi) {
  std::vector<Point2> points;
  for (const Vec3& p : vertices)
    if (p.z() >= lo && p.z() <= hi) points.emplace_back(p.x(), p.y());
  for (const Triangle& t : triangles)
    for (int i = 0; i < 3; ++i) {
      const Vec3 &a = vertices[t[i]], &b = vertices[t[(i + 1) % 3]];
      for (double plane : {lo, hi})
        if ((a.z() < plane && b.z() > plane) || (a.z() > plane && b.z() < plane)) {
          const double s = (plane - a.z()) / (b.z() - a.z());
          points.emplace_back(a.x() + s * (b.x() - a.x()), a.y() + s * (b.y() - a.y()));
        }
    }
  const Ring hull = convexHull(points);
  if (hull.size() < 3) return {};
  return regionFromPolygons({hull});
}

Mesh boxMesh(const Box& box) {
  Mesh mesh;
  for (int i = 0; i < 8; ++i)
    mesh.vertices.emplace_back(i & 1 ? box.max.x() : box.min.x(), i & 2 ? box.max.y() : box.min.y(),
                               i & 4 ? box.max.z() : box.min.z());
  // Two triangles per face, counter-clockwise seen from outside.
  mesh.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                    {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  return mesh;
}

}  // namespace art2part
