// The moves of one roughing operation from the regions of its levels (clearing_paths.h), in its setup's frame.
// With stay-down links, piece by piece (PieceSchedule): the connected pieces of every level's centre region in an order
// that finishes the pocket the tool is in before it crosses to the next, each linked to the last without leaving the
// material proven clear (the pieces cut, ClearedLevel, and the stock the slabs hold, LinkClearance). Level after
// level would cross the part between pockets at every level. The order is nearest first, then shortened by or-opt
// under the same rule (ordered_tour.h, each piece entered and left where the nearest-first cut did); the pieces are
// cut again in that order, and the quicker of the two cuts is kept (a piece is entered from where the tool is, so the
// shortened travel is a model). Without stay-down links, level after level.
// Why the piece order is sound: the regions were planned for the whole level order, and a piece is cut only after every
// piece above it whose box lies within the reach of the tool's body up to that piece's slab top, plus the cutter's
// radius, of its own (the stock such a piece removes lies within a cutter radius of it, and no wider part of the body
// meets its slab): what is left above when it is cut, within the body's reach, is what the plan left. Pieces below it,
// cut before or not, only take stock away. Links are proven from the slabs as they stand: their final stock plus the
// pieces still to come grown by the cutter's radius.
#pragma once

#include <functional>
#include <optional>
#include <vector>

#include "art2part/geometry/top_down_schedule.h"
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
  bool by_engagement = false;  // each level front by front (clearLevelByEngagement, with `engagement`), else zig-zag
  EngagementOptions engagement;
};

// The operation's moves, starting with a rapid at the clearance plane and ending with a retract to it (none when no
// level has a centre region). `stats` is added to; the final retract counts.
std::vector<ClearingPoint> operationMoves(const OperationLevels& levels, const Tool& tool,
                                          const OperationMovesOptions& options, ClearingStats& stats);

// A connected piece of one level's centre region.
struct LevelPiece {
  std::size_t level = 0;  // index into the levels, top down
  Region rings;           // the outer ring first, then its holes
};

// Every level's pieces, handed out one at a time in an order to cut them (TopDownSchedule, the level index as the
// depth), each chosen from where the tool ended the one before (not from that piece as a whole: a long piece ends at
// one end of it). A piece is ready once every piece of a level above whose box lies within `reach` of its box is cut;
// among the ready pieces, first the first piece of the top level, then the one nearest the tool (0 inside it; at a
// tie, the deepest: down the pocket the tool is in).
// How far apart a piece of level `deeper` and one of level `shallower` (indices into the levels, top down) may lie
// for the deeper one to wait.
using LevelReach = std::function<double(std::size_t shallower, std::size_t deeper)>;

class PieceSchedule {
 public:
  PieceSchedule(const std::vector<ClearingLevel>& levels, double reach);  // one reach for every pair of levels
  // The reach given per pair of levels, never more than `most_reach`.
  PieceSchedule(const std::vector<ClearingLevel>& levels, double most_reach, const LevelReach& reach);
  const std::vector<LevelPiece>& pieces() const { return pieces_; }
  // The index into pieces() of the next piece, now taken as cut, with the tool at `at` (none: the first piece);
  // pieces().size() once every piece is taken.
  std::size_t next(const std::optional<Point2>& at);
  // Per piece: the pieces it waits for (TopDownSchedule::waitsFor).
  std::vector<std::vector<std::size_t>> waitsFor() const { return schedule_.waitsFor(); }

 private:
  std::vector<LevelPiece> pieces_;
  TopDownSchedule schedule_;
};

}  // namespace art2part
