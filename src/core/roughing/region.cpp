#include "art2part/roughing/region.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <thread>
#include <utility>

#include "art2part/common/parallel.h"

namespace art2part {

using ClipperLib::cInt;
using ClipperLib::IntPoint;
using ClipperLib::Path;
using ClipperLib::Paths;

IntPoint toRegionPoint(const Point2& p) {
  return IntPoint(static_cast<cInt>(std::llround(p.x() * kRegionScale)),
                  static_cast<cInt>(std::llround(p.y() * kRegionScale)));
}

Point2 fromRegionPoint(const IntPoint& p) {
  return Point2(static_cast<double>(p.X) / kRegionScale, static_cast<double>(p.Y) / kRegionScale);
}

namespace {

thread_local RegionFailureTally* innermost_tally = nullptr;

bool execute(const Region& a, const Region& b, ClipperLib::ClipType type, Region& out) {
  ClipperLib::Clipper clipper;
  const bool any = clipper.AddPaths(a, ClipperLib::ptSubject, true) | clipper.AddPaths(b, ClipperLib::ptClip, true);
  out.clear();
  // With no edge at all Execute says false (nothing to sweep): the empty result is the answer.
  return clipper.Execute(type, out, ClipperLib::pftNonZero, ClipperLib::pftNonZero) || !any;
}

// Clipper's results are outer rings (counter-clockwise) with holes (clockwise) inside them, so a hole is smaller than
// the largest outer ring and the total is not negative. Clipper 6.4 breaks that now and then where hundreds of
// slivers under a square mm touch an outline (CTC-02 seen 2.8 deg off z: a shadow's outline came out clockwise,
// -417,032 mm2 beside its real hole of -248,497, and the forbidden region grown from it lost 237,807 mm2 of shadow).
bool wellFormed(const Region& region) {
  double total = 0, largest_outer = 0, largest_hole = 0;
  for (const Path& path : region) {
    const double area = ClipperLib::Area(path);
    total += area;
    if (area > 0) largest_outer = std::max(largest_outer, area);
    else largest_hole = std::max(largest_hole, -area);
  }
  return total >= 0 && (largest_hole == 0 || largest_hole < largest_outer);
}

// The rings of a result as a set by the even-odd rule: right whatever their orientation when only the orientation
// went wrong (the rings themselves neither cross nor overlap).
Region evenOdd(const Region& region) {
  ClipperLib::Clipper clipper;
  clipper.AddPaths(region, ClipperLib::ptSubject, true);
  Region out;
  clipper.Execute(ClipperLib::ctUnion, out, ClipperLib::pftEvenOdd, ClipperLib::pftEvenOdd);
  return out;
}

// Clipper 6.4 gives up, now and then, on edges it cannot order at an intersection (Execute returns false and the
// result is empty: a union that loses everything), or returns rings of the wrong sense (see wellFormed). Retried with
// vertices closer than 0.2 um merged, then on a grid of 1 um; a result still ill-formed is taken by the even-odd
// rule. A failure left after that is counted (RegionFailureTally) and the result is empty or as Clipper gave it.
Region clip(const Region& a, const Region& b, ClipperLib::ClipType type) {
  Region out;
  if (execute(a, b, type, out) && wellFormed(out)) return out;
  Region ca = a, cb = b;
  ClipperLib::CleanPolygons(ca, 2.0);
  ClipperLib::CleanPolygons(cb, 2.0);
  if (execute(ca, cb, type, out) && wellFormed(out)) return out;
  for (Region* r : {&ca, &cb})
    for (Path& path : *r)
      for (IntPoint& p : path) p = IntPoint((p.X / 10) * 10, (p.Y / 10) * 10);
  ClipperLib::CleanPolygons(ca, 1.0);
  ClipperLib::CleanPolygons(cb, 1.0);
  if (execute(ca, cb, type, out)) {
    if (wellFormed(out)) return out;
    Region repaired = evenOdd(out);
    if (wellFormed(repaired)) return repaired;
  }
  RegionFailureTally::countFailure();
  return out;
}

double cross(const Point2& a, const Point2& b) { return a.x() * b.y() - a.y() * b.x(); }

// Where segment a-b meets segment p-q, as parameters along a-b: the crossing or touching point, or the ends of the
// stretch where they run along each other (then `along` is set). None if apart.
std::vector<double> meetings(const Point2& a, const Point2& b, const Point2& p, const Point2& q, bool& along) {
  const Point2 r = b - a, s = q - p;
  const double d = cross(r, s), rr = r.squaredNorm();
  along = false;
  if (std::abs(d) <= 1e-12 * std::sqrt(rr * s.squaredNorm())) {  // parallel: apart, or along one line
    if (std::abs(cross(r, p - a)) > 1e-9 * std::sqrt(rr)) return {};
    const double tp = (p - a).dot(r) / rr, tq = (q - a).dot(r) / rr;
    const double lo = std::max(0.0, std::min(tp, tq)), hi = std::min(1.0, std::max(tp, tq));
    if (lo > hi) return {};
    along = true;
    return {lo, hi};
  }
  const double t = cross(p - a, s) / d, u = cross(p - a, r) / d, eps = 1e-9;
  if (u < -eps || u > 1 + eps || t < -eps || t > 1 + eps) return {};
  return {std::clamp(t, 0.0, 1.0)};
}

}  // namespace

Region regionFromPolygons(const std::vector<Ring>& polygons) {
  Paths paths;
  paths.reserve(polygons.size());
  for (const Ring& ring : polygons) {
    if (ring.size() < 3) continue;
    Path path;
    path.reserve(ring.size());
    for (const Point2& p : ring) path.push_back(toRegionPoint(p));
    if (ClipperLib::Area(path) == 0) continue;
    if (!ClipperLib::Orientation(path)) ClipperLib::ReversePath(path);
    paths.push_back(std::move(path));
  }
  return clip(paths, {}, ClipperLib::ctUnion);
}

RegionFailureTally::RegionFailureTally() : outer_(innermost_tally) { innermost_tally = this; }

RegionFailureTally::~RegionFailureTally() {
  innermost_tally = outer_;
  if (outer_) outer_->count_ += count_;
}

void RegionFailureTally::countFailure() { countFailures(1); }

void RegionFailureTally::countFailures(long n) {
  if (innermost_tally) innermost_tally->count_ += n;
}

void parallelForRegions(int count, const std::function<void(int)>& body) {
  const std::thread::id caller = std::this_thread::get_id();
  std::atomic<long> failures{0};
  parallelFor(count, 0, [&](int k) {
    if (std::this_thread::get_id() == caller) return body(k);  // one thread: the caller's tally counts them
    const RegionFailureTally tally;
    body(k);
    failures += tally.count();
  });
  RegionFailureTally::countFailures(failures);
}

std::vector<Ring> regionRings(const Region& region) {
  std::vector<Ring> rings;
  rings.reserve(region.size());
  for (const Path& path : region) {
    Ring ring;
    ring.reserve(path.size());
    for (const IntPoint& p : path) ring.push_back(fromRegionPoint(p));
    rings.push_back(std::move(ring));
  }
  return rings;
}

Region unite(const Region& a, const Region& b) { return clip(a, b, ClipperLib::ctUnion); }
Region subtract(const Region& a, const Region& b) { return clip(a, b, ClipperLib::ctDifference); }
Region intersect(const Region& a, const Region& b) { return clip(a, b, ClipperLib::ctIntersection); }

namespace {

// ClipperOffset's notion of the lowest vertex: largest y, then smallest x.
bool lower(const IntPoint& p, const IntPoint& q) { return p.Y > q.Y || (p.Y == q.Y && p.X < q.X); }

IntPoint lowestVertex(const Path& path) {
  IntPoint lowest = path[0];
  for (const IntPoint& p : path)
    if (lower(p, lowest)) lowest = p;
  return lowest;
}

// ClipperOffset takes the ring holding the lowest vertex (the first such ring on a tie) for an outer ring, and when
// that ring winds clockwise it turns every ring over: the region then shrinks where it should grow. Clipper's own
// results can carry a degenerate hole through an outer ring's lowest vertex (CTC-02: a 4-point hole of no area made a
// holder's forbidden region shrink instead of grow by 20.5 mm, 1,302 holder collisions). Outer rings go in first, so
// that ties go to them, and a hole reaching below every outer ring (so lying in none) is left out.
Region outerRingsFirst(const Region& region) {
  Region outer, holes;
  for (const Path& path : region) {
    if (path.size() < 3) continue;
    (ClipperLib::Area(path) > 0 ? outer : holes).push_back(path);
  }
  if (outer.empty()) return region;
  IntPoint lowest = lowestVertex(outer[0]);
  for (const Path& path : outer) {
    const IntPoint p = lowestVertex(path);
    if (lower(p, lowest)) lowest = p;
  }
  for (const Path& path : holes)
    if (!lower(lowestVertex(path), lowest)) outer.push_back(path);
  return outer;
}

}  // namespace

// Round joins are flattened into chords whose vertices lie on the true arc. The default, 5 um, is far inside the
// finishing allowance that forbidden regions keep, and gives 99 vertices per full turn of a 10 mm radius instead of
// 222 at 1 um (offsets are most of roughing's time).
Region offsetRegion(const Region& given, double mm, double arc_tolerance) {
  if (given.empty()) return {};
  const Region region = outerRingsFirst(given);
  auto grow = [&](const Region& from) {
    ClipperLib::ClipperOffset offset(2.0, arc_tolerance * kRegionScale);
    offset.AddPaths(from, ClipperLib::jtRound, ClipperLib::etClosedPolygon);
    Region out;
    offset.Execute(out, mm * kRegionScale);
    return out;
  };
  Region out = grow(region);
  // The offset unites its pieces with a Clipper that may give up or turn rings over (see clip): a region grown to
  // nothing or ill-formed is retried with near vertices merged, then taken by the even-odd rule, and counted when
  // that does not help either.
  const bool lost = out.empty() && mm > 0 && regionArea(region) > 0;
  if (lost || !wellFormed(out)) {
    Region clean = region;
    ClipperLib::CleanPolygons(clean, 2.0);
    clean = outerRingsFirst(clean);
    out = grow(clean);
    if (!out.empty() && !wellFormed(out)) out = evenOdd(out);
    if ((out.empty() && lost) || !wellFormed(out)) RegionFailureTally::countFailure();
  }
  return out;
}

namespace {

// Squared distance (integer units) from p to segment a-b.
double segmentDistance2(const IntPoint& p, const IntPoint& a, const IntPoint& b) {
  const double abx = static_cast<double>(b.X - a.X), aby = static_cast<double>(b.Y - a.Y);
  const double apx = static_cast<double>(p.X - a.X), apy = static_cast<double>(p.Y - a.Y);
  const double len2 = abx * abx + aby * aby;
  const double t = len2 > 0 ? std::clamp((apx * abx + apy * aby) / len2, 0.0, 1.0) : 0.0;
  const double dx = apx - t * abx, dy = apy - t * aby;
  return dx * dx + dy * dy;
}

// Douglas-Peucker on the open chain path[from..to] (indices modulo n), marking the vertices kept.
void keepChain(const Path& path, std::size_t from, std::size_t to, double tolerance2, std::vector<char>& keep) {
  const std::size_t n = path.size();
  std::vector<std::pair<std::size_t, std::size_t>> stack{{from, to}};
  while (!stack.empty()) {
    const auto [a, b] = stack.back();
    stack.pop_back();
    double worst = -1;
    std::size_t at = a;
    for (std::size_t k = a + 1; k < b; ++k) {
      const double d = segmentDistance2(path[k % n], path[a % n], path[b % n]);
      if (d > worst) worst = d, at = k;
    }
    if (worst <= tolerance2) continue;
    keep[at % n] = 1;
    stack.push_back({a, at});
    stack.push_back({at, b});
  }
}

}  // namespace

Region simplifyRegion(const Region& region, double tolerance) {
  const double tolerance2 = tolerance * kRegionScale * tolerance * kRegionScale;
  Region out;
  out.reserve(region.size());
  for (const Path& path : region) {
    const std::size_t n = path.size();
    if (n <= 4) {
      out.push_back(path);
      continue;
    }
    // Anchors: vertex 0 and the vertex farthest from it; each chain between them simplified on its own.
    std::size_t far = 0;
    double far2 = -1;
    for (std::size_t k = 1; k < n; ++k) {
      const double dx = static_cast<double>(path[k].X - path[0].X), dy = static_cast<double>(path[k].Y - path[0].Y);
      if (dx * dx + dy * dy > far2) far2 = dx * dx + dy * dy, far = k;
    }
    std::vector<char> keep(n, 0);
    keep[0] = keep[far] = 1;
    keepChain(path, 0, far, tolerance2, keep);
    keepChain(path, far, n, tolerance2, keep);
    Path simple;
    for (std::size_t k = 0; k < n; ++k)
      if (keep[k]) simple.push_back(path[k]);
    // A ring within the tolerance of a segment stays; so does one that simplifying would turn over or cross itself
    // (its signed area changes sign or by more than its perimeter times the tolerance allows): an outer ring turned
    // over would cut a hole out of the region.
    const double before = ClipperLib::Area(path), after = simple.size() >= 3 ? ClipperLib::Area(simple) : 0;
    double perimeter = 0;
    for (std::size_t k = 0; k < n; ++k) {
      const IntPoint &a = path[k], &b = path[(k + 1) % n];
      perimeter += std::hypot(static_cast<double>(b.X - a.X), static_cast<double>(b.Y - a.Y));
    }
    const bool faithful = simple.size() >= 3 && (before > 0) == (after > 0) &&
                          std::abs(after - before) <= perimeter * tolerance * kRegionScale + 1;
    out.push_back(faithful ? std::move(simple) : path);
  }
  return out;
}

Region dropThinPieces(const Region& region, double half_width) {
  Region out;
  for (const RegionPiece& piece : regionPieces(region))
    if (!offsetRegion(piece.rings, -half_width).empty()) out.insert(out.end(), piece.rings.begin(), piece.rings.end());
  return out;
}

Region dropSlivers(const Region& region, double min_area_mm2) {
  Region out;
  for (const RegionPiece& piece : regionPieces(region))
    if (piece.area_mm2 >= min_area_mm2) out.insert(out.end(), piece.rings.begin(), piece.rings.end());
  return out;
}

Region fillSmallHoles(const Region& region, double max_area_mm2) {
  const double limit = max_area_mm2 * kRegionScale * kRegionScale;
  Region out;
  out.reserve(region.size());
  for (const Path& path : region) {
    const double area = ClipperLib::Area(path);
    if (area < 0 && -area < limit) continue;
    out.push_back(path);
  }
  return out;
}

double regionArea(const Region& region) {
  double area = 0;
  for (const Path& path : region) area += ClipperLib::Area(path);
  return area / (kRegionScale * kRegionScale);
}

bool regionEmpty(const Region& region) { return region.empty() || regionArea(region) <= 0; }

bool regionContains(const Region& region, const Point2& p) {
  const IntPoint q = toRegionPoint(p);
  int winding = 0;
  for (const Path& path : region) {
    const int in = ClipperLib::PointInPolygon(q, path);
    if (in == -1) return true;  // on a ring
    if (in == 1) winding += ClipperLib::Orientation(path) ? 1 : -1;
  }
  return winding > 0;
}

double regionDistance(const Region& region, const Point2& p) {
  if (regionContains(region, p)) return 0;
  double nearest = std::numeric_limits<double>::infinity();
  for (const Path& path : region)
    for (std::size_t i = 0; i < path.size(); ++i) {
      const Point2 a = fromRegionPoint(path[i]), b = fromRegionPoint(path[(i + 1) % path.size()]);
      const Point2 ab = b - a;
      const double t = ab.squaredNorm() > 0 ? std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0) : 0.0;
      nearest = std::min(nearest, (a + t * ab - p).squaredNorm());
    }
  return std::sqrt(nearest);
}

