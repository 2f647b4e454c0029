#include "art2part/roughing/operation_moves.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <optional>

#include "art2part/geometry/ordered_tour.h"
#include "art2part/roughing/forbidden_region.h"
#include "art2part/roughing/link_clearance.h"

namespace art2part {

namespace {

// Links may hop over the centre regions of this many levels above (ClearedLevel): the nearest ones are the lowest
// hops; farther up, the clearance plane costs little more.
constexpr std::size_t kLinkLevels = 3;
// mm: a shortened order of the pieces is cut (a second time) only when its travel is at least this much shorter.
constexpr double kShorterTourMm = 5;
// mm: a move within this of a level's height is at the level.
constexpr double kLevelTolMm = 1e-6;

// Writes levels one after the other, linking each to where the last one left the tool.
class MoveWriter {
 public:
  MoveWriter(const OperationMovesOptions& options, ClearingStats& stats)
      : options_(options), clearing_(options.clearing), stats_(stats) {}

  void level(ClearingLevel clear) {
    clear.from = at_;
    const std::vector<ClearingPoint> moves = options_.by_engagement
                                                 ? clearLevelByEngagement(clear, clearing_, options_.engagement, &stats_)
                                                 : clearLevel(clear, clearing_, &stats_);
    moves_.insert(moves_.end(), moves.begin(), moves.end());
    if (!moves.empty()) at_ = moves.back().tip;
  }

  const std::optional<Eigen::Vector3d>& at() const { return at_; }
  const std::vector<ClearingPoint>& moves() const { return moves_; }

  std::vector<ClearingPoint> finish() {
    if (at_ && at_->z() < clearing_.clearance_z) {
      moves_.push_back({Eigen::Vector3d(at_->x(), at_->y(), clearing_.clearance_z), ClearingMove::Rapid});
      ++stats_.retracts;
    }
    return std::move(moves_);
  }

