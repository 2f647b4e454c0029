// Clearing one slab: zig-zag passes per connected piece of the centre region, a contour pass over its rings, ramped
// or plunged entries. See clearing_paths.h for the contract.
#include "art2part/roughing/clearing_paths.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <utility>

#include "path_writer.h"

namespace art2part {

namespace {

using namespace clearing_detail;

double cross(const Point2& a, const Point2& b) { return a.x() * b.y() - a.y() * b.x(); }

// The closed segments a-b and p-q meet, touching included: links that graze the boundary count as blocked.
bool segmentsMeet(const Point2& a, const Point2& b, const Point2& p, const Point2& q) {
  if (std::max(p.x(), q.x()) < std::min(a.x(), b.x()) || std::min(p.x(), q.x()) > std::max(a.x(), b.x()) ||
      std::max(p.y(), q.y()) < std::min(a.y(), b.y()) || std::min(p.y(), q.y()) > std::max(a.y(), b.y()))
    return false;
  const double o1 = cross(b - a, p - a), o2 = cross(b - a, q - a);
  const double o3 = cross(q - p, a - p), o4 = cross(q - p, b - p);
  return !((o1 > 0 && o2 > 0) || (o1 < 0 && o2 < 0) || (o3 > 0 && o4 > 0) || (o3 < 0 && o4 < 0));
}

// The scan frame: zig-zag lines run along u, at constant v.
struct ScanFrame {
  double c = 1, s = 0;
  explicit ScanFrame(double angle_deg) : c(std::cos(angle_deg * kPi / 180)), s(std::sin(angle_deg * kPi / 180)) {}
  Point2 toScan(const Point2& p) const { return Point2(c * p.x() + s * p.y(), -s * p.x() + c * p.y()); }
  Point2 fromScan(const Point2& q) const { return Point2(c * q.x() - s * q.y(), s * q.x() + c * q.y()); }
};

struct Edge {
  Point2 a, b;               // region frame, mm
  Point2 sa, sb;             // scan frame
  std::size_t first, count;  // the ring's edges: first .. first + count - 1
};

struct Crossing {  // of a scan line with a ring edge
  double u = 0, t = 0;  // along the line, along the edge
  std::size_t edge = 0;
};

struct End {  // of an interval: a crossing moved just inside the region
  Point2 at, scan;  // region frame, scan frame
  std::size_t edge = 0;
};

struct Interval {  // a stretch of a scan line inside the piece, `low` at the lower u
  End low, high;
  bool used = false;
};

// The zig-zag of one connected piece (an outer ring and its holes): scan lines centred over the piece's extent across
// the direction, cut into intervals by even-odd over the ring crossings, chained into boustrophedon passes.
class PieceScan {
 public:
  PieceScan(const Region& rings, const ScanFrame& frame, const ClearingOptions& options)
      : frame_(frame),
        stepover_(std::max(options.stepover, 0.01)),
        min_length_(std::max(options.min_segment, 4 * kInset)) {
    for (const ClipperLib::Path& path : rings) {
      const std::size_t first = edges_.size();
      for (std::size_t i = 0; i < path.size(); ++i) {
        const Point2 a = fromRegionPoint(path[i]), b = fromRegionPoint(path[(i + 1) % path.size()]);
        if (a != b) edges_.push_back({a, b, frame.toScan(a), frame.toScan(b), first, 0});
      }
      for (std::size_t e = first; e < edges_.size(); ++e) edges_[e].count = edges_.size() - first;
    }
    for (const Edge& edge : edges_) {
      v_min_ = std::min({v_min_, edge.sa.y(), edge.sb.y()});
      v_max_ = std::max({v_max_, edge.sa.y(), edge.sb.y()});
    }
    if (edges_.empty()) return;
    cutLines(gridHeights());
    if (std::all_of(lines_.begin(), lines_.end(), [](const auto& line) { return line.empty(); }))
      cutLines(widestHeight());  // a narrow piece that the grid missed: one line
  }

  std::vector<Polyline> passes() {
    std::vector<Polyline> out;
    for (std::size_t k = 0; k < lines_.size(); ++k)
      for (Interval& first : lines_[k])
        if (!first.used) out.push_back(passFrom(k, first));
    return out;
  }