Region ringsMeeting(const Region& region, const Point2& lo, const Point2& hi) {
  const IntPoint a = toRegionPoint(lo), b = toRegionPoint(hi);
  Region out;
  for (const Path& path : region) {
    if (path.empty()) continue;
    IntPoint min = path[0], max = path[0];
    for (const IntPoint& p : path) {
      min.X = std::min(min.X, p.X), min.Y = std::min(min.Y, p.Y);
      max.X = std::max(max.X, p.X), max.Y = std::max(max.Y, p.Y);
    }
    if (max.X >= a.X && min.X <= b.X && max.Y >= a.Y && min.Y <= b.Y) out.push_back(path);
  }
  return out;
}

RegionLocator::RegionLocator(const Region& region) {
  std::size_t edges = 0;
  cInt lo = 0, hi = 0;
  bool first = true;
  for (const Path& path : region)
    for (const IntPoint& p : path) {
      lo = first ? p.Y : std::min(lo, p.Y);
      hi = first ? p.Y : std::max(hi, p.Y);
      first = false;
      ++edges;
    }
  if (edges == 0) return;
  // About eight edges a band where the edges spread evenly; a band is never thinner than 1 um.
  const std::size_t count = std::clamp<std::size_t>(edges / 8, 1, 4096);
  y0_ = lo;
  band_ = std::max<cInt>(10, (hi - lo) / static_cast<cInt>(count) + 1);
  bands_.resize(static_cast<std::size_t>((hi - lo) / band_) + 1);
  for (const Path& path : region) {
    const std::size_t n = path.size();
    for (std::size_t i = 0; i < n; ++i) {
      const Edge e{path[i], path[(i + 1) % n]};
      const std::size_t from = static_cast<std::size_t>((std::min(e.a.Y, e.b.Y) - y0_) / band_);
      const std::size_t to = static_cast<std::size_t>((std::max(e.a.Y, e.b.Y) - y0_) / band_);
      for (std::size_t k = from; k <= to; ++k) bands_[k].push_back(e);
    }
  }
}

