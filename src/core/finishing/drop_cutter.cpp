// Drop-cutter of ball, bull and flat end mills against a triangle mesh (drop_cutter.h): facet, edge and vertex contacts,
// triangles rasterised into cells sorted by height.
#include "art2part/finishing/drop_cutter.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace art2part {

namespace {

// Planes steeper than this (|n.z|) leave the facet test to their edges and vertices: the facet's contact height
// divides by n.z, and its maximum over the disc lies on the triangle's boundary anyway when the plane is vertical.
constexpr double kMinFacetNz = 1e-9;
// Edges shorter than this in x-y (vertical ones) are left to their two vertices, where their maximum lies.
constexpr double kMinEdgeLength = 1e-12;
// Cell side in tool radii: a footprint meets 3 x 3 cells at most, and a cell holds few triangles of a wall.
constexpr double kCellPerRadius = 1.0;
// The grid never has more cells than this (a tiny tool over a large mesh): the cell grows instead.
constexpr double kMaxCells = 16e6;

enum class Shape { Ball, Flat, Bull };

struct Facet {
  bool valid = false;
  double k0 = 0, kx = 0, ky = 0;  // tip = k0 + kx x + ky y where the tool sits on the plane
  double ex[3] = {0, 0, 0}, ey[3] = {0, 0, 0}, ec[3] = {0, 0, 0};  // inside the shifted triangle: all >= 0
};

struct Edge {
  double ax = 0, ay = 0, az = 0;  // start
  double ux = 0, uy = 0;          // unit direction in x-y
  double length = 0;              // in x-y
  double slope = 0;               // dz per mm of x-y
  double zmax = 0;
};

struct TriangleData {
  Facet facet;
  int edges[3] = {-1, -1, -1};     // edges this triangle owns (evaluates), -1 for the others
  int vertices[3] = {-1, -1, -1};  // likewise
};

struct Entry {
  double zmax, xmin, xmax, ymin, ymax;
  int triangle;
};

}  // namespace

struct DropCutter::Impl {
  Shape shape = Shape::Ball;
  double R = 0, r = 0, Rp = 0, R2 = 0;
  std::vector<Vec3> vertices;
  std::vector<TriangleData> triangles;
  std::vector<Edge> edges;
  double x0 = 0, y0 = 0, cell = 1;
  int nx = 0, ny = 0;
  std::vector<int> cell_start;  // nx * ny + 1
  std::vector<Entry> entries;
  Box box;

  double profile(double d) const {
    switch (shape) {
      case Shape::Flat: return 0;
      case Shape::Ball: return R - std::sqrt(std::max(0.0, R2 - d * d));
      case Shape::Bull: {
        if (d <= Rp) return 0;
        const double t = d - Rp;
        return r - std::sqrt(std::max(0.0, r * r - t * t));
      }
    }
    return 0;
  }

  void build(const std::vector<Triangle>& tris);
  void evaluate(int t, double x, double y, double& best, int& best_triangle) const;
  void evaluateEdge(const Edge& e, double x, double y, double& best, bool& improved) const;
  double bullOffset(double a, double m) const;
};

namespace {

Facet makeFacet(const Vec3& a, const Vec3& b, const Vec3& c, double Rp, double r) {
  Facet f;
  Vec3 n = (b - a).cross(c - a);
  const double len = n.norm();
  if (!(len > 0)) return f;
  n /= len;
  if (n.z() < 0) n = -n;
  if (n.z() < kMinFacetNz) return f;
  const double nxy = std::hypot(n.x(), n.y());
  const double ux = nxy > 1e-12 ? n.x() / nxy : 0, uy = nxy > 1e-12 ? n.y() / nxy : 0;
  // The tool's support point towards the plane lies at c - off in x-y: the contact is inside the triangle iff c lies in
  // the triangle shifted by +off.
  const double offx = Rp * ux + r * n.x(), offy = Rp * uy + r * n.y();
  const double d = n.dot(a);
  f.k0 = (d + r + Rp * nxy) / n.z() - r;
  f.kx = -n.x() / n.z();
  f.ky = -n.y() / n.z();
  const double qx[3] = {a.x() + offx, b.x() + offx, c.x() + offx};
  const double qy[3] = {a.y() + offy, b.y() + offy, c.y() + offy};
  const double area2 = (qx[1] - qx[0]) * (qy[2] - qy[0]) - (qy[1] - qy[0]) * (qx[2] - qx[0]);
  if (std::abs(area2) < 1e-18) return f;
  const double sign = area2 > 0 ? 1.0 : -1.0;
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3;
    const double dx = qx[j] - qx[i], dy = qy[j] - qy[i];
    f.ex[i] = -dy * sign;
    f.ey[i] = dx * sign;
    f.ec[i] = (dy * qx[i] - dx * qy[i]) * sign;
  }
  f.valid = true;
  return f;
}

