// Internal to the roughing stage: writing the moves of one level (clearing_paths.cpp, engagement_clearing.cpp share
// it). A PathWriter keeps where the tool is and how it gets to the next cut: a feed along the level inside a region
// that is cleared, a hop at the lowest height proven clear (ClearingLevel), or the clearance plane; and how it enters
// the level there: a plunge in air, a ramp along the cut or round a ring.
#pragma once

#include <algorithm>
#include <cmath>
#include <optional>
#include <utility>
#include <vector>

#include "art2part/common/angles.h"
#include "art2part/roughing/clearing_paths.h"

namespace art2part {
namespace clearing_detail {

constexpr double kMinRampRun = 0.5;            // mm: a path shorter than this is no ramp
constexpr double kInset = 3.0 / kRegionScale;  // mm a point on a ring edge is moved into the region before rounding
constexpr int kProbeDirections = 16;           // directions tried for a ramp where the pass itself is too short
constexpr double kSameColumn = 1e-6;           // mm: a link this short across is straight down the tool's column

using Polyline = std::vector<Point2>;

inline double pathLength(const Polyline& path) {
  double length = 0;
  for (std::size_t i = 1; i < path.size(); ++i) length += (path[i] - path[i - 1]).norm();
  return length;
}

inline double ringPerimeter(const Polyline& ring) {
  return ring.empty() ? 0 : pathLength(ring) + (ring.back() - ring.front()).norm();
}

// The point at `t` along the ring edge a-b, moved inwards (a region lies left of its edges, outer rings and holes
// alike) and rounded to the region's grid: strictly inside that edge whatever the rounding, so regionContains holds.
inline Point2 insetOnEdge(const Point2& a, const Point2& b, double t) {
  const Point2 d = b - a;
  const Point2 left(-d.y(), d.x());
  return fromRegionPoint(toRegionPoint(a + t * d + kInset / d.norm() * left));
}

class PathWriter {
 public:
  PathWriter(const ClearingLevel& level, const ClearingOptions& options, ClearingStats& stats)
      : level_(level),
        options_(options),
        stats_(stats),
        safe_z_(std::max(level.top + options.safe_height, level.z)),
        slope_(std::tan(std::clamp(options.ramp_angle_deg, 0.01, 89.0) * kPi / 180)),
        feed_(std::max(options.feed_mm_min, 1.0)),
        rapid_(std::max(options.rapid_mm_min, 1.0)) {
    if (options.stay_down && level.from) tool_ = *level.from;
  }

  // The tool has a position: it has moved at this level, or came from the level before.
  bool placed() const { return !moves_.empty() || tool_.has_value(); }
  Point2 at() const { return position().head<2>(); }
  bool atLevel() const { return placed() && position().z() == level_.z; }
  // Where the tool comes from, to weigh where to start: where it is, else the level's start_near; none before the
  // first move of a level without either.
  std::optional<Point2> comesFrom() const {
    if (placed()) return at();
    return level_.start_near;
  }

  void add(const Point2& p, double z, ClearingMove move) {
    const Eigen::Vector3d tip(p.x(), p.y(), z);
    if (placed() && (position() - tip).norm() < 1e-9) return;
    if (move == ClearingMove::Rapid && z == options_.clearance_z && placed() && position().z() < options_.clearance_z)
      ++stats_.retracts;
    moves_.push_back({tip, move});
  }
  void feed(const Point2& p) { add(p, level_.z, ClearingMove::Feed); }

  void retract() {
    if (placed() && position().z() < options_.clearance_z) add(at(), options_.clearance_z, ClearingMove::Rapid);
  }

