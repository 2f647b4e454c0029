// Constant-engagement clearing: fronts grown from the cleared ground (engagement_clearing.h has the rule and the bound).
#include "art2part/roughing/engagement_clearing.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>

#include "path_writer.h"

namespace art2part {

namespace {

using namespace clearing_detail;

constexpr double kFrontArcTolerance = 0.01;  // mm: the fronts' round joins (finer buys vertices, not engagement)
constexpr double kOnOldFront = 0.04;         // mm: a front vertex this near the ground cleared before did not move
// mm inside the cleared ground where the tool may rapid down: the material a front leaves was measured up to 0.094 mm
// beyond where its regions (offsets, simplification, grid) put it, so a margin of several times that
constexpr double kRapidInset = 0.25;
constexpr double kHelixLeast = 0.05;         // mm: a piece thinner than this round its deepest point gets no helix
constexpr int kHelixSides = 24;
constexpr int kMaxFronts = 20000;
constexpr double kClosingWindowMm = 1.0;     // beyond 2 rho round a front's growth: the material its closing needs
constexpr double kLeastCornerShare = 0.2;    // the last bounded phase's corner radius, in tool radii (at least)
constexpr double kTransitionStep = 0.5;      // mm: edges longer than this are cut where they leave the old front
constexpr double kLeastStrandedMm2 = 1e-3;   // stranded centres (cutStranded) of less area are the offsets' noise

Region disc(const Point2& centre, double radius) {
  Ring ring;
  for (int i = 0; i < kHelixSides; ++i) {
    const double angle = 2 * kPi * i / kHelixSides;
    ring.push_back(centre + radius * Point2(std::cos(angle), std::sin(angle)));
  }
  return regionFromPolygons({ring});
}

// The point of the piece deepest inside it, found by bisecting the erosion that still leaves something, and how
// deep it is (0 for a piece thinner than the bisection's resolution).
std::pair<Point2, double> deepestPoint(const Region& piece) {
  Point2 lo = Point2::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (const Ring& ring : regionRings(piece))
    for (const Point2& p : ring) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  double inside = 0, outside = 0.5 * (hi - lo).minCoeff() + 1e-3;
  Region deepest = piece;
  for (int i = 0; i < 14 && outside - inside > 1e-3; ++i) {
    const double d = 0.5 * (inside + outside);
    Region eroded = offsetRegion(piece, -d, kFrontArcTolerance);
    if (regionEmpty(eroded)) {
      outside = d;
    } else {
      inside = d;
      deepest = std::move(eroded);
    }
  }
  const std::vector<Ring> rings = regionRings(deepest);
  Point2 centre = Point2::Zero();
  for (const Point2& p : rings.front()) centre += p / static_cast<double>(rings.front().size());
  if (!regionContains(deepest, centre)) centre = rings.front().front();
  return {centre, inside};
}

// A stretch of a front to cut: `path` from the ground cleared before into the new one (its first point lies on the
// old front, unless the whole ring is new: then `closed`).
struct Stretch {
  Polyline path;
  bool closed = false;
  std::size_t next = 0;  // the next stretch along the same ring (itself when it is the ring's only one)
  Polyline gap;          // the ring from this stretch's end to the next one's start: on the old front
};

// The point of segment a-b where it leaves `old` for good, going from a to b (a in old, b not): the last old point
// found scanning back from b in steps of kTransitionStep, then bisected to 1e-3 mm.
Point2 leavesOld(const RegionLocator& old, const Point2& a, const Point2& b) {
  const double length = (b - a).norm();
  double out = 1, in = 0;  // along a-b: out is known outside, in inside
  for (double t = 1 - kTransitionStep / length; t > 0; t -= kTransitionStep / length) {
    if (old.contains(a + t * (b - a))) {
      in = t;
      break;
    }
    out = t;
  }
  while ((out - in) * length > 1e-3) {
    const double t = 0.5 * (in + out);
    (old.contains(a + t * (b - a)) ? in : out) = t;
  }
  return a + in * (b - a);
}

// A front ring and, per vertex, whether it moved (lies outside the old ground).
struct FrontRing {
  Ring ring;
  std::vector<bool> moved;
};

// The ring with a vertex added where an edge longer than kTransitionStep runs from old ground out of it or back
// (the vertex on old ground): else a long edge with one end on old ground (a wall edge whose collinear vertices the
// union merged) counted as moved whole, and the tool fed along it over ground cut before (the whole length of a
// strip, front after front).
FrontRing withTransitions(const Ring& ring, const RegionLocator& old) {
  const std::size_t n = ring.size();
  std::vector<bool> moved(n);
  for (std::size_t i = 0; i < n; ++i) moved[i] = !old.contains(ring[i]);
  FrontRing refined;
  refined.ring.reserve(n);
  refined.moved.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t j = (i + 1) % n;
    refined.ring.push_back(ring[i]);
    refined.moved.push_back(moved[i]);
    if (moved[i] == moved[j] || (ring[j] - ring[i]).norm() <= kTransitionStep) continue;
    refined.ring.push_back(moved[i] ? leavesOld(old, ring[j], ring[i]) : leavesOld(old, ring[i], ring[j]));
    refined.moved.push_back(false);
  }
  return refined;
}

// The stretches of `next`'s rings that moved beyond `before_grown` (the ground cleared before, grown by
// kOnOldFront), material on their right (a region's rings have the region on their left): climb milling.
std::vector<Stretch> newStretches(const Region& next, const Region& before_grown) {
  const RegionLocator old(before_grown);
  std::vector<Stretch> stretches;
  for (const Ring& next_ring : regionRings(next)) {
    const auto [ring, moved] = withTransitions(next_ring, old);
    const std::size_t n = ring.size();
    if (n < 3) continue;
    std::vector<bool> edge(n);  // edge i runs from vertex i to vertex i + 1
    std::size_t still = n;
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t j = (i + 1) % n;
      edge[i] = moved[i] || moved[j] || !old.contains(0.5 * (ring[i] + ring[j]));
      if (!edge[i]) still = i;
    }
    if (still == n) {  // the whole ring moved
      Polyline path(ring.begin(), ring.end());
      path.push_back(ring.front());
      stretches.push_back({std::move(path), true, stretches.size(), {}});
      continue;
    }
    // From the end of a still edge round the ring: stretches, each followed by the still stretch after it.
    const std::size_t first = stretches.size();
    Polyline path, gap, lead;  // lead: the still edges before the first stretch
    for (std::size_t k = 1; k <= n; ++k) {
      const std::size_t i = (still + k) % n;
      if (edge[i]) {
        if (path.empty()) {
          (stretches.size() > first ? stretches.back().gap : lead) = std::move(gap);
          gap.clear();
          path.push_back(ring[i]);
        }
        path.push_back(ring[(i + 1) % n]);
      } else {
        if (!path.empty()) stretches.push_back({std::move(path), false, stretches.size() + 1, {}});
        path.clear();
        if (gap.empty()) gap.push_back(ring[i]);
        gap.push_back(ring[(i + 1) % n]);
      }
    }
    if (stretches.size() > first) {  // the last one runs on to the first, through the still edges at the start
      if (!lead.empty()) gap.insert(gap.end(), lead.begin() + (gap.empty() ? 0 : 1), lead.end());
      stretches.back().gap = std::move(gap);
      stretches.back().next = first;
    }
  }
  return stretches;
}

