#include "art2part/simulation/sweep.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <memory>

#include "art2part/common/parallel.h"

namespace art2part {

const char* collisionKindName(CollisionKind kind) {
  switch (kind) {
    case CollisionKind::Shank: return "shank";
    case CollisionKind::Holder: return "holder";
    case CollisionKind::Rapid: return "rapid";
  }
  return "?";
}

namespace {

constexpr int kRowBlock = 4;       // rows per block handed out to the threads in turn
constexpr int kTileColumns = 16;   // a tile: kTileColumns rays of kRowBlock rows, all of one thread's
constexpr int kGougeSamples = 8;   // points measured between the ends of a long removed span
constexpr double kInfinity = 1e300;

// First and last coordinate of material along every ray, by family: most rays a pose's box meets are rejected on
// these without touching their span lists.
using Extents = std::array<std::vector<Span>, 3>;

Span extentOf(const SpanList& spans) {
  return spans.empty() ? Span{kInfinity, -kInfinity} : Span{spans.front().lo, spans.back().hi};
}

// The widest stretch of air between two spans of material along a ray (empty, lo >= hi, when there is none): a piece
// whose span lies inside it cuts nothing there, the usual case for the flutes of a finishing tool over a pocket.
Span widestGap(const SpanList& spans) {
  Span gap{0, 0};
  for (std::size_t i = 1; i < spans.size(); ++i)
    if (spans[i].lo - spans[i - 1].hi > gap.length()) gap = {spans[i - 1].hi, spans[i].lo};
  return gap;
}

bool inside(const Span& a, const Span& b) { return a.lo >= b.lo && a.hi <= b.hi; }

Extents stockExtents(const Stock& stock) {
  Extents e;
  for (int axis = 0; axis < 3; ++axis)
    for (const SpanList& spans : stock.dexels[axis]) e[axis].push_back(extentOf(spans));
  return e;
}

Extents stockGaps(const Stock& stock) {
  Extents e;
  for (int axis = 0; axis < 3; ++axis)
    for (const SpanList& spans : stock.dexels[axis]) e[axis].push_back(widestGap(spans));
  return e;
}

Extents solidExtents(const MeshDexels& solid) {
  Extents e;
  for (int axis = 0; axis < 3; ++axis)
    for (int ray = 0; ray < solid.lattice().rayCount(axis); ++ray) {
      const bool empty = solid.begin(axis, ray) == solid.end(axis, ray);
      e[axis].push_back(empty ? Span{kInfinity, -kInfinity}
                              : Span{solid.begin(axis, ray)->lo, (solid.end(axis, ray) - 1)->hi});
    }
  return e;
}

void mergeFinding(MoveFinding& into, const MoveFinding& from) {
  if (from.gouge_mm > into.gouge_mm) {
    into.gouge_mm = from.gouge_mm;
    into.gouge_point = from.gouge_point;
    into.gouge_tip = from.gouge_tip;
  }
  if (from.collision_mm > into.collision_mm) {
    into.collision_mm = from.collision_mm;
    into.collision = from.collision;
    into.collision_point = from.collision_point;
    into.collision_tip = from.collision_tip;
  }
}

// Where the tip was when the tool, sliding along the ray through the pose's slide, first reached coordinate t (its
// span at the pose being `span`): its leading end meets t then.
Vec3 tipWhenReached(const SweepPose& pose, Span span, int axis, double t) {
  Vec3 tip = pose.pose.tip;
  if (pose.slide > 0.0) tip[axis] -= std::clamp(span.hi - t, 0.0, pose.slide);
  if (pose.slide < 0.0) tip[axis] += std::clamp(t - span.lo, 0.0, -pose.slide);
  return tip;
}

// The sub-step that leaves cusps of at most half the tolerance between poses on the walls the flutes cut
// (step^2 / (8 rho) for the flutes' widest radius rho): at a coarse lattice half the spacing would leave more, and a
// later rapid past such a wall would read the cusps as a collision (0.03 mm for a 20 mm tool at a 3.1 mm lattice).
double cuspStep(const ToolSolid& tool, double tolerance) {
  double rho = 0;
  for (const ToolPiece& piece : tool.pieces)
    if (piece.zone == ToolZone::Flutes) rho = std::max(rho, piece.maxRadius());
  return rho > 0 ? std::sqrt(4.0 * rho * std::max(tolerance, 1e-4)) : kInfinity;
}

// Where material may lie along the rays of each tile of a family: the union of its rays' extents, recomputed when
// one of them has changed since (a pose's box rejects a whole tile on it, most of the tool, shank and holder in air).
// A worker keeps its own and reads only the tiles of its rows.
class TileExtents {
 public:
  TileExtents(const DexelLattice& lattice, const Extents& extents) : lattice_(lattice), extents_(extents) {
    for (int axis = 0; axis < 3; ++axis) {
      columns_[axis] = (lattice.cells[DexelLattice::uAxis(axis)] + kTileColumns - 1) / kTileColumns;
      const int rows = (lattice.cells[DexelLattice::vAxis(axis)] + kRowBlock - 1) / kRowBlock;
      tiles_[axis].assign(static_cast<std::size_t>(columns_[axis]) * rows, Span{});
      stale_[axis].assign(tiles_[axis].size(), 1);
    }
  }

