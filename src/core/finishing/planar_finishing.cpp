// Floors and walls along one direction with flat end mills (planar_finishing.h).
#include "art2part/finishing/planar_finishing.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>

#include "art2part/roughing/clearing_paths.h"
#include "art2part/roughing/forbidden_region.h"
#include "art2part/roughing/shadow.h"
#include "point_grid.h"

namespace art2part {

namespace {

// A level's shadow is taken this far above it, so a floor lying at the level is not its own shadow (the tool's flat
// bottom may touch it); a gouge of at most this much could go unnoticed by the planner (the simulation sees it).
constexpr double kAbove = 1e-3;
constexpr double kTraceSpacing = 0.5;      // mm between the samples of a wall's trace
// mm: a wall sample within the cutter's radius plus this of a pass is reached (the ring lies within the offsets' arc
// tolerance of the exact offset, and is spread into points 0.5 mm apart: a chord's sag on the smallest radius).
constexpr double kReachSlack = 0.01;
constexpr double kCoveredShrink = 0.002;   // mm the swept discs are taken smaller by, for the floor left to rest tools
constexpr double kThinLeft = 0.01;         // mm: strips of a floor left thinner than twice this are no rest work
constexpr double kSliver = 0.01;           // mm^2: a tool reaching less than this is no rest tool
constexpr double kSafeHeight = 1.0;        // mm above the allowance where a descent changes from rapid to feed
constexpr double kLevelMerge = 0.01;       // mm: levels closer than this are one
constexpr double kFinishArc = 0.002;       // mm: chords of the cutter's offset arcs (inside them: a gouge of at most this)

struct Floor {
  int target = -1;
  double z = 0;
  Region left;  // not yet reached
};

struct Wall {
  int target = -1;
  double lo = 0, hi = 0;
  std::vector<Point2> samples;
  std::vector<double> weight;                               // mm of trace each sample stands for
  std::vector<std::vector<std::pair<double, double>>> done;  // per sample: height intervals reached, merged

