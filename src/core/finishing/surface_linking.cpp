// The order of the passes (waterline nearest next from the top, raster zig-zag), joins along the CL surface, and 3-axis links.
#include <algorithm>
#include <cmath>

#include "surface_passes.h"

namespace art2part::surface {

namespace {

double distanceXY(const Vec3& a, const Vec3& b) { return std::hypot(b.x() - a.x(), b.y() - a.y()); }

// The CL points strictly between a and b along the CL surface, when the link is short, stays in the region and the
// body clears all along it (true); false otherwise.
bool surfaceLink(const Context& ctx, const Vec3& a, const Vec3& b, std::vector<Vec3>& between) {
  if (distanceXY(a, b) > ctx.feed_link) return false;
  std::vector<Vec3> link{a};
  followSurface(ctx, a, b, link);
  for (const Vec3& p : link)
    if (!ctx.inRegion(p.x(), p.y()) || !ctx.bodyClear(p)) return false;
  link = thin(link, ctx.gouge_tolerance, ctx.leave_tolerance, false);
  between.assign(link.begin() + 1, link.end() - 1);
  return true;
}

struct Builder {
  const Context& ctx;
  Ordered out;
  Pass current;
  bool have = false;
  Vec3 position = Vec3::Zero();  // where the tool is: the end of the last pass

  void emit() {
    if (current.points.size() >= 2) out.passes.push_back(std::move(current));
    current = Pass{};
  }

  // Appends a pass (already oriented): joined to the current one along the CL surface when allowed.
  void append(const Pass& pass) {
    if (pass.points.size() < 2) return;
    if (!current.points.empty()) {
      std::vector<Vec3> link;
      if (surfaceLink(ctx, current.points.back(), pass.points.front(), link)) {
        current.points.insert(current.points.end(), link.begin(), link.end());
        current.points.insert(current.points.end(), pass.points.begin(), pass.points.end());
        position = current.points.back();
        return;
      }
      emit();
    }
    current = pass;
    current.closed = false;
    position = current.points.back();
    have = true;
  }
};

// A loop (last point = first) started at its point nearest to `from`.
Pass rotatedLoop(const Pass& loop, const Vec3& from) {
  const std::vector<Vec3>& p = loop.points;
  std::size_t best = 0;
  for (std::size_t k = 0; k + 1 < p.size(); ++k)
    if (distanceXY(p[k], from) < distanceXY(p[best], from)) best = k;
  Pass out;
  out.points.assign(p.begin() + best, p.end() - 1);
  out.points.insert(out.points.end(), p.begin(), p.begin() + best + 1);
  return out;
}

// Waterline contours by where they may start (every point of a loop, an open contour's first, and its last when it
// may be cut either way), bucketed on a square grid, for the next contour from a point: the nearest by x-y distance to
// a start plus the height between (the contour below on a wall is nearer than the next one across the part at the
// same level).
class ContourIndex {
 public:
  ContourIndex(const std::vector<const Pass*>& contours, bool both_ways)
      : contours_(contours), both_ways_(both_ways), done_(contours.size(), 0) {
    Box box;
    for (const Pass* c : contours)
      for (const Vec3& p : c->points) box.extend(p);
    if (box.empty()) return;
    x0_ = box.min.x();
    y0_ = box.min.y();
    cell_ = std::max({kMinCell, (box.max.x() - x0_) / kCellsAcross, (box.max.y() - y0_) / kCellsAcross});
    nx_ = static_cast<int>((box.max.x() - x0_) / cell_) + 1;
    ny_ = static_cast<int>((box.max.y() - y0_) / cell_) + 1;
    cells_.resize(static_cast<std::size_t>(nx_) * ny_);
    seen_.assign(contours.size(), 0);
    for (int k = 0; k < static_cast<int>(contours.size()); ++k)
      forStarts(*contours[k], [&](const Vec3& p) {
        std::vector<int>& in = cells_[cellOf(p)];
        if (in.empty() || in.back() != k) in.push_back(k);
      });
  }
  void take(int k) { done_[k] = 1; }
  // The nearest contour not taken (there must be one).
  int nearest(const Vec3& from) {
    ++stamp_;
    const int ci = column(from.x()), cj = row(from.y());
    int best = -1;
    double best_d = kInf;
    for (int ring = 0; ring <= std::max(nx_, ny_); ++ring) {
      if (best >= 0 && (ring - 1) * cell_ > best_d) break;  // every start in this ring is farther in x-y alone
      for (int j = cj - ring; j <= cj + ring; ++j) {
        if (j < 0 || j >= ny_) continue;
        const bool edge_row = j == cj - ring || j == cj + ring;
        for (int i = ci - ring; i <= ci + ring; i += edge_row ? 1 : 2 * std::max(ring, 1)) {
          if (i < 0 || i >= nx_) continue;
          for (int k : cells_[static_cast<std::size_t>(j) * nx_ + i]) {
            if (done_[k] || seen_[k] == stamp_) continue;
            seen_[k] = stamp_;
            const double d = distance(*contours_[k], from);
            if (d < best_d) best_d = d, best = k;
          }
        }
      }
    }
    return best;
  }