 private:
  // Lines `stepover` apart, centred over [v_min, v_max]: no point of the piece is farther than stepover/2 in v.
  std::vector<double> gridHeights() const {
    const double span = v_max_ - v_min_;
    const int n = std::max(1, static_cast<int>(std::ceil(span / stepover_ - 1e-9)));
    const double first = v_min_ + 0.5 * (span - (n - 1) * stepover_);
    std::vector<double> heights(n);
    for (int k = 0; k < n; ++k) heights[k] = first + k * stepover_;
    return heights;
  }

  // The one height, of a few across the extent, whose longest interval is longest (none if all are too short).
  std::vector<double> widestHeight() {
    constexpr int kSamples = 9;
    double best_v = 0, best_length = 0;
    for (int i = 0; i < kSamples; ++i) {
      const double v = v_min_ + (i + 0.5) / kSamples * (v_max_ - v_min_);
      cutLines({v});
      for (const Interval& interval : lines_[0]) {
        const double length = (interval.high.scan - interval.low.scan).norm();
        if (length > best_length) best_v = v, best_length = length;
      }
    }
    return best_length > 0 ? std::vector<double>{best_v} : std::vector<double>{};
  }

  // Intervals on the lines at `heights` (ascending), and per strip between consecutive lines the edges that reach
  // into it. A crossing counts where v_a <= v < v_b (half-open), so a vertex on a line is counted once or twice, never
  // in a way that breaks the even-odd pairing.
  void cutLines(const std::vector<double>& heights) {
    heights_ = heights;
    std::vector<std::vector<Crossing>> crossings(heights.size());
    strips_.assign(heights.size() > 1 ? heights.size() - 1 : 0, {});
    for (std::size_t e = 0; e < edges_.size(); ++e) {
      const Edge& edge = edges_[e];
      const double lo = std::min(edge.sa.y(), edge.sb.y()), hi = std::max(edge.sa.y(), edge.sb.y());
      const std::size_t first = std::lower_bound(heights.begin(), heights.end(), lo) - heights.begin();
      for (std::size_t k = first; k < heights.size() && heights[k] < hi; ++k) {
        const double t = (heights[k] - edge.sa.y()) / (edge.sb.y() - edge.sa.y());
        crossings[k].push_back({edge.sa.x() + t * (edge.sb.x() - edge.sa.x()), t, e});
      }
      for (std::size_t j = first > 0 ? first - 1 : 0; j < strips_.size() && heights[j] <= hi; ++j)
        strips_[j].push_back(e);
    }
    lines_.assign(heights.size(), {});
    for (std::size_t k = 0; k < heights.size(); ++k) {
      std::vector<Crossing>& line = crossings[k];
      std::sort(line.begin(), line.end(), [](const Crossing& p, const Crossing& q) { return p.u < q.u; });
      for (std::size_t i = 0; i + 1 < line.size(); i += 2)
        if (line[i + 1].u - line[i].u >= min_length_) {
          Interval interval;
          if (end(line[i], heights[k], 1, interval.low) && end(line[i + 1], heights[k], -1, interval.high))
            lines_[k].push_back(interval);
        }
    }
  }

  // The crossing moved just inside its edge onto the region's grid; next to a sharp corner, where that may leave the
  // region, moved along the line into the interval (`inward`: +1 or -1 in u) instead. False if nothing is inside.
  bool end(const Crossing& crossing, double v, int inward, End& out) const {
    const Edge& edge = edges_[crossing.edge];
    out.edge = crossing.edge;
    out.at = insetOnEdge(edge.a, edge.b, crossing.t);
    for (double along : {4 * kInset, 1e-3, 1e-2}) {
      if (nearEdgeInside(crossing.edge, out.at)) break;
      out.at = fromRegionPoint(toRegionPoint(frame_.fromScan({crossing.u + inward * along, v})));
    }
    out.scan = frame_.toScan(out.at);
    return nearEdgeInside(crossing.edge, out.at);
  }

