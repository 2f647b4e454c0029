#include "art2part/roughing/operation_moves.h"

#include <algorithm>
#include <limits>
#include <optional>

#include "art2part/roughing/forbidden_region.h"
#include "art2part/roughing/link_clearance.h"

namespace art2part {

namespace {

// Links may hop over the centre regions of this many levels above (ClearedLevel): the nearest ones are the lowest
// hops; farther up, the clearance plane costs little more.
constexpr std::size_t kLinkLevels = 3;

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

// The widest the tool's body is within the operation's height (from its lowest level to the top of its highest
// slab): zones above that never meet a slab's stock, whatever the level the tip is at.
double bodyReach(const Tool& tool, const OperationLevels& levels) {
  double reach = tool.diameter / 2;
  if (levels.levels.empty()) return reach;
  const double depth = levels.levels.front().top - levels.levels.back().z;
  for (const BodyZone& zone : bodyZones(tool))
    if (zone.from < depth) reach = std::max(reach, zone.radius);
  if (toolLength(tool) < depth) reach = std::max(reach, holderTopRadius(tool));  // the spindle side above it
  return reach;
}

// Piece after piece as PieceSchedule hands them out; links over the pieces cut (ClearedLevel) and over the slabs as
// they stand: each slab's final stock plus what its pieces still to come will take there (their centres grown by the
// cutter's radius).
void pieceByPiece(const OperationLevels& levels, const Tool& tool, const OperationMovesOptions& options,
                  MoveWriter& writer) {
  const double r = tool.diameter / 2, reach = r - reachShortfall(options);
  PieceSchedule schedule(levels.levels, bodyReach(tool, levels) + options.holder_margin + r);
  const std::vector<LevelPiece>& pieces = schedule.pieces();
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
  for (std::size_t k = schedule.next(toolAt()); k < pieces.size(); k = schedule.next(toolAt())) {
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
    writer.level(std::move(clear));
    remember(cleared, levels.levels[piece.level].z, piece.rings, reachShortfall(options));
    std::vector<std::size_t>& left = pending[piece.level];
    left.erase(std::find(left.begin(), left.end(), k));
    if (piece.level < slabs) link_clearance.replaceSlab(piece.level, slabNow(piece.level), {});
  }
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

std::size_t PieceSchedule::next(const std::optional<Point2>& at) {
  if (!at) return schedule_.first();
  return schedule_.next(*at, [this, &at](std::size_t i) { return regionDistance(pieces_[i].rings, *at); });
}

std::vector<ClearingPoint> operationMoves(const OperationLevels& levels, const Tool& tool,
                                          const OperationMovesOptions& options, ClearingStats& stats) {
  MoveWriter writer(options, stats);
  if (options.clearing.stay_down) pieceByPiece(levels, tool, options, writer);
  else levelByLevel(levels, tool, options, writer);
  return writer.finish();
}

}  // namespace art2part