Edge makeEdge(const Vec3& a, const Vec3& b) {
  Edge e;
  e.ax = a.x();
  e.ay = a.y();
  e.az = a.z();
  const double dx = b.x() - a.x(), dy = b.y() - a.y();
  e.length = std::hypot(dx, dy);
  e.zmax = std::max(a.z(), b.z());
  if (e.length < kMinEdgeLength) {
    e.length = 0;
    return e;
  }
  e.ux = dx / e.length;
  e.uy = dy / e.length;
  e.slope = (b.z() - a.z()) / e.length;
  return e;
}

// The x range of the projected triangle within the strip ya <= y <= yb (empty: lo > hi).
void stripRange(const Vec3* p, double ya, double yb, double& lo, double& hi) {
  lo = std::numeric_limits<double>::infinity();
  hi = -lo;
  for (int i = 0; i < 3; ++i) {
    const Vec3& u = p[i];
    const Vec3& v = p[(i + 1) % 3];
    if (u.y() >= ya && u.y() <= yb) {
      lo = std::min(lo, u.x());
      hi = std::max(hi, u.x());
    }
    for (double yl : {ya, yb}) {
      if ((u.y() - yl) * (v.y() - yl) < 0) {
        const double x = u.x() + (yl - u.y()) / (v.y() - u.y()) * (v.x() - u.x());
        lo = std::min(lo, x);
        hi = std::max(hi, x);
      }
    }
  }
}

}  // namespace