  // To `start`, ready to cut there. True: the tool is at the level at `start` (fed along the level, only where
  // `may_feed`, on a straight segment inside `feed_region`: where the level's cuts may run, or what they have
  // cleared); false: it stands at the safe height above `start` and must enter. `entry_s` is what the entry would
  // take (minutes are compared, not judged: any choice here is sound).
  bool linkTo(const Point2& start, bool may_feed, double entry_s) {
    return linkTo(start, may_feed, entry_s, level_.centre);
  }
  bool linkTo(const Point2& start, bool may_feed, double entry_s, const Region& feed_region) {
    if (!placed()) {
      add(start, options_.clearance_z, ClearingMove::Rapid);
      descend(start, options_.clearance_z);
      return false;
    }
    const Link link = planLink(start, may_feed, entry_s, feed_region);
    if (!link.way.empty()) {
      for (const Point2& p : link.way) feed(p);
      if (options_.stay_down) ++stats_.level_links;
      return true;
    }
    if (link.hop < options_.clearance_z) ++stats_.hops;
    moveAbove(start, link.hop);
    return false;
  }

  // Whether linkTo(start, may_feed, entry_s) would reach `start` along the level.
  bool linksAlongLevel(const Point2& start, bool may_feed, double entry_s) const {
    return placed() && !planLink(start, may_feed, entry_s, level_.centre).way.empty();
  }

  // Seconds to reach the level from the safe height at `start`: a plunge in air, else a ramp forth and back.
  double entrySeconds(const Point2& start) const { return entrySeconds(regionContains(level_.air, start)); }
  double entrySeconds(bool in_air) const {
    const double drop = safe_z_ - level_.z;
    if (drop <= 0) return 0;
    if (in_air) return 60 * drop / feed_;
    return 60 * 2 * (drop / slope_) / feed_;
  }
  // What starting a cut at `start` costs, in seconds, to choose the next cut by: the way there straight at the rapid
  // rate from where the tool comes (comesFrom; 0 without) and the entry (`in_air`: a plunge, else a ramp).
  double startSeconds(const Point2& start, bool in_air) const {
    const std::optional<Point2> from = comesFrom();
    return (from ? 60 * (start - *from).norm() / rapid_ : 0.0) + entrySeconds(in_air);
  }

  // What starting a cut at `start` costs when it is entered from the side, from the air point `side`
  // (sideEntry): the way to `side` at the rapid rate, a plunge there and a feed to `start`.
  double sideStartSeconds(const Point2& start, const Point2& side) const {
    return startSeconds(side, true) + 60 * (start - side).norm() / feed_;
  }

  // A point of the level's air from which a cut starting at `start` (not in air) is entered more quickly than by a
  // ramp: a plunge there, then a straight feed to `start` inside `centre` that runs at most a tool diameter
  // (ClearingOptions::tool_radius; 0: none) through the stock at the level, as a zig-zag line does. The nearest
  // point of the air's rings, moved into the air; none where that does not hold.
  std::optional<Point2> sideEntry(const Point2& start) const {
    const double drop = safe_z_ - level_.z;
    const double limit = std::min(2 * options_.tool_radius, 2 * drop / slope_ - drop);
    if (!(limit > 0) || regionEmpty(level_.air)) return std::nullopt;
    double best = limit * limit;
    std::optional<std::pair<Point2, Point2>> edge;
    double at = 0;
    for (const ClipperLib::Path& path : level_.air)
      for (std::size_t i = 0; i < path.size(); ++i) {
        const Point2 a = fromRegionPoint(path[i]), b = fromRegionPoint(path[(i + 1) % path.size()]);
        const Point2 d = b - a;
        const double length2 = d.squaredNorm();
        if (length2 == 0) continue;
        const double t = std::clamp((start - a).dot(d) / length2, 0.0, 1.0);
        const double distance2 = (a + t * d - start).squaredNorm();
        if (distance2 < best) best = distance2, edge.emplace(a, b), at = t;
      }
    if (!edge) return std::nullopt;
    const Point2 side = insetOnEdge(edge->first, edge->second, at);
    if (!regionContains(level_.air, side) || !segmentInside(level_.centre, side, start)) return std::nullopt;
    return side;
  }

