// travelOrder against brute force: on small random instances every permutation from the first point is tried; the
// order found is a permutation from the first point, no 2-opt reversal shortens it, it is no longer than nearest
// neighbour, and within a margin of the optimum; on a grid of holes it finds the serpentine.
#include "art2part/geometry/travel_order.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <random>

using namespace art2part;

namespace {

double planar(const Vec3& d) { return d.head<2>().norm(); }  // across the axis, z

double pathLength(const std::vector<Vec3>& p, const std::vector<int>& order) {
  double length = 0;
  for (std::size_t k = 1; k < order.size(); ++k) length += planar(p[order[k]] - p[order[k - 1]]);
  return length;
}

double optimum(const std::vector<Vec3>& p) {
  std::vector<int> order(p.size());
  std::iota(order.begin(), order.end(), 0);
  double best = 1e300;
  do best = std::min(best, pathLength(p, order));
  while (std::next_permutation(order.begin() + 1, order.end()));
  return best;
}

double nearestNeighbour(const std::vector<Vec3>& p) {
  std::vector<int> order{0};
  std::vector<char> used(p.size(), 0);
  used[0] = 1;
  while (order.size() < p.size()) {
    int best = -1;
    for (int j = 0; j < static_cast<int>(p.size()); ++j)
      if (!used[j] && (best < 0 || planar(p[j] - p[order.back()]) < planar(p[best] - p[order.back()]))) best = j;
    used[best] = 1;
    order.push_back(best);
  }
  return pathLength(p, order);
}

}  // namespace

TEST(TravelOrder, NoReversalShortensItAndItIsNearTheOptimum) {
  std::mt19937 random(11);
  std::uniform_real_distribution<double> unit(0, 100);
  double worst = 0;
  for (int trial = 0; trial < 200; ++trial) {
    SCOPED_TRACE(trial);
    std::vector<Vec3> p;
    for (int k = 0; k < 3 + trial % 6; ++k) p.emplace_back(unit(random), unit(random), unit(random));  // z: the axis
    const std::vector<int> order = travelOrder(p, Vec3::UnitZ());
    ASSERT_EQ(order.size(), p.size());
    EXPECT_EQ(order.front(), 0);
    std::vector<int> sorted = order;
    std::sort(sorted.begin(), sorted.end());
    for (int k = 0; k < static_cast<int>(p.size()); ++k) EXPECT_EQ(sorted[k], k);
    const double length = pathLength(p, order);
    for (std::size_t i = 1; i + 1 < order.size(); ++i)
      for (std::size_t j = i + 1; j < order.size(); ++j) {
        std::vector<int> other = order;
        std::reverse(other.begin() + i, other.begin() + j + 1);
        EXPECT_GE(pathLength(p, other), length - 1e-3);
      }
    EXPECT_LE(length, nearestNeighbour(p) + 1e-9);
    const double best = optimum(p);
    EXPECT_LE(length, 1.3 * best);
    worst = std::max(worst, length / best);
  }
  std::printf("worst ratio to the optimum over 200 instances of 3-8 points: %.3f\n", worst);
}

TEST(TravelOrder, AGridOfHolesIsASerpentine) {
  // 4 rows of 10 holes 10 mm apart, listed column by column from alternate rows (as faces came): the least travel
  // from the first is 39 steps of 10 mm.
  std::vector<Vec3> p;
  for (int i = 0; i < 10; ++i)
    for (int j : {0, 3, 1, 2}) p.emplace_back(10.0 * i, 10.0 * j, 5.0 * (i % 2));
  const std::vector<int> order = travelOrder(p, Vec3::UnitZ());
  EXPECT_NEAR(pathLength(p, order), 390, 1e-6);
  EXPECT_TRUE(travelOrder({}, Vec3::UnitZ()).empty());
}