  int tileOf(int axis, int iu, int iv) const { return iu / kTileColumns + columns_[axis] * (iv / kRowBlock); }
  void changed(int axis, int tile) { stale_[axis][tile] = 1; }

  Span extent(int axis, int tile_u, int tile_v) {
    const int tile = tile_u + columns_[axis] * tile_v;
    if (stale_[axis][tile]) {
      Span e{kInfinity, -kInfinity};
      const int nu = lattice_.cells[DexelLattice::uAxis(axis)], nv = lattice_.cells[DexelLattice::vAxis(axis)];
      for (int iv = tile_v * kRowBlock; iv < std::min(nv, (tile_v + 1) * kRowBlock); ++iv)
        for (int iu = tile_u * kTileColumns; iu < std::min(nu, (tile_u + 1) * kTileColumns); ++iu) {
          const Span& ray = extents_[axis][lattice_.rayIndex(axis, iu, iv)];
          e.lo = std::min(e.lo, ray.lo);
          e.hi = std::max(e.hi, ray.hi);
        }
      tiles_[axis][tile] = e;
      stale_[axis][tile] = 0;
    }
    return tiles_[axis][tile];
  }

 private:
  const DexelLattice& lattice_;
  const Extents& extents_;
  std::array<int, 3> columns_{};
  std::array<std::vector<Span>, 3> tiles_;
  std::array<std::vector<std::uint8_t>, 3> stale_;
};

struct Ray {
  int axis, index, tile;
  double u, v;  // its two lattice coordinates

  Vec3 origin() const {  // 0 along it
    Vec3 o = Vec3::Zero();
    o[DexelLattice::uAxis(axis)] = u;
    o[DexelLattice::vAxis(axis)] = v;
    return o;
  }
};

// The deepest level cut seen, and the row ending the run that cut it.
struct LevelCut {
  double mm = 0;
  int row = -1;
  std::vector<double> by_height_mm3;  // OperationSweep::level_cut_by_height_mm3
};

// One thread's share of the sweep: the rows it owns in every family.
class Worker {
 public:
  Worker(Stock& stock, Extents& extents, Extents& gaps, const MeshDexels& part, const Extents& part_extents,
         const PartDistance& distance, const SweepOptions& options, int thread, int threads)
      : stock_(stock), extents_(extents), gaps_(gaps), tiles_(stock.lattice, extents), part_(part),
        part_extents_(part_extents), distance_(distance), options_(options), thread_(thread), threads_(threads) {}

  // Every run given over this worker's rows, in order, until `stop` is raised; after each, the rows swept so far go
  // to `rows_done`.
  void run(const Toolpath& path, const std::vector<StraightRun>& runs, const std::vector<const ToolSolid*>& tools,
           std::atomic<int>& rows_done, const std::atomic<bool>& stop) {
    for (const StraightRun& run : runs) {
      if (stop.load(std::memory_order_relaxed)) return;
      sweepRun(path, *tools[run.last], run);
      rows_done.store(run.last + 1, std::memory_order_relaxed);
    }
  }

