// Moves of the 2.5-D finishing passes (finishing_moves.h).
#include "finishing_moves.h"

#include "art2part/geometry/ordered_tour.h"
#include "art2part/geometry/top_down_schedule.h"
#include "art2part/roughing/operation_moves.h"

namespace art2part::finishing_detail {

// Rapid descents (below the clearance plane) moved to where the tool comes down clear of the allowance, joined to the
// descent's foot by a feed; where there is none nearby, the descent is a feed.
std::vector<ClearingPoint> safeDescents(const std::vector<ClearingPoint>& moves, const SafeDescent& safe,
                                        const DescentLimit& limit, double max_shift) {
  std::vector<ClearingPoint> out;
  out.reserve(moves.size());
  for (std::size_t i = 0; i < moves.size(); ++i) {
    const ClearingPoint& m = moves[i];
    const bool descent = m.move == ClearingMove::Rapid && !out.empty() && m.tip.z() < out.back().tip.z() - 1e-9 &&
                         (m.tip.head<2>() - out.back().tip.head<2>()).norm() < 1e-6;
    if (!descent) {
      out.push_back(m);
      continue;
    }
    Point2 at;
    if (safe.at(m.tip.head<2>(), max_shift, at)) {
      const double floor = limit.at(at);
      out.back().tip.head<2>() = at;  // the rapid across ends over the safe point
      if (floor < m.tip.z()) {
        out.push_back({Vec3(at.x(), at.y(), m.tip.z()), ClearingMove::Rapid});
      } else {
        if (floor < out.back().tip.z()) out.push_back({Vec3(at.x(), at.y(), floor), ClearingMove::Rapid});
        out.push_back({Vec3(at.x(), at.y(), m.tip.z()), ClearingMove::Feed});
      }
      if ((at - m.tip.head<2>()).norm() > 1e-6) out.push_back({m.tip, ClearingMove::Feed});
    } else {
      out.push_back({m.tip, ClearingMove::Feed});
    }
  }
  return out;
}

// Cuts one stretch of ring at height z: entered from the open side (the region lies left of a climb stretch) where
// the straight lead-in stays in the region, else straight down at its first point.
void cutStretch(const ContourStretch& s, double z, double top, double lead, const Region& allowed,
                const SafeDescent& safe, const DescentLimit& limit, PathWriter& out) {
  const Point2& p0 = s.points.front();
  const Point2 t = (s.points[1] - p0).normalized();
  Point2 start = p0 + Point2(-t.y(), t.x()) * lead;
  if (!segmentInside(allowed, start, p0)) start = p0;
  Point2 down;
  if (safe.at(start, 2 * lead, down)) {
    out.enter(down, top + kSafeHeight, top + kSafeHeight, limit.at(down));
    out.move(Vec3(start.x(), start.y(), top + kSafeHeight), MoveKind::Feed);
    out.move(Vec3(start.x(), start.y(), z), MoveKind::Feed);
  } else {
    out.enter(start, z, top + kSafeHeight, std::numeric_limits<double>::infinity());  // feed all the way down
  }
  for (const Point2& p : s.points) out.move(Vec3(p.x(), p.y(), z), MoveKind::Feed);
  if (s.closed) out.move(Vec3(p0.x(), p0.y(), z), MoveKind::Feed);
  // Lead out the way it came in, off the wall.
  const Point2& pn = s.closed ? p0 : s.points.back();
  const Point2& pp = s.closed ? s.points.back() : s.points[s.points.size() - 2];
  const Point2 u = (pn - pp).normalized();
  const Point2 off = pn + Point2(-u.y(), u.x()) * lead;
  if (segmentInside(allowed, pn, off)) out.move(Vec3(off.x(), off.y(), z), MoveKind::Feed);
}

namespace {

constexpr int kStartTries = 16;  // vertices of a closed stretch, nearest first, tried for a lead-in in the region

// The squared x-y distance from `at` to the nearest vertex of a closed stretch, or to the first of an open one.
double squaredToStart(const ContourStretch& s, const Point2& at) {
  double d = (s.points.front() - at).squaredNorm();
  if (s.closed)
    for (const Point2& p : s.points) d = std::min(d, (p - at).squaredNorm());
  return d;
}

// A closed stretch turned to start at its vertex nearest `at` among those whose lead-in from the open side stays in
// `allowed` (cutStretch's entry), the kStartTries nearest tried; unchanged when none of them has one.
void startNearest(ContourStretch& s, const Point2& at, double lead, const Region& allowed) {
  if (!s.closed || s.points.size() < 3) return;
  std::vector<std::size_t> by_distance(s.points.size());
  for (std::size_t i = 0; i < by_distance.size(); ++i) by_distance[i] = i;
  const std::size_t tries = std::min<std::size_t>(kStartTries, by_distance.size());
  std::partial_sort(by_distance.begin(), by_distance.begin() + static_cast<std::ptrdiff_t>(tries), by_distance.end(),
                    [&](std::size_t a, std::size_t b) {
                      return (s.points[a] - at).squaredNorm() < (s.points[b] - at).squaredNorm();
                    });
  for (std::size_t k = 0; k < tries; ++k) {
    const std::size_t i = by_distance[k];
    const Point2& p0 = s.points[i];
    const Point2 t = (s.points[(i + 1) % s.points.size()] - p0).normalized();
    if (!segmentInside(allowed, p0 + Point2(-t.y(), t.x()) * lead, p0)) continue;
    if (i > 0) std::rotate(s.points.begin(), s.points.begin() + static_cast<std::ptrdiff_t>(i), s.points.end());
    return;
  }
}

// The walls cut nearest first under the top-down rule, then or-opt's order where quicker as written (cutWalls),
// from where `from` stands; with `nearest_starts` each closed stretch starts where the order first reaches it, at
// its vertex nearest the tool (startNearest), else at its first.
PathWriter wallsInOrder(std::vector<WallStretch> walls, bool nearest_starts, double lead, double reach,
                        const DescentLimit& limit, double rapid_mm_min, const PathWriter& from) {
  std::vector<ScheduledItem> items;
  items.reserve(walls.size());
  for (const WallStretch& w : walls) {
    ScheduledItem item{-w.z, w.stretch.points.front(), w.stretch.points.front()};
    for (const Point2& p : w.stretch.points) item.lo = item.lo.cwiseMin(p), item.hi = item.hi.cwiseMax(p);
    items.push_back(item);
  }
  TopDownSchedule schedule(std::move(items), 2 * reach);  // boxes grown by the reach each meet
  // Each stretch is entered at its first point and left at its last (its start, closed), whatever the order.
  const auto stopOf = [](const WallStretch& w) {
    const Point2& first = w.stretch.points.front();
    const Point2& last = w.stretch.closed ? first : w.stretch.points.back();
    return TourStop{Vec3(first.x(), first.y(), w.z), Vec3(last.x(), last.y(), w.z)};
  };
  std::vector<TourStop> stops(walls.size());
  Vec3 at = from.at();
  auto distance = [&](std::size_t i) {
    const double d = nearest_starts ? std::sqrt(squaredToStart(walls[i].stretch, at.head<2>()))
                                    : (walls[i].stretch.points.front() - at.head<2>()).norm();
    return d + std::abs(walls[i].z - at.z());
  };
  std::vector<std::size_t> nearest;
  for (std::size_t i = schedule.next(at.head<2>(), distance); i < walls.size();
       i = schedule.next(at.head<2>(), distance)) {
    if (nearest_starts) startNearest(walls[i].stretch, at.head<2>(), lead, *walls[i].allowed);
    stops[i] = stopOf(walls[i]);
    nearest.push_back(i);
    at = stops[i].exit;
  }
  auto write = [&](const std::vector<std::size_t>& order, PathWriter& path) {
    for (std::size_t i : order) {
      const WallStretch& w = walls[i];
      cutStretch(w.stretch, w.z, w.top, lead, *w.allowed, *w.safe, limit, path);
    }
  };
  PathWriter by_nearest = from;
  write(nearest, by_nearest);
  const std::vector<std::size_t> shortened = shortenedOrder(stops, nearest, schedule.waitsFor());
  if (shortened == nearest) return by_nearest;
  // The model counts straight travel; the links written (a hop at the height the stock proves clear, a feed down
  // where no rapid may come) decide the time: the shortened order only where it is quicker as written.
  PathWriter by_shortened = from;
  write(shortened, by_shortened);
  const bool quicker = by_shortened.secondsToRetract(rapid_mm_min) < by_nearest.secondsToRetract(rapid_mm_min);
  return quicker ? by_shortened : by_nearest;
}

}  // namespace

void cutWalls(const std::vector<WallStretch>& walls, double lead, double reach, const DescentLimit& limit,
              double rapid_mm_min, PathWriter& out) {
  PathWriter at_first = wallsInOrder(walls, false, lead, reach, limit, rapid_mm_min, out);
  const bool closed = std::any_of(walls.begin(), walls.end(), [](const WallStretch& w) { return w.stretch.closed; });
  if (!closed) {
    out = std::move(at_first);
    return;
  }
  // Starting each ring nearest the tool also ends it there, which can lengthen the way to the next: the quicker as
  // written is kept (CTC-01 was 1 s slower with nearest starts everywhere, ANC101 4 s quicker).
  PathWriter at_nearest = wallsInOrder(walls, true, lead, reach, limit, rapid_mm_min, out);
  const bool quicker = at_nearest.secondsToRetract(rapid_mm_min) < at_first.secondsToRetract(rapid_mm_min);
  out = std::move(quicker ? at_nearest : at_first);
}

namespace {

// Where a floor piece's moves enter it (the first at its level) and leave it (the last): or-opt's model of the piece.
TourStop floorStop(const std::vector<ClearingPoint>& moves, double z) {
  TourStop stop;
  if (moves.empty()) return stop;
  stop.entry = moves.front().tip;
  for (const ClearingPoint& m : moves)
    if (std::abs(m.tip.z() - z) < 1e-6) {
      stop.entry = m.tip;
      break;
    }
  stop.exit = moves.back().tip;
  return stop;
}

// The floors written piece by piece in the nearest order and in or-opt's (the quicker as written), from `out`; with
// `start_near` each piece starts where it is quickest to reach from where the order leaves the tool
// (ClearingLevel::start_near), else at its cheapest entry wherever that is.
struct PiecesWritten {
  PathWriter path;
  bool as_levels = false;  // the nearest order was one piece per level, in level order
};
PiecesWritten floorsByPieces(const std::vector<FloorLevel>& floors, const std::vector<ClearingLevel>& levels,
                             const ClearingOptions& clearing, const DescentLimit& limit, double reach,
                             double rapid_mm_min, bool start_near, const PathWriter& before) {
  const double shift = 2 * clearing.tool_radius;
  PathWriter out = before;
  PieceSchedule schedule(levels, reach);
  const std::vector<LevelPiece>& pieces = schedule.pieces();
  // A piece's clearing does not depend on the order: each is cleared once and written in every order tried.
  std::vector<std::vector<ClearingPoint>> moves(pieces.size());
  std::vector<TourStop> stops(pieces.size());
  std::vector<std::size_t> nearest;
  bool as_levels = pieces.size() == levels.size();  // one piece per level, cut in level order so far
  std::optional<Point2> at;
  if (start_near && out.started()) at = out.at().head<2>();
  for (std::size_t i = schedule.next(at); i < pieces.size(); i = schedule.next(at)) {
    as_levels = as_levels && i == nearest.size() && pieces[i].level == i;
    const FloorLevel& floor = floors[pieces[i].level];
    ClearingLevel level = levels[pieces[i].level];
    level.centre = pieces[i].rings;
    if (start_near) level.start_near = at;
    moves[i] = safeDescents(clearLevel(level, clearing), *floor.safe, limit, shift);
    stops[i] = floorStop(moves[i], level.z);
    out.clearing(moves[i]);
    nearest.push_back(i);
    at = out.at().head<2>();
  }
  const std::vector<std::size_t> shortened = shortenedOrder(stops, nearest, schedule.waitsFor());
  if (shortened != nearest) {
    PathWriter by_shortened = before;
    for (std::size_t i : shortened) by_shortened.clearing(moves[i]);
    if (by_shortened.secondsToRetract(rapid_mm_min) < out.secondsToRetract(rapid_mm_min)) out = std::move(by_shortened);
  }
  return {std::move(out), as_levels};
}

}  // namespace

void cutFloors(const std::vector<FloorLevel>& floors, const ClearingOptions& clearing, const DescentLimit& limit,
               double reach, double rapid_mm_min, PathWriter& out) {
  std::vector<ClearingLevel> levels;
  levels.reserve(floors.size());
  for (const FloorLevel& f : floors) levels.push_back(f.clear);
  const PathWriter before = out;
  auto quicker = [rapid_mm_min, &out](PathWriter&& other) {
    if (other.secondsToRetract(rapid_mm_min) < out.secondsToRetract(rapid_mm_min)) out = std::move(other);
  };
  // Starting each piece nearest the tool shortens the way there, but the entry it picks may cost more as written
  // (a descent where no rapid may come is a feed): each order is written both ways, the quickest kept.
  PiecesWritten first = floorsByPieces(floors, levels, clearing, limit, reach, rapid_mm_min, false, before);
  const bool as_levels = first.as_levels;
  out = std::move(first.path);
  quicker(floorsByPieces(floors, levels, clearing, limit, reach, rapid_mm_min, true, before).path);
  for (const bool start_near : {false, true}) {
    if (as_levels && !start_near) continue;  // the same clearing as the pieces' first order
    PathWriter by_levels = before;
    for (const FloorLevel& f : floors) {
      ClearingLevel level = f.clear;
      if (start_near && by_levels.started()) level.start_near = by_levels.at().head<2>();
      by_levels.clearing(safeDescents(clearLevel(level, clearing), *f.safe, limit, 2 * clearing.tool_radius));
    }
    quicker(std::move(by_levels));
  }
}

}  // namespace art2part::finishing_detail
