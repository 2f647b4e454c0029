// Surface finishing of free-form faces (thesis 4.2: 2-DOF surface milling with ball and bull end mills): spheres,
// tori, cones off the tool axis, B-spline and mesh regions, slanted planes their setup neither squares nor parallels.
//
// 3-axis, per setup direction: the cutter location (CL) surface by drop-cutter (drop_cutter.h: the lowest tip height at
// which the cutter touches the whole part from above, every triangle, not only the face's, so no face is gouged). A CL
// height map on a grid (map_pitch) finds the region to finish: the nodes where the tool touches one of the faces'
// triangles, and where a face triangle's facet contact lies (the triangle shifted by the tool's contact offset, so
// walls whose CL surface is a vertical cliff are found too), grown by a margin of one stepover. Its slope (the CL
// map's gradient, for a ball the surface's own slope at the contact) splits it: raster passes where it is below
// steep_angle_deg + kSteepOverlapDeg, waterline passes (iso-height contours of the CL surface by marching squares,
// every crossing refined by drops) where it is above steep_angle_deg - kSteepOverlapDeg, so the band between is cut by
// both and no seam is left. Waterline runs first (top down), so the stock left on the walls is gone before raster
// passes lift beside them.
//
// Stepover, from the local curvature: the scallop depends on the spacing of the cutter centres along the CL surface
// (scallopStepover, exact for a ball on a circle): convex faces allow more than a flat, concave ones less. Each node of
// the CL map asks for a spacing: the flat's, or for a concave part radius P the concave one; P is the face's B-rep
// radius (spheres, cylinders, cones, tori) or, for planes and mesh faces, from the CL surface's bend across the passes
// (rows) or up the slope (levels), P = 1 / curvature + R, unless that bend is a crease (the tool against both sides of
// a hollow it does not fit: rest finishing's). Convex faces are taken as flat (no gain claimed). Raster passes on a
// slope alpha across them are s / cos(alpha) apart along the surface, so a node's row spacing is its centre spacing
// times cos alpha; waterline levels the centre spacing times sin of the node's slope. Each row is placed at the least
// spacing of the nodes between it and the previous one, each level likewise: tight spots tighten only the rows and
// levels that cross them. A tessellated face is a chain of facets: a concave crease of angle theta between two passes
// raises their cusp by c theta / 4 + R theta^2 / 8 (the balls sit on planes meeting at it), which the node's spacing
// also takes, from the dihedral angles of its contact triangle's smooth edges (a mesh with coarse concave facets gets
// closer passes; load STEP parts with a chordal tolerance well below the scallop). The tool's effective radius: the
// ball's; a bull's corner radius (its flat bottom only ever lowers the cusp); a flat end mill leaves a staircase,
// h = s sin(alpha) across a slope, h = dz cos(alpha) down one.
//
// Points along a pass start sample_step apart and are subdivided by extra drops wherever the CL surface leaves the chord
// by more than the chordal tolerance allows, then thinned where the chord keeps within it (a flat stretch is one move).
// Half the tolerance may lie below the CL surface (a gouge that deep, within the part's tolerance); what a chord may
// leave above it adds to the cusp, so it is kept small and the spacing is taken for the scallop less it (surface_
// passes.h: kRasterLeaveShare, kContourLeaveShare). Waterline contours likewise, laterally.
//
// 5-axis: a ball's cutting sphere does not depend on its axis, so the ball centres come from a drop along the face's
// own direction (the centre of its thinned visibility cone, thesis 4.1.3) and the axis at each point is the setup
// direction tilted towards that direction only as far as the shank and holder need to clear the part and the stock
// left, the tilt smoothed along the pass (at most max_tilt_rate deg per mm), checked by an exact test of the tool's
// cylinders (continued up their axis, so the retract along the axis is clear too) against the triangles.
//
// Shank and holder: kept clear of the part grown by `skin` (what roughing left: its allowance and stairs) plus the
// holder margin, by a height map of the part along the tool direction (a cylinder of radius r dropped at (x, y) lands
// at the highest part point within r: the body zone starting h above the tip collides iff that is above tip + h; the
// map's nodes take r grown by the node spacing so the nearest node answers for any point), and of the stock roughing
// left beyond the skin (its slabs: a zone over a slab's region grown by the zone's radius clears when its bottom is
// above the slab's top, the slab's material being anywhere up to its top). Points where they cannot clear are left
// out and their area reported: a finishing tool is no roughing tool, and its holder rubbing the stairs a coarse
// roughing left is a collision, not a cut.
//
// Order: waterline contours first, each the one nearest the tool (down a feature before across the part; an open one
// from its nearer end unless waterline_both_ways is off), then raster rows zig-zag.
// Linking: consecutive passes are joined along the CL surface (a feed, every point dropped) when the link is at most
// feed_link_mm long and stays in the region with the body clear (zig-zag rasters, waterline levels stepping down);
// otherwise the tool lifts at feed until it clears the part grown by the skin and the stock left, and then moves over
// at a safe height (the highest of that clearance along the way, plus link_margin) when that is under the clearance
// height (and the next pass starts within short_link_mm, when one is set), else rapids at the clearance height.
#pragma once

#include <string>
#include <vector>

#include "art2part/geometry/part.h"
#include "art2part/roughing/roughing.h"
#include "art2part/setup/setup_plan.h"
#include "art2part/tooling/tool.h"
#include "art2part/tooling/toolpath.h"