  const std::map<int, MoveFinding>& findings() const { return findings_; }
  std::int64_t poses() const { return poses_; }
  // By op, by family: the length of material removed along this worker's rays, mm.
  const std::map<int, std::array<double, 3>>& removedLength() const { return removed_length_; }
  // By op: the deepest level cut on this worker's rays and the row it was cut on (OperationSweep).
  const std::map<int, LevelCut>& deepestLevelCut() const { return deepest_level_cut_; }

 private:
  bool owns(int row) const { return (row / kRowBlock) % threads_ == thread_; }

  void sweepRun(const Toolpath& path, const ToolSolid& tool, const StraightRun& run) {
    const CutterLocation& end = path[run.last];
    const bool rapid = end.move == MoveKind::Rapid;
    const ToolPose to{end.tip, end.axis};
    removed_here_ = &removed_length_[end.op];  // a run never spans two ops (straightRuns)
    level_cut_ = nullptr;
    if (run.placed) {
      finding_ = MoveFinding();
      for (int axis = 0; axis < 3; ++axis) cutPose(tool, {to, 0.0, 0.0}, rapid, axis);
      keep(finding_, run.first);
      ++poses_;
      return;
    }
    const ToolPose from{path[run.first - 1].tip, path[run.first - 1].axis};
    if (!rapid && isLevel(from, to)) {
      level_cut_ = &deepest_level_cut_[end.op];
      level_row_ = run.last;
      level_axis_ = to.axis;
      level_height_ = to.tip.dot(to.axis);
    }
    const double step = std::min(options_.step_fraction * stock_.lattice.minSpacing(),
                                 options_.cusp_step ? cuspStep(tool, options_.tolerance) : kInfinity);
    const double deviation = std::max(0.5 * options_.tolerance, 1e-4);
    std::size_t most = 0;
    for (int axis = 0; axis < 3; ++axis) {
      const std::vector<SweepPose> poses = movePoses(from, to, tool, stock_.lattice.box, step, deviation, axis);
      for (std::size_t s = 0; s < poses.size(); ++s) {
        finding_ = MoveFinding();
        cutPose(tool, poses[s], rapid, axis);
        if (finding_.gouge_mm > 0 || finding_.collision_mm > 0)
          attribute(path, run, static_cast<double>(s) / poses.size(), static_cast<double>(s + 1) / poses.size());
      }
      most = std::max(most, poses.size());
    }
    poses_ += static_cast<std::int64_t>(most);
  }

  // Hands what one pose found to the moves of the run whose stretch holds each point found (within the part of the
  // run, fractions f0..f1, that the pose stands for).
  void attribute(const Toolpath& path, const StraightRun& run, double f0, double f1) {
    const Vec3 start = path[run.first - 1].tip, line = path[run.last].tip - start;
    auto moveAt = [&](const Vec3& point) {
      const double length = line.squaredNorm();
      const double f = length > 0.0 ? std::clamp((point - start).dot(line) / length, f0, f1) : f1;
      int lo = run.first, hi = run.last;  // the first move ending at or beyond f (ends advance along the line)
      while (lo < hi) {
        const int mid = (lo + hi) / 2;
        if ((path[mid].tip - start).dot(line) < f * length) lo = mid + 1;
        else hi = mid;
      }
      return lo;
    };
    const MoveFinding found = finding_;
    MoveFinding gouge, collision;
    gouge.gouge_mm = found.gouge_mm;
    gouge.gouge_point = found.gouge_point;
    gouge.gouge_tip = found.gouge_tip;
    collision = found;
    collision.gouge_mm = 0;
    if (gouge.gouge_mm > 0) keep(gouge, moveAt(found.gouge_tip));
    if (collision.collision_mm > 0) keep(collision, moveAt(found.collision_tip));
  }

