#include "art2part/roughing/roughing.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "art2part/roughing/shadow.h"

namespace art2part {

namespace {

constexpr double kPi = 3.14159265358979323846;

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// A part of the tool body above the flutes that is wider than the cutter: from..to above the tip, its radius.
struct BodyZone {
  double from = 0, to = 0, radius = 0;
};

// The body above the flutes: shank and holder steps. A shank no wider than the cutter follows where the flutes have
// cleared, in principle; it is checked all the same, since the cleared area is known only to the accuracy of the
// offsets and of the passes.
std::vector<BodyZone> bodyZones(const Tool& tool) {
  std::vector<BodyZone> zones;
  if (tool.stickout > tool.flute_length) zones.push_back({tool.flute_length, tool.stickout, tool.shank_diameter / 2});
  // Holder steps whose radii differ by less than 10 mm are merged, as wide as the wider: one offset per level
  // instead of one per step (a collet chuck's nut, body and flange), at the price of a few mm of reach under it.
  double from = tool.stickout;
  const std::size_t first_holder = zones.size();
  for (const HolderStep& step : tool.holder) {
    const double radius = step.diameter / 2;
    if (zones.size() > first_holder && std::abs(zones.back().radius - radius) < 10) {
      zones.back().to += step.length;
      zones.back().radius = std::max(zones.back().radius, radius);
    } else {
      zones.push_back({from, from + step.length, radius});
    }
    from += step.length;
  }
  return zones;
}

// The part and its stock in one setup's frame.
struct SetupGeometry {
  std::vector<Vec3> part;   // part vertices in the frame
  Mesh stock;               // stock mesh, vertices in the frame
  double stock_top = 0, stock_bottom = 0;
};

SetupGeometry setupGeometry(const Part& part, const Setup& setup, const RoughingOptions& options) {
  SetupGeometry g;
  g.part = toFrame(part.mesh.vertices, setup.frame);
  g.stock = roughingStock(part, options);
  g.stock.vertices = toFrame(g.stock.vertices, setup.frame);
  g.stock_top = -1e300;
  g.stock_bottom = 1e300;
  for (const Vec3& p : g.stock.vertices) {
    g.stock_top = std::max(g.stock_top, p.z());
    g.stock_bottom = std::min(g.stock_bottom, p.z());
  }
  return g;
}

double stepdownFor(const Tool& tool, const RoughingOptions& options) {
  double step = options.stepdown > 0 ? options.stepdown : (tool.max_stepdown > 0 ? tool.max_stepdown : tool.diameter / 2);
  return std::min(step, tool.flute_length);
}

double stepoverFor(const Tool& tool, const RoughingOptions& options) {
  const double step = options.stepover > 0 ? options.stepover : (tool.max_stepover > 0 ? tool.max_stepover : 0.4 * tool.diameter);
  return std::min(step, 0.9 * tool.diameter);  // passes must overlap or ridges stay between them
}

// The heights whose shadows an operation needs: its levels, and above each the bottom of every wide body zone.
std::vector<double> shadowHeights(const std::vector<RoughingLevel>& levels, const std::vector<BodyZone>& zones) {
  std::vector<double> heights;
  for (const RoughingLevel& l : levels) {
    heights.push_back(l.z);
    for (const BodyZone& zone : zones) heights.push_back(l.z + zone.from);
  }
  return heights;
}

// The stock a previous operation left in the slab [z, top] (its slabs contain ours: our levels include theirs).
const Region* beforeRemaining(const std::vector<SlabState>& before, double z, double top) {
  for (const SlabState& s : before)
    if (z >= s.z - 1e-9 && top <= s.top + 1e-9) return &s.remaining;
  return nullptr;
}

void appendMoves(const std::vector<ClearingPoint>& moves, const SetupFrame& frame, const Tool& tool, int setup_index,
                 RoughingOperation& op) {
  for (const ClearingPoint& m : moves) {
    CutterLocation cl;
    cl.setup = setup_index;
    cl.tool = tool.id;
    cl.move = m.move == ClearingMove::Rapid ? MoveKind::Rapid : MoveKind::Feed;
    cl.tip = fromFrame(m.tip, frame);
    cl.axis = frame.z;
    if (!op.path.empty() && op.path.back().move == cl.move && (op.path.back().tip - cl.tip).norm() < 1e-9) continue;
    op.path.push_back(cl);
  }
}

void countEntries(const ClearingStats& stats, RoughingOperation& op) {
  op.plunges += stats.plunges_into_stock;
  op.ramps += stats.ramps;
  op.retracts += stats.retracts;
}

void estimateTime(const Tool& tool, const RoughingOptions& options, RoughingOperation& op) {
  op.feed_mm = toolpathLength(op.path, MoveKind::Feed);
  op.rapid_mm = toolpathLength(op.path, MoveKind::Rapid);
  op.seconds = 60.0 * (op.feed_mm / std::max(1.0, tool.feed_mm_min) + op.rapid_mm / std::max(1.0, options.rapid_mm_min));
}

}  // namespace

Mesh roughingStock(const Part& part, const RoughingOptions& options) {
  if (options.stock_mesh) return *options.stock_mesh;
  Box box = boundingBox(part.mesh);
  box.min -= Vec3::Constant(options.stock_margin);
  box.max += Vec3::Constant(options.stock_margin);
  return boxMesh(box);
}

std::vector<RoughingLevel> roughingLevels(const Part& part, const std::vector<Vec3>& frame_vertices,
                                          double stock_top, double stock_bottom, double stepdown,
                                          const RoughingOptions& options) {
  std::vector<RoughingLevel> critical;
  if (options.critical_heights) {
    const double cos_limit = std::cos(options.critical_angle_deg * kPi / 180);
    std::vector<char> seen(part.faces.size(), 0);
    for (int t = 0; t < part.mesh.triangleCount(); ++t) {
      const int f = t < static_cast<int>(part.triangle_face.size()) ? part.triangle_face[t] : -1;
      if (f < 0 || f >= static_cast<int>(part.faces.size()) || seen[f] || part.faces[f].type != SurfaceType::Plane)
        continue;
      seen[f] = 1;
      const Triangle& tri = part.mesh.triangles[t];
      const Vec3 &a = frame_vertices[tri[0]], &b = frame_vertices[tri[1]], &c = frame_vertices[tri[2]];
      const Vec3 n = (b - a).cross(c - a).normalized();
      if (n.z() < cos_limit) continue;  // not facing up, square to the direction
      const double z = (a.z() + b.z() + c.z()) / 3 + options.allowance;
      if (z < stock_top - 1e-6 && z > stock_bottom + 1e-6) critical.push_back({z, true});
    }
  }
  std::sort(critical.begin(), critical.end(), [](const RoughingLevel& p, const RoughingLevel& q) { return p.z > q.z; });
  // Regular levels between consecutive fixed heights (stock top, critical heights, stock bottom), evenly spaced at
  // most `stepdown` apart.
  std::vector<RoughingLevel> fixed = critical;
  fixed.push_back({stock_bottom, false});
  std::vector<RoughingLevel> levels;
  double top = stock_top;
  for (const RoughingLevel& f : fixed) {
    if (top - f.z < 0.02) {  // a critical height a hair below the previous one: merged
      if (f.critical && !levels.empty()) levels.back().critical = true;
      continue;
    }
    const int n = std::max(1, static_cast<int>(std::ceil((top - f.z) / stepdown - 1e-9)));
    for (int i = 1; i < n; ++i) levels.push_back({top - (top - f.z) * i / n, false});
    levels.push_back(f);
    top = f.z;
  }
  return levels;
}

RoughingOperation roughSetup(const Part& part, const Setup& setup, int setup_index, const Tool& tool,
                             const RoughingOptions& options, const std::vector<SlabState>* before,
                             std::vector<SlabState>* after) {
  const auto start = std::chrono::steady_clock::now();
  RoughingOperation op;
  op.setup = setup_index;
  op.tool = tool.id;
  op.kind = before ? "rest roughing" : "roughing";
  const SetupGeometry g = setupGeometry(part, setup, options);
  std::vector<RoughingLevel> levels =
      roughingLevels(part, g.part, g.stock_top, g.stock_bottom, stepdownFor(tool, options), options);
  if (before) {  // our slabs must each lie in one of the previous operation's slabs
    for (const SlabState& s : *before)
      if (std::none_of(levels.begin(), levels.end(), [&](const RoughingLevel& l) { return std::abs(l.z - s.z) < 1e-9; }))
        levels.push_back({s.z, false});
    std::sort(levels.begin(), levels.end(), [](const RoughingLevel& p, const RoughingLevel& q) { return p.z > q.z; });
  }
  const double r = tool.diameter / 2;
  // A rest pass keeps a hair more than the allowance so that it never grazes the thin skin its predecessor left.
  const double allowance = options.allowance + (before ? 0.05 : 0.0);
  const std::vector<BodyZone> zones = bodyZones(tool);
  ClearingOptions clearing;
  clearing.stepover = stepoverFor(tool, options);
  clearing.ramp_angle_deg = options.ramp_angle_deg;
  clearing.clearance_z = g.stock_top + options.clearance;

  const ShadowStack shadows(g.part, part.mesh.triangles, shadowHeights(levels, zones));
  std::vector<SlabState> slabs;
  std::vector<Region> left_above;  // left_above[j]: the union of the stock left in slabs 0..j
  Region forbidden;  // everything forbidden at this level, and so at any above
  double top = g.stock_top;
  for (RoughingLevel& level : levels) {
    const double z = level.z;
    const Region& shadow = shadows.at(z);
    Region stock = stockSlabRegion(g.stock.vertices, g.stock.triangles, z, top);
    if (before) {
      const Region* left = beforeRemaining(*before, z, top);
      stock = left ? intersect(stock, *left) : Region{};
    }
    // What this operation is to remove: all the stock, or for a rest pass what lies beyond the allowance.
    Region target = stock;
    if (before) target = dropSlivers(offsetRegion(offsetRegion(subtract(stock, offsetRegion(shadow, allowance)), -0.02), 0.02), 0.01);

    Region forbid = offsetRegion(shadow, r + allowance);
    for (const BodyZone& zone : zones) {
      // Stock left in every slab reaching above the zone's bottom (also those above its top: the spindle is wider
      // still), and the part above the zone's bottom.
      Region body = shadows.at(z + zone.from);
      std::size_t n = 0;
      while (n < slabs.size() && slabs[n].top > z + zone.from) ++n;
      if (n > 0) body = unite(body, left_above[n - 1]);
      forbid = unite(forbid, offsetRegion(body, zone.radius + options.holder_margin));
    }
    // Shadows and the stock left above only grow downwards, so forbid holds every level above's already.
    forbidden = std::move(forbid);

    ClearingLevel clear;
    clear.z = z;
    clear.top = top;
    clear.centre = regionEmpty(target) ? Region{} : dropSlivers(subtract(offsetRegion(target, r + (before ? 0.5 : 1.0)), forbidden), 0.001);
    clear.air = subtract(clear.centre, offsetRegion(stock, r + 0.1));
    ClearingStats stats;
    const std::vector<ClearingPoint> moves = clearLevel(clear, clearing, &stats);
    appendMoves(moves, setup.frame, tool, setup_index, op);
    countEntries(stats, op);

    const Region cleared = offsetRegion(clear.centre, r - 0.05);
    SlabState slab{z, top, subtract(stock, cleared)};
    level.cleared_mm2 = regionArea(intersect(stock, cleared));
    level.remaining_mm2 = regionArea(slab.remaining);
    level.rings = static_cast<int>(clear.centre.size());
    left_above.push_back(left_above.empty() ? slab.remaining : unite(left_above.back(), slab.remaining));
    slabs.push_back(std::move(slab));
    top = z;
  }
  op.levels = std::move(levels);
  estimateTime(tool, options, op);
  if (after) *after = std::move(slabs);
  op.plan_seconds = secondsSince(start);
  return op;
}

}  // namespace art2part
