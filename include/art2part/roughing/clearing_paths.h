// Clearing one slab (thesis 4.1.2 step 7, 5.1): zig-zag passes and a contour pass over the region the tool centre may
// sweep at one level, linked inside that region or over a clearance plane, entered by a ramp (or straight down where
// the tool meets no stock). Everything here is in a setup frame: x, y in the slice plane, z along the tool axis (up).
#pragma once

#include <Eigen/Core>
#include <functional>
#include <optional>
#include <vector>

#include "art2part/roughing/region.h"

namespace art2part {

enum class ClearingMove {
  Rapid,    // positioning in air (clearance plane, or straight down over cleared material)
  Feed,     // cutting at the level
  Ramp,     // descending into material along the path at the ramp angle
  Plunge,   // straight down at the plunge feed: where the tool meets no stock (`air`), or with no room to ramp
};

struct ClearingPoint {
  Eigen::Vector3d tip;  // setup frame, mm: where the move ends
  ClearingMove move = ClearingMove::Feed;
};

// A level of the same operation, cleared before this one: once its moves are done the tool may stand at any height
// from `z` up over any point of `centre` without meeting stock or part. Why: the column over every point of a centre
// region is clear above the slab's top (roughing.h), and with the contour pass the moves sweep every point of stock
// within the tool radius of `centre` down to `z` (such a point q, within r of p in centre, is within r of the ring
// that the segment from p to it crosses or of the ring nearest it, which the contour follows wherever a point within
// r of it may be stock: not in `air`; or else has the disc of radius r round it in `centre` and is within
// stepover/2 < r of a zig-zag feed: zigzagInset).
struct ClearedLevel {
  double z = 0;
  Region centre;
};

struct ClearingLevel {
  double z = 0;          // the level: tool tip height of every cutting move
  double top = 0;        // the top of the slab: above it, every point of `centre` has been cleared already
  Region centre;         // where the tool centre may go at this level and everything in it is to be cleared
  double stepover = 0;   // mm between passes at this level (a thin slab's wider one); 0: ClearingOptions::stepover
  double engagement_deg = 0;  // engagement clearing's limit at this level (a thin slab's wider one); 0: its options'
  Region air;            // where the tool centre may plunge straight down (its disc meets no stock in the slab)
  Region stock_reach;    // where the tool centre's disc meets stock in the slab, inside `centre` or not (air is
                         // `centre` less this); engagement clearing only (the material round the region)
  // Above `top`, the column within the tool radius of every point of `centre` is clear: the levels above swept it
  // (a main pass: each level's centre lies in the one above's). A rest pass's levels above cleared only the pieces
  // where they had stock to remove, so skins thinner than that may stand over its centre (CTC-01's step-up pass: a
  // rapid at the safe height over the centre met 0.06 mm of one): false, and links over the slab are not taken at
  // the safe height nor over this operation's cleared levels, only where the stock model proves them clear.
  // A later setup's pass cuts only the stock the in-process model proves (provenSlabs), so its levels above leave
  // the model's film on faces earlier setups cut, wherever it stands over its centres (ANC101: a main pass's rapids
  // down to the safe height met 1.3 mm of it): both flags false, and every descent to the safe height over a start
  // point is a rapid only down to the lowest height `clear_height` proves clear, a plunge at the feed below it.
  bool column_clear = true;
  bool descents_clear = true;
  // Stay-down links only (ClearingOptions::stay_down):
  std::optional<Eigen::Vector3d> from;  // where the tool is (the last point of the level before); none: the
                                        // clearance plane. Its column must be clear from its height up.
  std::vector<ClearedLevel> cleared;    // levels above this one already cleared, nearest first
  // Where the tool comes from when `from` is not given (it is not a move: the caller links from there), so the level
  // starts at the pass end, ring vertex or piece quickest to reach from it; none: the cheapest entry, wherever it is.
  // clearLevel only (finishing floors set it); clearLevelByEngagement goes by `from` alone.
  std::optional<Point2> start_near;
  // The lowest height in [lowest, ceiling) at which a model of the stock proves the straight way from a to b clear
  // for the whole tool, else `ceiling` (LinkClearance); empty: the regions above only.
  std::function<double(const Point2& a, const Point2& b, double lowest, double ceiling)> clear_height;
};

struct ClearingOptions {
  double stepover = 4;          // mm between zig-zag passes
  double angle_deg = 0;         // zig-zag direction in the slice plane, from the frame's x axis
  double ramp_angle_deg = 3;    // entries: the slope of the ramp
  double safe_height = 1;       // mm above `top` where a rapid descent stops and the ramp starts
  double clearance_z = 0;       // the clearance plane (above all stock): links that leave `centre` retract to it
  double min_segment = 0.05;    // mm: zig-zag intervals shorter than this are dropped
  bool contour_pass = true;     // a pass along every ring of `centre` after the zig-zag
  // The cutter's radius r: with the contour pass, the zig-zag covers only the piece eroded by
  // zigzagInset(stepover, r), the band outside it being the contour's (clearLevel says why every point is still
  // swept). 0: the zig-zag runs to the rings, the contour retracing a band it already cut.
  double tool_radius = 0;
  // Links between passes, pieces and levels. false: every pass is reached over the clearance plane (contours by a
  // feed where the straight way lies in `centre`). true: by whichever of these takes less time at the rates below,
  // a feed at the level along a straight segment in `centre` (a full-width cut at most, which the library's
  // step-downs allow), or a hop at the lowest height proven clear over the whole segment (top + safe_height over
  // `centre`, z + safe_height over a cleared level's centre: ClearedLevel), then the entry; the clearance plane only
  // where neither holds. The level ends where its last cut ends (no retract): the caller links the next level from
  // there and retracts at the end.
  bool stay_down = false;
  double feed_mm_min = 1000;    // the tool's feed: the cost of a link along the level, and of a ramp
  double rapid_mm_min = 10000;  // the machine's rapid rate: the cost of a hop
};

// mm the zig-zag keeps inside the rings a contour pass follows, with passes `stepover` apart of a cutter of `radius`:
// min(stepover / 2, radius - stepover / 2) less a hair for the offset's arcs, 0 when that is not positive.
// Why these bounds: a point of stock within the radius of a ring the contour follows is swept by it; any other point
// q of stock the level is to take has the whole disc of radius r round it in `centre`, so the line nearest q across
// the direction (at most stepover/2 away) lies at least r - stepover/2 inside the rings there, and so in the eroded
// piece: the zig-zag sweeps q. And the contour then cuts a band at most a stepover wide (the lines are centred over
// the eroded piece, the first within inset + stepover/2 of the ring): no deeper radially than a zig-zag pass.
double zigzagInset(double stepover, double radius);

// The moves that clear `level.centre`. Each connected piece of it, eroded by zigzagInset when there is a contour pass
// and options.tool_radius is set, gets zig-zag lines along the direction, `stepover` apart and centred over the
// (eroded) piece's extent across them (a piece left with no interval gets one line, at the widest of a few heights),
// cut into intervals by the region (shorter than min_segment: dropped). Intervals are chained into boustrophedon
// passes: from the end of one, to the unused interval on the next line whose end that alternates the direction is
// nearest, joined by a feed along a straight segment in `centre` or else along the ring between them (round an
// island); where there is none, the pass ends and the next one starts at the lowest unused interval, after a retract
// to the clearance plane, a rapid above the start and a rapid down to top + safe_height. A pass is entered at an end
// in `air` by a plunge; from the side where air lies within a diameter (tool_radius set) by a straight way in
// `centre` and that is quicker than a ramp (a plunge at the nearest air point, a feed to the end: the zig-zag, kept
// zigzagInset inside the rings, no longer reaches the air band round open stock); elsewhere by a ramp at
// ramp_angle_deg forth and back along its first interval (or its first 0.5 mm, or a short segment in `centre`;
// failing all, a plunge counted in plunges_into_stock), stopping where it reaches z and feeding back to the start.
// Then, if asked, each ring of `centre` (perimeter at least min_segment), nearest first, followed once at z from its
// vertex nearest the tool: joined by a feed where the straight way lies in `centre`, else entered from the side as a
// pass is, else by a ramp round the ring itself, the lap then running from where the ramp reached z back to there.
// The edges of a ring that lie in `air` are not followed (the tool's disc meets no stock there): the rest of it is cut
// as open stretches in the ring's direction, each from an air vertex (a plunge). With the contour pass every point of
// `centre` lies within stepover/2 + zigzagInset (+ min_segment) of a feed at z or of a ring edge in air, and every
// point of stock within the tool radius of `centre` is swept (ClearedLevel says why): a point within r of a ring edge
// in air is no stock.
// Pieces are taken, and a piece's passes, cheapest start first: from either end, by the seconds of a straight rapid
// from the tool and of the entry there (a plunge in air is quicker than a ramp), each reached as `stay_down` says.
// Without stay_down the first point is a rapid at the clearance plane, the last a retract to it and sideways rapids are
// at the clearance plane only; with it, sideways rapids also run at the heights that ClearedLevel and `top` prove
// clear, over the regions that prove it. A piece no point of which lies farther than stepover/2 from its rings (a
// narrow band, as rest passes leave) gets no zig-zag when there is a contour pass: the contour covers it. Every
// Feed/Ramp/Plunge point lies in `centre` (x, y) at a height in [z, top + safe_height]; every cutting segment lies in
// `centre` (to within the region grid); nothing descends more steeply than the ramp angle but plunges. `stats`, if
// given, is added to.
struct ClearingStats {
  int passes = 0, contours = 0;    // zig-zag passes and contour passes
  int ramps = 0;                   // entries by a ramp
  int plunges_in_air = 0;          // straight down where the tool meets no stock
  int plunges_into_stock = 0;      // straight down into stock: only for a pass too short to ramp along
  int column_plunges = 0;          // down at the feed to the safe height, from the lowest height the stock model
                                   // proves clear (ClearingLevel::descents_clear false)
  int retracts = 0;                // rapids up to the clearance plane, the last one included
  int level_links = 0;             // stay-down: links fed along the level
  int hops = 0;                    // stay-down: links over cleared material below the clearance plane
  double unbounded_mm = 0;         // engagement clearing: mm cut where the engagement bound does not hold
};
std::vector<ClearingPoint> clearLevel(const ClearingLevel& level, const ClearingOptions& options,
                                      ClearingStats* stats = nullptr);

// Figures of a list of moves.
double clearingLength(const std::vector<ClearingPoint>& moves, bool cutting);  // mm of Feed+Ramp+Plunge, or Rapid

}  // namespace art2part