bool RegionLocator::contains(const Point2& p) const {
  if (bands_.empty()) return false;
  const IntPoint q = toRegionPoint(p);
  if (q.Y < y0_ || (q.Y - y0_) / band_ >= static_cast<cInt>(bands_.size())) return false;
  int winding = 0;
  for (const Edge& e : bands_[static_cast<std::size_t>((q.Y - y0_) / band_)]) {
    if (std::max(e.a.X, e.b.X) < q.X || std::min(e.a.Y, e.b.Y) > q.Y || std::max(e.a.Y, e.b.Y) < q.Y) continue;
    // Which side of the edge q lies: > 0 left (seen along a -> b), 0 on its line.
    const __int128 side = static_cast<__int128>(e.b.X - e.a.X) * (q.Y - e.a.Y) -
                          static_cast<__int128>(q.X - e.a.X) * (e.b.Y - e.a.Y);
    if (side == 0 && std::min(e.a.X, e.b.X) <= q.X) return true;  // on the edge (within its box, on its line)
    if (e.a.Y <= q.Y && e.b.Y > q.Y && side > 0) ++winding;         // crosses the ray upwards, q on its left
    else if (e.a.Y > q.Y && e.b.Y <= q.Y && side < 0) --winding;    // downwards, q on its right
  }
  return winding > 0;
}

