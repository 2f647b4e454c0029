// The CPU shadow map for volume visibility: conservative rasterisation of the part's heights along a direction.
#include "volume_visibility_height_map.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace art2part::volume {

namespace {

// A point in pixel coordinates with its height along d.
struct P {
  double x, y, h;
};

// Pixel range [lo, hi] covering the interval [a, b] of pixel coordinates, clamped to the map.
void pixelRange(double a, double b, int n, int& lo, int& hi) {
  lo = std::max(0, static_cast<int>(std::floor(a)));
  hi = std::min(n - 1, static_cast<int>(std::floor(b)));
}

// Edge function of a -> b: positive to the left. Shifted by half the pixel's extent along the edge normal
// (0.5 (|ex| + |ey|)) it is >= 0 exactly when the pixel square reaches the left half-plane: the separating-axis
// test of a square against an edge.
struct Edge {
  double a, b, c, slack;
  Edge(const P& p, const P& q)
      : a(-(q.y - p.y)), b(q.x - p.x), c(-(a * p.x + b * p.y)), slack(0.5 * (std::abs(a) + std::abs(b))) {}
  double at(double x, double y) const { return a * x + b * y + c; }
};

// The largest height of the triangle over the closed pixel square [i, i+1] x [j, j+1]: clip the triangle to the
// square (Sutherland-Hodgman, heights interpolated along the way, exact since height is linear) and take the top
// vertex. Only for pixels the triangle's edges cross: there the plane's value at a pixel corner can lie far above
// anything the triangle reaches (a face seen almost edge-on has a steep plane), and using it would block voxels
// that sit beside, not behind, the face.
double clippedTop(const P* tri, int i, int j) {
  P poly[8], next[8];
  int n = 3;
  std::copy(tri, tri + 3, poly);
  // Half-planes as (axis, bound, keep below?): x >= i, x <= i+1, y >= j, y <= j+1.
  const struct { bool y; double bound; bool below; } planes[4] = {{false, double(i), false}, {false, i + 1.0, true},
                                                                  {true, double(j), false}, {true, j + 1.0, true}};
  for (const auto& pl : planes) {
    auto side = [&](const P& q) { return (pl.y ? q.y : q.x) - pl.bound; };
    auto keep = [&](const P& q) { return pl.below ? side(q) <= 0 : side(q) >= 0; };
    int m = 0;
    for (int k = 0; k < n; ++k) {
      const P& a = poly[k];
      const P& b = poly[(k + 1) % n];
      if (keep(a)) next[m++] = a;
      if (keep(a) != keep(b)) {
        const double t = side(a) / (side(a) - side(b));
        next[m++] = P{a.x + t * (b.x - a.x), a.y + t * (b.y - a.y), a.h + t * (b.h - a.h)};
      }
    }
    n = m;
    if (n == 0) return -std::numeric_limits<double>::infinity();
    std::copy(next, next + n, poly);
  }
  double top = poly[0].h;
  for (int k = 1; k < n; ++k) top = std::max(top, poly[k].h);
  return top;
}

void raise(float& cell, double value) { cell = std::max(cell, static_cast<float>(value)); }

}  // namespace

void HeightMap::reset(const Vec3& dir, const Box& box, double pixel) {
  d = dir.normalized();
  // Any axis not parallel to d makes the frame; the least aligned one keeps it well conditioned.
  Eigen::Index axis = 0;
  d.cwiseAbs().minCoeff(&axis);
  e1 = d.cross(Vec3::Unit(axis)).normalized();
  e2 = d.cross(e1);
  double u1 = -std::numeric_limits<double>::infinity(), v1 = u1;
  u0 = v0 = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 8; ++k) {
    const Vec3 p(k & 1 ? box.max.x() : box.min.x(), k & 2 ? box.max.y() : box.min.y(),
                 k & 4 ? box.max.z() : box.min.z());
    u0 = std::min(u0, p.dot(e1)), u1 = std::max(u1, p.dot(e1));
    v0 = std::min(v0, p.dot(e2)), v1 = std::max(v1, p.dot(e2));
  }
  // One pixel of slack on each side so that a voxel centre on the box's rim still falls inside the map.
  u0 -= pixel, v0 -= pixel;
  inv_pixel = 1.0 / pixel;
  w = static_cast<int>(std::ceil((u1 - u0) * inv_pixel)) + 2;
  h = static_cast<int>(std::ceil((v1 - v0) * inv_pixel)) + 2;
  height.assign(static_cast<std::size_t>(w) * h, -std::numeric_limits<float>::infinity());
}

