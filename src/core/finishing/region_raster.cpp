// Regions on a grid of nodes and grown there (region_raster.h).
#include "art2part/finishing/region_raster.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "art2part/geometry/mesh.h"

namespace art2part {

int NodeGrid::nearestI(double x) const {
  return std::clamp(static_cast<int>(std::lround((x - x0) / pitch)), 0, nx - 1);
}

int NodeGrid::nearestJ(double y) const {
  return std::clamp(static_cast<int>(std::lround((y - y0) / pitch)), 0, ny - 1);
}

namespace {

constexpr double kNone = -std::numeric_limits<double>::infinity();

// Heights per cell of a grid: the cell of node (i, j) is the pitch square centred on it.
struct CellHeights {
  NodeGrid grid;
  std::vector<double> height;
  void raise(int i, int j, double h) {
    if (i < 0 || j < 0 || i >= grid.nx || j >= grid.ny) return;
    double& at = height[grid.node(i, j)];
    at = std::max(at, h);
  }
};

// Raises the cells whose node lies inside the region (even-odd over its rings: Clipper's regions are unions, so that
// is their winding rule too), row by row from the crossings of the rings' edges.
void raiseNodesInside(CellHeights& cells, const Region& region, double h) {
  const NodeGrid& g = cells.grid;
  std::vector<std::vector<double>> crossings(g.ny);
  for (const ClipperLib::Path& ring : region)
    for (std::size_t k = 0; k < ring.size(); ++k) {
      const Point2 a = fromRegionPoint(ring[k]), b = fromRegionPoint(ring[(k + 1) % ring.size()]);
      if (a.y() == b.y()) continue;
      const double lo = std::min(a.y(), b.y()), hi = std::max(a.y(), b.y());
      // Rows with lo <= y < hi: each crossing counted once where two edges meet at a vertex.
      const int first = std::max(0, static_cast<int>(std::ceil((lo - g.y0) / g.pitch)));
      const int last = std::min(g.ny - 1, static_cast<int>(std::ceil((hi - g.y0) / g.pitch)) - 1);
      for (int j = first; j <= last; ++j) {
        const double y = g.y(j);
        if (y < lo || y >= hi) continue;
        crossings[j].push_back(a.x() + (y - a.y()) * (b.x() - a.x()) / (b.y() - a.y()));
      }
    }
  for (int j = 0; j < g.ny; ++j) {
    std::vector<double>& xs = crossings[j];
    std::sort(xs.begin(), xs.end());
    for (std::size_t k = 0; k + 1 < xs.size(); k += 2) {
      const int from = std::max(0, static_cast<int>(std::ceil((xs[k] - g.x0) / g.pitch)));
      const int to = std::min(g.nx - 1, static_cast<int>(std::floor((xs[k + 1] - g.x0) / g.pitch)));
      for (int i = from; i <= to; ++i) cells.raise(i, j, h);
    }
  }
}

// Raises every cell the segment a-b passes through (cell coordinates: node i's cell is [i, i + 1) in u = (x - x0) /
// pitch + 1/2), walking from cell to cell across their sides (Amanatides and Woo); the part of the segment outside
// the grid is clipped off first. Through a corner both neighbours are taken.
void raiseCellsAlong(CellHeights& cells, Point2 a, Point2 b, double h) {
  const NodeGrid& g = cells.grid;
  const auto u = [&](const Point2& p) { return Point2((p.x() - g.x0) / g.pitch + 0.5, (p.y() - g.y0) / g.pitch + 0.5); };
  Point2 p = u(a), q = u(b);
  // Liang-Barsky against [0, nx] x [0, ny].
  double t0 = 0, t1 = 1;
  const Point2 d = q - p;
  const double lows[2] = {0, 0}, highs[2] = {static_cast<double>(g.nx), static_cast<double>(g.ny)};
  for (int axis = 0; axis < 2; ++axis) {
    if (d[axis] == 0) {
      if (p[axis] < lows[axis] || p[axis] > highs[axis]) return;
      continue;
    }
    double ta = (lows[axis] - p[axis]) / d[axis], tb = (highs[axis] - p[axis]) / d[axis];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    if (t0 > t1) return;
  }
  const Point2 s = p + t0 * d, e = p + t1 * d;
  int i = static_cast<int>(std::floor(s.x())), j = static_cast<int>(std::floor(s.y()));
  const int ie = static_cast<int>(std::floor(e.x())), je = static_cast<int>(std::floor(e.y()));
  const int si = e.x() > s.x() ? 1 : -1, sj = e.y() > s.y() ? 1 : -1;
  const double dx = e.x() - s.x(), dy = e.y() - s.y();
  const double inf = std::numeric_limits<double>::infinity();
  double next_x = dx != 0 ? ((si > 0 ? i + 1 : i) - s.x()) / dx : inf;
  double next_y = dy != 0 ? ((sj > 0 ? j + 1 : j) - s.y()) / dy : inf;
  const double step_x = dx != 0 ? std::abs(1 / dx) : inf, step_y = dy != 0 ? std::abs(1 / dy) : inf;
  for (int steps = std::abs(ie - i) + std::abs(je - j); steps > 0; --steps) {
    cells.raise(i, j, h);
    if (next_x < next_y) {
      i += si;
      next_x += step_x;
    } else {
      j += sj;
      next_y += step_y;
    }
  }
  cells.raise(i, j, h);
  cells.raise(ie, je, h);
}

// The occupied stretch of a row of cells: its cells lo..hi (the rest hold nothing), with the maxima of its prefixes
// and suffixes and, for windows inside it, those of blocks of the window's length from their start and from their end
// (van Herk, Gil and Werman).
struct RowStretch {
  int lo = 0, hi = -1;
  const double* cells = nullptr;  // the row's cell lo
  std::vector<double> prefix, suffix, block_start, block_end;
};

// Per output column c (cell first + c stride) the highest cell of the stretch within w of it: the sliding maximum
// over windows of 2 w + 1, clipped to the stretch.
void slidingMax(RowStretch& row, int w, int first, int stride, std::vector<double>& out) {
  const int m = row.hi - row.lo + 1, width = 2 * w + 1;
  const double* a = row.cells;
  if (m > width) {  // windows may lie inside the stretch
    row.block_start.resize(m);
    row.block_end.resize(m);
    for (int e = 0; e < m; ++e) row.block_start[e] = e % width == 0 ? a[e] : std::max(row.block_start[e - 1], a[e]);
    for (int e = m - 1; e >= 0; --e)
      row.block_end[e] = e % width == width - 1 || e == m - 1 ? a[e] : std::max(row.block_end[e + 1], a[e]);
  }
  for (std::size_t k = 0; k < out.size(); ++k) {
    const int c = first + static_cast<int>(k) * stride - row.lo;  // in the stretch's indices
    const int from = c - w, to = c + w;
    if (to < 0 || from >= m) {
      out[k] = kNone;
    } else if (from <= 0) {
      out[k] = row.prefix[std::min(to, m - 1)];
    } else if (to >= m - 1) {
      out[k] = row.suffix[from];
    } else {
      out[k] = std::max(row.block_end[from], row.block_start[to]);
    }
  }
}

}  // namespace

std::vector<std::vector<double>> highestNear(const NodeGrid& grid, const std::vector<RegionAtHeight>& levels,
                                             const std::vector<double>& radii, double cell) {
  if (!(grid.pitch > 0)) throw InputError("highestNear: the grid's pitch must be positive");
  if (!(cell > 0)) throw InputError("highestNear: the cells' pitch must be positive");
  for (double r : radii)
    if (!(r >= 0)) throw InputError("highestNear: a radius must be at least 0");
  // Cells of the grid's pitch divided by the least whole number that brings them to `cell` or under; the grid's node
  // (i, j) is the cells' (pad + f i, pad + f j).
  const int f = std::max(1, static_cast<int>(std::ceil(grid.pitch / cell - 1e-9)));
  const double q = grid.pitch / f;
  double reach = 0;
  for (double r : radii) reach = std::max(reach, r + q);
  // The cells padded by those a region can reach the grid's nodes from.
  const int pad = static_cast<int>(std::ceil(reach / q)) + 1;
  CellHeights cells;
  cells.grid = NodeGrid{grid.x0 - pad * q, grid.y0 - pad * q, q, (grid.nx - 1) * f + 1 + 2 * pad,
                        (grid.ny - 1) * f + 1 + 2 * pad};
  cells.height.assign(cells.grid.size(), kNone);
  for (const RegionAtHeight& level : levels) {
    if (level.region == nullptr) continue;
    raiseNodesInside(cells, *level.region, level.height);
    for (const ClipperLib::Path& ring : *level.region)
      for (std::size_t k = 0; k < ring.size(); ++k)
        raiseCellsAlong(cells, fromRegionPoint(ring[k]), fromRegionPoint(ring[(k + 1) % ring.size()]), level.height);
  }
  const NodeGrid& padded = cells.grid;
  std::vector<RowStretch> rows(padded.ny);
  for (int j = 0; j < padded.ny; ++j) {
    RowStretch& row = rows[j];
    const double* c = cells.height.data() + static_cast<std::ptrdiff_t>(j) * padded.nx;
    row.lo = 0;
    while (row.lo < padded.nx && c[row.lo] == kNone) ++row.lo;
    row.hi = padded.nx - 1;
    while (row.hi >= row.lo && c[row.hi] == kNone) --row.hi;
    if (row.hi < row.lo) continue;
    row.cells = c + row.lo;
    const int m = row.hi - row.lo + 1;
    row.prefix.resize(m);
    row.suffix.resize(m);
    for (int e = 0; e < m; ++e) row.prefix[e] = std::max(e > 0 ? row.prefix[e - 1] : kNone, row.cells[e]);
    for (int e = m - 1; e >= 0; --e) row.suffix[e] = std::max(e + 1 < m ? row.suffix[e + 1] : kNone, row.cells[e]);
  }

  std::vector<std::vector<double>> maps;
  std::vector<double> out(grid.nx);
  const int last_column = pad + (grid.nx - 1) * f;
  for (double r : radii) {
    std::vector<double> map(grid.size(), kNone);
    // The nodes within r of a cell's square: rows dj with the square's nearer side |dj| q - q / 2 within r, each
    // with the columns di likewise. Rows dj and -dj take the same windows.
    const int k = static_cast<int>(std::floor((r + 0.5 * q) / q));
    for (int dj = 0; dj <= k; ++dj) {
      const double across = std::max(0.0, dj * q - 0.5 * q);
      const int w = static_cast<int>(std::floor((std::sqrt(std::max(0.0, r * r - across * across)) + 0.5 * q) / q));
      for (int source = 0; source < padded.ny; ++source) {
        RowStretch& row = rows[source];
        if (row.hi < row.lo || row.hi < pad - w || row.lo > last_column + w) continue;
        int targets[2], count = 0;  // the grid's rows it reaches: cell rows source -+ dj on a node's row
        for (const int cell_row : {source - pad - dj, source - pad + dj}) {
          if (count == 1 && dj == 0) break;
          if (cell_row < 0 || cell_row % f != 0 || cell_row / f >= grid.ny) continue;
          targets[count++] = cell_row / f;
        }
        if (count == 0) continue;
        slidingMax(row, w, pad, f, out);
        for (int t = 0; t < count; ++t) {
          double* at = map.data() + static_cast<std::ptrdiff_t>(targets[t]) * grid.nx;
          for (int i = 0; i < grid.nx; ++i) at[i] = std::max(at[i], out[i]);
        }
      }
    }
    maps.push_back(std::move(map));
  }
  return maps;
}

}  // namespace art2part
