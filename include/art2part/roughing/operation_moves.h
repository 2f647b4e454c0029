// The moves of one roughing operation from the regions of its levels (clearing_paths.h), in its setup's frame.
// Level after level, top down, each linked to the next without leaving the material proven clear (stay-down links:
// the centre regions of the levels cut, and the stock their slabs hold, LinkClearance). A rest pass's pieces lie in a
// few places round the part, and level after level would cross the part between them at every level: with
// `by_clusters`, its pieces are gathered into clusters (pieces closer than the tool's widest radius within the
// operation's height + margin + cutter radius to each other, transitively, at any levels) and each cluster is cut top
// down before the next one.
// Why that order is sound: the regions were planned for the whole level order, and a piece of one cluster is farther
// from every piece of another than the tool's body reaches plus the cutter's radius, so the stock another cluster has
// yet to remove, which lies within a cutter radius of its pieces, is out of the body's reach at every height. Links
// inside a cluster are proven from the cluster's own levels only; between clusters they go over the clearance plane.
#pragma once

#include <vector>

#include "art2part/roughing/clearing_paths.h"
#include "art2part/roughing/engagement_clearing.h"
#include "art2part/roughing/roughing.h"
#include "art2part/tooling/tool.h"

namespace art2part {

struct OperationLevels {
  std::vector<ClearingLevel> levels;  // top down: z, top, centre, air (links are filled in here)
  std::vector<SlabState> slabs;       // per level: the stock it leaves (for the stock-model links)
  std::vector<Region> swept;          // per level: its centre region grown by the tool radius (what it sweeps)
};

struct OperationMovesOptions {
  ClearingOptions clearing;   // stay_down decides whether links are kept low at all
  double holder_margin = 0.5;  // mm kept between the body and the stock on a link (LinkClearance)
  bool by_clusters = false;    // cut cluster after cluster (rest passes), else level after level
  bool by_engagement = false;  // each level front by front (clearLevelByEngagement, with `engagement`), else zig-zag
  EngagementOptions engagement;
};

// The operation's moves, starting with a rapid at the clearance plane and ending with a retract to it (none when no
// level has a centre region). `stats` is added to; the final retract counts.
std::vector<ClearingPoint> operationMoves(const OperationLevels& levels, const Tool& tool,
                                          const OperationMovesOptions& options, ClearingStats& stats);

// The clusters of pieces: for each cluster, per level (index into levels), the rings of its pieces there; clusters in
// the order of their highest piece. Pieces whose boxes lie within `reach` of each other share a cluster, so pieces of
// different clusters lie farther apart than `reach`.
std::vector<std::vector<Region>> pieceClusters(const std::vector<ClearingLevel>& levels, double reach);

}  // namespace art2part
