// Surface finishing of free-form faces (thesis 4.2: 2-DOF surface milling with ball and bull end mills): spheres,
// tori, cones off the tool axis, B-spline and mesh regions, slanted planes their setup neither squares nor parallels.
//
// 3-axis, per setup direction: the cutter location surface by drop-cutter (drop_cutter.h: the lowest tip height at
// which the cutter touches the whole part from above, every triangle, not only the face's, so no face is gouged),
// sampled along passes. Steep and shallow regions are split at a slope angle so the scallop target holds on both:
// raster passes on the shallow part (stepover across the passes from the scallop and the slope across them),
// waterline passes (iso-height contours of the cutter location surface) on the steep part (height step from the
// scallop and the slope). The stepover comes from the local curvature: a ball of radius R on a surface of radius rho
// across the feed leaves h ~ (w^2 / 8)(1/R + 1/rho) on a convex face, (w^2 / 8)(1/R - 1/rho) on a concave one, w the
// spacing along the surface; the least rho over the face is taken (B-rep radii where the face has them, the mesh's
// curvature otherwise). Points along a pass are spaced so the chord between them stays within the chordal tolerance
// of the cutter location surface.
//
// 5-axis: a ball's cutting sphere does not depend on its axis, so the ball centres come from a drop along the face's
// own direction (the centre of its thinned visibility cone, thesis 4.1.3) and the axis at each point is the setup
// direction tilted towards that direction only as far as the shank and holder need to clear the part and the stock
// left, the tilt smoothed along the pass (at most max_tilt_rate deg per mm).
//
// Shank and holder: kept clear of the part grown by `skin` (what roughing left: its allowance and stairs) plus the
// holder margin, by a height map of the part along the tool direction (a cylinder of radius r dropped at (x, y) lands
// at the highest part point within r: the body zone starting h above the tip collides iff that is above tip + h).
// Points where they cannot clear are left out and their area reported.
#pragma once

#include <string>
#include <vector>

#include "art2part/geometry/part.h"
#include "art2part/setup/setup_plan.h"
#include "art2part/tooling/tool.h"
#include "art2part/tooling/toolpath.h"

namespace art2part {

struct SurfaceFinishingOptions {
  double scallop = 0.01;            // mm: the cusp height left between passes on free-form faces
  double steep_angle_deg = 40;      // 3-axis: slopes steeper than this (from the plane square to the tool) get waterline
  double chordal_tolerance = 0.005; // mm: a straight move between two points stays this close to the CL surface
  double sample_step = 0.0;         // mm along a pass before chordal refinement; 0 = a tenth of the tool radius
  double skin = 0.5;                // mm of stock beyond the part that the shank and holder must clear (allowance + stairs)
  double holder_margin = 0.5;       // mm more between shank or holder and that
  double clearance = 5.0;           // mm above the highest point of the part along the direction: the retract height
  double max_tilt_deg = 60;         // 5-axis: the most the axis leans from the setup direction
  double max_tilt_rate_deg_mm = 2;  // 5-axis: how fast the axis may turn along a pass
  int threads = 0;                  // 0 = the hardware's
};

struct SurfaceFinishingResult {
  Toolpath path;                // part frame; op = 0 (the caller numbers operations), setup and tool set
  double stepover_mm = 0;       // raster stepover used on a flat (the least over the faces, curvature included)
  double height_step_mm = 0;    // waterline height step used
  double least_radius_mm = 0;   // the least curvature radius taken over the faces (infinity: flat)
  double planned_area_mm2 = 0;  // area of the faces' triangles the passes reach (the planner's belief)
  double skipped_area_mm2 = 0;  // area of the faces' triangles left out because the body could not clear
  long drops = 0;               // drop-cutter queries
  double seconds = 0;
};

// 3-axis finishing of `faces` (ids into part.faces) of a closed part from `frame.z` with a ball, bull or flat end mill.
// Throws InputError for a tool that is not an end mill or an empty face list.
SurfaceFinishingResult finishSurfaces3Axis(const Part& part, const std::vector<int>& faces, const SetupFrame& frame,
                                           const Tool& tool, int setup, const SurfaceFinishingOptions& options = {});

// 5-axis finishing of `faces` with a ball end mill: centres from a drop along `face_direction` (unit, part frame), the
// axis leaning from `frame.z` towards it as the body needs. Throws InputError for a tool that is not a ball end mill.
SurfaceFinishingResult finishSurfaces5Axis(const Part& part, const std::vector<int>& faces, const SetupFrame& frame,
                                           const Vec3& face_direction, const Tool& tool, int setup,
                                           const SurfaceFinishingOptions& options = {});

// The stepover between passes of a ball (or bull: its corner radius) end mill of radius `tool_radius` leaving a cusp of
// `scallop` on a surface whose least radius of curvature across the passes is `surface_radius` (infinity: flat;
// positive: convex; negative: concave, |surface_radius| > tool_radius).
double scallopStepover(double tool_radius, double scallop, double surface_radius);

}  // namespace art2part