 private:
  static constexpr double kMinCell = 1.0;        // mm
  static constexpr double kCellsAcross = 256.0;  // the grid's cells along the longer side, at most
  int column(double x) const { return std::clamp(static_cast<int>((x - x0_) / cell_), 0, nx_ - 1); }
  int row(double y) const { return std::clamp(static_cast<int>((y - y0_) / cell_), 0, ny_ - 1); }
  std::size_t cellOf(const Vec3& p) const { return static_cast<std::size_t>(row(p.y())) * nx_ + column(p.x()); }
  template <class Visit>
  void forStarts(const Pass& c, Visit visit) const {
    if (c.closed) {
      for (const Vec3& p : c.points) visit(p);
      return;
    }
    visit(c.points.front());
    if (both_ways_) visit(c.points.back());
  }
  double distance(const Pass& c, const Vec3& from) const {
    double d = kInf;
    forStarts(c, [&](const Vec3& p) { d = std::min(d, distanceXY(p, from)); });
    return d + std::abs(c.points.front().z() - from.z());
  }
  const std::vector<const Pass*>& contours_;
  bool both_ways_ = false;
  std::vector<char> done_;
  std::vector<int> seen_;
  int stamp_ = 0;
  double x0_ = 0, y0_ = 0, cell_ = 1;
  int nx_ = 0, ny_ = 0;
  std::vector<std::vector<int>> cells_;
};

}  // namespace

Ordered orderPasses(const Context& ctx, const std::vector<std::vector<Pass>>& levels,
                    const std::vector<std::vector<Pass>>& rows) {
  Builder b{ctx, {}, {}, false, Vec3::Zero()};
  // Waterline: from the top, the nearest contour next whatever its level (down a feature before across the part).
  std::vector<const Pass*> contours;
  for (const std::vector<Pass>& level : levels) {
    if (!level.empty()) ++b.out.levels;
    for (const Pass& pass : level)
      if (!pass.points.empty()) contours.push_back(&pass);
  }
  ContourIndex index(contours, ctx.contours_both_ways);
  for (std::size_t n = 0; n < contours.size(); ++n) {
    const int next = b.have ? index.nearest(b.position) : 0;
    index.take(next);
    ++b.out.contours;
    const Pass& pass = *contours[next];
    if (pass.closed && b.have) {
      b.append(rotatedLoop(pass, b.position));
    } else if (ctx.contours_both_ways && b.have &&
               distanceXY(pass.points.back(), b.position) < distanceXY(pass.points.front(), b.position)) {
      Pass reversed = pass;
      std::reverse(reversed.points.begin(), reversed.points.end());
      b.append(reversed);
    } else {
      b.append(pass);
    }
  }
  // Raster: from the lowest row with runs left, zig-zag upwards through the run nearest the last end.
  std::vector<std::vector<bool>> done(rows.size());
  for (std::size_t r = 0; r < rows.size(); ++r) done[r].assign(rows[r].size(), false);
  auto oriented = [&](const Pass& run) {
    if (!b.have || distanceXY(run.points.front(), b.position) <= distanceXY(run.points.back(), b.position)) return run;
    Pass reversed = run;
    std::reverse(reversed.points.begin(), reversed.points.end());
    return reversed;
  };
  auto nearestRun = [&](std::size_t r, double limit) {
    std::size_t best = rows[r].size();
    double best_d = limit;
    for (std::size_t k = 0; k < rows[r].size(); ++k) {
      if (done[r][k]) continue;
      const double d = b.have ? std::min(distanceXY(rows[r][k].points.front(), b.position),
                                         distanceXY(rows[r][k].points.back(), b.position))
                              : 0;
      if (d <= best_d) best_d = d, best = k;
      if (!b.have) break;  // the first run of the row
    }
    return best;
  };
  for (std::size_t start = 0; start < rows.size();) {
    const std::size_t k = nearestRun(start, kInf);
    if (k == rows[start].size()) {
      ++start;
      continue;
    }
    std::size_t r = start;
    std::size_t run = k;
    while (true) {
      done[r][run] = true;
      ++b.out.raster_runs;
      b.append(oriented(rows[r][run]));
      if (r + 1 >= rows.size()) break;
      const std::size_t next = nearestRun(r + 1, ctx.feed_link);
      if (next == rows[r + 1].size()) break;
      ++r;
      run = next;
    }
  }
  b.emit();
  return b.out;
}

Linked link3Axis(const Context& ctx, const std::vector<Pass>& passes, double short_link, double link_margin,
                 double clearance_z) {
  Linked out;
  auto push = [&](const Vec3& p, MoveKind kind) { out.moves.push_back(Move{p, kind}); };
  // The height above a point where the tool clears the part grown by the skin, and its body the grown part.
  auto lift = [&](const Vec3& p) { return std::min(clearance_z, std::max(p.z(), ctx.safe.at(p.x(), p.y()) + link_margin)); };
  auto above = [](const Vec3& p, double z) { return Vec3(p.x(), p.y(), z); };
  for (std::size_t n = 0; n < passes.size(); ++n) {
    const Vec3& s = passes[n].points.front();
    const double ls = lift(s);
    if (n == 0) {
      push(above(s, clearance_z), MoveKind::Rapid);
    } else {
      const Vec3& e = passes[n - 1].points.back();
      const double le = lift(e);
      if (le > e.z()) push(above(e, le), MoveKind::Feed);
      const double over = std::max({ctx.safe.along(e, s) + link_margin, le, ls});
      if (distanceXY(e, s) <= short_link && over < clearance_z) {
        if (over > le) push(above(e, over), MoveKind::Rapid);
        push(above(s, over), MoveKind::Rapid);
      } else {
        push(above(e, clearance_z), MoveKind::Rapid);
        push(above(s, clearance_z), MoveKind::Rapid);
        ++out.retracts;
      }
    }
    if (out.moves.back().p.z() > ls) push(above(s, ls), MoveKind::Rapid);
    push(s, MoveKind::Feed);
    for (std::size_t k = 1; k < passes[n].points.size(); ++k) push(passes[n].points[k], MoveKind::Feed);
  }
  if (!passes.empty()) {
    const Vec3& e = passes.back().points.back();
    const double le = lift(e);
    if (le > e.z()) push(above(e, le), MoveKind::Feed);
    push(above(e, clearance_z), MoveKind::Rapid);
  }
  return out;
}

}  // namespace art2part::surface