void DropCutter::Impl::build(const std::vector<Triangle>& tris) {
  const int n = static_cast<int>(tris.size());
  const int nv = static_cast<int>(vertices.size());
  for (const Triangle& t : tris)
    for (int k = 0; k < 3; ++k)
      if (t[k] < 0 || t[k] >= nv) throw InputError("drop-cutter: a triangle refers to vertex " + std::to_string(t[k]) +
                                                   " of " + std::to_string(nv));
  triangles.resize(n);
  // Ownership: each vertex and each edge is evaluated by the lowest-numbered triangle that has it.
  std::vector<int> vertex_owner(nv, -1);
  for (int t = n - 1; t >= 0; --t)
    for (int k = 0; k < 3; ++k) vertex_owner[tris[t][k]] = t;
  std::vector<std::pair<long long, int>> keys;  // (edge key, triangle * 3 + k)
  keys.reserve(3 * static_cast<std::size_t>(n));
  for (int t = 0; t < n; ++t)
    for (int k = 0; k < 3; ++k) {
      const long long a = tris[t][k], b = tris[t][(k + 1) % 3];
      keys.emplace_back(std::min(a, b) * nv + std::max(a, b), 3 * t + k);
    }
  std::sort(keys.begin(), keys.end());
  for (std::size_t i = 0; i < keys.size(); ++i) {
    if (i > 0 && keys[i].first == keys[i - 1].first) continue;  // sorted: the first holds the lowest triangle
    const int t = keys[i].second / 3, k = keys[i].second % 3;
    const Vec3& a = vertices[tris[t][k]];
    const Vec3& b = vertices[tris[t][(k + 1) % 3]];
    if (a == b) continue;
    triangles[t].edges[k] = static_cast<int>(edges.size());
    edges.push_back(makeEdge(a, b));
  }
  for (int t = 0; t < n; ++t) {
    TriangleData& d = triangles[t];
    for (int k = 0; k < 3; ++k)
      if (vertex_owner[tris[t][k]] == t) {
        d.vertices[k] = tris[t][k];
        vertex_owner[tris[t][k]] = -2;  // a triangle listing a vertex twice evaluates it once
      }
    d.facet = makeFacet(vertices[tris[t][0]], vertices[tris[t][1]], vertices[tris[t][2]], Rp, r);
  }
  // Cells.
  for (const Triangle& t : tris)
    for (int k = 0; k < 3; ++k) box.extend(vertices[t[k]]);
  if (box.empty()) return;
  cell = kCellPerRadius * R;
  const double w = box.max.x() - box.min.x(), h = box.max.y() - box.min.y();
  while ((w / cell + 1) * (h / cell + 1) > kMaxCells) cell *= 2;
  x0 = box.min.x();
  y0 = box.min.y();
  nx = static_cast<int>(w / cell) + 1;
  ny = static_cast<int>(h / cell) + 1;
  std::vector<std::pair<int, int>> cell_triangle;  // (cell, triangle)
  cell_triangle.reserve(2 * static_cast<std::size_t>(n));
  for (int t = 0; t < n; ++t) {
    const Vec3 p[3] = {vertices[tris[t][0]], vertices[tris[t][1]], vertices[tris[t][2]]};
    const double ylo = std::min({p[0].y(), p[1].y(), p[2].y()}), yhi = std::max({p[0].y(), p[1].y(), p[2].y()});
    const int j0 = std::clamp(static_cast<int>((ylo - y0) / cell), 0, ny - 1);
    const int j1 = std::clamp(static_cast<int>((yhi - y0) / cell), 0, ny - 1);
    for (int j = j0; j <= j1; ++j) {
      double lo, hi;
      stripRange(p, std::max(ylo, y0 + j * cell), std::min(yhi, y0 + (j + 1) * cell), lo, hi);
      if (lo > hi) continue;
      const int i0 = std::clamp(static_cast<int>((lo - x0) / cell), 0, nx - 1);
      const int i1 = std::clamp(static_cast<int>((hi - x0) / cell), 0, nx - 1);
      for (int i = i0; i <= i1; ++i) cell_triangle.emplace_back(j * nx + i, t);
    }
  }
  cell_start.assign(static_cast<std::size_t>(nx) * ny + 1, 0);
  for (const auto& ct : cell_triangle) ++cell_start[ct.first + 1];
  for (std::size_t c = 1; c < cell_start.size(); ++c) cell_start[c] += cell_start[c - 1];
  entries.resize(cell_triangle.size());
  std::vector<int> fill(cell_start.begin(), cell_start.end() - 1);
  for (const auto& ct : cell_triangle) {
    const Triangle& t = tris[ct.second];
    const Vec3& a = vertices[t[0]];
    const Vec3& b = vertices[t[1]];
    const Vec3& c = vertices[t[2]];
    entries[fill[ct.first]++] = Entry{std::max({a.z(), b.z(), c.z()}), std::min({a.x(), b.x(), c.x()}),
                                      std::max({a.x(), b.x(), c.x()}), std::min({a.y(), b.y(), c.y()}),
                                      std::max({a.y(), b.y(), c.y()}), ct.second};
  }
  for (std::size_t c = 0; c + 1 < cell_start.size(); ++c)
    std::sort(entries.begin() + cell_start[c], entries.begin() + cell_start[c + 1],
              [](const Entry& p, const Entry& q) { return p.zmax > q.zmax; });
}