  double reachedHeight(std::size_t i) const {
    double h = 0;
    for (const auto& [a, b] : done[i]) h += std::max(0.0, std::min(b, hi) - std::max(a, lo));
    return h;
  }
  bool complete(std::size_t i) const { return reachedHeight(i) >= hi - lo - 1e-3; }
  bool bandDone(std::size_t i, double a, double b) const {
    for (const auto& [p, q] : done[i])
      if (p <= a + 1e-6 && q >= b - 1e-6) return true;
    return false;
  }
  void markDone(std::size_t i, double a, double b) {
    auto& list = done[i];
    list.emplace_back(a, b);
    std::sort(list.begin(), list.end());
    std::vector<std::pair<double, double>> merged;
    for (const auto& iv : list) {
      if (!merged.empty() && iv.first <= merged.back().second + 1e-6) merged.back().second = std::max(merged.back().second, iv.second);
      else merged.push_back(iv);
    }
    list = std::move(merged);
  }
};

// Everything about the group that does not depend on the tool.
struct GroupGeometry {
  std::vector<Vec3> vertices;  // the part in the frame
  Box stock;                   // the stock's box in the frame
  std::vector<Floor> floors;
  std::vector<Wall> walls;
  std::map<int, std::vector<int>> triangles_of;  // per target face
};

std::vector<Point2> traceSamples(const std::vector<Vec3>& vertices, const Mesh& mesh, const std::vector<int>& triangles,
                                 std::vector<double>& weight) {
  std::map<std::pair<long, long>, std::size_t> seen;
  std::vector<Point2> samples;
  for (int t : triangles)
    for (int e = 0; e < 3; ++e) {
      const Vec3& a = vertices[mesh.triangles[t][e]];
      const Vec3& b = vertices[mesh.triangles[t][(e + 1) % 3]];
      const Point2 pa(a.x(), a.y()), pb(b.x(), b.y());
      const double length = (pb - pa).norm();
      if (length < 1e-6) continue;  // a vertical edge of the wall
      const int pieces = std::max(1, static_cast<int>(std::ceil(length / kTraceSpacing)));
      for (int k = 0; k < pieces; ++k) {
        const Point2 p = pa + (pb - pa) * ((k + 0.5) / pieces);
        const std::pair<long, long> key(std::lround(p.x() / 0.05), std::lround(p.y() / 0.05));
        if (seen.count(key)) continue;  // the same stretch of trace from the triangle above or below
        seen[key] = samples.size();
        samples.push_back(p);
        weight.push_back(length / pieces);
      }
    }
  return samples;
}

GroupGeometry groupGeometry(const Part& part, const PlanarGroup& group) {
  GroupGeometry g;
  g.vertices = toFrame(part.mesh.vertices, group.frame);
  for (const Vec3& p : toFrame(group.stock.vertices, group.frame)) g.stock.extend(p);
  for (int t = 0; t < part.mesh.triangleCount() && t < static_cast<int>(part.triangle_face.size()); ++t)
    g.triangles_of[part.triangle_face[t]].push_back(t);
  for (int i = 0; i < static_cast<int>(group.targets.size()); ++i) {
    const PlanarTarget& target = group.targets[i];
    const std::vector<int>& tris = g.triangles_of[target.face];
    if (tris.empty()) continue;
    double lo = 1e300, hi = -1e300;
    for (int t : tris)
      for (int c = 0; c < 3; ++c) {
        lo = std::min(lo, g.vertices[part.mesh.triangles[t][c]].z());
        hi = std::max(hi, g.vertices[part.mesh.triangles[t][c]].z());
      }
    if (target.kind == FinishingKind::FaceMill) {
      std::vector<Ring> polygons;
      for (int t : tris) {
        Ring ring;
        for (int c = 0; c < 3; ++c) ring.emplace_back(g.vertices[part.mesh.triangles[t][c]].x(), g.vertices[part.mesh.triangles[t][c]].y());
        polygons.push_back(ring);
      }
      g.floors.push_back({i, 0.5 * (lo + hi), regionFromPolygons(polygons)});
    } else {
      Wall wall;
      wall.target = i;
      wall.lo = lo;
      wall.hi = hi;
      wall.samples = traceSamples(g.vertices, part.mesh, tris, wall.weight);
      wall.done.resize(wall.samples.size());
      if (hi - lo > 1e-3 && !wall.samples.empty()) g.walls.push_back(std::move(wall));
    }
  }
  return g;
}

// What one level of one tool does.
struct LevelWork {
  double z = 0;
  std::vector<int> floors;                     // indices into GroupGeometry::floors
  std::vector<std::pair<int, double>> walls;   // wall index and the top of the band this level finishes
};

// The levels of a tool over what is left: each floor's height, and for each wall the bands of the flute length less
// the margin from its foot up, evenly; highest first.
std::vector<LevelWork> levelsFor(const GroupGeometry& g, const Tool& tool, const PlanarFinishingOptions& options) {
  std::vector<LevelWork> levels;
  auto at = [&](double z) -> LevelWork& {
    for (LevelWork& l : levels)
      if (std::abs(l.z - z) < kLevelMerge) return l;
    levels.push_back({z, {}, {}});
    return levels.back();
  };
  for (int i = 0; i < static_cast<int>(g.floors.size()); ++i)
    if (!regionEmpty(g.floors[i].left)) at(g.floors[i].z).floors.push_back(i);
  const double band = std::max(1.0, tool.flute_length - options.band_margin);
  for (int w = 0; w < static_cast<int>(g.walls.size()); ++w) {
    const Wall& wall = g.walls[w];
    bool open = false;
    for (std::size_t s = 0; s < wall.samples.size() && !open; ++s) open = !wall.complete(s);
    if (!open) continue;
    const int n = std::max(1, static_cast<int>(std::ceil((wall.hi - wall.lo) / band - 1e-9)));
    const double h = (wall.hi - wall.lo) / n;
    for (int k = 0; k < n; ++k) {
      const double z = wall.lo + k * h;
      at(z).walls.push_back({w, k == n - 1 ? wall.hi : z + h});
    }
  }
  std::sort(levels.begin(), levels.end(), [](const LevelWork& a, const LevelWork& b) { return a.z > b.z; });
  return levels;
}

// Shank and holder zones: the holder also keeps clear of the allowance roughing left on faces not yet finished.
std::vector<BodyZone> finishingZones(const Tool& tool, double allowance) {
  std::vector<BodyZone> zones = bodyZones(tool);
  for (BodyZone& z : zones)
    if (z.from >= tool.stickout - 1e-9) z.radius += allowance;
  return zones;
}

class PathWriter {
 public:
  PathWriter(const SetupFrame& frame, const Tool& tool, int setup, double clearance_z)
      : frame_(frame), tool_(tool), setup_(setup), clearance_z_(clearance_z) {}