// The point of the region's rings nearest `p`, and the unit normal into the region at the edge it lies on.
std::pair<Point2, Point2> nearestOnRings(const Region& region, const Point2& p) {
  std::pair<Point2, Point2> best{p, Point2::Zero()};
  double best_d = std::numeric_limits<double>::infinity();
  for (const Ring& ring : regionRings(region))
    for (std::size_t i = 0; i < ring.size(); ++i) {
      const Point2 &a = ring[i], &b = ring[(i + 1) % ring.size()];
      const Point2 d = b - a;
      if (d.squaredNorm() == 0) continue;
      const double t = std::clamp((p - a).dot(d) / d.squaredNorm(), 0.0, 1.0);
      const Point2 q = a + t * d;
      if ((q - p).squaredNorm() < best_d) best = {q, Point2(-d.y(), d.x()).normalized()}, best_d = (q - p).squaredNorm();
    }
  return best;
}

ClearingLevel lowLinks(ClearingLevel level, const ClearingOptions& options) {
  if (!options.stay_down) {
    level.cleared.clear();
    level.clear_height = nullptr;
  }
  return level;
}

ClearingOptions withStayDown(ClearingOptions options) {
  options.stay_down = true;
  return options;
}

class FrontCutter {
 public:
  // The fronts of a level are many short stretches: they are always linked low, over this level's cleared ground
  // or its slab (`top`, the level's own proofs); the proofs from other levels and the stock model only with
  // options.stay_down, which also decides whether the level ends with a retract.
  FrontCutter(const ClearingLevel& level, const ClearingOptions& options, const EngagementOptions& engagement,
              ClearingStats& stats)
      : level_(lowLinks(level, options)),
        options_(options),
        low_(withStayDown(options)),
        engagement_(engagement),
        stats_(stats),
        writer_(level_, low_, stats) {}