namespace art2part {

// Overlap of the raster and waterline regions around steep_angle_deg, in degrees of slope each way.
constexpr double kSteepOverlapDeg = 5;

struct SurfaceFinishingOptions {
  double scallop = 0.01;            // mm: the cusp height left between passes on free-form faces
  double steep_angle_deg = 40;      // 3-axis: slopes steeper than this (from the plane square to the tool) get waterline
  double chordal_tolerance = 0.005; // mm: a straight move between two points stays this close to the CL surface
  double sample_step = 0.0;         // mm along a pass before chordal refinement; 0 = a tenth of the tool radius
  double map_pitch = 0.0;           // mm between nodes of the CL height map; 0 = a quarter of the tool radius (coarser
                                    // where the map would pass 16 M nodes)
  double region_margin = 0.0;       // mm the faces' region grows by beyond their edges; 0 = one stepover
  double skin = 0.5;                // mm of stock beyond the part that the shank and holder must clear (allowance + stairs)
  double holder_margin = 0.5;       // mm more between shank or holder and that
  double clearance = 5.0;           // mm above the highest point of the part along the direction: the retract height
  double link_margin = 1.0;         // mm: short links pass this high above what the tool must clear
  double feed_link_mm = 0.0;        // links along the CL surface up to this long; 0 = the tool's diameter
  double short_link_mm = 0.0;       // links at a safe height up to this long, longer ones retract; 0 = any length (the
                                    // height the clearance maps prove clear along the link: part, skin and stock)
  bool waterline_both_ways = true;  // an open waterline contour (a wall the region or the holder cuts short) is cut
                                    // from whichever end is nearer the tool: down a wall level after level with no
                                    // move back the contour's length, climb and conventional milling in turn; false:
                                    // climb only (from its start). Closed contours are climb always.
  double max_tilt_deg = 60;         // 5-axis: the most the axis leans from the setup direction
  double tilt_step_deg = 2;         // 5-axis: the tilt is searched in steps of this
  double max_tilt_rate_deg_mm = 2;  // 5-axis: how fast the axis may turn along a pass
  int threads = 0;                  // 0 = the hardware's
};

struct SurfaceFinishingResult {
  Toolpath path;                // part frame; op = 0 (the caller numbers operations), setup and tool set
  double stepover_mm = 0;       // spacing of the cutter centres along the CL surface on a flat (scallopStepover)
  double raster_stepover_mm = 0;  // mean x-y distance between raster passes
  double height_step_mm = 0;    // mean waterline height step
  double least_radius_mm = 0;   // the tightest concave part radius that set a spacing (negative); infinity: none
  double planned_area_mm2 = 0;  // area of the faces' triangles the passes reach (the planner's belief)
  double skipped_area_mm2 = 0;  // area of the faces' triangles left out because the body could not clear
  double unreached_area_mm2 = 0;  // area of the faces' triangles the tool cannot touch from here (too big, hidden,
                                  // facing away): for rest finishing or another setup
  int raster_passes = 0;        // raster runs cut
  int waterline_levels = 0;     // heights with at least one contour
  int waterline_contours = 0;   // contours cut
  int retracts = 0;             // links through the clearance height
  long drops = 0;               // drop-cutter queries (the CL map, passes, refinement, links)
  double seconds = 0;
  double seconds_map = 0;       // of which the CL map and the clearance maps,
  double seconds_raster = 0;    // the raster rows,
  double seconds_waterline = 0; // the waterline levels
};

// 3-axis finishing of `faces` (ids into part.faces) of a closed part from `frame.z` with a ball, bull or flat end mill.
// `stock_beyond`: what roughing left in `frame` beyond the skin (stockBeyondSkin, finishing.h, of
// RoughingPlan::stock_left of the setup when the frame is the setup's, with options.skin), slabs top down; the shank,
// holder and links keep clear of it as of the part grown by the skin. Empty: nothing known beyond the skin. Throws
// InputError for a tool that is not an end mill, an empty face list, a face id out of range or options out of range.
SurfaceFinishingResult finishSurfaces3Axis(const Part& part, const std::vector<int>& faces, const SetupFrame& frame,
                                           const Tool& tool, int setup, const SurfaceFinishingOptions& options = {},
                                           const std::vector<SlabState>& stock_beyond = {});

// 5-axis finishing of `faces` with a ball end mill: centres from a drop along `face_direction` (unit, part frame), the
// axis leaning from `frame.z` towards it (in their common plane) as the body needs, at most max_tilt_deg and never past
// face_direction. Passes are planned as 3-axis ones along face_direction (raster and waterline); each pass is cut with
// its own tilts and every link retracts along the tool axis above the part. Points where no tilt clears are left out
// (skipped_area_mm2). Throws InputError for a tool that is not a ball end mill, and as finishSurfaces3Axis.
SurfaceFinishingResult finishSurfaces5Axis(const Part& part, const std::vector<int>& faces, const SetupFrame& frame,
                                           const Vec3& face_direction, const Tool& tool, int setup,
                                           const SurfaceFinishingOptions& options = {});

// The spacing of the cutter centres, measured along the CL surface, of a ball (or bull: its corner radius) end mill of
// radius `tool_radius` leaving a cusp of `scallop` on a surface whose radius of curvature across the passes is
// `surface_radius` (infinity: flat; positive: convex; negative: concave, |surface_radius| > tool_radius). Exact for a
// circle: the centres lie on a circle of radius D = rho + R (convex) or |rho| - R (concave), phi apart, the cusp where
// the two balls meet: 1 - cos(phi / 2) = (2 R h - h^2) / (2 x D) with x = rho + h or |rho| - h, spacing D phi. Flat:
// 2 sqrt(2 R h - h^2); to first order h = c^2 rho / (8 R (rho + R)), the notes' (w^2 / 8)(1/R + 1/rho) with the
// spacing on the surface w = c rho / (rho + R). A scallop of the tool radius or more returns the diameter. Throws
// InputError for a radius or scallop that is not positive, or a concave radius not above the tool radius.
double scallopStepover(double tool_radius, double scallop, double surface_radius);

}  // namespace art2part