  void keep(const MoveFinding& found, int move) {
    if (found.gouge_mm > 0 || found.collision_mm > 0) mergeFinding(findings_[move], found);
  }

  void cutPose(const ToolSolid& tool, const SweepPose& pose, bool rapid, int axis) {
    for (const ToolPiece& piece : tool.pieces) {
      cutPiece(piece, pose, rapid, axis);
      if (pose.rise > 0.0) cutPiece(risePiece(piece, pose.rise), pose, rapid, axis);
    }
  }

  void cutPiece(const ToolPiece& piece, const SweepPose& pose, bool rapid, int axis) {
    Box box = pieceBox(piece, pose.pose);
    box.min[axis] -= std::max(pose.slide, 0.0);
    box.max[axis] -= std::min(pose.slide, 0.0);
    box.min = box.min.cwiseMax(stock_.lattice.box.min);
    box.max = box.max.cwiseMin(stock_.lattice.box.max);
    if (!box.empty()) cutFamily(piece, pose, rapid, axis, box);
  }

  // The piece's rays of this family within `box`, a tile at a time: a tile whose material lies beyond the box along
  // the rays is passed over whole.
  void cutFamily(const ToolPiece& piece, const SweepPose& pose, bool rapid, int axis, const Box& box) {
    const DexelLattice& lattice = stock_.lattice;
    const int u = DexelLattice::uAxis(axis), v = DexelLattice::vAxis(axis);
    const auto us = lattice.indexRange(u, box.min[u], box.max[u]);
    const auto vs = lattice.indexRange(v, box.min[v], box.max[v]);
    const PieceOnRays on_rays(piece, pose.pose, axis);
    for (int tile_v = vs[0] / kRowBlock; tile_v <= vs[1] / kRowBlock; ++tile_v) {
      if (!owns(tile_v * kRowBlock)) continue;
      const std::array<int, 2> rows{std::max(vs[0], tile_v * kRowBlock),
                                    std::min(vs[1], (tile_v + 1) * kRowBlock - 1)};
      for (int tile_u = us[0] / kTileColumns; tile_u <= us[1] / kTileColumns; ++tile_u) {
        const Span tile = tiles_.extent(axis, tile_u, tile_v);
        if (tile.lo > box.max[axis] || tile.hi < box.min[axis]) continue;
        const std::array<int, 2> columns{std::max(us[0], tile_u * kTileColumns),
                                         std::min(us[1], (tile_u + 1) * kTileColumns - 1)};
        cutRays(piece, on_rays, pose, rapid, axis, box, columns, rows);
      }
    }
  }

  void cutRays(const ToolPiece& piece, const PieceOnRays& on_rays, const SweepPose& pose, bool rapid, int axis,
               const Box& box, std::array<int, 2> columns, std::array<int, 2> rows) {
    const DexelLattice& lattice = stock_.lattice;
    const int u = DexelLattice::uAxis(axis), v = DexelLattice::vAxis(axis);
    for (int iv = rows[0]; iv <= rows[1]; ++iv) {
      const double cv = lattice.coordinate(v, iv);
      for (int iu = columns[0]; iu <= columns[1]; ++iu) {
        const int ray = lattice.rayIndex(axis, iu, iv);
        const Span material = extents_[axis][ray];
        if (material.lo > box.max[axis] || material.hi < box.min[axis]) continue;
        if (inside(Span{box.min[axis], box.max[axis]}, gaps_[axis][ray])) continue;
        const double cu = lattice.coordinate(u, iu);
        Span span;
        if (!on_rays.span(cu, cv, span)) continue;
        const Span swept{span.lo - std::max(pose.slide, 0.0), span.hi - std::min(pose.slide, 0.0)};
        if (swept.hi <= material.lo || swept.lo >= material.hi || inside(swept, gaps_[axis][ray])) continue;
        const Ray r{axis, ray, tiles_.tileOf(axis, iu, iv), cu, cv};
        if (piece.zone != ToolZone::Flutes || rapid) checkCollision(piece, pose, rapid, r, span, swept);
        if (piece.zone == ToolZone::Flutes) cut(pose, r, span, swept);
      }
    }
  }

