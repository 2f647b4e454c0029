// Constant-engagement clearing of one slab (issue 19 item 3; the adaptive / trochoidal family of high-speed roughing):
// instead of zig-zag passes a stepover apart, which bury the cutter's whole width at the start of every pass and in
// every corner, the region the tool has cleared grows front by front, each front at most `a` beyond the last, so the
// arc of the cutter's edge in material (the radial engagement) stays under a set angle. A low engagement lets a
// high-efficiency cutter take its whole flute length per level at a higher feed (radial chip thinning): its cutting
// data in tools.yaml (Tool::max_engagement_deg, max_stepdown, feed_mm_min).
//
// The fronts: C0 = where the disc already meets no stock in the slab (ClearingLevel::air), plus, for a piece of the
// centre region with no air, a helix at its deepest point. Then G = C(k) grown by a, clipped to the centre region, and
// C(k+1) = C(k) united with G less the closing by rho of what lies beyond G: the centre region beyond it, and outside
// the centre region where the disc would meet stock (ClearingLevel::stock_reach: the part, the stock the body keeps
// clear of). The closing fills the concave corners of that material, which are the turns of the new front round
// material (a front meeting a wall among them), to a radius of at least rho (a sharp turn buries the cutter), and
// gaps in it narrower than 2 rho. When the fronts stop growing, rho is halved, down to a fifth of the tool radius
// (each phase with its own band a(rho)), then dropped: the last fronts, into corners and channels, have no engagement
// bound (ClearingStats::unbounded_mm). The connected pieces of material are cleared one after the other, nearest
// first; where a piece touches several pieces of cleared ground (a slot open at both ends), the fronts grow from the
// one nearest the tool and take the others in as they come within a band of them (one crossing, not one per front).
//
// The moves: the new stretches of each front (from where an edge leaves the ground cleared before, not from the far
// end of a long edge along a wall that ground shares), material on the tool's right (climb milling with the spindle turning
// clockwise), the nearest first (a front that moved whole from its vertex nearest the tool), going on round a front
// along the stretches that did not move (they lie on cleared ground) where that is quicker than a hop; else a hop over
// the slab, a rapid down a column of cleared ground 0.05 mm inside it to the safe height, a plunge and a short feed
// onto the front. Over 90 degrees the band is wider than r: where a front closes a hole of material (or pinches a
// neck off) whose half-width lies between r and the band, the centres farther than r from the new rings and the old
// ground are cut round their own rings (no bound claimed there), else their material stood uncut.
//
// The bound: a cutter of radius r on a path turning round material outside at radius rho, cutting a band a wide,
// meets material over the angle theta with (rho + r - a)^2 = rho^2 + r^2 + 2 rho r cos(theta) (a straight path is
// rho -> infinity: a = r (1 - cos theta)); engagementStepover solves it for a. Measured by an independent sweep in
// test_engagement_clearing.cpp: over the angle (plus the sweep's own error) on under 1 % of the cut beyond the last
// phase's length; the known exception, a strip open only at its ends, 2.2 % by at most 6 degrees: the fronts fan
// out from the corners where the air meets the walls (each front's fillet of radius rho passes through the corner).
#pragma once

#include <vector>

#include "art2part/roughing/clearing_paths.h"

namespace art2part {

// How far short of the centre region's boundary the ground the fronts cut may stop: a front vertex within 0.04 mm of
// the ground cleared before counts as unmoved and is not cut, fronts are simplified, and a phase ends when its front
// adds under min_growth_mm2. What the proofs of a level cut by engagement take off its centre region (the discs it
// swept, the columns it cleared for links: roughing.cpp, operation_moves.cpp); measured shortfalls stay under 0.11 mm.
constexpr double kEngagementReachShortfallMm = 0.2;

struct EngagementOptions {
  double tool_radius = 5;           // mm: the cutter's radius
  double max_engagement_deg = 40;   // the arc of the cutter's edge in material, at most, where the bound holds
  double corner_radius = 0;         // mm: the least radius of a turn with material outside; 0 = the tool's diameter
  double min_growth_mm2 = 0.05;     // a front adding less area than this ends a phase
};

// The widest band a cutter of radius `tool_radius` may take on a path turning at `corner_radius` round material
// outside with its engagement at most `angle_deg` (the straight-path value when corner_radius is 0 or infinite).
// Throws std::invalid_argument for a radius <= 0 or an angle outside (0, 180].
double engagementStepover(double tool_radius, double corner_radius, double angle_deg);

// The moves that clear `level.centre` front by front, as above (`level.stock_reach` must be given). Links inside the
// level are kept low whatever options.stay_down says (a front is many short stretches); the proofs of other levels
// and of the stock model (ClearedLevel, clear_height) and the level's end without a retract only with it. Entries and
// the clearance plane as clearLevel (clearing_paths.h); options.stepover is unused; every cutting move at z lies in
// `centre`. `stats` is added to: passes counts the front stretches cut, contours the helix laps, unbounded_mm the
// length cut in the last phase.
std::vector<ClearingPoint> clearLevelByEngagement(const ClearingLevel& level, const ClearingOptions& options,
                                                  const EngagementOptions& engagement, ClearingStats* stats = nullptr);

}  // namespace art2part