  std::vector<ClearingPoint> cut() {
    const double r = engagement_.tool_radius;
    const double rho = engagement_.corner_radius > 0 ? engagement_.corner_radius : 2 * r;
    cleared_ = intersect(level_.air, level_.centre);
    solid_ = subtract(level_.stock_reach, level_.centre);
    seedPieces(r);
    // Each connected piece of the material is cleared whole before the next (nearest first): fronts over the whole
    // level would tour every piece at every front. Phases of shrinking corner radius: each keeps the bound with its
    // own band; what the closing by one radius holds back (corners, gaps, the first rounds of a helix) the next takes.
    for (RegionPiece& piece : regionPieces(subtract(level_.centre, cleared_))) waiting_.push_back(std::move(piece.rings));
    while (!waiting_.empty()) {
      const std::size_t j = nearestWaiting();
      area_ = unite(waiting_[j], cleared_);
      holdFarGround(waiting_[j]);
      waiting_.erase(waiting_.begin() + static_cast<std::ptrdiff_t>(j));
      for (double radius = rho; radius >= kLeastCornerShare * r; radius *= 0.5)
        grow(engagementStepover(r, radius, engagement_.max_engagement_deg), radius, false);
      grow(engagementStepover(r, 0, engagement_.max_engagement_deg), 0, true);
      for (const Region& ground : held_) cleared_ = unite(cleared_, ground);
      held_.clear();
    }
    if (!options_.stay_down) writer_.retract();
    return writer_.take();
  }

 private:
  // The squared distance from the tool to the nearest vertex of the region's first ring (0 before the first move).
  double distanceTo(const Region& region) const {
    if (!writer_.placed() || region.empty()) return 0;
    double d = std::numeric_limits<double>::infinity();
    for (const ClipperLib::IntPoint& p : region.front()) d = std::min(d, (fromRegionPoint(p) - writer_.at()).squaredNorm());
    return d;
  }

  std::size_t nearestWaiting() const {
    std::size_t best = 0;
    for (std::size_t j = 1; j < waiting_.size(); ++j)
      if (distanceTo(waiting_[j]) < distanceTo(waiting_[best])) best = j;
    return best;
  }