  // Material in the swept span reaches into the piece as deep as the deepest point of the span at the pose that the
  // slide carries it to.
  void checkCollision(const ToolPiece& piece, const SweepPose& pose, bool rapid, const Ray& r, Span span,
                      Span swept) {
    for (const Span& s : stock_.ray(r.axis, r.index)) {
      if (s.lo >= swept.hi) break;
      const Span overlap{std::max(s.lo, swept.lo), std::min(s.hi, swept.hi)};
      if (overlap.hi <= overlap.lo) continue;
      const Span at_pose{std::max(overlap.lo + std::min(pose.slide, 0.0), span.lo),
                         std::min(overlap.hi + std::max(pose.slide, 0.0), span.hi)};
      if (at_pose.hi <= at_pose.lo) continue;
      Vec3 where;
      const double depth = deepestOnSpan(piece, pose.pose, r.origin(), r.axis, at_pose, &where);
      if (depth <= options_.tolerance || depth <= finding_.collision_mm) continue;
      finding_.collision_mm = depth;
      finding_.collision = rapid ? CollisionKind::Rapid
                                 : (piece.zone == ToolZone::Holder ? CollisionKind::Holder : CollisionKind::Shank);
      finding_.collision_point = where;
      finding_.collision_tip = tipWhenReached(pose, span, r.axis, 0.5 * (overlap.lo + overlap.hi));
    }
  }

  void cut(const SweepPose& pose, const Ray& r, Span span, Span swept) {
    removed_.clear();
    SpanList& spans = stock_.ray(r.axis, r.index);
    subtractSpan(spans, swept, &removed_);
    if (removed_.empty()) return;
    for (const Span& removed : removed_) (*removed_here_)[r.axis] += removed.length();
    if (level_cut_) measureLevelCut(r);
    extents_[r.axis][r.index] = extentOf(spans);
    gaps_[r.axis][r.index] = widestGap(spans);
    tiles_.changed(r.axis, r.tile);
    const Span part = part_extents_[r.axis][r.index];
    if (removed_.front().lo >= part.hi || removed_.back().hi <= part.lo) return;
    for (const Span& removed : removed_)
      for (const SolidSpan* p = part_.begin(r.axis, r.index); p != part_.end(r.axis, r.index); ++p) {
        if (p->lo >= removed.hi) break;
        const Span inside{std::max(removed.lo, p->lo), std::min(removed.hi, p->hi)};
        if (inside.hi > inside.lo) measureGouge(pose, r, span, inside, {p->lo, p->hi});
      }
  }

  // A feed keeping the tip at one height along a fixed axis.
  static bool isLevel(const ToolPose& from, const ToolPose& to) {
    constexpr double kSameAxis = 1e-9, kSameHeight = 1e-6;
    return (from.axis - to.axis).squaredNorm() < kSameAxis && std::abs((to.tip - from.tip).dot(to.axis)) < kSameHeight;
  }

  // The highest point removed along the ray above the level (an end of a removed span: height is linear along it),
  // and the removed spans' volume by height.
  void measureLevelCut(const Ray& r) {
    const double base = r.origin().dot(level_axis_) - level_height_, slope = level_axis_[r.axis];
    const double cell = stock_.lattice.cellArea(r.axis) / 3.0;  // Stock::volume's measure
    for (const Span& removed : removed_) {
      const double h0 = base + slope * removed.lo, h1 = base + slope * removed.hi;
      const double low = std::max(std::min(h0, h1), 0.0), high = std::max(std::max(h0, h1), 0.0);
      if (high > level_cut_->mm) level_cut_->mm = high, level_cut_->row = level_row_;
      std::vector<double>& bins = level_cut_->by_height_mm3;
      const int first = static_cast<int>(low / kLevelCutBinMm), last = static_cast<int>(high / kLevelCutBinMm);
      if (static_cast<int>(bins.size()) <= last) bins.resize(last + 1, 0.0);
      if (first == last) {
        bins[first] += removed.length() * cell;
        continue;
      }
      const double per_height = removed.length() * cell / (high - low);  // the span's volume spread evenly in height
      for (int b = first; b <= last; ++b)
        bins[b] += per_height * (std::min(high, (b + 1) * kLevelCutBinMm) - std::max(low, b * kLevelCutBinMm));
    }
  }