bool segmentInside(const Region& region, const Point2& a, const Point2& b) {
  if (!regionContains(region, a) || !regionContains(region, b)) return false;
  if (a == b) return true;
  // Cut a-b wherever it meets a ring (crossing it, touching a vertex, running along an edge): each piece between cuts
  // lies wholly inside or wholly outside, so its middle decides, unless the piece runs along an edge (the boundary).
  std::vector<double> cuts{0, 1};
  std::vector<std::pair<double, double>> on_boundary;
  const Point2 lo = a.cwiseMin(b), hi = a.cwiseMax(b);
  for (const Path& path : region) {
    const std::size_t n = path.size();
    for (std::size_t i = 0; i < n; ++i) {
      const Point2 p = fromRegionPoint(path[i]), q = fromRegionPoint(path[(i + 1) % n]);
      if (std::max(p.x(), q.x()) < lo.x() || std::min(p.x(), q.x()) > hi.x() || std::max(p.y(), q.y()) < lo.y() ||
          std::min(p.y(), q.y()) > hi.y())
        continue;
      bool along = false;
      const std::vector<double> ts = meetings(a, b, p, q, along);
      cuts.insert(cuts.end(), ts.begin(), ts.end());
      if (along) on_boundary.emplace_back(ts[0], ts[1]);
    }
  }
  std::sort(cuts.begin(), cuts.end());
  for (std::size_t i = 0; i + 1 < cuts.size(); ++i) {
    if (cuts[i + 1] - cuts[i] < 1e-12) continue;
    const double t = 0.5 * (cuts[i] + cuts[i + 1]);
    if (std::any_of(on_boundary.begin(), on_boundary.end(),
                    [t](const std::pair<double, double>& s) { return s.first <= t && t <= s.second; }))
      continue;
    if (!regionContains(region, a + t * (b - a))) return false;
  }
  return true;
}

