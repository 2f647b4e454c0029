// Waterline passes over the steep part of the region: iso-height contours of the CL surface by marching squares on the
// CL map, each crossing placed by drops (on the low side, within the leave tolerance), contours refined until every
// chord keeps within the gouge and leave tolerances of the contour laterally, cut only where the body clears.
#include <algorithm>
#include <cmath>
#include <unordered_map>
#include <unordered_set>

#include "surface_passes.h"

namespace art2part::surface {

namespace {

struct Cell {
  int i, j;
  double lo, hi;  // the corners' least and greatest CL height
};

// Corners c0 (i, j), c1 (i+1, j), c2 (i+1, j+1), c3 (i, j+1); edge k runs from corner k to corner k+1. In cell units.
constexpr double kCorner[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
constexpr double kEdgeMid[4][2] = {{0.5, 0}, {1, 0.5}, {0.5, 1}, {0, 0.5}};

long edgeId(const Grid& g, int i, int j, int k) {
  switch (k) {
    case 0: return 2L * g.node(i, j);
    case 1: return 2L * g.node(i + 1, j) + 1;
    case 2: return 2L * g.node(i, j + 1);
    default: return 2L * g.node(i, j) + 1;
  }
}

// The drops made along each edge of the map by earlier levels (a wall is crossed by every level: its bracket is found
// once), by edge id.
using EdgeSamples = std::unordered_map<long, std::vector<Vec3>>;

struct Level {
  const Context& ctx;
  double z;
  double precision;  // mm: crossings are bracketed this closely
  EdgeSamples& samples;
  std::unordered_map<long, Vec3> crossings;

  bool high(const Vec3& p) const { return p.z() >= z; }
  Vec3 at(double x, double y) const { return Vec3(x, y, ctx.drop(x, y)); }

  // Between a point on the high side and one on the low side: the crossing, on the low side of a bracket `precision`
  // wide (the tool at height z there stays above the CL surface). False position with the Illinois halving (which
  // keeps both ends moving), and when the line through the bracket puts the crossing within half the precision of
  // the new point, one more drop just past it to close the bracket at once. Where the CL surface jumps (a cliff) the
  // false position degrades to a bisection-like shrinking, never worse than the halving it forces.
  Vec3 bisect(Vec3 inside, Vec3 outside, std::vector<Vec3>* record = nullptr) const {
    auto at = [&](double x, double y) {
      const Vec3 p(x, y, ctx.drop(x, y));
      if (record) record->push_back(p);
      return p;
    };
    double fi = inside.z() - z, fo = outside.z() - z;  // >= 0, < 0 (fi, fo scaled by the halving)
    int side = 0;
    double width = std::hypot(outside.x() - inside.x(), outside.y() - inside.y());
    while (width > precision) {
      double t = fi - fo > 0 ? fi / (fi - fo) : 0.5;
      t = std::clamp(t, 0.02, 0.98);
      const double ux = (outside.x() - inside.x()) / width, uy = (outside.y() - inside.y()) / width;
      const Vec3 m = at(inside.x() + t * width * ux, inside.y() + t * width * uy);
      const double fm = m.z() - z;
      if (fm >= 0) {
        inside = m, fi = fm;
        if (side == 1) fo *= 0.5;
        side = 1;
      } else {
        outside = m, fo = fm;
        if (side == -1) fi *= 0.5;
        side = -1;
      }
      width = std::hypot(outside.x() - inside.x(), outside.y() - inside.y());
      if (width <= precision) break;
      const double slope = ((inside.z() - z) - (outside.z() - z)) / width;  // > 0
      if (slope > 0 && std::abs(fm) / slope < 0.5 * precision) {
        const double s = fm >= 0 ? 0.9 * precision : -0.9 * precision;  // towards the other end
        const Vec3 p = at(m.x() + s * ux, m.y() + s * uy);
        if (high(p)) {
          if (p.z() - z < fi) fi = p.z() - z;
          inside = p;
        } else {
          if (p.z() - z > fo) fo = p.z() - z;
          outside = p;
        }
        width = std::hypot(outside.x() - inside.x(), outside.y() - inside.y());
      }
    }
    return Vec3(outside.x(), outside.y(), z);
  }

  // The crossing along origin + t (ux, uy), 0 < t <= tmax, origin not on it: steps out by the secant's estimate (at
  // least doubling) until the class changes, then brackets it. False when it does not within tmax.
  bool along(const Vec3& origin, double ux, double uy, double t, double tmax, Vec3& out) const {
    const bool origin_high = high(origin);
    double t_prev = 0, f_prev = origin.z() - z;
    while (t <= tmax) {
      const Vec3 p = at(origin.x() + t * ux, origin.y() + t * uy);
      const double f = p.z() - z;
      if (high(p) != origin_high) {
        const Vec3 q = at(origin.x() + t_prev * ux, origin.y() + t_prev * uy);
        out = origin_high ? bisect(q, p) : bisect(p, q);
        return true;
      }
      double next = 2 * t;
      if (f != f_prev) {
        const double estimate = t - f * (t - t_prev) / (f - f_prev);
        if (estimate > t) next = std::max(next, 1.1 * estimate);
      }
      t_prev = t, f_prev = f;
      t = t < tmax ? std::min(next, tmax) : 2 * tmax;
    }
    return false;
  }

  Vec3 crossing(int i, int j, int k) {
    const long id = edgeId(ctx.grid, i, j, k);
    auto it = crossings.find(id);
    if (it != crossings.end()) return it->second;
    const Grid& g = ctx.grid;
    const int a = k, b = (k + 1) % 4;
    const int ia = i + static_cast<int>(kCorner[a][0]), ja = j + static_cast<int>(kCorner[a][1]);
    const int ib = i + static_cast<int>(kCorner[b][0]), jb = j + static_cast<int>(kCorner[b][1]);
    const Vec3 pa(g.x(ia), g.y(ja), ctx.height[g.node(ia, ja)]), pb(g.x(ib), g.y(jb), ctx.height[g.node(ib, jb)]);
    // The tightest bracket the drops along this edge already give: walking from its high end, the first drop on the
    // low side and the one before it.
    std::vector<Vec3>& known = samples[id];
    const Vec3& from = high(pa) ? pa : pb;
    const Vec3& to = high(pa) ? pb : pa;
    std::vector<std::pair<double, Vec3>> order{{0.0, from}, {1e300, to}};
    for (const Vec3& q : known) order.emplace_back(std::hypot(q.x() - from.x(), q.y() - from.y()), q);
    std::sort(order.begin(), order.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    std::size_t low = 1;
    while (high(order[low].second)) ++low;
    const Vec3 c = bisect(order[low - 1].second, order[low].second, &known);
    crossings.emplace(id, c);
    return c;
  }

  // Keeps the chord p-q within the gouge tolerance of the contour on its high side and the leave tolerance on its low
  // side (q excluded from `out`): looks across the chord's middle that far towards the contour; when it is not there,
  // finds it and splits the chord at it.
  void refine(const Vec3& p, const Vec3& q, std::vector<Vec3>& out, int depth) {
    const double len = std::hypot(q.x() - p.x(), q.y() - p.y());
    if (len <= ctx.min_step || depth > 40) return;
    const double dx = (q.x() - p.x()) / len, dy = (q.y() - p.y()) / len;
    const Vec3 m = at(0.5 * (p.x() + q.x()), 0.5 * (p.y() + q.y()));
    const double sign = high(m) ? -1 : 1;  // towards the contour: away from the high side (the right) when on it
    const double ux = sign * dy, uy = -sign * dx;
    // The chord's middle on the high side gouges, on the low side leaves material.
    const double near = high(m) ? ctx.gouge_tolerance : ctx.contour_leave;
    const Vec3 probe = at(m.x() + near * ux, m.y() + near * uy);
    if (high(probe) != high(m)) return;  // the contour is within half the tolerance of the chord here
    Vec3 c;
    if (!along(probe, ux, uy, near, len, c)) return;  // no contour near this chord's middle: nothing to follow
    refine(p, c, out, depth + 1);
    out.push_back(c);
    refine(c, q, out, depth + 1);
  }
};

// The oriented segments of one cell at level z, as pairs of edge indices (from, to).
int cellSegments(const Level& level, const Cell& cell, int out[2][2]) {
  const Context& ctx = level.ctx;
  const Grid& g = ctx.grid;
  bool h[4];
  int count = 0;
  for (int k = 0; k < 4; ++k) {
    const int i = cell.i + static_cast<int>(kCorner[k][0]), j = cell.j + static_cast<int>(kCorner[k][1]);
    h[k] = ctx.height[g.node(i, j)] >= level.z;
    count += h[k];
  }
  if (count == 0 || count == 4) return 0;
  // Each segment cuts off a reference corner from the rest: (edge before it, edge after it, corner).
  int cuts[2][3];
  int n = 0;
  if (count == 1 || count == 3) {
    for (int k = 0; k < 4; ++k)
      if (h[k] != h[(k + 1) % 4] && h[k] != h[(k + 3) % 4]) cuts[n++][0] = (k + 3) % 4, cuts[n - 1][1] = k, cuts[n - 1][2] = k;
  } else if (h[0] == h[2]) {  // saddle: the centre's height decides which pair of corners is joined
    const double cx = g.x(cell.i) + 0.5 * g.pitch, cy = g.y(cell.j) + 0.5 * g.pitch;
    const bool centre = ctx.drop(cx, cy) >= level.z;
    for (int k = 0; k < 4; ++k)
      if (h[k] != centre) cuts[n++][0] = (k + 3) % 4, cuts[n - 1][1] = k, cuts[n - 1][2] = k;
  } else {  // two neighbouring corners on each side
    for (int k = 0; k < 4; ++k)
      if (h[k] && h[(k + 1) % 4]) cuts[n++][0] = (k + 1) % 4, cuts[n - 1][1] = (k + 3) % 4, cuts[n - 1][2] = k;
  }
  for (int s = 0; s < n; ++s) {
    const int a = cuts[s][0], b = cuts[s][1], c = cuts[s][2];
    const double px = kEdgeMid[a][0], py = kEdgeMid[a][1], qx = kEdgeMid[b][0], qy = kEdgeMid[b][1];
    const double side = (qx - px) * (kCorner[c][1] - py) - (qy - py) * (kCorner[c][0] - px);  // < 0: c on the right
    const bool forward = (side < 0) == h[c];
    out[s][0] = forward ? a : b;
    out[s][1] = forward ? b : a;
  }
  return n;
}

// Splits a contour where the body cannot clear; a loop cut somewhere becomes the open stretches between the cuts.
void keepClear(const Context& ctx, Pass contour, std::vector<Pass>& out) {
  // A chord is clear when the body's clearance stays below its height all along it (the map sampled half a pitch
  // apart answers for every point between: contour points may lie a cell's diagonal apart, more than a point's
  // nearest node answers for).
  auto chordClear = [&](const Vec3& a, const Vec3& b) {
    return ctx.body.along(a, b) <= std::min(a.z(), b.z()) + ctx.body_tolerance;
  };
  std::vector<Vec3>& p = contour.points;
  std::size_t first_bad = p.size();
  for (std::size_t k = 0; k < p.size() && first_bad == p.size(); ++k) {
    if (!ctx.bodyClear(p[k])) first_bad = k;
    else if (k + 1 < p.size() && !chordClear(p[k], p[k + 1])) first_bad = k + 1;
  }
  if (first_bad == p.size()) {
    out.push_back(std::move(contour));
    return;
  }
  if (contour.closed) {  // start the walk where the contour cannot be cut (a point, or just after a chord)
    const std::size_t s = first_bad % (p.size() - 1);
    std::vector<Vec3> rotated(p.begin() + s, p.end() - 1);
    rotated.insert(rotated.end(), p.begin(), p.begin() + s + 1);
    p = rotated;
  }
  Pass run;
  auto flush = [&] {
    if (run.points.size() >= 2) out.push_back(run);
    run.points.clear();
  };
  for (const Vec3& q : p) {
    if (!ctx.bodyClear(q)) {
      flush();
      continue;
    }
    if (!run.points.empty() && !chordClear(run.points.back(), q)) flush();
    run.points.push_back(q);
  }
  flush();
}

std::vector<Pass> contoursAt(const Context& ctx, const std::vector<Cell>& cells, double z, EdgeSamples& samples) {
  Level level{ctx, z, ctx.crossing_precision, samples, {}};
  std::unordered_map<long, long> next;     // edge id -> edge id of the segment leaving it
  std::unordered_map<long, Cell> where;    // edge id -> a cell it belongs to (to compute its crossing)
  std::unordered_map<long, int> edge_of;   // edge id -> its index within that cell
  std::unordered_set<long> has_incoming;
  for (const Cell& cell : cells) {
    if (cell.hi < z || cell.lo >= z) continue;
    int segments[2][2];
    const int n = cellSegments(level, cell, segments);
    for (int s = 0; s < n; ++s) {
      const long a = edgeId(ctx.grid, cell.i, cell.j, segments[s][0]);
      const long b = edgeId(ctx.grid, cell.i, cell.j, segments[s][1]);
      next[a] = b;
      has_incoming.insert(b);
      where.emplace(a, cell);
      edge_of.emplace(a, segments[s][0]);
      where.emplace(b, cell);
      edge_of.emplace(b, segments[s][1]);
    }
  }
  auto pointOf = [&](long id) {
    const Cell& c = where.at(id);
    return level.crossing(c.i, c.j, edge_of.at(id));
  };
  std::vector<Pass> out;
  std::unordered_set<long> used;
  auto walk = [&](long start) {
    Pass contour;
    long id = start;
    std::vector<long> ids{id};
    used.insert(id);
    for (auto it = next.find(id); it != next.end(); it = next.find(id)) {
      id = it->second;
      if (id == start) {
        contour.closed = true;
        break;
      }
      if (used.count(id)) break;
      used.insert(id);
      ids.push_back(id);
    }
    if (contour.closed) ids.push_back(start);
    if (ids.size() < 2) return;
    std::vector<Vec3> raw;
    for (long e : ids) raw.push_back(pointOf(e));
    // The turn at each crossing (its neighbours' directions); a loop's ends are its neighbours across the seam.
    const std::size_t n = raw.size();
    std::vector<double> turn(n, M_PI);
    for (std::size_t k = 0; k < n; ++k) {
      const bool inner = k > 0 && k + 1 < n;
      if (!inner && !(contour.closed && n > 3)) continue;
      const Vec3& a = k > 0 ? raw[k - 1] : raw[n - 2];
      const Vec3& c = k + 1 < n ? raw[k + 1] : raw[1];
      const Vec3& b = raw[k];
      const double t1 = std::atan2(b.y() - a.y(), b.x() - a.x()), t2 = std::atan2(c.y() - b.y(), c.x() - b.x());
      turn[k] = std::abs(std::remainder(t2 - t1, 2 * M_PI));
    }
    contour.points.push_back(raw.front());
    for (std::size_t k = 1; k < n; ++k) {
      // An arc through the crossings with chord L turning by theta leaves its chord by L theta / 8; a chord whose
      // neighbours turn so little that twice that stays within the tolerances is taken as it is (a wall of the part
      // is straight between crossings, up to the crossings' own scatter within the leave tolerance), the rest are
      // looked at.
      const double len = std::hypot(raw[k].x() - raw[k - 1].x(), raw[k].y() - raw[k - 1].y());
      const double sag = 0.25 * len * std::max(turn[k - 1], turn[k]);
      if (sag > std::min(ctx.gouge_tolerance, ctx.contour_leave)) level.refine(raw[k - 1], raw[k], contour.points, 0);
      contour.points.push_back(raw[k]);
    }
    // The body is checked at every point before thinning: a thinned chord runs by all of them (a long straight wall
    // is one move, and the holder must clear all along it).
    std::vector<Pass> clear;
    keepClear(ctx, std::move(contour), clear);
    for (Pass& piece : clear) {
      piece.points = thin(piece.points, ctx.gouge_tolerance, ctx.contour_leave, true);
      out.push_back(std::move(piece));
    }
  };
  std::vector<long> starts;
  for (const auto& kv : next)
    if (!has_incoming.count(kv.first)) starts.push_back(kv.first);
  std::sort(starts.begin(), starts.end());  // the same contours whatever the hash order
  for (long s : starts) walk(s);
  std::vector<long> rest;
  for (const auto& kv : next) rest.push_back(kv.first);
  std::sort(rest.begin(), rest.end());
  for (long s : rest)
    if (!used.count(s)) walk(s);
  return out;
}

}  // namespace

std::vector<std::vector<Pass>> waterlineLevels(const Context& ctx, double& mean_step) {
  const Grid& g = ctx.grid;
  std::vector<Cell> cells;
  std::vector<std::pair<double, double>> nodes;  // (height, level spacing) of the waterline nodes
  for (int j = 0; j < g.ny; ++j)
    for (int i = 0; i < g.nx; ++i)
      if (ctx.waterline[g.node(i, j)]) nodes.emplace_back(ctx.height[g.node(i, j)], ctx.level_spacing[g.node(i, j)]);
  for (int j = 0; j + 1 < g.ny; ++j)
    for (int i = 0; i + 1 < g.nx; ++i) {
      const int corners[4] = {g.node(i, j), g.node(i + 1, j), g.node(i + 1, j + 1), g.node(i, j + 1)};
      bool in = false, computed = true;
      double lo = kInf, hi = -kInf;
      for (int c : corners) {
        in = in || ctx.waterline[c];
        computed = computed && !std::isnan(ctx.height[c]);
        lo = std::min(lo, ctx.height[c]);
        hi = std::max(hi, ctx.height[c]);
      }
      if (in && computed) cells.push_back({i, j, lo, hi});
    }
  mean_step = 0;
  if (cells.empty() || nodes.empty()) return {};
  std::sort(nodes.begin(), nodes.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  const double top = nodes.front().first, bottom = nodes.back().first;
  // The least spacing of the nodes within [z - step, z + above], shrinking step to it.
  std::size_t from = 0;
  auto stepBelow = [&](double z, double above) {
    while (from < nodes.size() && nodes[from].first > z + above) ++from;
    double step = kInf;
    for (std::size_t k = from; k < nodes.size() && nodes[k].first >= z - step; ++k) step = std::min(step, nodes[k].second);
    return step;
  };
  std::vector<double> zs;
  double z = top - 0.5 * stepBelow(top, 0);
  while (true) {
    zs.push_back(z);
    if (z <= bottom) break;
    z -= stepBelow(z, 0);
  }
  if (zs.size() > 1) mean_step = (zs.front() - zs.back()) / (zs.size() - 1);
  // Levels in consecutive blocks, a block's levels in turn (sharing the drops along the edges they cross).
  std::vector<std::vector<Pass>> out(zs.size());
  const int count = static_cast<int>(zs.size());
  const int blocks = std::min(count, 2 * threadCount(ctx.threads));
  parallelFor(blocks, ctx.threads, [&](int b) {
    EdgeSamples samples;
    for (int k = b * count / blocks; k < (b + 1) * count / blocks; ++k) out[k] = contoursAt(ctx, cells, zs[k], samples);
  });
  return out;
}

}  // namespace art2part::surface