  // Of the connected pieces of cleared ground the piece of material `piece` touches, all but the one nearest the
  // tool (the largest before the first move) are held back: the fronts grow from that one alone and take each held
  // piece in when they come within a band of it (absorbHeldGround). Fronts grown from every piece at once meet the
  // material at both ends of a strip, and the tool crossed the strip at every front.
  void holdFarGround(const Region& piece) {
    const Region touching = offsetRegion(piece, kOnOldFront, kFrontArcTolerance);
    std::vector<Region> grounds;
    for (RegionPiece& ground : regionPieces(cleared_))
      if (!regionEmpty(intersect(ground.rings, touching))) grounds.push_back(std::move(ground.rings));
    if (grounds.size() < 2) return;
    std::size_t keep = 0;
    for (std::size_t i = 1; i < grounds.size(); ++i) {
      const bool nearer = writer_.placed() ? distanceTo(grounds[i]) < distanceTo(grounds[keep])
                                           : regionArea(grounds[i]) > regionArea(grounds[keep]);
      if (nearer) keep = i;
    }
    for (std::size_t i = 0; i < grounds.size(); ++i)
      if (i != keep) cleared_ = subtract(cleared_, grounds[i]), held_.push_back(std::move(grounds[i]));
  }

  // The held pieces of ground that `grown` (the cleared ground grown by the front's band) meets join the cleared
  // ground; true when any did.
  bool absorbHeldGround(const Region& grown) {
    const std::size_t before = held_.size();
    for (std::size_t i = 0; i < held_.size();) {
      if (regionEmpty(intersect(held_[i], grown))) {
        ++i;
        continue;
      }
      cleared_ = unite(cleared_, held_[i]);
      held_.erase(held_.begin() + static_cast<std::ptrdiff_t>(i));
    }
    return held_.size() < before;
  }

  // A helix at the deepest point of every piece of the centre region with no cleared ground in it.
  // A piece too thin for one (under kHelixLeast round its deepest point) is cut by a lap round its outer ring, which
  // sweeps all of it, and counts as cleared.
  void seedPieces(double r) {
    for (const RegionPiece& piece : regionPieces(level_.centre)) {
      if (!regionEmpty(intersect(piece.rings, cleared_))) continue;
      const auto [centre, depth] = deepestPoint(piece.rings);
      const bool thin = depth < kHelixLeast;
      const Region seed = thin ? piece.rings : disc(centre, std::min(0.5 * r, 0.9 * depth));
      std::vector<Ring> rings = regionRings(seed);
      Polyline ring(rings.front().begin(), rings.front().end());
      std::pair<std::size_t, Point2> lap{ring.size() - 1, ring.front()};
      if (!writer_.linkTo(ring.front(), false, 0, cleared_)) lap = writer_.enterRing(ring);
      for (std::size_t k = 1; k <= ring.size(); ++k) writer_.feed(ring[(lap.first + k) % ring.size()]);
      writer_.feed(lap.second);
      ++stats_.contours;
      if (thin) stats_.unbounded_mm += pathLength(ring) + (ring.back() - ring.front()).norm();
      cleared_ = unite(cleared_, seed);
    }
  }

  // Fronts a apart until they stop moving. With rho > 0 the material beyond the front is closed by rho first: its
  // concave corners, which are the front's turns round material, filled to a radius of rho (the front goes round
  // them later, when they are shallow); gaps in it narrower than 2 rho are filled too.
  // The closing is taken of the material within 2 rho (+ kClosingWindowMm) of the growth only: a point of the growth
  // lies in the closing of the material when every disc of radius rho holding it meets the material, and those discs
  // lie within 2 rho of it, so the material farther away changes nothing there (and the level's whole material, offset
  // out and back at every front, was most of the planning time).
  // A phase ends when a front adds less than min_growth_mm2 to the area the front before it reached: measured against
  // the ground after simplification, the vertices simplification trims off came back every front and CTC-01's fronts
  // crept on by a fraction of a mm^2 each, up to kMaxFronts per phase.
  void grow(double a, double rho, bool unbounded) {
    double reached_mm2 = regionArea(cleared_);
    for (int k = 0; k < kMaxFronts && !regionEmpty(cleared_); ++k) {
      Region grown = offsetRegion(cleared_, a, kFrontArcTolerance);
      if (absorbHeldGround(grown)) grown = offsetRegion(cleared_, a, kFrontArcTolerance);
      Region next = intersect(grown, area_);
      if (rho > 0) {
        const Region window = offsetRegion(subtract(next, cleared_), 2 * rho + kClosingWindowMm, kFrontArcTolerance);
        const Region beyond = intersect(unite(subtract(level_.centre, next), solid_), window);
        const Region closed = offsetRegion(offsetRegion(beyond, rho, kFrontArcTolerance), -rho, kFrontArcTolerance);
        next = subtract(next, closed);
      }
      next = unite(cleared_, next);
      const double next_mm2 = regionArea(next);
      if (next_mm2 - reached_mm2 < engagement_.min_growth_mm2) return;
      reached_mm2 = next_mm2;
      reach_ = offsetRegion(cleared_, kOnOldFront, kFrontArcTolerance);
      band_ = a;
      cutStretches(newStretches(next, reach_), unbounded);
      if (a > engagement_.tool_radius) cutStranded(next);
      cleared_ = intersect(simplifyRegion(next, 0.125 * kOnOldFront), level_.centre);  // fewer vertices, still inside
    }
  }