 private:
  const OperationMovesOptions& options_;
  const ClearingOptions& clearing_;
  ClearingStats& stats_;
  std::optional<Eigen::Vector3d> at_;  // where the last level left the tool
  std::vector<ClearingPoint> moves_;
};

// How far the level's proofs keep inside its centre region: engagement fronts may stop short of it.
double reachShortfall(const OperationMovesOptions& options) {
  return options.by_engagement ? kEngagementReachShortfallMm : 0.0;
}

// A level cut, for the links of the levels after it: where its centres went, `shortfall` inside its centre region.
void remember(std::vector<ClearedLevel>& cleared, double z, const Region& centre, double shortfall) {
  if (regionEmpty(centre)) return;
  Region reached = shortfall > 0 ? offsetRegion(centre, -shortfall) : centre;
  if (regionEmpty(reached)) return;
  cleared.insert(cleared.begin(), {z, std::move(reached)});
  if (cleared.size() > kLinkLevels) cleared.pop_back();
}

// Level after level; links over the levels cut and over the stock their slabs hold.
void levelByLevel(const OperationLevels& levels, const Tool& tool, const OperationMovesOptions& options,
                  MoveWriter& writer) {
  std::vector<ClearedLevel> cleared;  // nearest first
  LinkClearance link_clearance(tool, options.holder_margin);
  for (std::size_t i = 0; i < levels.levels.size(); ++i) {
    ClearingLevel clear = levels.levels[i];
    clear.cleared = cleared;
    clear.clear_height = [&link_clearance](const Point2& a, const Point2& b, double lowest, double ceiling) {
      return link_clearance.lowestClear(a, b, lowest, ceiling);
    };
    writer.level(std::move(clear));
    if (i < levels.slabs.size()) link_clearance.addSlab(levels.slabs[i], levels.swept[i]);
    remember(cleared, levels.levels[i].z, levels.levels[i].centre, reachShortfall(options));
  }
}

// The widest the tool's body is up to `height` above the tip: zones above that never meet stock below it.
double bodyReachWithin(const Tool& tool, double height) {
  double reach = tool.diameter / 2;
  for (const BodyZone& zone : bodyZones(tool))
    if (zone.from < height) reach = std::max(reach, zone.radius);
  if (toolLength(tool) < height) reach = std::max(reach, holderTopRadius(tool));  // the spindle side above it
  return reach;
}

// The order pieces are cut in (PieceSchedule): a piece of level `deeper` waits for those of level `shallower` within
// the body's reach up to the shallower slab's top, the holder margin and the cutter's radius (operation_moves.h).
PieceSchedule pieceSchedule(const OperationLevels& levels, const Tool& tool, const OperationMovesOptions& options) {
  const std::vector<ClearingLevel>& at = levels.levels;
  const double beyond = options.holder_margin + tool.diameter / 2;
  const double most = at.empty() ? beyond : bodyReachWithin(tool, at.front().top - at.back().z) + beyond;
  return PieceSchedule(at, most, [&tool, &at, beyond](std::size_t shallower, std::size_t deeper) {
    return bodyReachWithin(tool, at[shallower].top - at[deeper].z) + beyond;
  });
}

// Where a piece was entered and left, from the moves the writer gave it (`from` on): entered at its first move at its
// level inside its rings (the link to it ends there), left where its last move ends. A piece that gave no moves
// stands where the tool was.
TourStop pieceStop(const std::vector<ClearingPoint>& moves, std::size_t from, const LevelPiece& piece, double z) {
  TourStop stop;
  if (from >= moves.size()) {
    if (from > 0) stop.entry = stop.exit = moves[from - 1].tip;
    return stop;
  }
  stop.entry = moves[from].tip;
  for (std::size_t i = from; i < moves.size(); ++i) {
    const Eigen::Vector3d& tip = moves[i].tip;
    if (std::abs(tip.z() - z) < kLevelTolMm && regionContains(piece.rings, Point2(tip.x(), tip.y()))) {
      stop.entry = tip;
      break;
    }
  }
  stop.exit = moves.back().tip;
  return stop;
}

// The pieces cut in one order: the moves (the final retract included), their counts, and per piece (pieces()'s
// index) where it was entered and left, the pieces in the order cut.
struct PiecePass {
  std::vector<ClearingPoint> moves;
  ClearingStats stats;
  std::vector<std::size_t> order;
  std::vector<TourStop> stops;
};

// The index of the next piece to cut with the tool at `at` (none: the first piece); the count of pieces once every
// piece is cut.
using NextPiece = std::function<std::size_t(const std::optional<Point2>& at)>;

// Piece after piece as `next` hands them out (an order PieceSchedule's rule allows); links over the pieces cut
// (ClearedLevel) and over the slabs as they stand: each slab's final stock plus what its pieces still to come will
// take there (their centres grown by the cutter's radius).
PiecePass cutPieces(const OperationLevels& levels, const Tool& tool, const OperationMovesOptions& options,
                    const std::vector<LevelPiece>& pieces, const NextPiece& next) {
  PiecePass pass;
  pass.stops.resize(pieces.size());
  MoveWriter writer(options, pass.stats);
  const double reach = tool.diameter / 2 - reachShortfall(options);
  std::vector<Region> sweeps;  // per piece: what it takes, at most
  std::vector<std::vector<std::size_t>> pending(levels.levels.size());  // per level: its pieces not cut yet
  for (std::size_t k = 0; k < pieces.size(); ++k) {
    sweeps.push_back(offsetRegion(pieces[k].rings, reach));
    pending[pieces[k].level].push_back(k);
  }
  // The slab's stock while pieces of it are still to come: its final stock, less what the level sweeps (the proofs
  // keep no band: link_clearance.h), plus those pieces' sweeps.
  const std::size_t slabs = std::min(levels.slabs.size(), levels.levels.size());
  std::vector<SlabState> finals(levels.slabs.begin(), levels.slabs.begin() + slabs);
  for (std::size_t i = 0; i < slabs; ++i) finals[i].remaining = subtract(finals[i].remaining, levels.swept[i]);
  auto slabNow = [&](std::size_t i) {
    if (pending[i].empty()) return finals[i];
    SlabState slab = finals[i];
    Region to_come;
    for (std::size_t k : pending[i]) to_come.insert(to_come.end(), sweeps[k].begin(), sweeps[k].end());
    slab.remaining = unite(slab.remaining, to_come);
    return slab;
  };
  LinkClearance link_clearance(tool, options.holder_margin);
  for (std::size_t i = 0; i < slabs; ++i) link_clearance.addSlab(slabNow(i), {});
  std::vector<ClearedLevel> cleared;
  auto toolAt = [&writer]() -> std::optional<Point2> {
    if (!writer.at()) return std::nullopt;
    return Point2(writer.at()->x(), writer.at()->y());
  };
  for (std::size_t k = next(toolAt()); k < pieces.size(); k = next(toolAt())) {
    const LevelPiece& piece = pieces[k];
    // The level as planned (its flags, step-over, engagement, stock_reach: its other pieces' stock too, material to
    // go round), narrowed to this piece.
    ClearingLevel clear = levels.levels[piece.level];
    clear.centre = piece.rings;
    clear.air = intersect(levels.levels[piece.level].air, piece.rings);
    clear.cleared = cleared;
    clear.clear_height = [&link_clearance](const Point2& a, const Point2& b, double lowest, double ceiling) {
      return link_clearance.lowestClear(a, b, lowest, ceiling);
    };
    const std::size_t from = writer.moves().size();
    writer.level(std::move(clear));
    pass.stops[k] = pieceStop(writer.moves(), from, piece, levels.levels[piece.level].z);
    pass.order.push_back(k);
    remember(cleared, levels.levels[piece.level].z, piece.rings, reachShortfall(options));
    std::vector<std::size_t>& left = pending[piece.level];
    left.erase(std::find(left.begin(), left.end(), k));
    if (piece.level < slabs) link_clearance.replaceSlab(piece.level, slabNow(piece.level), {});
  }
  pass.moves = writer.finish();
  return pass;
}

// Seconds the moves take at the options' feed and rapid rates (ramps and plunges at the feed): to compare two
// orders of the same pieces.
double movesSeconds(const std::vector<ClearingPoint>& moves, const ClearingOptions& options) {
  return 60 * (clearingLength(moves, true) / options.feed_mm_min + clearingLength(moves, false) / options.rapid_mm_min);
}

// The pieces in PieceSchedule's nearest-first order; then, when or-opt (ordered_tour.h) finds an order under the
// same rule whose travel between the pieces (as they were entered and left) is shorter, cut in that order too, and
// kept when its moves take less time (each piece is entered from where the tool is, so the travel was a model).
// Engagement clearing is cut once: its fronts cost too much planning to cut twice.
PiecePass pieceByPiece(const OperationLevels& levels, const Tool& tool, const OperationMovesOptions& options) {
  PieceSchedule schedule = pieceSchedule(levels, tool, options);
  const std::vector<LevelPiece>& pieces = schedule.pieces();
  PiecePass nearest = cutPieces(levels, tool, options, pieces,
                                [&schedule](const std::optional<Point2>& at) { return schedule.next(at); });
  if (options.by_engagement || pieces.size() < 3) return nearest;
  const std::vector<std::size_t> order = shortenedOrder(nearest.stops, nearest.order, schedule.waitsFor());
  if (tourTravel(nearest.stops, order) >= tourTravel(nearest.stops, nearest.order) - kShorterTourMm) return nearest;
  std::size_t taken = 0;
  PiecePass shortened = cutPieces(levels, tool, options, pieces, [&](const std::optional<Point2>&) {
    return taken < order.size() ? order[taken++] : pieces.size();
  });
  const double before = movesSeconds(nearest.moves, options.clearing);
  return movesSeconds(shortened.moves, options.clearing) < before ? shortened : nearest;
}

void addStats(ClearingStats& to, const ClearingStats& from) {
  to.passes += from.passes;
  to.contours += from.contours;
  to.ramps += from.ramps;
  to.plunges_in_air += from.plunges_in_air;
  to.plunges_into_stock += from.plunges_into_stock;
  to.column_plunges += from.column_plunges;
  to.retracts += from.retracts;
  to.level_links += from.level_links;
  to.hops += from.hops;
  to.unbounded_mm += from.unbounded_mm;
}

}  // namespace

namespace {

std::vector<LevelPiece> levelPieces(const std::vector<ClearingLevel>& levels) {
  std::vector<LevelPiece> pieces;
  for (std::size_t i = 0; i < levels.size(); ++i)
    for (RegionPiece& piece : regionPieces(levels[i].centre)) pieces.push_back({i, std::move(piece.rings)});
  return pieces;
}

std::vector<ScheduledItem> scheduledPieces(const std::vector<LevelPiece>& pieces) {
  std::vector<ScheduledItem> items;
  items.reserve(pieces.size());
  for (const LevelPiece& piece : pieces) {
    ScheduledItem item{static_cast<double>(piece.level), Point2::Constant(std::numeric_limits<double>::infinity()),
                       Point2::Constant(-std::numeric_limits<double>::infinity())};
    for (const Ring& ring : regionRings(piece.rings))
      for (const Point2& p : ring) item.lo = item.lo.cwiseMin(p), item.hi = item.hi.cwiseMax(p);
    items.push_back(item);
  }
  return items;
}

}  // namespace

PieceSchedule::PieceSchedule(const std::vector<ClearingLevel>& levels, double reach)
    : pieces_(levelPieces(levels)), schedule_(scheduledPieces(pieces_), reach) {}

PieceSchedule::PieceSchedule(const std::vector<ClearingLevel>& levels, double most_reach, const LevelReach& reach)
    : pieces_(levelPieces(levels)),
      schedule_(scheduledPieces(pieces_), most_reach,
                [&reach](const ScheduledItem& shallower, const ScheduledItem& deeper) {
                  return reach(static_cast<std::size_t>(shallower.depth), static_cast<std::size_t>(deeper.depth));
                }) {}

std::size_t PieceSchedule::next(const std::optional<Point2>& at) {
  if (!at) return schedule_.first();
  return schedule_.next(*at, [this, &at](std::size_t i) { return regionDistance(pieces_[i].rings, *at); });
}

std::vector<ClearingPoint> operationMoves(const OperationLevels& levels, const Tool& tool,
                                          const OperationMovesOptions& options, ClearingStats& stats) {
  if (options.clearing.stay_down) {
    PiecePass pass = pieceByPiece(levels, tool, options);
    addStats(stats, pass.stats);
    return std::move(pass.moves);
  }
  MoveWriter writer(options, stats);
  levelByLevel(levels, tool, options, writer);
  return writer.finish();
}

}  // namespace art2part