  // Down to the level at the start of an open pass: a plunge in air, else a ramp forth and back along the pass's
  // first stretch (at least kMinRampRun long), else along a short segment around the start, else a plunge (counted).
  // The tool ends at the start of the pass.
  void enterPass(const Polyline& pass) {
    if (enteredStraight(pass.front())) return;
    Polyline ramp = passPrefix(pass);
    if (pathLength(ramp) < kMinRampRun) ramp = probe(pass.front());
    rampOrPlunge(ramp, pass.front());
  }

  // Down to the level at ring[0]: by a ramp round the ring, or as for a pass. Returns where the lap at the level
  // starts and ends: a point on the edge from vertex `first` (ring[0] on the edge into it, without a ramp).
  std::pair<std::size_t, Point2> enterRing(const Polyline& ring) {
    const std::pair<std::size_t, Point2> at_start{ring.size() - 1, ring.front()};
    if (enteredStraight(ring.front())) return at_start;
    if (ringPerimeter(ring) < kMinRampRun) {
      rampOrPlunge(probe(ring.front()), ring.front());
      return at_start;
    }
    ++stats_.ramps;
    return rampAround(ring);
  }

  // Down to the level where the tool stands, over ground this level's cuts have cleared: with `rapid` (the column
  // is clear from the level up, by a margin) a rapid to the safe height over the level first, then a plunge.
  void descendOverCleared(bool rapid) {
    if (atLevel()) return;
    const double near = level_.z + options_.safe_height;
    if (rapid && position().z() > near) add(at(), near, ClearingMove::Rapid);
    add(at(), level_.z, ClearingMove::Plunge);
    ++stats_.plunges_in_air;
  }

  std::vector<ClearingPoint> take() { return std::move(moves_); }

 private:
  Eigen::Vector3d position() const { return moves_.empty() ? *tool_ : moves_.back().tip; }

  // How linkTo reaches `start` from where the tool is: the feeds along the level (ending at `start`), or none and
  // the height of the hop over (the clearance plane without stay_down).
  struct Link {
    Polyline way;
    double hop = 0;
  };
  Link planLink(const Point2& start, bool may_feed, double entry_s, const Region& feed_region) const {
    const Point2 from = at();
    const bool inside = (may_feed || options_.stay_down) && segmentInside(level_.centre, from, start);
    const bool feed_inside =
        may_feed && inside && (&feed_region == &level_.centre || segmentInside(feed_region, from, start));
    if (!options_.stay_down) {
      if (feed_inside && atLevel()) return {{start}, 0};
      return {{}, options_.clearance_z};
    }
    const double run = (start - from).norm(), z = position().z();
    const double hop = std::max(hopHeight(from, start, inside), z);
    const double hop_s = 60 * ((hop - z) + run + (hop - safe_z_)) / rapid_ + entry_s;
    if (feed_inside && atLevel() && 60 * run / feed_ <= hop_s) return {{start}, hop};
    if (may_feed && !inside && atLevel() && &feed_region == &level_.centre) {
      const Polyline way = roundOneRing(from, start);
      if (!way.empty() && 60 * pathLength(way) / feed_ <= hop_s) return {Polyline(way.begin() + 1, way.end()), hop};
    }
    return {{}, hop};
  }

  // Up to `height`, over to above `start`, straight down to the safe height above the slab.
  void moveAbove(const Point2& start, double height) {
    add(at(), height, ClearingMove::Rapid);
    add(start, height, ClearingMove::Rapid);
    descend(start, height);
  }

  // From `height` over `start` down to the safe height above the slab: a rapid, or where descents are not known clear
  // (ClearingLevel::descents_clear) a rapid down to the lowest height the stock model proves clear and a plunge at the
  // feed below it.
  void descend(const Point2& start, double height) {
    double proven = safe_z_;
    if (!level_.descents_clear && level_.clear_height && height > safe_z_)
      proven = level_.clear_height(start, start, safe_z_, height);
    if (proven > safe_z_) {
      add(start, proven, ClearingMove::Rapid);
      add(start, safe_z_, ClearingMove::Plunge);
      ++stats_.column_plunges;
      return;
    }
    add(start, safe_z_, ClearingMove::Rapid);
  }