std::vector<RegionPiece> regionPieces(const Region& region) {
  ClipperLib::Clipper clipper;
  clipper.AddPaths(region, ClipperLib::ptSubject, true);
  ClipperLib::PolyTree tree;
  clipper.Execute(ClipperLib::ctUnion, tree, ClipperLib::pftNonZero, ClipperLib::pftNonZero);
  std::vector<RegionPiece> pieces;
  // Outer rings are the nodes at even depth; their children are holes, whose children are outer rings again.
  std::vector<const ClipperLib::PolyNode*> stack(tree.Childs.begin(), tree.Childs.end());
  while (!stack.empty()) {
    const ClipperLib::PolyNode* outer = stack.back();
    stack.pop_back();
    RegionPiece piece;
    piece.rings.push_back(outer->Contour);
    double area = ClipperLib::Area(outer->Contour);
    for (const ClipperLib::PolyNode* hole : outer->Childs) {
      piece.rings.push_back(hole->Contour);
      area += ClipperLib::Area(hole->Contour);
      for (const ClipperLib::PolyNode* inner : hole->Childs) stack.push_back(inner);
    }
    piece.area_mm2 = area / (kRegionScale * kRegionScale);
    pieces.push_back(std::move(piece));
  }
  return pieces;
}

}  // namespace art2part