  // `p`, a hair from edge e, is inside the region by e and its neighbours (the wedges at its two corners).
  bool nearEdgeInside(std::size_t e, const Point2& p) const {
    auto left = [&](const Edge& edge) { return cross(edge.b - edge.a, p - edge.a) >= 0; };
    auto wedge = [&](const Edge& in, const Edge& out) {
      return cross(in.b - in.a, out.b - out.a) >= 0 ? left(in) && left(out) : left(in) || left(out);
    };
    return wedge(edges_[step(e, false)], edges_[e]) && wedge(edges_[e], edges_[step(e, true)]);
  }

  // The next edge of e's ring, or the one before.
  std::size_t step(std::size_t e, bool ahead) const {
    const Edge& edge = edges_[e];
    return edge.first + (e - edge.first + (ahead ? 1 : edge.count - 1)) % edge.count;
  }

  // A boustrophedon pass from `first` (cut along +u): on each following line, the unused interval entered at the end
  // that alternates the direction, nearest to where the tool is, joined by a link inside the piece.
  Polyline passFrom(std::size_t k, Interval& first) {
    first.used = true;
    Polyline pass{first.low.at, first.high.at};
    const End* at = &first.high;
    bool forward = false;  // the direction of the cut on the next line
    for (++k; k < lines_.size(); ++k) {
      Polyline via;
      Interval* next = reachable(k, *at, forward, via);
      if (!next) break;
      next->used = true;
      const End& entry = forward ? next->low : next->high;
      pass.insert(pass.end(), via.begin(), via.end());
      pass.push_back(entry.at);
      at = forward ? &next->high : &next->low;
      pass.push_back(at->at);
      forward = !forward;
    }
    return pass;
  }

  // The unused interval on line k nearest to `from` by its entry end, with the points of the link between (none for
  // a straight link).
  Interval* reachable(std::size_t k, const End& from, bool forward, Polyline& via) {
    std::vector<std::pair<double, Interval*>> candidates;
    for (Interval& interval : lines_[k])
      if (!interval.used)
        candidates.push_back({((forward ? interval.low : interval.high).scan - from.scan).squaredNorm(), &interval});
    std::stable_sort(candidates.begin(), candidates.end(),
                     [](const auto& p, const auto& q) { return p.first < q.first; });
    for (const auto& candidate : candidates) {
      const End& entry = forward ? candidate.second->low : candidate.second->high;
      if (linkClear(k - 1, from.scan, entry.scan) || ringLink(k - 1, from.edge, entry.edge, via))
        return candidate.second;
    }
    return nullptr;
  }

  // Both ends lie strictly inside the piece; a straight link stays inside if it meets none of the edges of its strip.
  bool linkClear(std::size_t strip, const Point2& a, const Point2& b) const {
    for (std::size_t e : strips_[strip])
      if (segmentsMeet(a, b, edges_[e].sa, edges_[e].sb)) return false;
    return true;
  }

  // A link along the ring from edge `from` to edge `to` that stays in the strip (round a convex island, where the
  // straight way cuts through it): the ring's vertices between, either way round.
  bool ringLink(std::size_t strip, std::size_t from, std::size_t to, Polyline& via) const {
    if (edges_[from].first != edges_[to].first) return false;
    const double lo = heights_[strip] - 1e-9, hi = heights_[strip + 1] + 1e-9;
    for (const bool ahead : {true, false}) {
      via.clear();
      for (std::size_t e = from; e != to;) {
        const Edge& edge = edges_[e];
        const Point2& vertex = ahead ? edge.sb : edge.sa;
        if (vertex.y() < lo || vertex.y() > hi) break;
        via.push_back(ahead ? edge.b : edge.a);
        e = step(e, ahead);
        if (e == to) return true;
      }
      if (from == to) return true;
    }
    via.clear();
    return false;
  }