  // With a band wider than the radius (over 90 degrees: a thin slab's engagement), material may stand more than r
  // from every ring the tool followed: where a front closes a hole of material whose half-width lies between r and
  // the band, or pinches a neck of it off, the new front has no ring there. Those centres (farther than r, less
  // kOnOldFront, from the new front's rings and from the ground cleared before) are cut round their own rings,
  // material on the right; they lie within the band less r of the old ground, so no point of them is farther than
  // r from their rings. No engagement bound is claimed there (ClearingStats::unbounded_mm).
  void cutStranded(const Region& next) {
    const double reach = engagement_.tool_radius - kOnOldFront;
    const Region stranded = subtract(offsetRegion(next, -reach, kFrontArcTolerance),
                                     offsetRegion(cleared_, reach, kFrontArcTolerance));
    std::vector<Stretch> stretches;
    for (const RegionPiece& piece : regionPieces(stranded)) {
      if (regionArea(piece.rings) < kLeastStrandedMm2) continue;
      for (const Ring& ring : regionRings(piece.rings)) {
        Polyline path(ring.rbegin(), ring.rend());
        path.push_back(path.front());
        stretches.push_back({std::move(path), true, stretches.size(), {}});
      }
    }
    cutStretches(std::move(stretches), true);
  }

  // The stretch nearest the tool first (a closed one, a whole ring that moved, from its vertex nearest the tool),
  // then on round its ring while the way along the old front between two stretches takes less time than a hop; each
  // stretch not reached so is entered from the cleared ground.
  void cutStretches(std::vector<Stretch> stretches, bool unbounded) {
    std::vector<bool> done(stretches.size(), false);
    std::size_t next = stretches.size();
    for (std::size_t n = 0; n < stretches.size(); ++n) {
      if (next == stretches.size()) {
        double nearest = std::numeric_limits<double>::infinity();
        std::size_t start = 0;
        for (std::size_t i = 0; i < stretches.size(); ++i) {
          if (done[i]) continue;
          const auto [at, d] = nearestStart(stretches[i]);
          if (d < nearest) next = i, start = at, nearest = d;
        }
        if (start > 0) startClosedAt(stretches[next].path, start);
        enterAt(stretches[next].path.front());
      }
      done[next] = true;
      const Stretch& stretch = stretches[next];
      for (const Point2& p : stretch.path) writer_.feed(p);
      if (unbounded) stats_.unbounded_mm += pathLength(stretch.path);
      ++stats_.passes;
      next = stretches.size();
      if (!stretch.closed && !done[stretch.next] && walkCheaper(stretch.gap)) {
        for (const Point2& p : stretch.gap) writer_.feed(p);
        next = stretch.next;
      }
    }
  }

  // Where to start `stretch` nearest the tool, and the squared distance: an open stretch at its first point (it
  // leaves the old front there), a closed one at any of its vertices. (0, 0) before the first move.
  std::pair<std::size_t, double> nearestStart(const Stretch& stretch) const {
    if (!writer_.placed()) return {0, 0.0};
    std::pair<std::size_t, double> best{0, (stretch.path.front() - writer_.at()).squaredNorm()};
    if (!stretch.closed) return best;
    for (std::size_t i = 1; i + 1 < stretch.path.size(); ++i)  // the last vertex repeats the first
      if ((stretch.path[i] - writer_.at()).squaredNorm() < best.second)
        best = {i, (stretch.path[i] - writer_.at()).squaredNorm()};
    return best;
  }