// The horizontal offset sigma >= 0 from the foot of the perpendicular (at horizontal distance a) to where the torus
// touches a line rising m > 0 per mm: the root of g'(sigma) = m - f'(rho) sigma / rho, in the corner angle phi
// (rho = R' + r sin phi, f'(rho) = tan phi), by Newton's steps kept inside a bracket that the sign of g' maintains.
double DropCutter::Impl::bullOffset(double a, double m) const {
  auto rhoAt = [&](double phi) { return Rp + r * std::sin(phi); };
  auto sigmaAt = [&](double phi) {
    const double rho = rhoAt(phi);
    return std::sqrt(std::max(0.0, rho * rho - a * a));
  };
  double lo = a > Rp ? std::asin(std::min(1.0, (a - Rp) / r)) : 0.0;
  double hi = 0.5 * M_PI;
  double phi = std::clamp(std::atan(m), lo, hi);
  for (int iteration = 0; iteration < 200; ++iteration) {
    if (!(phi > lo && phi < hi)) phi = 0.5 * (lo + hi);
    const double s = std::sin(phi), c = std::cos(phi);
    const double rho = Rp + r * s;
    const double sigma = std::sqrt(std::max(0.0, rho * rho - a * a));
    const double G = (s / c) * sigma / rho - m;  // = -g'(sigma)
    if (G > 0) hi = phi; else lo = phi;
    if (std::abs(G) * (sigmaAt(hi) - sigmaAt(lo)) <= kBullContactTolerance || hi - lo < 1e-15) return sigma;
    const double dG = sigma / (rho * c * c) + (sigma > 0 ? a * a * r * s / (sigma * rho * rho) : 0.0);
    phi = dG > 0 ? phi - G / dG : 0.5 * (lo + hi);
  }
  return sigmaAt(0.5 * (lo + hi));
}

void DropCutter::Impl::evaluateEdge(const Edge& e, double x, double y, double& best, bool& improved) const {
  if (e.length == 0) return;
  const double dx = x - e.ax, dy = y - e.ay;
  const double s0 = dx * e.ux + dy * e.uy;
  const double a = std::abs(dx * e.uy - dy * e.ux);
  if (a >= R) return;
  const double half = std::sqrt(R2 - a * a);
  const double lo = std::max(0.0, s0 - half), hi = std::min(e.length, s0 + half);
  if (lo > hi) return;
  const double m = e.slope;
  const double line_top = e.az + m * (m >= 0 ? hi : lo);
  if (shape == Shape::Flat) {  // f = 0 on the disc: the line's highest point on the chord
    if (line_top > best) best = line_top, improved = true;
    return;
  }
  if (line_top - profile(a) <= best) return;  // no point of the chord can do better
  double sigma;
  if (shape == Shape::Ball) {
    sigma = m * half / std::sqrt(1 + m * m);  // the circle of radius `half` touching the line
  } else {
    sigma = m == 0 ? 0.0 : std::copysign(bullOffset(a, std::abs(m)), m);
  }
  const double s = s0 + sigma;
  if (s < 0 || s > e.length) return;  // the maximum over the edge is at an end: a vertex
  const double z = e.az + m * s - profile(std::sqrt(a * a + sigma * sigma));
  if (z > best) best = z, improved = true;
}

void DropCutter::Impl::evaluate(int t, double x, double y, double& best, int& best_triangle) const {
  const TriangleData& d = triangles[t];
  bool improved = false;
  for (int k = 0; k < 3; ++k) {
    if (d.vertices[k] < 0) continue;
    const Vec3& p = vertices[d.vertices[k]];
    if (p.z() <= best) continue;
    const double dx = p.x() - x, dy = p.y() - y, d2 = dx * dx + dy * dy;
    if (d2 > R2) continue;
    const double z = p.z() - profile(std::sqrt(d2));
    if (z > best) best = z, improved = true;
  }
  const Facet& f = d.facet;
  if (f.valid && f.ex[0] * x + f.ey[0] * y + f.ec[0] >= 0 && f.ex[1] * x + f.ey[1] * y + f.ec[1] >= 0 &&
      f.ex[2] * x + f.ey[2] * y + f.ec[2] >= 0) {
    const double z = f.k0 + f.kx * x + f.ky * y;
    if (z > best) best = z, improved = true;
  }
  for (int k = 0; k < 3; ++k) {
    if (d.edges[k] < 0) continue;
    const Edge& e = edges[d.edges[k]];
    if (e.zmax <= best) continue;
    evaluateEdge(e, x, y, best, improved);
  }
  if (improved) best_triangle = t;
}