  void move(const Vec3& p, MoveKind kind) {
    CutterLocation cl;
    cl.setup = setup_;
    cl.tool = tool_.id;
    cl.move = kind;
    cl.tip = fromFrame(p, frame_);
    cl.axis = frame_.z;
    if (!path_.empty() && (path_.back().tip - cl.tip).norm() < 1e-9) return;
    path_.push_back(cl);
    at_ = p;
    started_ = true;
  }
  void clearing(const std::vector<ClearingPoint>& moves) {
    for (const ClearingPoint& m : moves) move(m.tip, m.move == ClearingMove::Rapid ? MoveKind::Rapid : MoveKind::Feed);
  }
  // To (x, y) at height z from wherever the tool is: up to the clearance plane, across, down fast to `safe` (or only
  // to `floor` when that is higher), then feed.
  void enter(const Point2& xy, double z, double safe, double floor) {
    if (started_ && at_.z() < clearance_z_ - 1e-9) move(Vec3(at_.x(), at_.y(), clearance_z_), MoveKind::Rapid);
    move(Vec3(xy.x(), xy.y(), clearance_z_), MoveKind::Rapid);
    const double fast = std::max(safe, floor);
    if (fast < clearance_z_) move(Vec3(xy.x(), xy.y(), fast), MoveKind::Rapid);
    move(Vec3(xy.x(), xy.y(), z), MoveKind::Feed);
  }
  void retract() {
    if (started_ && at_.z() < clearance_z_ - 1e-9) move(Vec3(at_.x(), at_.y(), clearance_z_), MoveKind::Rapid);
  }
  Toolpath take() {
    retract();
    return std::move(path_);
  }
  const Vec3& at() const { return at_; }

 private:
  SetupFrame frame_;
  const Tool& tool_;
  int setup_;
  double clearance_z_;
  Toolpath path_;
  Vec3 at_ = Vec3::Zero();
  bool started_ = false;
};

// Where the tool may come straight down at rapid: its disc clear of the allowance roughing left on every face above
// the level (the allowed region eroded by that and a margin). A descent elsewhere moves to the nearest such point
// within reach, comes down there and feeds across at the height it came down to; failing that it feeds all the way.
class SafeDescent {
 public:
  SafeDescent(const Region& allowed, double allowance)
      : allowed_(allowed), safe_(offsetRegion(allowed, -(allowance + kDescentMargin))), locator_(safe_) {}

  // The point to come down at for a descent at `p`, and whether there is one (else feed down at p).
  bool at(const Point2& p, double max_shift, Point2& out) const {
    if (locator_.contains(p)) return out = p, true;
    double best = max_shift * max_shift;
    bool found = false;
    for (const ClipperLib::Path& ring : safe_)
      for (std::size_t i = 0; i < ring.size(); ++i) {
        const Point2 a = fromRegionPoint(ring[i]), b = fromRegionPoint(ring[(i + 1) % ring.size()]);
        const Point2 ab = b - a;
        const double t = ab.squaredNorm() > 0 ? std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0) : 0.0;
        const Point2 q = a + t * ab;
        const double d = (q - p).squaredNorm();
        if (d >= best) continue;
        // A hair inside the safe region, and a straight way from there to p in the allowed region.
        const Point2 inside = q + (q - p).normalized() * 0.01;
        if (!locator_.contains(inside) || !segmentInside(allowed_, inside, p)) continue;
        best = d, out = inside, found = true;
      }
    return found;
  }

 private:
  static constexpr double kDescentMargin = 0.2;
  const Region& allowed_;
  Region safe_;
  RegionLocator locator_;
};

// How far down a rapid may come at a point: to the top of the highest slab of stock roughing left whose material
// lies within the tool's radius (and a margin) of the point; below that the tool feeds. The part and its allowance
// are kept off by SafeDescent; what this sees is stock roughing could not reach.
class DescentLimit {
 public:
  DescentLimit(const std::vector<SlabState>& slabs, double radius) : slabs_(slabs), reach_(radius + kMargin) {}
  // The lowest height a rapid may reach at p (-infinity: all the way).
  double at(const Point2& p) const {
    const Point2 lo = p - Point2(reach_, reach_), hi = p + Point2(reach_, reach_);
    for (const SlabState& slab : slabs_) {  // top down
      const Region near = ringsMeeting(slab.remaining, lo, hi);
      if (near.empty()) continue;
      if (regionContains(near, p) || distanceToRings(near, p) <= reach_) return slab.top + kSafeHeight;
    }
    return -std::numeric_limits<double>::infinity();
  }

