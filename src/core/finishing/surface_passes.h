// Internal to surface finishing (surface_finishing.h): the cutter-location (CL) height map and its regions, the
// clearance maps, raster and waterline passes, their order and linking. Coordinates are those of the drop frame (z along
// the tool axis), mm.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <vector>

#include "art2part/common/parallel.h"
#include "art2part/finishing/drop_cutter.h"
#include "art2part/finishing/region_raster.h"
#include "art2part/finishing/surface_finishing.h"
#include "art2part/geometry/part.h"
#include "art2part/roughing/roughing.h"

namespace art2part::surface {

constexpr double kInf = std::numeric_limits<double>::infinity();

using Grid = NodeGrid;  // region_raster.h
// Nodes `pitch` apart over the x-y extent of `box`. Throws InputError past kMaxGridNodes (a pitch far too fine).
Grid gridOver(const Box& box, double pitch);
constexpr double kMaxGridNodes = 64e6;

// A cylinder of the tool above its tip, tested against the part grown by `grow`: it clears at tip height t iff the
// highest part point within radius + grow of the axis is at most t + height - grow (the zone is taken to reach up for
// ever, which is what a 3-axis tool coming down from above needs: the spindle is above it).
struct Zone {
  double radius = 0;
  double height = 0;
  double grow = 0;
};
// The shank and the holder's steps, those another zone makes redundant (wider and starting lower) left out.
std::vector<Zone> bodyZones(const Tool& tool, double grow);

// The lowest tip height at which every zone clears, per node of a grid. Each node takes the zones' radii grown by the
// grid's pitch, so that a node answers for every point within a pitch of it: the nearest node for a point, the
// nearest nodes of samples half a pitch apart for a segment.
struct ClearanceMap {
  Grid grid;
  std::vector<double> tip;  // -inf where nothing is near
  double at(double x, double y) const { return tip.empty() ? -kInf : tip[grid.nearest(x, y)]; }
  double along(const Vec3& a, const Vec3& b) const;  // the highest over the x-y segment a-b
};
ClearanceMap clearanceMap(const std::vector<Vec3>& vertices, const std::vector<Triangle>& triangles, const Grid& grid,
                          const std::vector<Zone>& zones, int threads, std::atomic<long>& drops);

// Raises the map where the zones meet stock: at every node within a zone's radius + grow + the grid's pitch of a
// slab's region, the tip at least the slab's top + grow - the zone's height (the slab's material may reach its top
// anywhere in its region); a node a little farther may be raised too: highestNear grows the regions on cells of
// kStockCell, or coarser where that would cut the map's pitch into more than kStockCellsPerPitch or the map into more
// than kStockCells (the cost grows as their square and with the cells), so by at most the cell's diagonal (the map
// grows every zone by its pitch anyway). `stock`: slabs in the map's frame, regions
// in mm as roughing's (region.h).
constexpr double kStockCell = 0.125;  // mm
constexpr double kStockCells = 1e6;
constexpr double kStockCellsPerPitch = 8;
void raiseOverStock(ClearanceMap& map, const std::vector<SlabState>& stock, const std::vector<Zone>& zones);

// What the passes need: the drop-cutter, the CL map with its regions, the clearance maps, tolerances.
struct Context {
  const DropCutter* cutter = nullptr;
  double floor = 0;            // below every part point: a drop that finds nothing returns it
  Grid grid;                   // the CL map's
  std::vector<double> height;  // CL tip height per node (NaN: not computed, away from the faces)
  std::vector<int> contact;    // triangle touched per node (-1: none)
  std::vector<double> slope;   // |gradient of the CL surface| per node
  std::vector<std::uint8_t> region, raster, waterline;  // the faces' region, and its shallow and steep parts
  std::vector<double> row_spacing;    // per raster node: the x-y distance to the next raster row its scallop allows
  std::vector<double> level_spacing;  // per waterline node: the height step to the next level its scallop allows
  ClearanceMap body;           // shank and holder vs the part grown by skin + holder margin: cut points clear it
  ClearanceMap safe;           // that and the cutter vs the part grown by the skin: the tool above it is free
  double gouge_tolerance = 0.0025;  // mm a chord may pass below the CL surface (into the part)
  double leave_tolerance = 0.0005;  // mm a raster chord may pass above it (material left, on top of the scallop)
  double contour_leave = 0.0025;    // mm a waterline chord may pass outside the contour (likewise)
  double crossing_precision = 0.000625;  // mm: contour points lie this close outside the contour
  double sample_step = 0.3;    // mm
  double min_step = 0.001;     // mm: subdivision stops here (a cliff of the CL surface)
  double body_tolerance = 1e-6;  // mm a cut point may lie below the body clearance (rounding)
  double feed_link = 6;        // mm: links along the CL surface up to this long
  bool contours_both_ways = false;  // open waterline contours may be cut end to start (conventional milling)
  int threads = 1;
  mutable std::atomic<long> drops{0};