  // The lowest height at which the straight way from `a` (where the tool stands) to `b` is proven clear: the safe
  // height over this level's centre (clear above its top), a cleared level's z + safe height over its centre (both
  // only where the column is clear: ClearingLevel::column_clear), what the stock model proves; else the clearance
  // plane.
  double hopHeight(const Point2& a, const Point2& b, bool inside_centre) const {
    // Straight below where the tool stands: the way up the column and back down it, over the clearance plane or not,
    // ends at the same point, so it need not climb (the column over the tool is where a retract goes anyway).
    if ((b - a).squaredNorm() < kSameColumn * kSameColumn) return safe_z_;
    if (inside_centre && level_.column_clear) return safe_z_;
    double best = options_.clearance_z;
    if (level_.column_clear)
      for (const ClearedLevel& cleared : level_.cleared) {
        const double height = std::max(cleared.z + options_.safe_height, safe_z_);
        if (height >= best) break;
        if (segmentInside(cleared.centre, a, b)) best = height;
      }
    if (best > safe_z_ && level_.clear_height) best = std::min(best, level_.clear_height(a, b, safe_z_, best));
    return best;
  }

  // A way from `a` to `b` inside `centre` where the straight one is not: round the one ring it crosses, from the
  // vertex of the first edge it crosses to the vertex of the last, the shorter way round whose straight ends stay
  // inside; empty when it crosses more than one ring or neither way stays inside.
  Polyline roundOneRing(const Point2& a, const Point2& b) const {
    const Point2 lo = a.cwiseMin(b), hi = a.cwiseMax(b);
    const ClipperLib::Path* crossed = nullptr;
    std::size_t first = 0, last = 0;
    double t_first = 2, t_last = -1;
    for (const ClipperLib::Path& path : level_.centre)
      for (std::size_t i = 0; i < path.size(); ++i) {
        const Point2 p = fromRegionPoint(path[i]), q = fromRegionPoint(path[(i + 1) % path.size()]);
        if (std::max(p.x(), q.x()) < lo.x() || std::min(p.x(), q.x()) > hi.x() || std::max(p.y(), q.y()) < lo.y() ||
            std::min(p.y(), q.y()) > hi.y())
          continue;
        const Point2 d = b - a, e = q - p;
        const double den = d.x() * e.y() - d.y() * e.x();
        if (std::abs(den) < 1e-12) continue;
        const Point2 w = p - a;
        const double t = (w.x() * e.y() - w.y() * e.x()) / den, u = (w.x() * d.y() - w.y() * d.x()) / den;
        if (t < 0 || t > 1 || u < 0 || u > 1) continue;
        if (crossed && crossed != &path) return {};
        crossed = &path;
        if (t < t_first) t_first = t, first = i;
        if (t > t_last) t_last = t, last = i;
      }
    if (!crossed) return {};
    const ClipperLib::Path& ring = *crossed;
    const std::size_t n = ring.size();
    Polyline best;
    for (const bool ahead : {true, false}) {
      // Ahead: from the end of the first edge crossed to the start of the last; back: the other way round.
      Polyline way{a};
      std::size_t v = ahead ? (first + 1) % n : first;
      const std::size_t stop = ahead ? last : (last + 1) % n;
      for (std::size_t steps = 0; steps <= n; ++steps) {
        way.push_back(fromRegionPoint(ring[v]));
        if (v == stop) break;
        v = ahead ? (v + 1) % n : (v + n - 1) % n;
      }
      way.push_back(b);
      if (way.size() > n + 2) continue;
      if (!segmentInside(level_.centre, a, way[1]) || !segmentInside(level_.centre, way[way.size() - 2], b)) continue;
      if (best.empty() || pathLength(way) < pathLength(best)) best = std::move(way);
    }
    return best;
  }