void HeightMap::rasterise(const Vec3& a3, const Vec3& b3, const Vec3& c3) {
  auto project = [&](const Vec3& p) {
    return P{(p.dot(e1) - u0) * inv_pixel, (p.dot(e2) - v0) * inv_pixel, p.dot(d)};
  };
  P p[3] = {project(a3), project(b3), project(c3)};
  double area2 = (p[1].x - p[0].x) * (p[2].y - p[0].y) - (p[2].x - p[0].x) * (p[1].y - p[0].y);
  if (std::abs(area2) < 1e-9) {
    // Seen edge-on: the triangle is a segment (or a point). It still blocks every pixel its edges touch, up to the
    // height it reaches inside the pixel: this is what keeps a thin wall parallel to d opaque.
    for (int k = 0; k < 3; ++k) {
      const P& s = p[k];
      const P& t = p[(k + 1) % 3];
      const Edge e(s, t);
      int i0, i1, j0, j1;
      pixelRange(std::min(s.x, t.x), std::max(s.x, t.x), w, i0, i1);
      pixelRange(std::min(s.y, t.y), std::max(s.y, t.y), h, j0, j1);
      for (int j = j0; j <= j1; ++j)
        for (int i = i0; i <= i1; ++i)
          if (std::abs(e.at(i + 0.5, j + 0.5)) <= e.slack) raise(height[std::size_t(j) * w + i], clippedTop(p, i, j));
    }
    return;
  }
  if (area2 < 0) std::swap(p[1], p[2]), area2 = -area2;  // back faces occlude too: orient counter-clockwise
  // Height as a plane over pixel coordinates; over a pixel square inside the triangle its largest value is at a
  // corner: the centre value plus half the gradient's L1 norm.
  const double ga = ((p[1].h - p[0].h) * (p[2].y - p[0].y) - (p[2].h - p[0].h) * (p[1].y - p[0].y)) / area2;
  const double gb = ((p[1].x - p[0].x) * (p[2].h - p[0].h) - (p[2].x - p[0].x) * (p[1].h - p[0].h)) / area2;
  const double g0 = p[0].h - ga * p[0].x - gb * p[0].y + 0.5 * (std::abs(ga) + std::abs(gb));
  const Edge e0(p[0], p[1]), e1e(p[1], p[2]), e2e(p[2], p[0]);
  int i0, i1, j0, j1;
  pixelRange(std::min({p[0].x, p[1].x, p[2].x}), std::max({p[0].x, p[1].x, p[2].x}), w, i0, i1);
  pixelRange(std::min({p[0].y, p[1].y, p[2].y}), std::max({p[0].y, p[1].y, p[2].y}), h, j0, j1);
  for (int j = j0; j <= j1; ++j) {
    const double y = j + 0.5;
    for (int i = i0; i <= i1; ++i) {
      const double x = i + 0.5;
      const double f0 = e0.at(x, y), f1 = e1e.at(x, y), f2 = e2e.at(x, y);
      if (f0 + e0.slack < 0 || f1 + e1e.slack < 0 || f2 + e2e.slack < 0) continue;  // square misses the triangle
      const bool whole = f0 >= e0.slack && f1 >= e1e.slack && f2 >= e2e.slack;         // square inside it
      raise(height[std::size_t(j) * w + i], whole ? g0 + ga * x + gb * y : clippedTop(p, i, j));
    }
  }
}

void HeightMap::rasteriseMesh(const Mesh& mesh) {
  for (int t = 0; t < mesh.triangleCount(); ++t) rasterise(mesh.corner(t, 0), mesh.corner(t, 1), mesh.corner(t, 2));
}

}  // namespace art2part::volume
