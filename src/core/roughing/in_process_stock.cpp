#include "art2part/roughing/in_process_stock.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "art2part/common/parallel.h"
#include "art2part/simulation/cylinder_sweep.h"
#include "art2part/simulation/mesh_dexels.h"
#include "art2part/simulation/part_distance.h"
#include "art2part/simulation/sweep.h"

namespace art2part {

namespace {

// The lattice's cells are never finer than this, whatever the rays asked: the model only needs to know where whole
// slabs of stock are gone.
constexpr double kFinestCellMm = 0.5;
constexpr int kMostThreads = 8;  // projecting the slabs

DexelLattice coarseLattice(const Box& box, long rays, double coarsest, long max_rays) {
  if (rays < 1 || !(coarsest > 0) || max_rays < 1)
    throw InputError("in-process stock: the ray counts must be at least 1 and the coarsest cell positive");
  const Vec3 s = box.size();
  const double area = s.x() * s.y();
  const double cell = std::min(std::sqrt(area / static_cast<double>(rays)), coarsest);
  return DexelLattice::over(box, std::max({kFinestCellMm, cell, std::sqrt(area / static_cast<double>(max_rays))}));
}

// A raster of the frame's x-y plane, a bit per cell.
struct Raster {
  double x0 = 0, y0 = 0, cell = 1;
  int nx = 0, ny = 0;
  std::vector<std::uint64_t> bits;
  void mark(double x, double y) {
    const int i = static_cast<int>(std::floor((x - x0) / cell)), j = static_cast<int>(std::floor((y - y0) / cell));
    if (i < 0 || j < 0 || i >= nx || j >= ny) return;
    const std::size_t k = static_cast<std::size_t>(j) * nx + i;
    bits[k >> 6] |= std::uint64_t(1) << (k & 63);
  }
  // Every cell a segment along a raster axis crosses (a sample every half cell marks no other).
  void markRun(const Point2& a, const Point2& b) {
    const int i0 = static_cast<int>(std::floor((std::min(a.x(), b.x()) - x0) / cell));
    const int i1 = static_cast<int>(std::floor((std::max(a.x(), b.x()) - x0) / cell));
    const int j0 = static_cast<int>(std::floor((std::min(a.y(), b.y()) - y0) / cell));
    const int j1 = static_cast<int>(std::floor((std::max(a.y(), b.y()) - y0) / cell));
    for (int j = std::max(j0, 0); j <= std::min(j1, ny - 1); ++j)
      for (int i = std::max(i0, 0); i <= std::min(i1, nx - 1); ++i) {
        const std::size_t k = static_cast<std::size_t>(j) * nx + i;
        bits[k >> 6] |= std::uint64_t(1) << (k & 63);
      }
  }
  bool marked(double x, double y) const {
    return at(static_cast<int>(std::floor((x - x0) / cell)), static_cast<int>(std::floor((y - y0) / cell)));
  }
  bool at(int i, int j) const {
    if (i < 0 || j < 0 || i >= nx || j >= ny) return false;
    const std::size_t k = static_cast<std::size_t>(j) * nx + i;
    return (bits[k >> 6] >> (k & 63)) & 1;
  }
};

// The marked cells grown by `grow` cells every way (a square, row pass then column pass), as a region: the runs of
// each row as rectangles. The raster's edge rows and columns reach `grow` cells past it.
Region rasterRegion(const Raster& r, int grow) {
  const int nx = r.nx + 2 * grow, ny = r.ny + 2 * grow;  // the grown raster, offset by `grow`
  std::vector<char> wide(static_cast<std::size_t>(nx) * ny, 0), grown(wide.size(), 0);
  bool any = false;
  std::vector<int> before(r.nx + 1);  // marked cells of the row left of each
  for (int j = 0; j < r.ny; ++j) {
    for (int i = 0; i < r.nx; ++i) before[i + 1] = before[i] + (r.at(i, j) ? 1 : 0);
    if (before[r.nx] == 0) continue;
    any = true;
    for (int w = 0; w < nx; ++w) {
      const int i = w - grow;  // the raster's column
      const int lo = std::clamp(i - grow, 0, r.nx), hi = std::clamp(i + grow + 1, 0, r.nx);
      if (before[hi] > before[lo]) wide[static_cast<std::size_t>(j + grow) * nx + w] = 1;
    }
  }
  if (!any) return {};
  for (int i = 0; i < nx; ++i) {
    int last = -1000000;
    for (int j = 0; j < ny; ++j) {
      if (wide[static_cast<std::size_t>(j) * nx + i]) last = j;
      if (j - last <= grow) grown[static_cast<std::size_t>(j) * nx + i] = 1;
    }
    last = 1000000;
    for (int j = ny - 1; j >= 0; --j) {
      if (wide[static_cast<std::size_t>(j) * nx + i]) last = j;
      if (last - j <= grow) grown[static_cast<std::size_t>(j) * nx + i] = 1;
    }
  }
  // A row's runs, each a rectangle that grows down the rows while the same run recurs (the union has far fewer
  // rectangles to merge: most of a slab's stock is blocks).
  struct Run {
    int i0, i1, j0;  // columns [i0, i1), first row
  };
  std::vector<Ring> rects;
  const auto close = [&](const Run& run, int j1) {  // rows [j0, j1)
    const double x0 = r.x0 + (run.i0 - grow) * r.cell, x1 = r.x0 + (run.i1 - grow) * r.cell;
    const double y0 = r.y0 + (run.j0 - grow) * r.cell, y1 = r.y0 + (j1 - grow) * r.cell;
    rects.push_back({Point2(x0, y0), Point2(x1, y0), Point2(x1, y1), Point2(x0, y1)});
  };
  std::vector<Run> open, next;  // the rectangles reaching the row above, by column
  for (int j = 0; j <= ny; ++j) {
    next.clear();
    std::size_t o = 0;
    for (int i = 0; j < ny && i < nx;) {
      if (!grown[static_cast<std::size_t>(j) * nx + i]) { ++i; continue; }
      int k = i;
      while (k < nx && grown[static_cast<std::size_t>(j) * nx + k]) ++k;
      while (o < open.size() && open[o].i0 < i) close(open[o++], j);
      if (o < open.size() && open[o].i0 == i && open[o].i1 == k) next.push_back(open[o++]);
      else next.push_back({i, k, j});
      i = k;
    }
    while (o < open.size()) close(open[o++], j);
    open.swap(next);
  }
  return regionFromPolygons(rects);
}

// A span end `t` that no span of the raw stock's ray `raw` ends at: a face an operation cut (untouched ends
// keep their value exactly).
bool cutEnd(double t, const SpanList& raw) {
  auto it = std::lower_bound(raw.begin(), raw.end(), t, [](const Span& s, double v) { return s.hi < v; });
  return it == raw.end() || (it->lo != t && it->hi != t);
}

}  // namespace

InProcessStock::InProcessStock(const Part& solid, const Mesh& stock, long rays, double coarsest, long max_rays) {
  Box box = boundingBox(stock);
  box.extend(boundingBox(solid.mesh).min);
  box.extend(boundingBox(solid.mesh).max);
  const DexelLattice lattice = coarseLattice(box, rays, coarsest, max_rays);
  part_ = std::make_unique<MeshDexels>(solid.mesh, lattice);
  stock_ = meshStock(MeshDexels(stock, lattice));
  addSolid(stock_, *part_);
  raw_ = stock_;
  distance_ = std::make_unique<PartDistance>(solid.mesh);
}

InProcessStock::~InProcessStock() = default;

double InProcessStock::cell() const { return stock_.lattice.spacing.maxCoeff(); }

double InProcessStock::doubt() const { return 0.5 * stock_.lattice.spacing.norm() + 2 * cell(); }

double InProcessStock::volume() const { return stock_.volume(); }

namespace {

// The part of `tool` at least `by` inside it everywhere, as a flat end mill whose tip lies `by` up the axis: radius
// less by `by` (and by a bull's corner), flutes shorter by `by` at both ends. False when nothing is left.
bool erodedTool(const Tool& tool, double by, Tool& eroded) {
  eroded = tool;
  eroded.type = ToolType::Flat;
  eroded.corner_radius = 0;
  eroded.diameter = tool.diameter - 2 * (by + (tool.type == ToolType::Flat ? 0.0 : tool.corner_radius));
  eroded.flute_length = tool.flute_length - 2 * by;
  eroded.stickout = tool.stickout - by;
  eroded.shank_diameter = std::min(tool.shank_diameter, eroded.diameter);
  eroded.max_stepdown = eroded.max_stepover = 0;  // cutting data the smaller solid would fail validation on
  return eroded.diameter > 0 && eroded.flute_length > 0;
}

}  // namespace

// What a tool eroded by half a cell's diagonal takes from a ray, the real tool takes from the whole cell around it:
// so every point of material left lies within half a cell's diagonal of material left on a ray, and the slabs need
// to grow by one cell only. Sweeping the real tool instead took away, between rays, corners it rounds off and walls it
// passes by (CTC-02: a later setup's holder met such remnants 0.42 mm deep, 473 collisions, with two cells grown);
// a tool thinner than a cell takes nothing from the model.
void InProcessStock::remove(const Toolpath& path, const std::vector<Tool>& tools) {
  if (path.empty()) return;
  const double by = 0.5 * std::sqrt(2.0) * stock_.lattice.spacing.maxCoeff();
  std::map<std::string, bool> cuts;
  for (const Tool& t : tools) {
    Tool eroded;
    cuts[t.id] = erodedTool(t, by, eroded);
    if (cuts[t.id] && !solids_.count(t.id)) solids_[t.id] = toolSolid(eroded, 0.01);
  }
  Toolpath shifted;
  shifted.reserve(path.size());
  for (const CutterLocation& cl : path)
    if (cuts[cl.tool]) {
      shifted.push_back(cl);
      shifted.back().tip += by * cl.axis.normalized();
    }
  if (shifted.empty()) return;
  // Only flutes take material (sweep.h). Moves of cylindrical flutes that keep their axis are swept in closed form
  // (cylinder_sweep.h), a ramp's pieces reaching at most half the erosion beyond its true sweep: still inside what
  // the real tool swept. The other runs pose by pose, each after the point it starts from and numbered apart (the
  // setup field) so that none continues another. Removal does not depend on the order.
  std::vector<SweptCylinder> exact;
  Toolpath rest;
  int runs_apart = 0;
  for (const StraightRun& run : straightRuns(shifted)) {
    const CutterLocation& end = shifted[run.last];
    const CutterLocation& start = run.placed ? end : shifted[run.first - 1];
    const std::size_t before = exact.size();
    bool cylinders = true;
    for (const ToolPiece& piece : solids_.at(end.tool).pieces)
      if (piece.zone == ToolZone::Flutes &&
          !(cylinders = sweptCylinders(piece, {start.tip, start.axis}, {end.tip, end.axis}, 0.5 * by, exact)))
        break;
    if (cylinders) continue;
    exact.resize(before);
    for (int row = run.placed ? run.first : run.first - 1; row <= run.last; ++row) {
      rest.push_back(shifted[row]);
      rest.back().setup = runs_apart;
    }
    ++runs_apart;
  }
  removeSweptCylinders(stock_, exact);
  SweepOptions options;
  options.cusp_step = false;
  if (!rest.empty()) sweepToolpath(stock_, *part_, *distance_, rest, solids_, options);
  for (std::vector<std::uint64_t>& memo : across_) memo.clear();
  asked_.clear();
}

std::vector<Region> InProcessStock::slabs(const SetupFrame& frame,
                                          const std::vector<std::pair<double, double>>& slabs) const {
  return project(frame, slabs, Projection::All);
}

std::vector<Region> InProcessStock::provenSlabs(const SetupFrame& frame,
                                                const std::vector<std::pair<double, double>>& slabs) const {
  return project(frame, slabs, Projection::Proven);
}

std::vector<Region> InProcessStock::cutSlabs(const SetupFrame& frame,
                                             const std::vector<std::pair<double, double>>& slabs) const {
  return project(frame, slabs, Projection::Cuts);
}

bool InProcessStock::stockAlong(int axis, const Vec3& p) const {
  const DexelLattice& lattice = stock_.lattice;
  const double reach = lattice.spacing.maxCoeff();
  const int u = DexelLattice::uAxis(axis), v = DexelLattice::vAxis(axis);
  const int iu = static_cast<int>(std::floor((p[u] - lattice.box.min[u]) / lattice.spacing[u]));
  const int iv = static_cast<int>(std::floor((p[v] - lattice.box.min[v]) / lattice.spacing[v]));
  if (iu < 0 || iv < 0 || iu >= lattice.cells[u] || iv >= lattice.cells[v]) return false;
  const int ray = lattice.rayIndex(axis, iu, iv);
  const SpanList& spans = stock_.ray(axis, ray);
  const double lo = p[axis] - reach, hi = p[axis] + reach;
  auto it = std::upper_bound(spans.begin(), spans.end(), lo, [](double t, const Span& s) { return t < s.hi; });
  return it != spans.end() && it->lo <= lo && it->hi >= hi && !partNear(axis, ray, p[axis]);
}

bool InProcessStock::partNear(int axis, int ray, double t) const {
  const double clearance = kPartClearanceCells * stock_.lattice.spacing.maxCoeff();
  for (const SolidSpan* s = part_->begin(axis, ray); s != part_->end(axis, ray); ++s)
    if (s->hi >= t - clearance && s->lo <= t + clearance) return true;
  return false;
}

// Stock at `p`: material a cell every way along the three axes (on the nearest ray of each family, one span holds
// [p - cell, p + cell] along the ray) and no part within kPartClearanceCells along any of them. A film the eroded
// tools left on a cut face (at most half a cell's diagonal thick along the face's normal) fails the first test along
// the axis nearest that normal for every face whose normal lies in a coordinate plane; the part fails the second, and
// so does the allowance with the film over a face finished to it (0.9 cell along the normal at 1.5 mm cells and a
// 0.3 mm allowance) along the axis nearest the face's normal when that lies within 25 deg of it.
bool InProcessStock::provenOnRay(int axis, int iu, int iv, const Span& span, const Vec3& p) const {
  const DexelLattice& lattice = stock_.lattice;
  const int c = static_cast<int>(std::floor((p[axis] - lattice.box.min[axis]) / lattice.spacing[axis]));
  if (c < 0 || c >= lattice.cells[axis]) return false;
  // stockAlong on the ray itself, whose span holding p is known.
  const double reach = lattice.spacing.maxCoeff();
  const int ray = lattice.rayIndex(axis, iu, iv);
  if (span.lo > p[axis] - reach || span.hi < p[axis] + reach || partNear(axis, ray, p[axis])) return false;
  const int words = (lattice.cells[axis] + 31) / 32;  // per ray
  std::uint64_t& word = across_[axis][static_cast<std::size_t>(ray) * words + c / 32];
  const int shift = 2 * (c % 32);
  std::uint64_t state = (word >> shift) & 3;
  if (state == 0) {
    state = stockAlong(DexelLattice::uAxis(axis), p) && stockAlong(DexelLattice::vAxis(axis), p) ? 1 : 2;
    word |= state << shift;
  }
  return state == 1;
}

std::vector<Region> InProcessStock::project(const SetupFrame& frame,
                                            const std::vector<std::pair<double, double>>& slabs,
                                            Projection what) const {
  const auto same = [&](const Asked& a) {
    return a.what == what && a.slabs == slabs && a.frame.origin == frame.origin && a.frame.x == frame.x &&
           a.frame.y == frame.y && a.frame.z == frame.z;
  };
  for (const Asked& a : asked_)
    if (same(a)) return a.regions;
  asked_.push_back({what, frame, slabs, walk(frame, slabs, what)});
  return asked_.back().regions;
}

std::vector<Region> InProcessStock::walk(const SetupFrame& frame, const std::vector<std::pair<double, double>>& slabs,
                                         Projection what) const {
  const bool proven = what == Projection::Proven;
  const double doubt_band = doubt();
  const DexelLattice& lattice = stock_.lattice;
  // The raster spans the lattice box's projection; its cells as large as the lattice's.
  Raster proto;
  proto.cell = lattice.spacing.maxCoeff();
  double x1 = -1e300, y1 = -1e300;
  proto.x0 = proto.y0 = 1e300;
  for (int c = 0; c < 8; ++c) {
    const Vec3 p(c & 1 ? lattice.box.max.x() : lattice.box.min.x(), c & 2 ? lattice.box.max.y() : lattice.box.min.y(),
                 c & 4 ? lattice.box.max.z() : lattice.box.min.z());
    const Vec3 d = p - frame.origin;
    proto.x0 = std::min(proto.x0, d.dot(frame.x));
    proto.y0 = std::min(proto.y0, d.dot(frame.y));
    x1 = std::max(x1, d.dot(frame.x));
    y1 = std::max(y1, d.dot(frame.y));
  }
  proto.nx = static_cast<int>(std::ceil((x1 - proto.x0) / proto.cell)) + 1;
  proto.ny = static_cast<int>(std::ceil((y1 - proto.y0) / proto.cell)) + 1;
  proto.bits.assign((static_cast<std::size_t>(proto.nx) * proto.ny + 63) / 64, 0);
  // Slabs by their bottom, highest first: a piece of a column visits only those it can reach (a hot loop: rays x
  // spans x slabs otherwise).
  std::vector<std::size_t> order(slabs.size());
  double tallest = 0;
  for (std::size_t i = 0; i < slabs.size(); ++i) {
    order[i] = i;
    tallest = std::max(tallest, slabs[i].second - slabs[i].first);
  }
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return slabs[a].first > slabs[b].first; });
  const double step = 0.5 * proto.cell;
  if (proven)  // the first proof since the model changed: every cell unasked
    for (int axis = 0; axis < 3; ++axis)
      if (across_[axis].empty())
        across_[axis].assign(static_cast<std::size_t>(lattice.rayCount(axis)) * ((lattice.cells[axis] + 31) / 32), 0);
  // The rays of rows [row0, row1) of family `axis` marked on `rasters`.
  const auto walkRows = [&](int axis, int row0, int row1, std::vector<Raster>& rasters) {
    const Vec3 along(frame.x[axis], frame.y[axis], frame.z[axis]);  // the rays' direction in the frame
    // A ray stands for a column a cell wide: its material reaches this far along the frame's z beyond the ray.
    const int u = DexelLattice::uAxis(axis), v = DexelLattice::vAxis(axis);
    // Proven material is only what lies in the slab.
    const double thick =
        proven ? 0.0 : 0.5 * (std::abs(frame.z[u]) * lattice.spacing[u] + std::abs(frame.z[v]) * lattice.spacing[v]);
    const int nu = lattice.cells[u];
    for (int iv = row0; iv < row1; ++iv)
      for (int iu = 0; iu < nu; ++iu) {
        const SpanList& spans = stock_.ray(axis, lattice.rayIndex(axis, iu, iv));
        if (spans.empty()) continue;
        const Vec3 ray0 = lattice.rayOrigin(axis, iu, iv);
        const Vec3 d = ray0 - frame.origin;
        const Vec3 origin(d.dot(frame.x), d.dot(frame.y), d.dot(frame.z));  // the ray at t = 0, in the frame
        if (what == Projection::Cuts) {  // each cut end on the slabs within the doubt of it
          const SpanList& raw = raw_.ray(axis, lattice.rayIndex(axis, iu, iv));
          for (const Span& span : spans)
            for (const double t : {span.lo, span.hi}) {
              if (!cutEnd(t, raw)) continue;
              const Vec3 at = origin + t * along;
              auto first = std::partition_point(order.begin(), order.end(),
                                                [&](std::size_t i) { return slabs[i].first - doubt_band > at.z(); });
              for (auto it = first; it != order.end() && slabs[*it].first + tallest + doubt_band >= at.z(); ++it)
                if (at.z() <= slabs[*it].second + doubt_band) rasters[*it].mark(at.x(), at.y());
            }
          continue;
        }
        for (const Span& span : spans) {
          const double za = origin.z() + span.lo * along.z(), zb = origin.z() + span.hi * along.z();
          const double zlo = std::min(za, zb), zhi = std::max(za, zb);
          // The first slab whose (grown) bottom is at or below the piece's top, down to those too low to reach it.
          auto first = std::partition_point(order.begin(), order.end(),
                                            [&](std::size_t i) { return slabs[i].first - thick > zhi; });
          for (auto it = first; it != order.end() && slabs[*it].first + tallest + thick >= zlo; ++it) {
            const std::size_t s = *it;
            const double lo = slabs[s].first - thick, hi = slabs[s].second + thick;
            if (hi < zlo || lo > zhi) continue;
            // The piece of the span inside the slab.
            double t0 = span.lo, t1 = span.hi;
            if (std::abs(along.z()) > 1e-12) {
              double a = (lo - origin.z()) / along.z(), b = (hi - origin.z()) / along.z();
              if (a > b) std::swap(a, b);
              t0 = std::max(t0, a);
              t1 = std::min(t1, b);
              if (t0 > t1) continue;
            }
            const Point2 p0(origin.x() + t0 * along.x(), origin.y() + t0 * along.y());
            const Point2 p1(origin.x() + t1 * along.x(), origin.y() + t1 * along.y());
            if (!proven && (std::abs(p1.x() - p0.x()) < 1e-9 || std::abs(p1.y() - p0.y()) < 1e-9)) {
              rasters[s].markRun(p0, p1);  // a frame square to the lattice: the samples below, at once
              continue;
            }
            const int n = static_cast<int>(std::ceil(std::max((p1 - p0).norm(), proven ? t1 - t0 : 0.0) / step)) + 1;
            for (int k = 0; k <= n; ++k) {
              const double f = static_cast<double>(k) / n;
              const Point2 q = p0 + (p1 - p0) * f;
              if (proven) {  // the proof costs three searches: not for a cell already marked
                if (rasters[s].marked(q.x(), q.y())) continue;
                Vec3 at = ray0;
                at[axis] = t0 + (t1 - t0) * f;
                if (!provenOnRay(axis, iu, iv, span, at)) continue;
              }
              rasters[s].mark(q.x(), q.y());
            }
          }
        }
      }
  };
  // Every family of rays (a wall thinner than a cell that one family passes between is crossed by another), each
  // thread its share of every family's rows on rasters of its own, merged after.
  const int threads = std::min(threadCount(0), kMostThreads);
  std::vector<std::vector<Raster>> own(threads, std::vector<Raster>(slabs.size(), proto));
  parallelFor(threads, threads, [&](int t) {
    for (int axis = 0; axis < 3; ++axis) {
      const int rows = lattice.cells[DexelLattice::vAxis(axis)];
      walkRows(axis, rows * t / threads, rows * (t + 1) / threads, own[t]);
    }
  });
  std::vector<Raster>& rasters = own[0];
  for (int t = 1; t < threads; ++t)
    for (std::size_t s = 0; s < slabs.size(); ++s)
      for (std::size_t w = 0; w < rasters[s].bits.size(); ++w) rasters[s].bits[w] |= own[t][s].bits[w];
  // A cell more: material lies within half a cell's diagonal of a ray's (see remove), and the points marked are half
  // a cell apart.
  // Proven stock grows back by two cells: its proof stops a cell inside the material, and a marked cell stands for a
  // point in it.
  const int grow = what == Projection::Proven ? 2
                   : what == Projection::Cuts  ? static_cast<int>(std::ceil(doubt_band / proto.cell))
                                               : 1;
  std::vector<Region> out(slabs.size());
  parallelForRegions(static_cast<int>(slabs.size()), [&](int s) { out[s] = rasterRegion(rasters[s], grow); });
  return out;
}

}  // namespace art2part