DropCutter::DropCutter(const std::vector<Vec3>& vertices, const std::vector<Triangle>& triangles, const Tool& tool) {
  checkTool(tool);
  auto impl = std::make_shared<Impl>();
  impl->R = 0.5 * tool.diameter;
  impl->R2 = impl->R * impl->R;
  switch (tool.type) {
    case ToolType::Ball: impl->shape = Shape::Ball; impl->r = impl->R; break;
    case ToolType::Flat: impl->shape = Shape::Flat; impl->r = 0; break;
    case ToolType::Bull: impl->shape = Shape::Bull; impl->r = tool.corner_radius; break;
    case ToolType::Drill:
      throw InputError("drop-cutter: tool '" + tool.id + "' is a drill (only ball, bull and flat end mills)");
  }
  impl->Rp = impl->R - impl->r;
  impl->vertices = vertices;
  impl->build(triangles);
  impl_ = impl;
}

double DropCutter::drop(double x, double y, double floor) const {
  int triangle;
  return drop(x, y, floor, &triangle);
}

double DropCutter::drop(double x, double y, double floor, int* triangle) const {
  const Impl& m = *impl_;
  double best = floor;
  int best_triangle = -1;
  if (m.nx > 0) {
    const double R = m.R;
    const int i0 = std::max(0, static_cast<int>(std::floor((x - R - m.x0) / m.cell)));
    const int i1 = std::min(m.nx - 1, static_cast<int>(std::floor((x + R - m.x0) / m.cell)));
    const int j0 = std::max(0, static_cast<int>(std::floor((y - R - m.y0) / m.cell)));
    const int j1 = std::min(m.ny - 1, static_cast<int>(std::floor((y + R - m.y0) / m.cell)));
    // The cell under the centre first: it holds the likeliest contact, and a high first answer stops the others early.
    const int ic = std::clamp(static_cast<int>(std::floor((x - m.x0) / m.cell)), i0, i1);
    const int jc = std::clamp(static_cast<int>(std::floor((y - m.y0) / m.cell)), j0, j1);
    auto visit = [&](int i, int j) {
      // Cells whose nearest point lies beyond the radius hold nothing under the footprint.
      const double cx = std::max({0.0, m.x0 + i * m.cell - x, x - (m.x0 + (i + 1) * m.cell)});
      const double cy = std::max({0.0, m.y0 + j * m.cell - y, y - (m.y0 + (j + 1) * m.cell)});
      if (cx * cx + cy * cy > m.R2) return;
      const int c = j * m.nx + i;
      for (int k = m.cell_start[c], end = m.cell_start[c + 1]; k < end; ++k) {
        const Entry& e = m.entries[k];
        if (e.zmax <= best) break;
        // The triangle's nearest point in x-y is at least as far as its box: no point of it rises above
        // zmax - f(that distance).
        const double dx = std::max({0.0, e.xmin - x, x - e.xmax}), dy = std::max({0.0, e.ymin - y, y - e.ymax});
        const double d2 = dx * dx + dy * dy;
        if (d2 > m.R2) continue;
        if (m.shape != Shape::Flat && e.zmax - m.profile(std::sqrt(d2)) <= best) continue;
        m.evaluate(e.triangle, x, y, best, best_triangle);
      }
    };
    if (i0 <= i1 && j0 <= j1) {
      visit(ic, jc);
      for (int j = j0; j <= j1; ++j)
        for (int i = i0; i <= i1; ++i)
          if (i != ic || j != jc) visit(i, j);
    }
  }
  *triangle = best_triangle;
  return best;
}

double DropCutter::radius() const { return impl_->R; }
double DropCutter::cornerRadius() const { return impl_->r; }
double DropCutter::profile(double d) const { return impl_->profile(d); }
Box DropCutter::bounds() const { return impl_->box; }
long DropCutter::binnedEntries() const { return static_cast<long>(impl_->entries.size()); }

}  // namespace art2part