  ScanFrame frame_;
  double stepover_, min_length_;
  std::vector<Edge> edges_;
  double v_min_ = std::numeric_limits<double>::infinity(), v_max_ = -std::numeric_limits<double>::infinity();
  std::vector<double> heights_;
  std::vector<std::vector<Interval>> lines_;      // per height, ascending u
  std::vector<std::vector<std::size_t>> strips_;  // per pair of consecutive heights: the edges reaching into it
};

// Moves at one level, with the entries, links and retracts between cuts.

// How a pass may be entered at one end: by a plunge where the end lies in air, else from the side (PathWriter::
// sideEntry) where there is a way in, else by a ramp.
struct PassEnd {
  bool air = false;
  std::optional<Point2> side;
};
using PassEnds = std::pair<PassEnd, PassEnd>;  // front, back

PassEnd passEnd(const Point2& end, const RegionLocator& in_air, const PathWriter& writer) {
  PassEnd e;
  e.air = in_air.contains(end);
  if (!e.air) e.side = writer.sideEntry(end);
  return e;
}

double startSeconds(const Point2& end, const PassEnd& how, const PathWriter& writer) {
  return how.side ? writer.sideStartSeconds(end, *how.side) : writer.startSeconds(end, how.air);
}

// What starting a pass costs at its cheaper end, and whether that is its back.
std::pair<double, bool> startCost(const Polyline& pass, const PassEnds& ends, const PathWriter& writer) {
  const double front = startSeconds(pass.front(), ends.first, writer);
  const double back = startSeconds(pass.back(), ends.second, writer);
  return {std::min(front, back), back < front};
}

// A piece's zig-zag passes, and how each end may be entered (looked up once: the passes are weighed at each choice).
struct PieceZigzag {
  std::vector<Polyline> passes;
  std::vector<PassEnds> ends;
};

// The piece, among those with passes left, with the cheapest pass start (the first, for the first).
std::size_t nextPiece(const std::vector<PieceZigzag>& pieces, const std::vector<bool>& done, const PathWriter& writer) {
  std::size_t best = pieces.size();
  double best_cost = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    if (done[i]) continue;
    for (std::size_t k = 0; k < pieces[i].passes.size(); ++k) {
      const double cost = startCost(pieces[i].passes[k], pieces[i].ends[k], writer).first;
      if (cost < best_cost) best = i, best_cost = cost;
    }
  }
  return best;
}

// The unused pass with the cheapest start, turned to start there (startCost); in front of it its side entry, unless
// the tool gets there along the level.
Polyline nextPass(std::vector<Polyline>& passes, std::vector<bool>& used, const std::vector<PassEnds>& ends,
                  const PathWriter& writer, bool stay_down) {
  std::size_t best = passes.size();
  std::pair<double, bool> best_cost{std::numeric_limits<double>::infinity(), false};
  for (std::size_t k = 0; k < passes.size(); ++k) {
    if (used[k]) continue;
    const std::pair<double, bool> cost = startCost(passes[k], ends[k], writer);
    if (cost.first < best_cost.first) best = k, best_cost = cost;
  }
  used[best] = true;
  Polyline pass = std::move(passes[best]);
  if (best_cost.second) std::reverse(pass.begin(), pass.end());
  const PassEnd& start = best_cost.second ? ends[best].second : ends[best].first;
  if (start.side && !writer.linksAlongLevel(pass.front(), stay_down, writer.entrySeconds(false)))
    pass.insert(pass.begin(), *start.side);
  return pass;
}

// A piece every point of which lies within half a stepover of its rings: the contour pass alone covers it.
bool coveredByContour(const RegionPiece& piece, const ClearingOptions& options) {
  return options.contour_pass && regionEmpty(offsetRegion(piece.rings, -0.5 * std::max(options.stepover, 0.01)));
}

void cutZigzag(const std::vector<RegionPiece>& pieces, const ClearingLevel& level, const ClearingOptions& options,
               PathWriter& writer, ClearingStats& stats) {
  const ScanFrame frame(options.angle_deg);
  const RegionLocator in_air(level.air);
  const double inset = options.contour_pass ? zigzagInset(options.stepover, options.tool_radius) : 0.0;
  std::vector<PieceZigzag> zigzags(pieces.size());
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    if (coveredByContour(pieces[i], options)) continue;
    const Region scanned = inset > 0 ? offsetRegion(pieces[i].rings, -inset) : pieces[i].rings;
    if (regionEmpty(scanned)) continue;
    zigzags[i].passes = PieceScan(scanned, frame, options).passes();
    for (const Polyline& pass : zigzags[i].passes)
      zigzags[i].ends.emplace_back(passEnd(pass.front(), in_air, writer), passEnd(pass.back(), in_air, writer));
  }
  std::vector<bool> done(zigzags.size(), false);
  for (std::size_t i = nextPiece(zigzags, done, writer); i < zigzags.size(); i = nextPiece(zigzags, done, writer)) {
    done[i] = true;
    std::vector<bool> used(zigzags[i].passes.size(), false);
    for (std::size_t n = 0; n < zigzags[i].passes.size(); ++n) {
      const Polyline pass = nextPass(zigzags[i].passes, used, zigzags[i].ends, writer, options.stay_down);
      if (!writer.linkTo(pass.front(), options.stay_down, writer.entrySeconds(pass.front()))) writer.enterPass(pass);
      for (const Point2& p : pass) writer.feed(p);
      ++stats.passes;
    }
  }
}

