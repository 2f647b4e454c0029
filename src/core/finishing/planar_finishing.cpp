// Floors and walls along one direction with flat end mills (planar_finishing.h).
#include "art2part/finishing/planar_finishing.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <memory>

#include "art2part/common/angles.h"
#include "art2part/roughing/clearing_paths.h"
#include "art2part/roughing/forbidden_region.h"
#include "art2part/roughing/shadow.h"
#include "finishing_moves.h"
#include "point_grid.h"

namespace art2part {

namespace {

using namespace finishing_detail;

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
constexpr double kLevelMerge = 0.01;       // mm: levels closer than this are one
constexpr double kZoneGrid = 2.0;          // mm: shank and holder bottoms' shadows on this grid (rounded down)
constexpr std::size_t kTrialLevels = 8;   // levels a tool's trial works (spread over its levels)
constexpr double kTrialArc = 0.02;         // mm: a trial's cutter offsets (it compares tools; the paths use kFinishArc)
// A tool kept from the depth by its flutes, shank or holder goes before a longer one of its diameter that reaches
// more, when it reaches at least this share of what that one does and feeds faster: the longer tool follows for the
// depth only (the next round), at its slower feed there, for one tool change more.
constexpr double kShortFirstShare = 0.5;
constexpr double kWindowMargin = 3.0;      // mm round a level's work where the exact cutter region is computed
constexpr double kSkinSlack = 0.05;        // mm beyond the allowance that still counts as skin, not stock left
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
  // What roughing left beyond its allowance (PlanarGroup::stock_beyond: stairs on slanted faces, corners no roughing
  // tool reached, stock standing free), slabs top down; and pointers to them as the forbidden region takes them. The
  // skin of the allowance itself is kept off by the holder margin.
  std::shared_ptr<const std::vector<SlabState>> thick;  // shared by the copies a tool's trial makes
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

}  // namespace

ShadowStack slabShadows(const std::vector<SlabState>& slabs, const std::vector<Vec3>& frame_vertices,
                        const std::vector<Triangle>& triangles) {
  std::vector<double> heights;
  for (const SlabState& slab : slabs) heights.push_back(slab.z);
  return ShadowStack(frame_vertices, triangles, heights);
}

std::vector<SlabState> stockBeyondSkin(const std::vector<SlabState>& stock_left, double skin,
                                       const ShadowStack& shadows) {
  std::vector<SlabState> thick;
  Region grown;  // the shadow grown by the skin and slack, from the gains of the heights so far (top down)
  int done = -1;
  for (const SlabState& slab : stock_left) {
    const int index = shadows.indexAt(slab.z);
    for (; done < index; ++done) grown = unite(grown, offsetRegion(shadows.gain(done + 1), skin + kSkinSlack));
    const Region band = index < 0 ? Region{} : subtract(grown, shadows.at(slab.z));
    Region left = dropThinPieces(subtract(slab.remaining, band), kThinLeft);
    if (!regionEmpty(left)) thick.push_back({slab.z, slab.top, std::move(left)});
  }
  return thick;
}

std::vector<SlabState> stockBeyondSkin(const std::vector<SlabState>& stock_left, double skin,
                                       const std::vector<Vec3>& frame_vertices,
                                       const std::vector<Triangle>& triangles) {
  if (stock_left.empty()) return {};
  return stockBeyondSkin(stock_left, skin, slabShadows(stock_left, frame_vertices, triangles));
}

namespace {

GroupGeometry groupGeometry(const Part& part, const PlanarGroup& group) {
  GroupGeometry g;
  g.vertices = toFrame(part.mesh.vertices, group.frame);
  g.thick = std::make_shared<const std::vector<SlabState>>(group.stock_beyond);
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
    // The foot exactly; the levels above on the kZoneGrid grid, rounded down (bands overlap the more): walls and tools
    // then share levels, and the group's shadow stack has fewer heights.
    double below = wall.lo;
    for (int k = 0; k < n; ++k) {
      const double z = k == 0 ? wall.lo : std::max(below, std::floor((wall.lo + k * h) / kZoneGrid) * kZoneGrid);
      const double top = k == n - 1 ? wall.hi : wall.lo + (k + 1) * h;
      at(z).walls.push_back({w, top});
      below = z;
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

// Where a level works: its floors' part left, and the box of each wall's samples still open at the level's band,
// grown by `grow`. Exact offsets are taken only there.
Region workWindow(const GroupGeometry& g, const LevelWork& level, double grow) {
  Region window;
  for (int f : level.floors) window = unite(window, g.floors[f].left);
  std::vector<Ring> boxes;
  for (const auto& [w, band_top] : level.walls) {
    const Wall& wall = g.walls[w];
    Point2 lo(1e300, 1e300), hi(-1e300, -1e300);
    for (std::size_t s = 0; s < wall.samples.size(); ++s)
      if (!wall.bandDone(s, level.z, band_top)) lo = lo.cwiseMin(wall.samples[s]), hi = hi.cwiseMax(wall.samples[s]);
    if (lo.x() > hi.x()) continue;
    lo -= Point2(0.5, 0.5), hi += Point2(0.5, 0.5);  // a wall along an axis has a flat box
    boxes.push_back({lo, Point2(hi.x(), lo.y()), hi, Point2(lo.x(), hi.y())});
  }
  return offsetRegion(unite(window, regionFromPolygons(boxes)), grow, kArcTolerance);
}

// The passes of one tool over what is left of the group.
struct ToolRun {
  Toolpath floors, walls;
  std::map<int, double> reached;        // per target: size reached by this tool
  std::map<int, double> deepest;        // per wall target: lowest height reached
  std::vector<int> floor_targets, wall_targets;
  double reached_total = 0;
};

// With `sample`, a trial works at most kTrialLevels of the levels, spread from the top down: enough to compare tools
// for a whole group (as roughing's choice samples its levels), a fraction of the cost.
ToolRun runTool(const PlanarGroup& group, GroupGeometry& g, const ShadowStack& shadows, const Tool& tool,
                const FinishingOptions& options, bool write_paths, bool sample = false) {
  ToolRun run;
  std::vector<LevelWork> levels = levelsFor(g, tool, options.planar);
  if (sample && levels.size() > kTrialLevels) {
    std::vector<LevelWork> sample;
    for (std::size_t i = 0; i < kTrialLevels; ++i) sample.push_back(levels[i * (levels.size() - 1) / (kTrialLevels - 1)]);
    levels = std::move(sample);
  }
  if (levels.empty()) return run;
  const double r = tool.diameter / 2;
  const std::vector<BodyZone> zones = finishingZones(tool, options.allowance);

  // Shank and holder by roughing's grown region (conservative: simplified, coarse chords); the cutter by the exact
  // offset of the level's shadow, so the tool touches the finished face (chords of kFinishArc inside the true arcs:
  // at most that much closer).
  ForbiddenRegion body(shadows, -1, zones, options.tools.holder_margin, false);
  ForbiddenRegion body_stock(shadows, -1, zones, options.tools.holder_margin, true);  // against g.thick
  std::vector<StockLeft> thick_left;
  for (const SlabState& slab : *g.thick) thick_left.push_back({slab.top, &slab.remaining});
  Box outline = g.stock;
  const Region universe = regionFromPolygons({{Point2(outline.min.x() - r - 1, outline.min.y() - r - 1),
                                               Point2(outline.max.x() + r + 1, outline.min.y() - r - 1),
                                               Point2(outline.max.x() + r + 1, outline.max.y() + r + 1),
                                               Point2(outline.min.x() - r - 1, outline.max.y() + r + 1)}});
  const double clearance_z = g.stock.max.z() + options.clearance;
  // Links between wall stretches and between floor passes stay down where the stock left proves the way clear (the
  // margin covers the skin the stock beyond it leaves out, and a clearance). Only for the paths: a trial writes none.
  std::shared_ptr<const LinkWay> link;
  if (write_paths && !g.thick->empty()) {
    auto way = std::make_shared<LinkWay>(
        LinkWay{LinkClearance(tool, options.allowance + kLinkClearance, LinkClearance::Beside::WholeTool),
                g.thick->back().z});
    for (const SlabState& slab : *g.thick) way->clearance.addSlab(slab, {});
    link = std::move(way);
  }
  PathWriter floor_path(group.frame, tool, group.setup, clearance_z, link);
  PathWriter wall_path(group.frame, tool, group.setup, clearance_z, std::move(link));
  ClearingOptions clearing;
  clearing.stepover = std::min(options.planar.floor_stepover, 0.9) * tool.diameter;
  clearing.clearance_z = clearance_z;
  clearing.safe_height = kSafeHeight;
  clearing.contour_pass = true;
  clearing.tool_radius = r;
  const double lead = std::min(r, 2.0) + options.allowance;
  const DescentLimit limit(*g.thick, r);
  std::vector<WallStretch> walls;  // every level's stretches, cut after the levels
  std::vector<FloorLevel> floors;  // every level's floor clearing, cut after the levels

  for (const LevelWork& level : levels) {
    const double zq = level.z + kAbove;
    // The cutter's region only where this level works (its floors and walls, grown by the radius and a margin): the
    // exact offset of the whole shadow at every level was most of finishing's time on big parts.
    const Region window = intersect(universe, workWindow(g, level, r + kWindowMargin));
    const Region near_shadow = intersect(shadows.at(zq), offsetRegion(window, r + kWindowMargin, kArcTolerance));
    // Holes of the shadow too small for the cutter's disc change nothing once it is grown by the radius.
    const Region cutter =
        offsetRegion(fillSmallHoles(near_shadow, kPi * r * r), r, write_paths ? kFinishArc : kTrialArc);
    Region allowed = dropSlivers(subtract(subtract(window, cutter), body.at(zq, {})), 1e-4);
    if (!thick_left.empty()) allowed = dropSlivers(subtract(allowed, body_stock.at(zq, thick_left)), 1e-4);
    if (regionEmpty(allowed)) continue;

    if (!level.floors.empty()) {
      Region target;
      for (int f : level.floors) target = unite(target, g.floors[f].left);
      const Region centre = dropSlivers(intersect(allowed, offsetRegion(target, 0.5 * r)), 1e-3);
      if (!regionEmpty(centre)) {
        if (write_paths) {  // cut once every level's are known (cutFloors)
          FloorLevel floor;
          floor.clear.z = level.z;
          floor.clear.top = level.z + options.allowance;
          floor.clear.centre = centre;
          floor.allowed = std::make_shared<const Region>(allowed);
          floor.safe = std::make_shared<const SafeDescent>(*floor.allowed, options.allowance);
          floors.push_back(std::move(floor));
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
      if (write_paths) {  // cut once every level's are known (cutWalls)
        auto level_allowed = std::make_shared<const Region>(std::move(allowed));
        auto safe = std::make_shared<const SafeDescent>(*level_allowed, options.allowance);
        for (const ContourStretch& s : stretches)
          walls.push_back({s, level.z, level.z + options.allowance, level_allowed, safe});
      }
    }
  }
  if (write_paths) {
    cutFloors(floors, clearing, limit, 2 * (r + kReachSlack), options.rapid_mm_min, floor_path);
    if (floor_path.started()) wall_path.startAt(floor_path.at());  // the walls follow the floors in the program
    cutWalls(walls, lead, r + kReachSlack, limit, options.rapid_mm_min, wall_path);
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
// One stack of shadows for every tool of a group: each level's height (just above it) exactly, and the bottoms of
// the tools' shanks and holders over it rounded down to a kZoneGrid grid (a lower height's shadow holds more: the
// zones stay clear, a shank reaching at most that much less deep). Levels depend on a wall and a tool alone, so the
// heights hold for every round of rest tools.
ShadowStack groupShadows(const Part& part, const GroupGeometry& g, const std::vector<const Tool*>& tools,
                         const FinishingOptions& options) {
  std::vector<double> heights;
  for (const Tool* t : tools)
    for (const LevelWork& l : levelsFor(g, *t, options.planar)) {
      heights.push_back(l.z + kAbove);
      for (const BodyZone& zone : finishingZones(*t, options.allowance))
        heights.push_back(std::floor((l.z + kAbove + zone.from) / kZoneGrid) * kZoneGrid);
    }
  std::sort(heights.begin(), heights.end());
  heights.erase(std::unique(heights.begin(), heights.end()), heights.end());
  return ShadowStack(g.vertices, part.mesh.triangles, heights);
}

// The tool to run next, and a longer one of its diameter to run after it for the depth it does not reach (the choice
// between them was made: kShortFirstShare), or none.
struct ToolChoice {
  const Tool* tool = nullptr;
  const Tool* then = nullptr;
};

ToolChoice nextTool(const ShadowStack& shadows, const PlanarGroup& group, const GroupGeometry& g,
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
  if (candidates.empty()) return {};
  std::stable_sort(candidates.begin(), candidates.end(), [](const Tool* a, const Tool* b) {
    if (a->diameter != b->diameter) return a->diameter > b->diameter;
    return a->flute_length < b->flute_length;
  });
  // Tools are compared on a sample of the levels; when the sample shows nothing the two most capable reach, on all.
  bool sample = true;
  std::map<const Tool*, double> reach;
  auto evaluate = [&](const Tool* t) {
    const auto it = reach.find(t);
    if (it != reach.end()) return it->second;
    GroupGeometry trial = g;
    return reach[t] = runTool(group, trial, shadows, *t, options, false, sample).reached_total;
  };
  const Tool* smallest = candidates.back();
  const Tool* longest = *std::max_element(candidates.begin(), candidates.end(), [](const Tool* a, const Tool* b) {
    return a->flute_length < b->flute_length || (a->flute_length == b->flute_length && a->diameter > b->diameter);
  });
  double best = std::max(evaluate(smallest), evaluate(longest));
  if (best <= kSliver) {
    sample = false;
    reach.clear();
    best = std::max(evaluate(smallest), evaluate(longest));
  }
  if (best <= kSliver) return {};
  for (auto chosen = candidates.begin(); chosen != candidates.end(); ++chosen) {
    if (evaluate(*chosen) < options.tools.area_fraction * best) continue;
    for (auto shorter = candidates.begin(); shorter != chosen; ++shorter)  // same diameter first, shortest flutes
      if (std::abs((*shorter)->diameter - (*chosen)->diameter) < 1e-9 &&
          (*shorter)->feed_mm_min > (*chosen)->feed_mm_min &&
          evaluate(*shorter) >= kShortFirstShare * evaluate(*chosen))
        return {*shorter, *chosen};
    return {*chosen};
  }
  return {smallest};
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
  const ShadowStack shadows = groupShadows(part, base, tools, options);
  std::vector<const Tool*> used;
  const Tool* previous = nullptr;
  const Tool* then = nullptr;  // the longer tool chosen to follow the last one
  int smaller = 0;  // tools narrower than the one before them (a longer one as wide is no rest tool of the budget)
  for (int pass = 0; !nothingLeft(g); ++pass) {
    const ToolChoice choice = then ? ToolChoice{then} : nextTool(shadows, group, g, tools, previous, used, options);
    const Tool* tool = choice.tool;
    then = choice.then;
    if (!tool) break;
    if (previous && tool->diameter < previous->diameter - 1e-9 && ++smaller > options.tools.max_rest_tools) break;
    used.push_back(tool);
    previous = tool;
    const auto start = std::chrono::steady_clock::now();
    ToolRun run = runTool(group, g, shadows, *tool, options, true);
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