  double drop(double x, double y) const {
    drops.fetch_add(1, std::memory_order_relaxed);
    return cutter->drop(x, y, floor);
  }
  bool inRegion(double x, double y) const { return region[grid.nearest(x, y)] != 0; }
  bool bodyClear(const Vec3& p) const { return p.z() >= body.at(p.x(), p.y()) - body_tolerance; }
};

// A cutting pass: points on the CL surface (tip heights), cut in order.
struct Pass {
  std::vector<Vec3> points;
  bool closed = false;  // a loop: the last point joins the first
};

// The chordal tolerance splits into half below the CL surface (a gouge, which the part's 0.01 mm tolerance absorbs)
// and a share above it (material left, on top of the scallop, so the passes' spacing is taken for the scallop less
// that share). Raster points are cheap to add: their chords keep kRasterLeaveShare. Waterline points cost a search
// across the contour each: their chords keep half, and contour points lie within kCrossingShare outside it; the
// levels' spacing is taken for the scallop less both (a waterline contour has ~sqrt(5) times fewer points for ~10 %
// more levels than at the raster's share).
constexpr double kRasterLeaveShare = 0.1;
constexpr double kContourLeaveShare = 0.5;
constexpr double kCrossingShare = 0.125;

// Appends the CL points after `a` up to `b` (both on the CL surface) along their x-y segment: samples at most
// ctx.sample_step apart, each interval halved by a drop until the CL surface keeps within the gouge and leave
// tolerances of its chord (vertically) or the interval is below ctx.min_step.
void followSurface(const Context& ctx, const Vec3& a, const Vec3& b, std::vector<Vec3>& out);
void refineInterval(const Context& ctx, const Vec3& a, const Vec3& b, std::vector<Vec3>& out);  // a excluded, b too
// Drops the points whose removal keeps the chord that replaces them within `gouge` below (or, `lateral`, for contours
// at one height, on the right of: the high side) and `leave` above (on the left of) every point dropped. Vertical
// distances along a line in x-y; lateral ones in x-y. The ends stay.
std::vector<Vec3> thin(const std::vector<Vec3>& points, double gouge, double leave, bool lateral);

// Raster rows across the raster region from its lowest y up, each the next at the least row_spacing of the nodes
// between them; each row its runs in +x order: points on the CL surface inside the region with the body clear,
// chordally refined and thinned. `mean_step` gets the mean distance between rows.
std::vector<std::vector<Pass>> rasterRows(const Context& ctx, double& mean_step);
// Waterline contours from the top of the waterline region down, each level the least level_spacing of the nodes
// between it and the one above (the first half that below the top), within the waterline region, the higher CL
// surface on the right of the motion (climb milling with a clockwise spindle, the wall being material).
std::vector<std::vector<Pass>> waterlineLevels(const Context& ctx, double& mean_step);

// The passes in cutting order: waterline contours from the top, each the nearest to where the tool is next (x-y
// distance to where it may start plus the height between, whatever its level: down a feature before across the
// part; loops started at their point nearest to the tool, open contours at their start, or at either end with
// ctx.contours_both_ways), then raster rows chained zig-zag. A pass that the one before reaches along the CL
// surface (at most ctx.feed_link long, in the region, the body clear) is joined to it into one pass.
struct Ordered {
  std::vector<Pass> passes;
  int raster_runs = 0, contours = 0, levels = 0;
};
Ordered orderPasses(const Context& ctx, const std::vector<std::vector<Pass>>& levels,
                    const std::vector<std::vector<Pass>>& rows);

// One move of a linked path, in the frame.
struct Move {
  Vec3 p = Vec3::Zero();
  MoveKind kind = MoveKind::Feed;
};
struct Linked {
  std::vector<Move> moves;
  int retracts = 0;
};
// 3-axis links between the ordered passes: lift at feed to where the tool clears the part grown by the skin (ctx.safe),
// then over at the safe height along the link when it is under `clearance_z` and the next pass starts within
// `short_link` (infinite: any), else through `clearance_z`.
Linked link3Axis(const Context& ctx, const std::vector<Pass>& passes, double short_link, double link_margin,
                 double clearance_z);

}  // namespace art2part::surface