 private:
  static constexpr double kMargin = 0.5;
  static double distanceToRings(const Region& region, const Point2& p) {
    double best = std::numeric_limits<double>::infinity();
    for (const ClipperLib::Path& ring : region)
      for (std::size_t i = 0; i < ring.size(); ++i) {
        const Point2 a = fromRegionPoint(ring[i]), b = fromRegionPoint(ring[(i + 1) % ring.size()]);
        const Point2 ab = b - a;
        const double t = ab.squaredNorm() > 0 ? std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0) : 0.0;
        best = std::min(best, (a + t * ab - p).norm());
      }
    return best;
  }
  const std::vector<SlabState>& slabs_;
  double reach_;
};

// Rapid descents (below the clearance plane) moved to where the tool comes down clear of the allowance, joined to the
// descent's foot by a feed; where there is none nearby, the descent is a feed.
std::vector<ClearingPoint> safeDescents(const std::vector<ClearingPoint>& moves, const SafeDescent& safe,
                                        const DescentLimit& limit, double max_shift) {
  std::vector<ClearingPoint> out;
  out.reserve(moves.size());
  for (std::size_t i = 0; i < moves.size(); ++i) {
    const ClearingPoint& m = moves[i];
    const bool descent = m.move == ClearingMove::Rapid && !out.empty() && m.tip.z() < out.back().tip.z() - 1e-9 &&
                         (m.tip.head<2>() - out.back().tip.head<2>()).norm() < 1e-6;
    if (!descent) {
      out.push_back(m);
      continue;
    }
    Point2 at;
    if (safe.at(m.tip.head<2>(), max_shift, at)) {
      const double floor = limit.at(at);
      out.back().tip.head<2>() = at;  // the rapid across ends over the safe point
      if (floor < m.tip.z()) {
        out.push_back({Vec3(at.x(), at.y(), m.tip.z()), ClearingMove::Rapid});
      } else {
        if (floor < out.back().tip.z()) out.push_back({Vec3(at.x(), at.y(), floor), ClearingMove::Rapid});
        out.push_back({Vec3(at.x(), at.y(), m.tip.z()), ClearingMove::Feed});
      }
      if ((at - m.tip.head<2>()).norm() > 1e-6) out.push_back({m.tip, ClearingMove::Feed});
    } else {
      out.push_back({m.tip, ClearingMove::Feed});
    }
  }
  return out;
}

// The passes of one tool over what is left of the group.
struct ToolRun {
  Toolpath floors, walls;
  std::map<int, double> reached;        // per target: size reached by this tool
  std::map<int, double> deepest;        // per wall target: lowest height reached
  std::vector<int> floor_targets, wall_targets;
  double reached_total = 0;
};

// Cuts one stretch of ring at height z: entered from the open side (the region lies right of a climb stretch) where
// the straight lead-in stays in the region, else straight down at its first point.
void cutStretch(const ContourStretch& s, double z, double top, double lead, const Region& allowed,
                const SafeDescent& safe, const DescentLimit& limit, PathWriter& out) {
  const Point2& p0 = s.points.front();
  const Point2 t = (s.points[1] - p0).normalized();
  Point2 start = p0 + Point2(t.y(), -t.x()) * lead;
  if (!segmentInside(allowed, start, p0)) start = p0;
  Point2 down;
  if (safe.at(start, 2 * lead, down)) {
    out.enter(down, top + kSafeHeight, top + kSafeHeight, limit.at(down));
    out.move(Vec3(start.x(), start.y(), top + kSafeHeight), MoveKind::Feed);
    out.move(Vec3(start.x(), start.y(), z), MoveKind::Feed);
  } else {
    out.enter(start, z, top + kSafeHeight, std::numeric_limits<double>::infinity());  // feed all the way down
  }
  for (const Point2& p : s.points) out.move(Vec3(p.x(), p.y(), z), MoveKind::Feed);
  if (s.closed) out.move(Vec3(p0.x(), p0.y(), z), MoveKind::Feed);
  // Lead out the way it came in, off the wall.
  const Point2& pn = s.closed ? p0 : s.points.back();
  const Point2& pp = s.closed ? s.points.back() : s.points[s.points.size() - 2];
  const Point2 u = (pn - pp).normalized();
  const Point2 off = pn + Point2(u.y(), -u.x()) * lead;
  if (segmentInside(allowed, pn, off)) out.move(Vec3(off.x(), off.y(), z), MoveKind::Feed);
  out.retract();
}

