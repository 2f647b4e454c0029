#include "art2part/roughing/voxel_roughing.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <optional>

#include "art2part/common/angles.h"
#include "art2part/geometry/adjacency.h"
#include "art2part/roughing/cone_thinning.h"
#include "art2part/roughing/forbidden_region.h"
#include "art2part/roughing/point_cones.h"
#include "art2part/roughing/shadow.h"
#include "art2part/roughing/slicing.h"
#include "art2part/roughing/tool_profiling.h"

namespace art2part {

namespace {

constexpr double kLayerOfDiameter = 0.8;    // slabs merged or cut to about this many tool diameters (buildSlabs)
constexpr double kMaterialSliverMm2 = 1.0;  // material of a slab in pieces smaller than this is left to finishing
constexpr double kSteepestTiltDeg = 85.0;   // the reach of a leaning body is measured at no more tilt than this

// A slab of stock the 3-axis operations left: its material (the part's section taken out) and, for the holder
// check of the slabs below, that material grown by the shank's and the holder's radii.
struct Slab {
  double z = 0, top = 0;
  Region remaining;   // stock and part section, as the 3-axis operation left it
  Region part;        // the part's section in the slab, grown by the allowance
  Region material;    // remaining - part: what this operation is for
  bool has_material = false;
  RegionLocator near_shank, near_holder;  // material grown by the shank's, the holder's radius (and the margin)
};

struct Voxel {
  Point2 xy;          // setup frame
  Vec3 point;         // the machining point (at the slab's bottom), part frame
  Vec3 tip;           // the tool's tip at its posture (pushed along the axis from the point), part frame
  bool material = false, air = false, live = false, cut = false;
  Vec3 axis = Vec3::UnitZ();  // part frame
  Cone cone;
};

// Everything the operation works with, built once per setup.
struct Context {
  const Part& part;
  const Setup& setup;
  const RoughingOptions& options;
  DirectionSet directions;
  Cone all, reach;
  PointCones cones;
  PartCollider collider;
  std::vector<Slab> slabs;  // top down
  double clearance_z = 0;   // setup frame

