#include "art2part/geometry/travel_order.h"

#include <algorithm>

namespace art2part {

namespace {

constexpr double kShorter = 1e-3;  // mm a reversal must gain: no endless trading of rounding

}  // namespace

std::vector<int> travelOrder(const std::vector<Vec3>& points, const Vec3& axis) {
  const int n = static_cast<int>(points.size());
  if (n == 0) return {};
  const Vec3 a = axis.normalized();
  std::vector<Vec3> flat;
  flat.reserve(points.size());
  for (const Vec3& p : points) flat.push_back(p - p.dot(a) * a);
  auto dist = [&](int i, int j) { return (flat[i] - flat[j]).norm(); };

  std::vector<int> order{0};
  std::vector<char> used(n, 0);
  used[0] = 1;
  for (int k = 1; k < n; ++k) {
    int best = -1;
    for (int j = 0; j < n; ++j)
      if (!used[j] && (best < 0 || dist(order.back(), j) < dist(order.back(), best))) best = j;
    used[best] = 1;
    order.push_back(best);
  }
  // 2-opt on the open path: edges (i-1, i) and (j, j+1) become (i-1, j) and (i, j+1) by reversing order[i..j]; with
  // j the last point there is no edge after it, and the reversal only changes the one edge before.
  for (bool improved = true; improved;) {
    improved = false;
    for (int i = 1; i + 1 < n; ++i)
      for (int j = i + 1; j < n; ++j) {
        const int p = order[i - 1], q = order[i], r = order[j];
        const double before = dist(p, q) + (j + 1 < n ? dist(r, order[j + 1]) : 0.0);
        const double after = dist(p, r) + (j + 1 < n ? dist(q, order[j + 1]) : 0.0);
        if (after < before - kShorter) {
          std::reverse(order.begin() + i, order.begin() + j + 1);
          improved = true;
        }
      }
  }
  return order;
}

}  // namespace art2part