  // The deepest point of part material removed along [g.lo, g.hi] (inside the part's span p). Skipped when even the
  // distance to the span's own ends cannot beat what is already known.
  void measureGouge(const SweepPose& pose, const Ray& r, Span span, Span g, Span p) {
    const double middle = 0.5 * (p.lo + p.hi);
    const double bound = middle >= g.lo && middle <= g.hi ? 0.5 * p.length()
                                                            : (middle < g.lo ? p.hi - g.lo : g.hi - p.lo);
    const double floor = std::max(options_.tolerance, finding_.gouge_mm);
    if (bound <= floor) return;
    const int between = g.length() > stock_.lattice.spacing[r.axis] ? kGougeSamples : 0;
    for (int s = 0; s < between + 2; ++s) {
      Vec3 point = r.origin();
      point[r.axis] = s == 0 ? g.lo : (s == 1 ? g.hi : g.lo + g.length() * (s - 1) / (between + 1));
      const double depth = distance_.distance(point);
      if (depth <= std::max(options_.tolerance, finding_.gouge_mm)) continue;
      finding_.gouge_mm = depth;
      finding_.gouge_point = point;
      finding_.gouge_tip = tipWhenReached(pose, span, r.axis, point[r.axis]);
    }
  }

  Stock& stock_;
  Extents& extents_;
  Extents& gaps_;      // widestGap of every ray
  TileExtents tiles_;  // of extents_, for this worker's rows
  const MeshDexels& part_;
  const Extents& part_extents_;
  const PartDistance& distance_;
  const SweepOptions& options_;
  int thread_, threads_;
  MoveFinding finding_;
  std::map<int, MoveFinding> findings_;
  std::int64_t poses_ = 0;
  SpanList removed_;
  std::map<int, std::array<double, 3>> removed_length_;
  std::array<double, 3>* removed_here_ = nullptr;  // the op of the run being swept
  std::map<int, LevelCut> deepest_level_cut_;
  LevelCut* level_cut_ = nullptr;  // the op's deepest level cut while the run is a level feed, else null
  int level_row_ = -1;             // the row ending that run
  Vec3 level_axis_ = Vec3::UnitZ();
  double level_height_ = 0;      // the run's tip height along level_axis_
};

std::vector<const ToolSolid*> toolOfEveryRow(const Toolpath& path, const std::map<std::string, ToolSolid>& tools) {
  std::vector<const ToolSolid*> out(path.size());
  for (std::size_t i = 0; i < path.size(); ++i) {
    const auto it = tools.find(path[i].tool);
    if (it == tools.end())
      throw InputError("toolpath point " + std::to_string(i) + " uses tool '" + path[i].tool +
                       "', which tools.json does not describe");
    out[i] = &it->second;
  }
  return out;
}

// The runs of rows [first, end) (end -1: the path's end); both ends must be tool placements or the path's ends.
std::vector<StraightRun> runsBetween(const Toolpath& path, int first, int end) {
  const int n = static_cast<int>(path.size());
  if (end < 0) end = n;
  auto boundary = [&](int row) { return row == 0 || row == n || (row > 0 && row < n && toolPlacedAt(path, row)); };
  if (first < 0 || first > end || end > n || !boundary(first) || !boundary(end))
    throw InputError("sweep: rows " + std::to_string(first) + " to " + std::to_string(end) + " of " +
                     std::to_string(n) + " do not begin and end where the tool is placed");
  std::vector<StraightRun> runs = straightRuns(path);
  std::vector<StraightRun> between;
  for (const StraightRun& run : runs)
    if (run.first >= first && run.first < end) between.push_back(run);
  return between;
}

// Every worker on a thread of its own (runTicking) while the calling thread reports the share of the rows the
// slowest has swept, when there is a sink, and raises the stop when the sink says so. True when it was stopped.
bool runReporting(std::vector<Worker>& workers, const Toolpath& path, const std::vector<StraightRun>& runs,
                  const std::vector<const ToolSolid*>& row_tools, const ProgressSink& progress) {
  const int n = static_cast<int>(workers.size());
  std::unique_ptr<std::atomic<int>[]> rows_done(new std::atomic<int>[n]);
  const int first = runs.empty() ? 0 : runs.front().first;
  for (int t = 0; t < n; ++t) rows_done[t].store(first);
  auto sweep = [&](int t, const std::atomic<bool>& stop) { workers[t].run(path, runs, row_tools, rows_done[t], stop); };
  auto report = [&] {
    if (!progress) return true;
    int done = static_cast<int>(path.size());
    for (int t = 0; t < n; ++t) done = std::min(done, rows_done[t].load(std::memory_order_relaxed));
    return reportProgress(progress, "verification", static_cast<double>(done) / path.size(),
                          "move " + std::to_string(done) + " of " + std::to_string(path.size()), done);
  };
  return runTicking(n, sweep, kSweepReportSeconds, report);
}

}  // namespace

SweepResult sweepToolpath(Stock& stock, const MeshDexels& part, const PartDistance& part_distance,
                          const Toolpath& path, const std::map<std::string, ToolSolid>& tools,
                          const SweepOptions& options, const ProgressSink& progress) {
  const auto start = std::chrono::steady_clock::now();
  const std::vector<const ToolSolid*> row_tools = toolOfEveryRow(path, tools);
  const std::vector<StraightRun> runs = runsBetween(path, options.first_row, options.end_row);
  const int threads = threadCount(options.threads);
  Extents extents = stockExtents(stock), gaps = stockGaps(stock);
  const Extents part_extents = solidExtents(part);
  std::vector<Worker> workers;
  for (int t = 0; t < threads; ++t)
    workers.emplace_back(stock, extents, gaps, part, part_extents, part_distance, options, t, threads);
  SweepResult result;
  result.cancelled = runReporting(workers, path, runs, row_tools, progress);
  for (const Worker& w : workers) {
    for (const auto& [row, finding] : w.findings()) mergeFinding(result.findings[row], finding);
    for (const auto& [op, length] : w.removedLength()) {
      double& volume = result.by_op[op].removed_mm3;
      for (int axis = 0; axis < 3; ++axis) volume += length[axis] * stock.lattice.cellArea(axis) / 3.0;
    }
    for (const auto& [op, cut] : w.deepestLevelCut()) {
      OperationSweep& o = result.by_op[op];
      if (cut.mm > o.deepest_level_cut_mm) o.deepest_level_cut_mm = cut.mm, o.deepest_level_cut_row = cut.row;
      std::vector<double>& bins = o.level_cut_by_height_mm3;
      if (bins.size() < cut.by_height_mm3.size()) bins.resize(cut.by_height_mm3.size(), 0.0);
      for (std::size_t b = 0; b < cut.by_height_mm3.size(); ++b) bins[b] += cut.by_height_mm3[b];
    }
  }
  result.poses = workers[0].poses();
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

double levelCutAbove(const OperationSweep& op, double height) {
  double above = 0;
  const auto& bins = op.level_cut_by_height_mm3;
  for (std::size_t b = static_cast<std::size_t>(std::max(0.0, std::ceil(height / kLevelCutBinMm - 1e-9)));
       b < bins.size(); ++b)
    above += bins[b];
  return above;
}

double levelCutDepth(const OperationSweep& op, double share) {
  const auto& bins = op.level_cut_by_height_mm3;
  double total = 0;
  for (const double v : bins) total += v;
  if (total <= 0) return 0;
  double under = 0;
  for (std::size_t b = 0; b < bins.size(); ++b) {
    under += bins[b];
    if (under >= share * total) return (b + 1) * kLevelCutBinMm;
  }
  return bins.size() * kLevelCutBinMm;
}

}  // namespace art2part
