// Finishing along one direction with flat end mills (thesis 4.3.1 plane faces, 4.3.2 cylindrical faces): the 2.5-D
// strategies. In the frame of the direction (z up along the tool):
//   floors  (planes square to z, facing it)  face milling at the floor's height: passes over the floor, `floor_stepover`
//           of the diameter apart, and a contour round the region the tool centre may sweep (clearing_paths.h), which
//           also finishes the foot of every wall round the floor
//   walls   (planes parallel to z: side milling; cylinders and extrusions along z: peripheral milling) contour passes
//           along the wall at levels from its top down, each finishing the band its flutes cover (the flute length
//           less `band_margin`), so a wall is finished in one pass when the flutes reach its depth
// At a level z the tool centre may go where the cutter's disc meets no part material above z (the part's shadow
// grown by the radius: no allowance, the tool touches the finished face), and where the shank and holder keep
// `holder_margin` clear of the part above their bottoms (the holder also clear of the roughing allowance still on
// other faces): roughing's ForbiddenRegion, grown level by level. That region's rings are where the tool touches the
// part; a wall is reached where a ring passes within the cutter's radius of it, and only the stretches of the rings
// near the walls to finish are cut, climb milling (material on the right of the feed, the spindle turning
// clockwise), entered from the open side.
// A wall deeper than the flutes reach with the shank clear is finished down to where the shank allows and reported
// partial; a smaller tool finishes what a larger one cannot reach (rest finishing), down to the smallest given.
//
// Reach figures are the planner's belief (floors: area of the floor under the swept discs; walls: length of the wall's
// trace within the cutter's radius of a pass, by band); the simulation judges.
#pragma once

#include <string>
#include <vector>

#include "art2part/finishing/finishing.h"
#include "art2part/roughing/region.h"

namespace art2part {

// A face finished along the direction of a PlanarGroup.
struct PlanarTarget {
  int face = -1;
  FinishingKind kind = FinishingKind::FaceMill;  // FaceMill (floor), SideMill (plane wall) or Contour (cylinder wall)
};

struct PlanarGroup {
  int setup = 0;
  SetupFrame frame;                  // z: the tool direction
  std::vector<PlanarTarget> targets;
  Mesh stock;                        // the stock's mesh in the part frame (its box bounds where the tool goes)
  // What roughing left in this frame beyond the allowance (stockBeyondSkin, finishing.h, of RoughingPlan::stock_left
  // of the setup when the frame is the setup's), slabs top down; rapids come down only to the top of the highest slab
  // whose stock lies within the tool's reach, and feed from there. Empty: nothing known beyond the allowance.
  std::vector<SlabState> stock_beyond;
};

// How much of a target the passes reach, by the planner's figures.
struct PlanarReach {
  int face = -1;
  double size = 0;                   // floor: area mm^2; wall: trace length x height, mm^2
  double reached = 0;                // of `size`
  std::vector<std::string> tools;    // tools that reached some of it, in order
  std::vector<int> operations;       // indices into PlanarResult::operations
  double deepest_reached = 0;        // walls: how far down (from the wall's top) the passes reach, mm
  double depth = 0;                  // walls: the wall's height along the direction, mm
};

struct PlanarResult {
  std::vector<FinishingOperation> operations;  // tool by tool, largest first; per tool floors then walls
  std::vector<PlanarReach> reach;              // one per target, in the group's order
};

// Finishes the group's targets with the given flat end mills, tool after tool, each over what the ones before left
// (rest finishing), at most options.tools.max_rest_tools of them narrower than the one before: each time the first
// (largest diameter, then shortest flutes) that reaches at least options.tools.area_fraction of what the most capable
// candidate reaches (the smallest for narrow corners, the longest-fluted for deep walls), or before it a faster one of
// its diameter with shorter flutes that reaches at least half what it does (the longer one then follows for the
// depth); after the first, only tools at most half the previous diameter, or as wide with longer flutes. `part` is the
// solid being machined (closed). Throws InputError for an empty tool list or a tool that is not a flat end mill.
PlanarResult finishPlanar(const Part& part, const PlanarGroup& group, const std::vector<const Tool*>& tools,
                          const FinishingOptions& options);

// ---- pieces, exposed for tests ----

// A stretch of a ring of the allowed region to cut: points in order (frame x, y), climb direction.
struct ContourStretch {
  std::vector<Point2> points;
  bool closed = false;  // the whole ring: the last point joins the first
};

// The stretches of the region's rings that pass within `reach` of any of `targets` (points, frame x-y), in climb
// direction (material on the right: the region on their left, Clipper's ring orientation), gaps along a ring shorter
// than `link_gap` bridged, each stretch extended by `lead` at both ends along its ring; a stretch covering nearly all
// its ring is the whole ring, closed. Ring vertices are spread at most `spacing` apart first.
std::vector<ContourStretch> contourStretches(const Region& allowed, const std::vector<Point2>& targets, double reach,
                                             double link_gap, double lead, double spacing = 0.5);

}  // namespace art2part
