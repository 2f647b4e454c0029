#include "art2part/roughing/operation_moves.h"

#include <algorithm>
#include <limits>
#include <numeric>
#include <optional>

#include "art2part/roughing/forbidden_region.h"
#include "art2part/roughing/link_clearance.h"

namespace art2part {

namespace {

// Links may hop over the centre regions of this many levels above (ClearedLevel): the nearest ones are the lowest
// hops; farther up, the clearance plane costs little more.
constexpr std::size_t kLinkLevels = 3;

struct Box2 {
  Point2 lo = Point2::Constant(std::numeric_limits<double>::infinity());
  Point2 hi = Point2::Constant(-std::numeric_limits<double>::infinity());
  bool meets(const Box2& other, double gap) const {
    return !((lo.array() > other.hi.array() + gap).any() || (other.lo.array() > hi.array() + gap).any());
  }
};

Box2 boxOf(const Region& rings) {
  Box2 box;
  for (const Ring& ring : regionRings(rings))
    for (const Point2& p : ring) box.lo = box.lo.cwiseMin(p), box.hi = box.hi.cwiseMax(p);
  return box;
}

std::size_t findRoot(std::vector<std::size_t>& parent, std::size_t i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

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

// The cluster whose first piece's box is nearest the tool (the first in order, at the start).
std::size_t nearestCluster(const std::vector<std::vector<Region>>& clusters, const std::vector<bool>& done,
                           const MoveWriter& writer) {
  std::size_t next = clusters.size();
  double nearest = std::numeric_limits<double>::infinity();
  for (std::size_t c = 0; c < clusters.size(); ++c) {
    if (done[c]) continue;
    double d = 0;
    if (writer.at()) {
      const auto first = std::find_if(clusters[c].begin(), clusters[c].end(), [](const Region& r) { return !r.empty(); });
      const Box2 box = boxOf(*first);
      const Point2 p = writer.at()->head<2>();
      d = (p.cwiseMax(box.lo).cwiseMin(box.hi) - p).squaredNorm();
    }
    if (d < nearest) next = c, nearest = d;
  }
  return next;
}

// Cluster after cluster, nearest first; each top down. Its links over its own levels cut, and over the slabs as they
// stand while it is cut: their final stock, plus what the clusters still to come will take there (their pieces
// grown by the cutter's radius).
void clusterByCluster(const OperationLevels& levels, const Tool& tool, const OperationMovesOptions& options,
                      MoveWriter& writer) {
  const double r = tool.diameter / 2;
  const std::vector<std::vector<Region>> clusters =
      pieceClusters(levels.levels, bodyReach(tool, levels) + options.holder_margin + r);
  std::vector<std::vector<Region>> sweeps(clusters.size());  // per cluster and level: what it takes there, at most
  for (std::size_t c = 0; c < clusters.size(); ++c)
    for (const Region& pieces : clusters[c])
      sweeps[c].push_back(pieces.empty() ? Region{} : offsetRegion(pieces, r - reachShortfall(options)));
  std::vector<bool> done(clusters.size(), false);
  for (std::size_t n = 0; n < clusters.size(); ++n) {
    const std::size_t next = nearestCluster(clusters, done, writer);
    done[next] = true;
    std::vector<ClearedLevel> cleared;
    LinkClearance link_clearance(tool, options.holder_margin);
    for (std::size_t i = 0; i < levels.levels.size(); ++i) {
      const Region& pieces = clusters[next][i];
      if (!pieces.empty()) {
        // The level as planned (its flags, step-over, engagement, stock_reach: other clusters' stock too, material
        // to go round), narrowed to this cluster's pieces.
        ClearingLevel clear = levels.levels[i];
        clear.centre = pieces;
        clear.air = intersect(levels.levels[i].air, pieces);
        clear.cleared = cleared;
        clear.clear_height = [&link_clearance](const Point2& a, const Point2& b, double lowest, double ceiling) {
          return link_clearance.lowestClear(a, b, lowest, ceiling);
        };
        writer.level(std::move(clear));
        remember(cleared, levels.levels[i].z, pieces, reachShortfall(options));
      }
      if (i >= levels.slabs.size()) continue;
      SlabState slab = levels.slabs[i];
      Region pending;
      for (std::size_t c = 0; c < clusters.size(); ++c)
        if (!done[c] && !sweeps[c][i].empty()) pending.insert(pending.end(), sweeps[c][i].begin(), sweeps[c][i].end());
      if (!pending.empty()) slab.remaining = unite(slab.remaining, pending);
      link_clearance.addSlab(slab, sweeps[next][i]);
    }
  }
}

}  // namespace

std::vector<std::vector<Region>> pieceClusters(const std::vector<ClearingLevel>& levels, double reach) {
  struct Piece {
    std::size_t level;
    Region rings;
    Box2 box;
  };
  std::vector<Piece> pieces;
  for (std::size_t i = 0; i < levels.size(); ++i)
    for (RegionPiece& piece : regionPieces(levels[i].centre)) {
      const Box2 box = boxOf(piece.rings);
      pieces.push_back({i, std::move(piece.rings), box});
    }
  std::vector<std::size_t> parent(pieces.size());
  std::iota(parent.begin(), parent.end(), 0);
  for (std::size_t a = 0; a < pieces.size(); ++a)
    for (std::size_t b = a + 1; b < pieces.size(); ++b)
      if (pieces[a].box.meets(pieces[b].box, reach)) parent[findRoot(parent, a)] = findRoot(parent, b);
  std::vector<std::vector<Region>> clusters;
  std::vector<std::size_t> index(pieces.size(), pieces.size());  // root -> cluster
  for (std::size_t p = 0; p < pieces.size(); ++p) {  // clusters in the order of their first (highest) piece
    const std::size_t root = findRoot(parent, p);
    if (index[root] == pieces.size()) {
      index[root] = clusters.size();
      clusters.emplace_back(levels.size());
    }
    Region& at = clusters[index[root]][pieces[p].level];
    at.insert(at.end(), pieces[p].rings.begin(), pieces[p].rings.end());
  }
  return clusters;
}

std::vector<ClearingPoint> operationMoves(const OperationLevels& levels, const Tool& tool,
                                          const OperationMovesOptions& options, ClearingStats& stats) {
  MoveWriter writer(options, stats);
  if (options.by_clusters && options.clearing.stay_down) clusterByCluster(levels, tool, options, writer);
  else levelByLevel(levels, tool, options, writer);
  return writer.finish();
}

}  // namespace art2part