ToolRun runTool(const Part& part, const PlanarGroup& group, GroupGeometry& g, const Tool& tool,
                const FinishingOptions& options, bool write_paths) {
  ToolRun run;
  const std::vector<LevelWork> levels = levelsFor(g, tool, options.planar);
  if (levels.empty()) return run;
  const double r = tool.diameter / 2;
  const std::vector<BodyZone> zones = finishingZones(tool, options.allowance);
  std::vector<double> heights;
  for (const LevelWork& l : levels) {
    heights.push_back(l.z + kAbove);
    for (const BodyZone& zone : zones) heights.push_back(l.z + kAbove + zone.from);
  }
  const ShadowStack shadows(g.vertices, part.mesh.triangles, heights);
  // Shank and holder by roughing's grown region (conservative: simplified, coarse chords); the cutter by the exact
  // offset of the level's shadow, so the tool touches the finished face (chords of kFinishArc inside the true arcs:
  // at most that much closer).
  ForbiddenRegion body(shadows, 0.0, zones, options.tools.holder_margin, false);
  Box outline = g.stock;
  const Region universe = regionFromPolygons({{Point2(outline.min.x() - r - 1, outline.min.y() - r - 1),
                                               Point2(outline.max.x() + r + 1, outline.min.y() - r - 1),
                                               Point2(outline.max.x() + r + 1, outline.max.y() + r + 1),
                                               Point2(outline.min.x() - r - 1, outline.max.y() + r + 1)}});
  const double clearance_z = g.stock.max.z() + options.clearance;
  PathWriter floor_path(group.frame, tool, group.setup, clearance_z), wall_path(group.frame, tool, group.setup, clearance_z);
  ClearingOptions clearing;
  clearing.stepover = std::min(options.planar.floor_stepover, 0.9) * tool.diameter;
  clearing.clearance_z = clearance_z;
  clearing.safe_height = kSafeHeight;
  clearing.contour_pass = true;
  const double lead = std::min(r, 2.0) + options.allowance;
  const DescentLimit limit(group.stock_left, r);

  for (const LevelWork& level : levels) {
    const double zq = level.z + kAbove;
    const Region cutter = offsetRegion(shadows.at(zq), r, kFinishArc);
    Region allowed = dropSlivers(subtract(subtract(universe, cutter), body.at(zq, {})), 1e-4);
    if (regionEmpty(allowed)) continue;

    if (!level.floors.empty()) {
      Region target;
      for (int f : level.floors) target = unite(target, g.floors[f].left);
      const Region centre = dropSlivers(intersect(allowed, offsetRegion(target, 0.5 * r)), 1e-3);
      if (!regionEmpty(centre)) {
        if (write_paths) {
          ClearingLevel clear;
          clear.z = level.z;
          clear.top = level.z + options.allowance;
          clear.centre = centre;
          floor_path.clearing(
              safeDescents(clearLevel(clear, clearing), SafeDescent(allowed, options.allowance), limit, 2 * r));
        }
        const Region swept = offsetRegion(centre, r - kCoveredShrink);
        for (int f : level.floors) {
          Floor& floor = g.floors[f];
          const double before = regionArea(floor.left);
          floor.left = dropThinPieces(subtract(floor.left, swept), kThinLeft);
          const double gained = before - regionArea(floor.left);
          if (gained > 0) {
            run.reached[floor.target] += gained;
            run.reached_total += gained;
            run.floor_targets.push_back(floor.target);
          }
        }
      }
    }

    if (!level.walls.empty()) {
      std::vector<Point2> points;
      for (const auto& [w, band_top] : level.walls) {
        const Wall& wall = g.walls[w];
        for (std::size_t s = 0; s < wall.samples.size(); ++s)
          if (!wall.bandDone(s, level.z, band_top)) points.push_back(wall.samples[s]);
      }
      const std::vector<ContourStretch> stretches =
          contourStretches(allowed, points, r + kReachSlack, options.planar.link_gap, lead);
      if (stretches.empty()) continue;
      std::vector<Point2> cut;
      for (const ContourStretch& s : stretches) cut.insert(cut.end(), s.points.begin(), s.points.end());
      // Reached: the samples within the cutter's radius (and the slack) of a cut stretch.
      const finishing_detail::PointGrid cut_grid(cut, r + kReachSlack);
      for (const auto& [w, band_top] : level.walls) {
        Wall& wall = g.walls[w];
        for (std::size_t s = 0; s < wall.samples.size(); ++s) {
          if (wall.bandDone(s, level.z, band_top)) continue;
          if (!cut_grid.anyWithin(wall.samples[s], r + kReachSlack)) continue;
          const double before = wall.reachedHeight(s);
          wall.markDone(s, level.z, band_top);
          const double gained = (wall.reachedHeight(s) - before) * wall.weight[s];
          run.reached[wall.target] += gained;
          run.reached_total += gained;
          auto& deepest = run.deepest.try_emplace(wall.target, 1e300).first->second;
          deepest = std::min(deepest, level.z);
          run.wall_targets.push_back(wall.target);
        }
      }
      if (write_paths) {
        const SafeDescent safe(allowed, options.allowance);
        // Nearest stretch next.
        std::vector<char> used(stretches.size(), 0);
        for (std::size_t k = 0; k < stretches.size(); ++k) {
          std::size_t best = 0;
          double best_d = 1e300;
          for (std::size_t i = 0; i < stretches.size(); ++i) {
            if (used[i]) continue;
            const double d = (stretches[i].points.front() - Point2(wall_path.at().x(), wall_path.at().y())).squaredNorm();
            if (d < best_d) best_d = d, best = i;
          }
          used[best] = 1;
          cutStretch(stretches[best], level.z, level.z + options.allowance, lead, allowed, safe, limit, wall_path);
        }
      }
    }
  }
  if (write_paths) {
    run.floors = floor_path.take();
    run.walls = wall_path.take();
  }
  return run;
}

}  // namespace

