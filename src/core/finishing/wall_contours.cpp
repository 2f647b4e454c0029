// The stretches of the allowed region's rings that run along walls to finish (planar_finishing.h).
#include <algorithm>
#include <cmath>

#include "art2part/finishing/planar_finishing.h"
#include "point_grid.h"

namespace art2part {

namespace {

using finishing_detail::PointGrid;

// The ring with its vertices spread at most `spacing` apart, and each point's arc length from the first.
struct DenseRing {
  std::vector<Point2> points;
  std::vector<double> at;  // arc length of each point from points[0]
  double perimeter = 0;
};

DenseRing densify(const Ring& ring, double spacing) {
  DenseRing d;
  const std::size_t n = ring.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Point2& a = ring[i];
    const Point2& b = ring[(i + 1) % n];
    const double length = (b - a).norm();
    const int pieces = std::max(1, static_cast<int>(std::ceil(length / spacing)));
    for (int k = 0; k < pieces; ++k) {
      d.points.push_back(a + (b - a) * (static_cast<double>(k) / pieces));
      d.at.push_back(d.perimeter + length * k / pieces);
    }
    d.perimeter += length;
  }
  return d;
}

// Arc length from point i forwards to point j (cyclic).
double forward(const DenseRing& d, std::size_t i, std::size_t j) {
  const double s = d.at[j] - d.at[i];
  return s >= 0 ? s : s + d.perimeter;
}

}  // namespace

std::vector<ContourStretch> contourStretches(const Region& allowed, const std::vector<Point2>& targets, double reach,
                                             double link_gap, double lead, double spacing) {
  std::vector<ContourStretch> out;
  if (targets.empty() || allowed.empty()) return out;
  const PointGrid grid(targets, std::max(reach, 1e-3));
  for (Ring ring : regionRings(allowed)) {
    if (ring.size() < 3) continue;
    const DenseRing d = densify(ring, spacing);
    const std::size_t n = d.points.size();
    std::vector<char> near(n);
    std::size_t count = 0;
    for (std::size_t i = 0; i < n; ++i) count += (near[i] = grid.anyWithin(d.points[i], reach)) ? 1 : 0;
    if (count == 0) continue;
    // Start the walk at a point that is not near (there is one unless the whole ring is).
    std::size_t start = 0;
    while (start < n && near[start]) ++start;
    if (start == n) {
      out.push_back({d.points, true});
      continue;
    }
    // Runs of near points in walking order, as [first, last] index pairs.
    std::vector<std::pair<std::size_t, std::size_t>> runs;
    for (std::size_t k = 0; k < n; ++k) {
      const std::size_t i = (start + k) % n;
      if (!near[i]) continue;
      if (!runs.empty() && runs.back().second == (i + n - 1) % n) runs.back().second = i;
      else runs.push_back({i, i});
    }
    // Bridge short gaps between consecutive runs (and between the last and the first, round the ring).
    std::vector<std::pair<std::size_t, std::size_t>> merged;
    for (const auto& run : runs) {
      if (!merged.empty() && forward(d, merged.back().second, run.first) < link_gap) merged.back().second = run.second;
      else merged.push_back(run);
    }
    if (merged.size() > 1 && forward(d, merged.back().second, merged.front().first) < link_gap) {
      merged.front().first = merged.back().first;
      merged.pop_back();
    }
    double covered = 0;
    for (const auto& run : merged) covered += forward(d, run.first, run.second) + 2 * lead;
    if (merged.size() == 1 && covered >= 0.95 * d.perimeter) {
      // Nearly the whole ring: cut it all, from the middle of the gap so the seam lies off the walls.
      std::vector<Point2> all;
      const std::size_t from = (merged[0].second + (forward(d, merged[0].second, merged[0].first) > 0 ? 1 : 0)) % n;
      for (std::size_t k = 0; k < n; ++k) all.push_back(d.points[(from + k) % n]);
      out.push_back({all, true});
      continue;
    }
    for (const auto& run : merged) {
      // Walk back `lead` from the first point and on `lead` past the last.
      std::size_t first = run.first, last = run.second;
      for (double back = 0; back < lead;) {
        const std::size_t p = (first + n - 1) % n;
        if (p == last) break;
        back += forward(d, p, first);
        first = p;
      }
      for (double on = 0; on < lead;) {
        const std::size_t q = (last + 1) % n;
        if (q == first) break;
        on += forward(d, last, q);
        last = q;
      }
      ContourStretch s;
      for (std::size_t i = first;; i = (i + 1) % n) {
        s.points.push_back(d.points[i]);
        if (i == last) break;
      }
      if (s.points.size() >= 2) out.push_back(std::move(s));
    }
  }
  return out;
}

}  // namespace art2part