  // A closed stretch (its last vertex repeats the first) turned to start and end at vertex `start`.
  static void startClosedAt(Polyline& path, std::size_t start) {
    path.pop_back();
    std::rotate(path.begin(), path.begin() + static_cast<std::ptrdiff_t>(start), path.end());
    path.push_back(path.front());
  }

  // Feeding along `gap` takes no longer than a hop over its ends (up over the slab, across, down).
  bool walkCheaper(const Polyline& gap) const {
    const double up = level_.top + options_.safe_height - level_.z;
    const double hop_s = 60 * (2 * up + (gap.back() - gap.front()).norm()) / options_.rapid_mm_min;
    return 60 * pathLength(gap) / options_.feed_mm_min <= hop_s + 60 * options_.safe_height / options_.feed_mm_min;
  }

  // To the level at `start` from the ground cleared before, at the point of it nearest `start` moved kRapidInset
  // into it (when that lies within the front's band of `start`): along the level where the way is cleared (to within the stretches' tolerance: such a link cuts at most
  // that deep), else a hop, a rapid down the clear column and a plunge; then a feed to `start`. Where no such point
  // is found, a hop and a plunge at `start` itself (through whatever the column holds, at the plunge rate).
  void enterAt(const Point2& start) {
    const auto [edge, inward] = nearestOnRings(cleared_, start);
    const Point2 inside = edge + kRapidInset * inward;
    const bool clear = inward.squaredNorm() > 0 && (inside - start).norm() <= band_ + 2 * kRapidInset &&
                       regionContains(cleared_, inside);
    const Point2 entry = clear ? inside : start;
    if (!writer_.linkTo(entry, true, 0, reach_)) writer_.descendOverCleared(clear);
    writer_.feed(start);
  }

  const ClearingLevel level_;
  const ClearingOptions& options_;
  const ClearingOptions low_;
  const EngagementOptions& engagement_;
  ClearingStats& stats_;
  PathWriter writer_;
  Region solid_;    // outside the centre region, where the disc would meet stock: material for the closing
  Region area_;     // the piece of material being cleared, with the cleared ground
  std::vector<Region> waiting_;  // pieces of material still to clear (connected pieces at the start)
  std::vector<Region> held_;     // pieces of cleared ground the fronts do not grow from yet (holdFarGround)
  double band_ = 0;  // the band the fronts of this phase take
  Region reach_;    // cleared_ grown by kOnOldFront: what did not move, and where links along the level stay
  Region cleared_;  // centres whose disc meets no material left at the level: the ground cleared
};

}  // namespace

double engagementStepover(double tool_radius, double corner_radius, double angle_deg) {
  if (!(tool_radius > 0) || !(angle_deg > 0) || angle_deg > 180)
    throw std::invalid_argument("engagementStepover: a positive radius and an angle in (0, 180] degrees");
  const double c = std::cos(angle_deg * kPi / 180);
  if (!(corner_radius > 0) || std::isinf(corner_radius)) return tool_radius * (1 - c);
  const double rho = corner_radius, r = tool_radius;
  return rho + r - std::sqrt(rho * rho + r * r + 2 * rho * r * c);
}

std::vector<ClearingPoint> clearLevelByEngagement(const ClearingLevel& level, const ClearingOptions& options,
                                                  const EngagementOptions& engagement, ClearingStats* stats) {
  ClearingStats local;
  ClearingStats& counts = stats ? *stats : local;
  if (regionEmpty(level.centre)) return {};
  EngagementOptions at_level = engagement;
  if (level.engagement_deg > 0) at_level.max_engagement_deg = level.engagement_deg;
  return FrontCutter(level, options, at_level, counts).cut();
}

}  // namespace art2part