namespace {

bool nothingLeft(const GroupGeometry& g) {
  for (const Floor& f : g.floors)
    if (!regionEmpty(f.left)) return false;
  for (const Wall& w : g.walls)
    for (std::size_t s = 0; s < w.samples.size(); ++s)
      if (!w.complete(s)) return false;
  return true;
}

// The kind of a tool's wall operation: side milling when plane walls make most of what it reached, else contour.
FinishingKind wallKind(const PlanarGroup& group, const ToolRun& run) {
  double planes = 0, others = 0;
  for (int t : run.wall_targets) (group.targets[t].kind == FinishingKind::SideMill ? planes : others) += 1;
  return planes >= others ? FinishingKind::SideMill : FinishingKind::Contour;
}

std::vector<int> facesOf(const PlanarGroup& group, std::vector<int> targets) {
  std::sort(targets.begin(), targets.end());
  targets.erase(std::unique(targets.begin(), targets.end()), targets.end());
  std::vector<int> faces;
  for (int t : targets) faces.push_back(group.targets[t].face);
  return faces;
}

// The next tool for what is left: the first tool (largest diameter, then shortest flutes) reaching at least
// area_fraction of what the most capable candidate reaches (the smallest, or the one with the longest flutes: a narrow
// corner wants the one, a deep wall the other). The first tool may be any; after it, tools at most half the previous
// diameter, or as wide with longer flutes (a deep wall the previous one's shank kept it from).
const Tool* nextTool(const Part& part, const PlanarGroup& group, const GroupGeometry& g,
                     const std::vector<const Tool*>& tools, const Tool* previous, const std::vector<const Tool*>& used,
                     const FinishingOptions& options) {
  std::vector<const Tool*> candidates;
  for (const Tool* t : tools) {
    if (std::find(used.begin(), used.end(), t) != used.end()) continue;
    if (previous && !(t->diameter <= 0.5 * previous->diameter + 1e-9 ||
                      (std::abs(t->diameter - previous->diameter) < 1e-9 && t->flute_length > previous->flute_length)))
      continue;
    candidates.push_back(t);
  }
  if (candidates.empty()) return nullptr;
  std::stable_sort(candidates.begin(), candidates.end(), [](const Tool* a, const Tool* b) {
    if (a->diameter != b->diameter) return a->diameter > b->diameter;
    return a->flute_length < b->flute_length;
  });
  std::map<const Tool*, double> reach;
  auto evaluate = [&](const Tool* t) {
    const auto it = reach.find(t);
    if (it != reach.end()) return it->second;
    GroupGeometry trial = g;
    return reach[t] = runTool(part, group, trial, *t, options, false).reached_total;
  };
  const Tool* smallest = candidates.back();
  const Tool* longest = *std::max_element(candidates.begin(), candidates.end(), [](const Tool* a, const Tool* b) {
    return a->flute_length < b->flute_length || (a->flute_length == b->flute_length && a->diameter > b->diameter);
  });
  const double best = std::max(evaluate(smallest), evaluate(longest));
  if (best <= kSliver) return nullptr;
  for (const Tool* t : candidates)
    if (evaluate(t) >= options.tools.area_fraction * best) return t;
  return smallest;
}

}  // namespace