  Context(const Part& p, const Setup& s, const RoughingOptions& o)
      : part(p), setup(s), options(o), directions(sampleSphere(o.five_axis.cone_level)), cones(p.mesh, directions),
        collider(p.mesh) {
    all.assign((directions.size() + 63) / 64, 0);
    for (int d = 0; d < directions.size(); ++d) all[d >> 6] |= std::uint64_t(1) << (d & 63);
    reach = reachCone(directions, s.frame.z, o.five_axis.max_tilt_deg);
  }
};

// The part's section in [z, top], sampled at its ends and middle, grown by the allowance.
Region partInSlab(const Part& part, const Adjacency& adjacency, const SetupFrame& f, double z, double top) {
  Region section;
  for (const double h : {z + 1e-3, 0.5 * (z + top), top - 1e-3})
    section = unite(section, sliceRegion(sliceMesh(part.mesh, adjacency, f.origin, f.x, f.y, f.z, h)));
  return section;
}

double bodyRadius(const Tool& tool, bool holder) {
  if (!holder) return tool.shank_diameter / 2;
  double r = tool.shank_diameter / 2;
  for (const HolderStep& step : tool.holder) r = std::max(r, step.diameter / 2);
  return r;
}

// Layers about 0.8 of the tool's diameter thick: a leaning tool cuts an inclined band about its diameter high. The
// 3-axis operations' slabs (1 mm apart where a rest pass re-roughed) are merged up to that thickness, their leftovers
// united, or a thicker one is cut into layers.
void buildSlabs(Context& c, const std::vector<SlabState>& left, const Tool& tool) {
  const Adjacency adjacency = buildAdjacency(c.part.mesh);
  const double thickness = kLayerOfDiameter * tool.diameter;
  std::vector<const SlabState*> order;
  for (const SlabState& s : left) order.push_back(&s);
  std::sort(order.begin(), order.end(), [](const SlabState* a, const SlabState* b) { return a->z > b->z; });
  double top = -1e300;
  auto add = [&](double z, double slab_top, Region remaining, Region part) {
    Slab slab;
    slab.z = z;
    slab.top = slab_top;
    slab.remaining = std::move(remaining);
    if (!regionEmpty(slab.remaining)) {
      slab.part = offsetRegion(part, c.options.allowance);
      slab.material = dropSlivers(subtract(slab.remaining, slab.part), kMaterialSliverMm2);
      slab.has_material = !regionEmpty(slab.material);
    }
    const double margin = c.options.clearing.holder_margin;
    slab.near_shank = RegionLocator(growForBody(slab.material, bodyRadius(tool, false) + margin));
    slab.near_holder = RegionLocator(growForBody(slab.material, bodyRadius(tool, true) + margin));
    c.slabs.push_back(std::move(slab));
  };
  for (std::size_t i = 0; i < order.size();) {
    const SlabState& s = *order[i];
    top = std::max(top, s.top);
    if (s.top - s.z > thickness) {  // thick: cut into layers
      const int layers = static_cast<int>(std::ceil((s.top - s.z) / thickness - 1e-9));
      for (int k = 0; k < layers; ++k) {
        const double z = s.z + k * (s.top - s.z) / layers, slab_top = s.z + (k + 1) * (s.top - s.z) / layers;
        add(z, slab_top, s.remaining,
            regionEmpty(s.remaining) ? Region{} : partInSlab(c.part, adjacency, c.setup.frame, z, slab_top));
      }
      ++i;
      continue;
    }
    // Thin: merged with those below while the layer stays thin enough.
    Region remaining, part;
    double z = s.z;
    std::size_t j = i;
    for (; j < order.size() && s.top - order[j]->z <= thickness + 1e-9; ++j) {
      z = order[j]->z;
      if (regionEmpty(order[j]->remaining)) continue;
      remaining = unite(remaining, order[j]->remaining);
      part = unite(part, partInSlab(c.part, adjacency, c.setup.frame, order[j]->z, order[j]->top));
    }
    add(z, s.top, std::move(remaining), std::move(part));
    i = j;
  }
  std::sort(c.slabs.begin(), c.slabs.end(), [](const Slab& a, const Slab& b) { return a.z > b.z; });
  c.clearance_z = top + c.options.clearing.clearance;
}

Vec3 inFrame(const Vec3& v, const SetupFrame& f) { return Vec3(v.dot(f.x), v.dot(f.y), v.dot(f.z)); }

// The tool's section in the slab plane, an ellipse r / cos(theta) long along the tilt (4.1.5), grown by the
// allowance: clear of the part's section at the tip's height.
bool footprintClear(const Slab& slab, const Point2& centre, const Vec3& axis_in_frame, double radius) {
  const double cos_t = std::max(axis_in_frame.z(), 0.05);
  Point2 along(axis_in_frame.x(), axis_in_frame.y());
  along = along.norm() > 1e-9 ? along.normalized() : Point2(1, 0);
  const Point2 across(-along.y(), along.x());
  Ring ellipse;
  Point2 lo(1e300, 1e300), hi(-1e300, -1e300);
  for (int k = 0; k < 32; ++k) {
    const double a = 2 * kPi * k / 32;
    ellipse.push_back(centre + radius / cos_t * std::cos(a) * along + radius * std::sin(a) * across);
    lo = lo.cwiseMin(ellipse.back()), hi = hi.cwiseMax(ellipse.back());
  }
  const Region near = ringsMeeting(slab.part, lo, hi);
  return near.empty() || regionEmpty(intersect(regionFromPolygons({ellipse}), near));
}

// Shank and holder out of the material left in the slabs above (with the tool descending along its axis from the
// clearance plane, every slab the axis crosses above the flutes sees the body up to that height pass).
bool clearOfStockAbove(const Context& c, const Tool& tool, std::size_t slab_index, const Vec3& tip_frame,
                       const Vec3& axis_frame) {
  if (axis_frame.z() <= 1e-6) return false;
  for (std::size_t s = 0; s < slab_index; ++s) {
    const Slab& slab = c.slabs[s];
    if (!slab.has_material) continue;
    const double h = (0.5 * (slab.z + slab.top) - tip_frame.z()) / axis_frame.z();
    if (h <= tool.flute_length) continue;
    const Vec3 at = tip_frame + h * axis_frame;
    const RegionLocator& near = h <= tool.stickout ? slab.near_shank : slab.near_holder;
    if (near.contains(Point2(at.x(), at.y()))) return false;
  }
  return true;
}

ProfileOptions profileOptions(const RoughingOptions& o) {
  ProfileOptions p;
  p.flute_margin = o.allowance;
  p.body_margin = o.clearing.holder_margin;
  p.max_tilt_deg = o.five_axis.max_tilt_deg;
  return p;
}

// The material of the voxel's own slab that earlier rows have not cut, grown by the shank's and the holder's radii
// (and the margin): a tool leaning far over lies along the slab, and its body must stay out of what stands there.
constexpr int kLayers = 4;  // sub-layers of a slab in which the cut of a leaning tool is tracked

struct Standing {
  struct Zone {
    double from = 0, to = 0;                 // heights above the tip
    std::array<RegionLocator, kLayers> near;  // per sub-layer: what stands there, grown by the zone's radius + margin
  };
  std::vector<Zone> zones;                   // shank, then each holder step, those starting within `inside`
  double z = 0, thickness = 0;
  double inside = 0;                         // the most the body stays in the slab at the reach's tilt, above the tip
};

// `cut` per sub-layer: where earlier rows' flutes passed at that height (a tool leaning far over cuts an inclined
// band, not the slab's whole column under its tip). Only what stands near `row` counts: clearOfStanding looks at the
// body while it is inside the slab, at most thickness x tan(max tilt) sideways from a tip, so the material is cut to
// the row's box grown by that and the widest zone's radius (the same answers there, a fraction of the work).
Standing standingMaterial(const Context& c, const Slab& slab, const std::array<Region, kLayers>& cut, const Tool& tool,
                          const std::vector<Voxel>& row) {
  Standing standing;
  standing.z = slab.z;
  standing.thickness = slab.top - slab.z;
  const double margin = c.options.clearing.holder_margin;
  const double tan_tilt = std::tan(std::min(c.options.five_axis.max_tilt_deg, kSteepestTiltDeg) * kPi / 180);
  // A zone starting higher above the tip than the body stays in the slab (thickness / cos(max tilt)) is never looked
  // at: the library's flutes are longer than that, so a slab 0.8 D thick usually needs none.
  const double inside = standing.inside = standing.thickness * std::sqrt(1 + tan_tilt * tan_tilt);
  std::vector<BodyZone> zones;
  double widest = 0;
  for (const BodyZone& body : bodyZones(tool))
    if (body.from <= inside) {
      zones.push_back(body);
      widest = std::max(widest, body.radius);
    }
  if (zones.empty()) return standing;
  const double reach = standing.thickness * tan_tilt + widest + margin + 1.0;
  Point2 lo(1e300, 1e300), hi(-1e300, -1e300);
  for (const Voxel& v : row) {
    lo = lo.cwiseMin(v.xy);
    hi = hi.cwiseMax(v.xy);
  }
  const Region window = regionFromPolygons({{Point2(lo.x() - reach, lo.y() - reach), Point2(hi.x() + reach, lo.y() - reach),
                                             Point2(hi.x() + reach, hi.y() + reach), Point2(lo.x() - reach, hi.y() + reach)}});
  const Region material = intersect(slab.material, window);
  for (const BodyZone& body : zones) {
    Standing::Zone z{body.from, body.to, {}};
    for (int k = 0; k < kLayers; ++k)
      z.near[k] = RegionLocator(growForBody(subtract(material, intersect(cut[k], window)), body.radius + margin));
    standing.zones.push_back(std::move(z));
  }
  return standing;
}

int layerOf(const Standing& standing, double z) {
  const double f = (z - standing.z) / std::max(standing.thickness, 1e-9);
  return std::clamp(static_cast<int>(f * kLayers), 0, kLayers - 1);
}

bool clearOfStanding(const Standing& standing, const Slab& slab, const Vec3& tip_frame, const Vec3& axis_frame) {
  const double leaves = axis_frame.z() > 1e-6 ? (slab.top - tip_frame.z()) / axis_frame.z() : 1e300;
  if (leaves > standing.inside + 1e-9) return false;  // a posture beyond what the zones were chosen for: refused
  for (const Standing::Zone& zone : standing.zones)
    for (double h = zone.from; h <= std::min(zone.to, leaves); h += 1.0) {
      const Vec3 at = tip_frame + h * axis_frame;
      if (zone.near[layerOf(standing, at.z())].contains(Point2(at.x(), at.y()))) return false;
    }
  return true;
}

// What the flutes of a tool at (tip, axis) (setup frame) take from each sub-layer: a disc a little inside the flutes'
// section where the axis crosses the sub-layer's middle, if the flutes reach that height.
void addCut(std::array<std::vector<Ring>, kLayers>& discs, const Slab& slab, const Tool& tool, const Vec3& tip,
            const Vec3& axis) {
  if (axis.z() <= 1e-6) return;
  for (int k = 0; k < kLayers; ++k) {
    const double z = slab.z + (k + 0.5) * (slab.top - slab.z) / kLayers;
    const double h = (z - tip.z()) / axis.z();
    if (h < 0 || h > tool.flute_length) continue;
    const Vec3 at = tip + h * axis;
    Ring ring;
    for (int i = 0; i < 8; ++i)
      ring.push_back(Point2(at.x(), at.y()) + 0.9 * tool.diameter / 2 * Point2(std::cos(i * kPi / 4), std::sin(i * kPi / 4)));
    discs[k].push_back(std::move(ring));
  }
}

// The standing material of a row, worked out when a voxel of the row first needs it.
struct LazyStanding {
  const Context& c;
  const Slab& slab;
  const std::array<Region, kLayers>& cut;
  const Tool& tool;
  const std::vector<Voxel>& row;
  std::optional<Standing> standing;
  const Standing& get() {
    if (!standing) standing = standingMaterial(c, slab, cut, tool, row);
    return *standing;
  }
};

// 4.1.3: the access direction from the voxel's cone by restricted thinning, checked by the footprint and profiled.
void orientVoxel(const Context& c, const Tool& tool, std::size_t slab_index, Voxel& v,
                 LazyStanding* standing = nullptr) {
  v.cone = c.cones.coneAt(v.point, c.all);
  const int d = accessDirection(c.directions, v.cone, &c.reach);
  if (d < 0) return;
  const Vec3 axis = c.directions.directions[d];
  if (!footprintClear(c.slabs[slab_index], v.xy, inFrame(axis, c.setup.frame), tool.diameter / 2 + c.options.allowance))
    return;
  const Posture posture = profileTool(c.collider, {&tool}, {v.point, axis}, c.setup.frame.z, profileOptions(c.options));
  if (!posture.live) return;
  const Vec3 tip_frame = inFrame(posture.pose.tip - c.setup.frame.origin, c.setup.frame);
  const Vec3 axis_frame = inFrame(posture.pose.axis, c.setup.frame);
  if (!clearOfStockAbove(c, tool, slab_index, tip_frame, axis_frame)) return;
  if (standing && !clearOfStanding(standing->get(), c.slabs[slab_index], tip_frame, axis_frame)) return;
  v.tip = posture.pose.tip;
  v.axis = posture.pose.axis;
  v.live = true;
}

// Rows of voxels over a slab's material, `spacing` apart, points every half of it, reaching a little beyond the
// material on both sides (so a pass can start in air). The rows run square to `tilt` (the mean sideways lean of the
// access directions, unit, in the slab plane): the tool then cuts with its side, and the rows come nearest the way
// out first (largest coordinate along `tilt`), so each row's approach along the axis crosses stock already cleared.
std::vector<std::vector<Voxel>> sampleRows(const Context& c, const Slab& slab, const Tool& tool, double spacing,
                                           const Point2& tilt) {
  std::vector<std::vector<Voxel>> rows;
  if (!slab.has_material) return rows;
  const double r = tool.diameter / 2, step = spacing / 2;
  const Point2 along(-tilt.y(), tilt.x());
  const Region near_region = offsetRegion(slab.material, r + 2 * step);
  const RegionLocator near(near_region), material(slab.material), occupied(offsetRegion(slab.remaining, r + 0.5));
  double s0 = 1e300, s1 = -1e300, q0 = 1e300, q1 = -1e300;
  for (const Ring& ring : regionRings(near_region))
    for (const Point2& p : ring) {
      s0 = std::min(s0, p.dot(along)); s1 = std::max(s1, p.dot(along));
      q0 = std::min(q0, p.dot(tilt)); q1 = std::max(q1, p.dot(tilt));
    }
  for (double q = q1 - step; q > q0; q -= spacing) {
    std::vector<Voxel> row;
    for (double s = s0; s <= s1; s += step) {
      const Point2 xy = s * along + q * tilt;
      if (!near.contains(xy)) {
        if (!row.empty()) rows.push_back(std::move(row)), row.clear();
        continue;
      }
      Voxel v;
      v.xy = xy;
      v.point = v.tip = fromFrame(Vec3(xy.x(), xy.y(), slab.z), c.setup.frame);
      v.material = material.contains(xy);
      v.air = !occupied.contains(xy);
      row.push_back(std::move(v));
    }
    if (!row.empty()) rows.push_back(std::move(row));
  }
  return rows;
}

// On a sample of the voxels (rows `spacing` apart, every `every`-th voxel of material): how many the tool reaches,
// and the sum of their axes' sideways lean (setup frame).
int countLive(const Context& c, const Tool& tool, double spacing, int every, Point2* lean = nullptr) {
  int live = 0, seen = 0;
  for (std::size_t s = 0; s < c.slabs.size(); ++s)
    for (std::vector<Voxel>& row : sampleRows(c, c.slabs[s], tool, spacing, Point2(0, 1)))
      for (Voxel& v : row) {
        if (!v.material || seen++ % every) continue;
        orientVoxel(c, tool, s, v);
        live += v.live;
        if (v.live && lean) {
          const Vec3 a = inFrame(v.axis, c.setup.frame);
          *lean += Point2(a.x(), a.y());
        }
      }
  return live;
}

// 4.1.4: neighbours are joined when their cones overlap enough and the tool half-way between is clear.
bool transition(const Context& c, const Tool& tool, const Voxel& a, const Voxel& b) {
  if (intersectionSolidAngle(c.directions, a.cone, b.cone) < c.options.five_axis.transition_sr) return false;
  const ToolPose mid{0.5 * (a.tip + b.tip), (a.axis + b.axis).normalized()};
  return c.collider.toolClear(tool, mid, c.options.allowance, c.options.clearing.holder_margin);
}

// The tool can come down its axis from the clearance plane to the voxel without meeting the part.
bool approachClear(const Context& c, const Tool& tool, const Voxel& v) {
  const Vec3 axis_frame = inFrame(v.axis, c.setup.frame);
  const double tip_z = (v.tip - c.setup.frame.origin).dot(c.setup.frame.z);
  const double length = (c.clearance_z - tip_z) / std::max(axis_frame.z(), 1e-6);
  const double step = std::max(5.0, 0.5 * toolLength(tool));
  for (double s = step; s < length + step; s += step)
    if (!c.collider.toolClear(tool, {v.tip + std::min(s, length) * v.axis, v.axis}, c.options.allowance,
                              c.options.clearing.holder_margin))
      return false;
  return true;
}

Vec3 overClearance(const Context& c, const Voxel& v) {
  const Vec3 axis_frame = inFrame(v.axis, c.setup.frame);
  const double tip_z = (v.tip - c.setup.frame.origin).dot(c.setup.frame.z);
  return v.tip + (c.clearance_z - tip_z) / std::max(axis_frame.z(), 1e-6) * v.axis;
}

// 4.1.5: the passes of one row: chains of joined live voxels trimmed to their material and the nearest voxel in air
// beyond it at each end (the entry and the exit), entered from air where an end is in air.
int emitRow(const Context& c, int setup_index, const Tool& tool, std::vector<Voxel>& row,
            RoughingOperation& op, VoxelRoughingStats& stats) {
  int passes = 0;
  std::size_t i = 0;
  while (i < row.size()) {
    if (!row[i].live) { ++i; continue; }
    std::size_t j = i;
    while (j + 1 < row.size() && row[j + 1].live) {
      if (!transition(c, tool, row[j], row[j + 1])) { ++stats.broken_transitions; break; }
      ++j;
    }
    std::size_t first = i, last = j;
    while (first <= last && !row[first].material) ++first;
    while (last > first && !row[last].material) --last;
    if (first <= last && row[first].material) {
      // Back to the nearest voxel in air before the material (the entry), forward to the nearest after it.
      std::size_t entry = first, exit = last;
      while (entry > i && !row[entry].air) --entry;
      while (exit < j && !row[exit].air) ++exit;
      first = row[entry].air ? entry : first;
      last = row[exit].air ? exit : last;
      std::vector<Voxel*> pass;
      for (std::size_t k = first; k <= last; ++k) pass.push_back(&row[k]);
      if (!pass.front()->air && pass.back()->air) std::reverse(pass.begin(), pass.end());
      if (approachClear(c, tool, *pass.front()) && approachClear(c, tool, *pass.back())) {
        if (!pass.front()->air) ++op.plunges;
        op.path.push_back(cutterLocation(setup_index, tool.id, MoveKind::Rapid, overClearance(c, *pass.front()),
                                   pass.front()->axis));
        for (Voxel* v : pass) {
          op.path.push_back(cutterLocation(setup_index, tool.id, MoveKind::Feed, v->tip, v->axis));
          v->cut = true;
        }
        op.path.push_back(cutterLocation(setup_index, tool.id, MoveKind::Feed, overClearance(c, *pass.back()),
                                   pass.back()->axis));
        ++op.retracts;
        ++passes;
      }
    }
    i = j + 1;
  }
  return passes;
}

}  // namespace

RoughingOperation voxelRoughSetup(const Part& part, const Setup& setup, int setup_index,
                                  const std::vector<const Tool*>& tools, const RoughingOptions& options,
                                  const std::vector<SlabState>& left, VoxelRoughingStats* stats_out) {
  const auto start = std::chrono::steady_clock::now();
  RoughingOperation op;
  op.setup = setup_index;
  op.kind = "5-axis roughing";
  VoxelRoughingStats stats;
  if (tools.empty() || left.empty()) return op;
  Context c(part, setup, options);
  // Tool: the one whose live voxels, on a sample, stand for the most material (count x the area of a sampled voxel x
  // the layer height: a larger tool reaches fewer voxels, each a larger piece).
  const int every = 3;
  const Tool* tool = nullptr;
  double most = 0;
  for (const Tool* t : tools) {
    c.slabs.clear();
    buildSlabs(c, left, *t);
    const double spacing = 2 * roughingStepover(*t, options);
    const double layer = c.slabs.empty() ? 0 : c.slabs.front().top - c.slabs.front().z;
    const double volume = countLive(c, *t, spacing, every) * every * spacing * spacing / 2 * layer;
    if (volume > most) most = volume, tool = t;
  }
  if (!tool) return op;
  c.slabs.clear();
  buildSlabs(c, left, *tool);
  Point2 lean = Point2::Zero();
  countLive(c, *tool, 2 * roughingStepover(*tool, options), every, &lean);
  const Point2 tilt = lean.norm() > 1e-9 ? Point2(lean.normalized()) : Point2(0, 1);
  op.tool = tool->id;
  const double spacing = roughingStepover(*tool, options);
  double tilt_sum = 0;
  for (std::size_t s = 0; s < c.slabs.size(); ++s) {
    RoughingLevel level;
    level.z = c.slabs[s].z;
    level.remaining_mm2 = regionArea(c.slabs[s].material);
    std::array<Region, kLayers> cut;  // where this slab's earlier rows took the flutes, per sub-layer
    for (std::vector<Voxel>& row : sampleRows(c, c.slabs[s], *tool, spacing, tilt)) {
      LazyStanding standing{c, c.slabs[s], cut, *tool, row, std::nullopt};
      for (Voxel& v : row) {
        orientVoxel(c, *tool, s, v, &standing);
        if (!v.material) continue;
        ++stats.voxels;
        if (!v.live) { ++stats.dead; continue; }
        ++stats.live;
        const double tilt = std::acos(std::clamp(v.axis.dot(setup.frame.z), -1.0, 1.0)) * 180 / kPi;
        tilt_sum += tilt;
        stats.max_tilt_deg = std::max(stats.max_tilt_deg, tilt);
      }
      level.rings += emitRow(c, setup_index, *tool, row, op, stats);
      std::array<std::vector<Ring>, kLayers> discs;
      for (const Voxel& v : row)
        if (v.cut)
          addCut(discs, c.slabs[s], *tool, inFrame(v.tip - setup.frame.origin, setup.frame), inFrame(v.axis, setup.frame));
      for (int k = 0; k < kLayers; ++k)
        if (!discs[k].empty()) cut[k] = unite(cut[k], regionFromPolygons(discs[k]));
    }
    stats.passes += level.rings;
    op.levels.push_back(level);
  }
  stats.mean_tilt_deg = stats.live ? tilt_sum / stats.live : 0;
  op.feed_mm = toolpathLength(op.path, MoveKind::Feed);
  op.rapid_mm = toolpathLength(op.path, MoveKind::Rapid);
  op.seconds = 60.0 * (op.feed_mm / std::max(1.0, tool->feed_mm_min) + op.rapid_mm / std::max(1.0, options.rapid_mm_min));
  stats.seconds = op.plan_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (stats_out) *stats_out = stats;
  return op;
}

}  // namespace art2part
