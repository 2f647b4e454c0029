// Surface finishing's grids: the grid, the body's clearance maps, following the CL surface, thinning.
#include <algorithm>
#include <cmath>
#include <map>

#include "surface_passes.h"

namespace art2part::surface {

Grid gridOver(const Box& box, double pitch) {
  if (!(pitch > 0)) throw InputError("surface finishing: grid pitch must be positive");
  Grid g;
  g.pitch = pitch;
  g.x0 = box.min.x();
  g.y0 = box.min.y();
  const double nx = std::ceil((box.max.x() - box.min.x()) / pitch) + 1;
  const double ny = std::ceil((box.max.y() - box.min.y()) / pitch) + 1;
  if (!(nx * ny <= kMaxGridNodes))
    throw InputError("surface finishing: a map of " + std::to_string(nx * ny) + " nodes at " + std::to_string(pitch) +
                     " mm pitch (too fine for the part's size)");
  g.nx = static_cast<int>(nx);
  g.ny = static_cast<int>(ny);
  return g;
}

std::vector<Zone> bodyZones(const Tool& tool, double grow) {
  std::vector<Zone> all;
  all.push_back({0.5 * tool.shank_diameter, tool.flute_length, grow});
  double h = tool.stickout;
  for (const HolderStep& step : tool.holder) {
    all.push_back({0.5 * step.diameter, h, grow});
    h += step.length;
  }
  std::vector<Zone> kept;
  for (std::size_t i = 0; i < all.size(); ++i) {
    bool dominated = false;
    for (std::size_t j = 0; j < all.size() && !dominated; ++j)
      if (j != i && all[j].radius >= all[i].radius && all[j].height <= all[i].height &&
          (all[j].radius > all[i].radius || all[j].height < all[i].height || j < i))
        dominated = true;
    if (!dominated) kept.push_back(all[i]);
  }
  return kept;
}

double ClearanceMap::along(const Vec3& a, const Vec3& b) const {
  if (tip.empty()) return -kInf;
  const double length = std::hypot(b.x() - a.x(), b.y() - a.y());
  const int n = std::max(1, static_cast<int>(std::ceil(length / (0.5 * grid.pitch))));
  double top = -kInf;
  for (int k = 0; k <= n; ++k) {
    const double t = static_cast<double>(k) / n;
    top = std::max(top, at(a.x() + t * (b.x() - a.x()), a.y() + t * (b.y() - a.y())));
  }
  return top;
}

ClearanceMap clearanceMap(const std::vector<Vec3>& vertices, const std::vector<Triangle>& triangles, const Grid& grid,
                          const std::vector<Zone>& zones, int threads, std::atomic<long>& drops) {
  ClearanceMap map;
  map.grid = grid;
  map.tip.assign(grid.size(), -kInf);
  // One flat drop-cutter per distinct radius (zones of one radius differ in height or growth only), over the
  // triangles within its radius of the grid: the others cannot meet it at any node (a small group's map on a large
  // part skips most of the mesh).
  std::map<double, std::shared_ptr<DropCutter>> cutters;
  for (const Zone& z : zones) {
    const double radius = z.radius + z.grow + grid.pitch;
    if (cutters.count(radius)) continue;
    const double x_lo = grid.x(0) - radius, x_hi = grid.x(grid.nx - 1) + radius;
    const double y_lo = grid.y(0) - radius, y_hi = grid.y(grid.ny - 1) + radius;
    std::vector<Triangle> near;
    for (const Triangle& t : triangles) {
      const Vec3 &a = vertices[t[0]], &b = vertices[t[1]], &c = vertices[t[2]];
      if (std::max({a.x(), b.x(), c.x()}) < x_lo || std::min({a.x(), b.x(), c.x()}) > x_hi ||
          std::max({a.y(), b.y(), c.y()}) < y_lo || std::min({a.y(), b.y(), c.y()}) > y_hi)
        continue;
      near.push_back(t);
    }
    Tool flat;
    flat.id = "zone";
    flat.type = ToolType::Flat;
    flat.diameter = 2 * radius;
    flat.flute_length = flat.stickout = 1;
    flat.shank_diameter = flat.diameter;
    cutters[radius] = std::make_shared<DropCutter>(vertices, near, flat);
  }
  parallelFor(grid.ny, threads, [&](int j) {
    long count = 0;
    for (int i = 0; i < grid.nx; ++i) {
      double top = -kInf;
      for (const Zone& z : zones) {
        const double highest = cutters.at(z.radius + z.grow + grid.pitch)->drop(grid.x(i), grid.y(j), -kInf);
        ++count;
        top = std::max(top, highest + z.grow - z.height);
      }
      map.tip[grid.node(i, j)] = top;
    }
    drops.fetch_add(count, std::memory_order_relaxed);
  });
  return map;
}

void raiseOverStock(ClearanceMap& map, const std::vector<SlabState>& stock, const std::vector<Zone>& zones) {
  if (map.tip.empty() || stock.empty()) return;
  std::vector<RegionAtHeight> levels;
  for (const SlabState& slab : stock) levels.push_back({&slab.remaining, slab.top});
  std::vector<double> radii;
  for (const Zone& zone : zones) radii.push_back(zone.radius + zone.grow + map.grid.pitch);
  const double per_pitch = std::clamp(std::floor(std::sqrt(kStockCells / static_cast<double>(map.grid.size()))), 1.0,
                                      kStockCellsPerPitch);
  const std::vector<std::vector<double>> near =
      highestNear(map.grid, levels, radii, std::max(kStockCell, map.grid.pitch / per_pitch));
  for (std::size_t z = 0; z < zones.size(); ++z)
    for (std::size_t n = 0; n < map.tip.size(); ++n)
      map.tip[n] = std::max(map.tip[n], near[z][n] + zones[z].grow - zones[z].height);
}

void refineInterval(const Context& ctx, const Vec3& a, const Vec3& b, std::vector<Vec3>& out) {
  if (std::hypot(b.x() - a.x(), b.y() - a.y()) <= ctx.min_step) return;
  const double x = 0.5 * (a.x() + b.x()), y = 0.5 * (a.y() + b.y());
  const Vec3 m(x, y, ctx.drop(x, y));
  const double above = 0.5 * (a.z() + b.z()) - m.z();  // the chord over the CL surface: material left
  if (above <= ctx.leave_tolerance && -above <= ctx.gouge_tolerance) return;
  refineInterval(ctx, a, m, out);
  out.push_back(m);
  refineInterval(ctx, m, b, out);
}

void followSurface(const Context& ctx, const Vec3& a, const Vec3& b, std::vector<Vec3>& out) {
  const double length = std::hypot(b.x() - a.x(), b.y() - a.y());
  const int n = std::max(1, static_cast<int>(std::ceil(length / ctx.sample_step)));
  Vec3 previous = a;
  for (int k = 1; k <= n; ++k) {
    const double t = static_cast<double>(k) / n;
    const double x = a.x() + t * (b.x() - a.x()), y = a.y() + t * (b.y() - a.y());
    const Vec3 p(x, y, k == n ? b.z() : ctx.drop(x, y));
    refineInterval(ctx, previous, p, out);
    out.push_back(p);
    previous = p;
  }
}

namespace {

double wrapAngle(double a) {
  while (a > M_PI) a -= 2 * M_PI;
  while (a <= -M_PI) a += 2 * M_PI;
  return a;
}

}  // namespace

// A sleeve from each anchor: the chords from the anchor that keep every point so far within the tolerance form an
// interval (of slopes along the line, or of directions in x-y); the next point is kept when its own chord leaves it.
std::vector<Vec3> thin(const std::vector<Vec3>& points, double gouge, double leave, bool lateral) {
  if (points.size() <= 2) return points;
  std::vector<Vec3> out{points.front()};
  std::size_t anchor = 0;
  while (anchor + 1 < points.size()) {
    const Vec3& a = points[anchor];
    double lo = -kInf, hi = kInf, farthest = 0, reference = 0;
    bool have_reference = false;
    std::size_t last_ok = anchor + 1;
    for (std::size_t k = anchor + 1; k < points.size(); ++k) {
      const Vec3& p = points[k];
      const double d = std::hypot(p.x() - a.x(), p.y() - a.y());
      double value;  // the chord's slope (vertical) or direction (lateral) that passes through p
      if (lateral) {
        if (d <= std::min(gouge, leave)) {  // too near to constrain a direction
          if (d + std::min(gouge, leave) < farthest) break;
          last_ok = k;
          continue;
        }
        const double angle = std::atan2(p.y() - a.y(), p.x() - a.x());
        if (!have_reference) reference = angle, have_reference = true;
        value = wrapAngle(angle - reference);
      } else {
        if (d <= 0) break;
        value = (p.z() - a.z()) / d;
      }
      if (k > anchor + 1 && (value < lo || value > hi || d + std::min(gouge, leave) < farthest)) break;
      last_ok = k;
      farthest = std::max(farthest, d);
      // Vertical: the chord's height at p may be `leave` above p or `gouge` below it. Lateral: p at angle a seen
      // along a chord of direction c lies d sin(a - c) to the chord's left; on its right (the high side) the chord
      // leaves material, on its left it gouges.
      const double below = lateral ? std::asin(std::min(1.0, gouge / d)) : gouge / d;
      const double up = lateral ? std::asin(std::min(1.0, leave / d)) : leave / d;
      lo = std::max(lo, value - below);
      hi = std::min(hi, value + up);
      if (lo > hi) break;
    }
    out.push_back(points[last_ok]);
    anchor = last_ok;
  }
  return out;
}

}  // namespace art2part::surface