// The vertex of `ring` nearest to `from`, and its squared distance.
std::pair<std::size_t, double> nearestVertex(const Polyline& ring, const Point2& from) {
  std::pair<std::size_t, double> best{0, std::numeric_limits<double>::infinity()};
  for (std::size_t i = 0; i < ring.size(); ++i)
    if ((ring[i] - from).squaredNorm() < best.second) best = {i, (ring[i] - from).squaredNorm()};
  return best;
}

// A stretch of a ring the contour pass follows: the whole ring (closed), or a run of its edges (open, in the ring's
// direction; cut from whichever end is nearer the tool).
struct RingStretch {
  Polyline path;
  bool closed = true;
};

// The stretches of `ring` to follow: all of it but the edges lying in `air`, where the tool's disc meets no stock
// and a lap would cut nothing. An open stretch runs from the air vertex before its first edge to the one after its
// last, so it starts where the tool may plunge.
std::vector<RingStretch> ringStretches(const Polyline& ring, const Region& air, const RegionLocator& in_air) {
  const std::size_t n = ring.size();
  std::vector<char> air_edge(n, 0);
  std::size_t air_edges = 0;
  if (!regionEmpty(air)) {
    std::vector<char> air_vertex(n);
    for (std::size_t i = 0; i < n; ++i) air_vertex[i] = in_air.contains(ring[i]);
    Point2 lo = ring[0], hi = ring[0];
    for (const Point2& p : ring) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
    const Region near = ringsMeeting(air, lo, hi);
    for (std::size_t i = 0; i < n; ++i)
      if (air_vertex[i] && air_vertex[(i + 1) % n] && segmentInside(near, ring[i], ring[(i + 1) % n]))
        air_edge[i] = 1, ++air_edges;
  }
  if (air_edges == 0) return {{ring, true}};
  std::vector<RingStretch> stretches;
  if (air_edges == n) return stretches;
  const std::size_t first_air = std::find(air_edge.begin(), air_edge.end(), 1) - air_edge.begin();
  RingStretch run{{}, false};
  for (std::size_t k = 1; k <= n; ++k) {  // edges from the one after an air edge, once round
    const std::size_t e = (first_air + k) % n;
    if (air_edge[e]) {
      if (!run.path.empty()) stretches.push_back(std::move(run)), run = {{}, false};
      continue;
    }
    if (run.path.empty()) run.path.push_back(ring[e]);
    run.path.push_back(ring[(e + 1) % n]);
  }
  if (!run.path.empty()) stretches.push_back(std::move(run));
  return stretches;
}

// Where a stretch starts nearest `from`: a closed ring at its nearest vertex, an open one at the nearer of its ends
// (both lie in air, where the tool may plunge; the zig-zag cuts both ways too, so neither way is the rule).
std::pair<std::size_t, double> nearestStart(const RingStretch& stretch, const Point2& from) {
  if (!stretch.closed) {
    const double front = (stretch.path.front() - from).squaredNorm(), back = (stretch.path.back() - from).squaredNorm();
    return back < front ? std::pair<std::size_t, double>{stretch.path.size() - 1, back}
                        : std::pair<std::size_t, double>{0, front};
  }
  return nearestVertex(stretch.path, from);
}