PlanarResult finishPlanar(const Part& part, const PlanarGroup& group, const std::vector<const Tool*>& tools,
                          const FinishingOptions& options) {
  if (tools.empty()) throw InputError("planar finishing: no flat end mill to finish with");
  for (const Tool* t : tools)
    if (t->type != ToolType::Flat)
      throw InputError("planar finishing: tool '" + t->id + "' is a " + toolTypeName(t->type) + ", not a flat end mill");
  PlanarResult result;
  const GroupGeometry base = groupGeometry(part, group);
  result.reach.resize(group.targets.size());
  for (int i = 0; i < static_cast<int>(group.targets.size()); ++i) result.reach[i].face = group.targets[i].face;
  for (const Floor& f : base.floors) result.reach[f.target].size = regionArea(f.left);
  for (const Wall& w : base.walls) {
    double length = 0;
    for (double x : w.weight) length += x;
    result.reach[w.target].size = length * (w.hi - w.lo);
    result.reach[w.target].depth = w.hi - w.lo;
  }
  if (base.floors.empty() && base.walls.empty()) return result;

  GroupGeometry g = base;
  std::vector<const Tool*> used;
  const Tool* previous = nullptr;
  for (int pass = 0; pass <= options.tools.max_rest_tools && !nothingLeft(g); ++pass) {
    const Tool* tool = nextTool(part, group, g, tools, previous, used, options);
    if (!tool) break;
    used.push_back(tool);
    previous = tool;
    const auto start = std::chrono::steady_clock::now();
    ToolRun run = runTool(part, group, g, *tool, options, true);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    auto add = [&](Toolpath&& path, FinishingKind kind, const std::vector<int>& targets) {
      if (path.empty() || targets.empty()) return;
      FinishingOperation op;
      op.setup = group.setup;
      op.kind = pass == 0 ? kind : FinishingKind::Rest;
      op.tool = tool->id;
      op.direction = group.frame.z;
      op.faces = facesOf(group, targets);
      op.path = std::move(path);
      op.plan_seconds = seconds;
      const int index = static_cast<int>(result.operations.size());
      for (int t : targets) {
        PlanarReach& reach = result.reach[t];
        if (std::find(reach.operations.begin(), reach.operations.end(), index) == reach.operations.end())
          reach.operations.push_back(index);
        if (std::find(reach.tools.begin(), reach.tools.end(), tool->id) == reach.tools.end()) reach.tools.push_back(tool->id);
      }
      result.operations.push_back(std::move(op));
    };
    add(std::move(run.floors), FinishingKind::FaceMill, run.floor_targets);
    add(std::move(run.walls), wallKind(group, run), run.wall_targets);
    for (const auto& [t, size] : run.reached) result.reach[t].reached += size;
    for (const auto& [t, z] : run.deepest)
      for (const Wall& w : g.walls)
        if (w.target == t) result.reach[t].deepest_reached = std::max(result.reach[t].deepest_reached, w.hi - z);
  }
  return result;
}

}  // namespace art2part
