// Points hashed on a square grid, for "is any of them within r of p" queries with r at most the cell (finishing's
// internal helper, not part of the library's interface).
#pragma once

#include <cmath>
#include <unordered_map>
#include <vector>

#include "art2part/roughing/region.h"

namespace art2part::finishing_detail {

class PointGrid {
 public:
  PointGrid(const std::vector<Point2>& points, double cell) : cell_(cell) {
    for (const Point2& p : points) cells_[key(cellOf(p.x()), cellOf(p.y()))].push_back(p);
  }
  // Some point lies within r (<= the cell) of p.
  bool anyWithin(const Point2& p, double r) const {
    const long i = cellOf(p.x()), j = cellOf(p.y());
    for (long a = i - 1; a <= i + 1; ++a)
      for (long b = j - 1; b <= j + 1; ++b) {
        const auto it = cells_.find(key(a, b));
        if (it == cells_.end()) continue;
        for (const Point2& q : it->second)
          if ((q - p).squaredNorm() <= r * r) return true;
      }
    return false;
  }

 private:
  long cellOf(double v) const { return static_cast<long>(std::floor(v / cell_)); }
  static long long key(long i, long j) {
    return (static_cast<long long>(i) << 32) ^ static_cast<long long>(static_cast<unsigned long>(j) & 0xffffffffUL);
  }
  double cell_;
  std::unordered_map<long long, std::vector<Point2>> cells_;
};

}  // namespace art2part::finishing_detail