// Every ring followed once at the level, nearest first, but where it lies in air; joined by a feed where the straight
// way is inside the region; a closed ring entered from the side where it can be (PathWriter::sideEntry), else by a
// ramp round it.
void cutContours(const std::vector<RegionPiece>& pieces, const ClearingLevel& level, const ClearingOptions& options,
                 PathWriter& writer, ClearingStats& stats) {
  const RegionLocator in_air(level.air);
  std::vector<RingStretch> stretches;
  for (const RegionPiece& piece : pieces)
    for (const Ring& ring : regionRings(piece.rings))
      if (ring.size() >= 3 && ringPerimeter(ring) >= options.min_segment)
        for (RingStretch& stretch : ringStretches(ring, level.air, in_air))
          if (stretch.closed || pathLength(stretch.path) >= options.min_segment)
            stretches.push_back(std::move(stretch));
  while (!stretches.empty()) {
    std::size_t next = 0, start = 0;
    double nearest = std::numeric_limits<double>::infinity();
    const std::optional<Point2> from = writer.comesFrom();
    for (std::size_t i = 0; i < stretches.size() && from; ++i) {
      const std::pair<std::size_t, double> at = nearestStart(stretches[i], *from);
      if (at.second < nearest) next = i, start = at.first, nearest = at.second;
    }
    RingStretch stretch = std::move(stretches[next]);
    stretches.erase(stretches.begin() + next);
    Polyline& path = stretch.path;
    if (!stretch.closed) {
      if (start != 0) std::reverse(path.begin(), path.end());
      if (!writer.linkTo(path.front(), true, writer.entrySeconds(path.front()))) writer.enterPass(path);
      for (const Point2& p : path) writer.feed(p);
      ++stats.contours;
      continue;
    }
    std::rotate(path.begin(), path.begin() + start, path.end());
    std::pair<std::size_t, Point2> lap{path.size() - 1, path.front()};
    const double entry_s = writer.entrySeconds(path.front());
    const bool straight = in_air.contains(path.front()) || writer.linksAlongLevel(path.front(), true, entry_s);
    const std::optional<Point2> side = straight ? std::nullopt : writer.sideEntry(path.front());
    if (side) {
      if (!writer.linkTo(*side, true, writer.entrySeconds(true))) writer.enterPass({*side, path.front()});
      writer.feed(path.front());
    } else if (!writer.linkTo(path.front(), true, entry_s)) {
      lap = writer.enterRing(path);
    }
    // Once round at the level, from where the tool reached it back to there.
    for (std::size_t k = 1; k <= path.size(); ++k) writer.feed(path[(lap.first + k) % path.size()]);
    writer.feed(lap.second);
    ++stats.contours;
  }
}

}  // namespace

double zigzagInset(double stepover, double radius) {
  // mm: the eroded rings lie on the region's grid and their arcs are chords: the inset is taken this much smaller,
  // so its bounds hold through the rounding.
  constexpr double kArcSlack = 0.05;
  return std::max(0.0, std::min(0.5 * stepover, radius - 0.5 * stepover) - kArcSlack);
}

std::vector<ClearingPoint> clearLevel(const ClearingLevel& level, const ClearingOptions& level_options,
                                      ClearingStats* stats) {
  ClearingStats local;
  ClearingStats& counts = stats ? *stats : local;
  if (regionEmpty(level.centre)) return {};
  ClearingOptions options = level_options;
  if (level.stepover > 0) options.stepover = level.stepover;
  const std::vector<RegionPiece> pieces = regionPieces(level.centre);
  PathWriter writer(level, options, counts);
  cutZigzag(pieces, level, options, writer, counts);
  if (options.contour_pass) cutContours(pieces, level, options, writer, counts);
  if (!options.stay_down) writer.retract();
  return writer.take();
}

double clearingLength(const std::vector<ClearingPoint>& moves, bool cutting) {
  double length = 0;
  for (std::size_t i = 1; i < moves.size(); ++i)
    if ((moves[i].move != ClearingMove::Rapid) == cutting) length += (moves[i].tip - moves[i - 1].tip).norm();
  return length;
}

}  // namespace art2part