  // At the level without a ramp: nothing to descend through, or a plunge in air.
  bool enteredStraight(const Point2& start) {
    if (safe_z_ <= level_.z) return true;
    if (!regionContains(level_.air, start)) return false;
    add(start, level_.z, ClearingMove::Plunge);
    ++stats_.plunges_in_air;
    return true;
  }

  void rampOrPlunge(const Polyline& ramp, const Point2& start) {
    if (ramp.size() < 2) {
      add(start, level_.z, ClearingMove::Plunge);
      ++stats_.plunges_into_stock;
      return;
    }
    ++stats_.ramps;
    rampForthAndBack(ramp);
  }

  // The shortest beginning of the pass that is at least kMinRampRun long (or the whole pass).
  static Polyline passPrefix(const Polyline& pass) {
    Polyline prefix{pass.front()};
    for (std::size_t i = 1; i < pass.size() && pathLength(prefix) < kMinRampRun; ++i) prefix.push_back(pass[i]);
    return prefix;
  }

  // The longest straight segment from `start` in `centre` among a few directions and lengths (none: empty).
  Polyline probe(const Point2& start) const {
    for (double length : {2.0, 1.0, kMinRampRun})
      for (int i = 0; i < kProbeDirections; ++i) {
        const double angle = 2 * kPi * i / kProbeDirections;
        const Point2 end = start + length * Point2(std::cos(angle), std::sin(angle));
        if (segmentInside(level_.centre, start, end)) return {start, end};
      }
    return {};
  }

  // From the safe height down to the level at slope_, walking the path forth and back; the last ramp move stops
  // where the level is reached, then the tool feeds back along the path to its start.
  void rampForthAndBack(const Polyline& path) {
    double z = safe_z_;
    std::size_t i = 0;
    int step = 1;
    while (true) {
      if ((step > 0 && i + 1 == path.size()) || (step < 0 && i == 0)) step = -step;
      const std::size_t j = i + step;
      const double run = (path[j] - path[i]).norm(), drop = run * slope_;
      if (z - drop <= level_.z) {
        const Point2 stop = path[i] + (z - level_.z) / drop * (path[j] - path[i]);
        // On a stretch along the boundary the stop may round outside: then on to the next vertex, less steeply.
        add(regionContains(level_.centre, stop) ? stop : path[j], level_.z, ClearingMove::Ramp);
        for (std::size_t back = std::min(i, j) + 1; back-- > 0;) feed(path[back]);
        return;
      }
      z -= drop;
      add(path[j], z, ClearingMove::Ramp);
      i = j;
    }
  }

  // From the safe height down to the level at (at most) slope_, round and round the closed ring from ring[0]; stops
  // on the edge where the level is reached, at a point moved just inside the region.
  std::pair<std::size_t, Point2> rampAround(const Polyline& ring) {
    double z = safe_z_;
    for (std::size_t i = 0;; i = (i + 1) % ring.size()) {
      const Point2 &a = ring[i], &b = ring[(i + 1) % ring.size()];
      const double run = (b - a).norm(), drop = run * slope_;
      if (run == 0) continue;
      if (z - drop <= level_.z) {
        const double t = std::min(1.0, ((z - level_.z) / slope_ + 2 * kInset) / run);  // a hair past: never steeper
        Point2 stop = insetOnEdge(a, b, t);
        if (!regionContains(level_.centre, stop)) stop = b;  // next to a sharp corner
        add(stop, level_.z, ClearingMove::Ramp);
        return {i, stop};
      }
      z -= drop;
      add(b, z, ClearingMove::Ramp);
    }
  }

  const ClearingLevel& level_;
  const ClearingOptions& options_;
  ClearingStats& stats_;
  double safe_z_, slope_, feed_, rapid_;
  std::optional<Eigen::Vector3d> tool_;  // where the tool was before the level's first move
  std::vector<ClearingPoint> moves_;
};

}  // namespace clearing_detail
}  // namespace art2part
