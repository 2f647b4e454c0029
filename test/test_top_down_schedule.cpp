// TopDownSchedule against a plain reading of its rule: on random boxes at random depths, every item is handed out
// once; no item comes before a shallower one whose box lies within the reach (checked over all pairs, not the
// schedule's sweep); and each hand-out is the nearest of the items ready at that moment by the caller's distance
// (found by scanning them all, without the box bound the schedule prunes with).
#include "art2part/geometry/top_down_schedule.h"

#include <gtest/gtest.h>

#include <random>

using namespace art2part;
using Eigen::Vector2d;

namespace {

bool withinReach(const ScheduledItem& a, const ScheduledItem& b, double reach) {
  return !((a.lo.array() > b.hi.array() + reach).any() || (b.lo.array() > a.hi.array() + reach).any());
}

// The distance a caller might give: to the box's far corner from the tool (never less than the box's distance).
double farCorner(const ScheduledItem& item, const Vector2d& at) {
  return (item.lo - at).cwiseAbs().cwiseMax((item.hi - at).cwiseAbs()).norm();
}

}  // namespace

TEST(TopDownSchedule, EveryItemComesAfterTheShallowerOnesWithinReachAndIsTheNearestReady) {
  std::mt19937 random(11);
  std::uniform_real_distribution<double> unit(0, 1);
  int waiting_pairs = 0;
  for (int trial = 0; trial < 40; ++trial) {
    SCOPED_TRACE(trial);
    std::vector<ScheduledItem> items(5 + random() % 60);
    for (ScheduledItem& item : items) {
      item.depth = static_cast<double>(random() % 5);
      item.lo = Vector2d(200 * unit(random), 200 * unit(random));
      item.hi = item.lo + Vector2d(40 * unit(random), 10 * unit(random));
    }
    const double reach = 15 * unit(random);
    TopDownSchedule schedule(items, reach);
    std::vector<bool> taken(items.size(), false);
    Vector2d at(100, 100);
    auto ready = [&](std::size_t i) {
      if (taken[i]) return false;
      for (std::size_t j = 0; j < items.size(); ++j)
        if (!taken[j] && items[j].depth < items[i].depth && withinReach(items[i], items[j], reach)) return false;
      return true;
    };
    for (std::size_t k = 0; k < items.size(); ++k) {
      double nearest = 1e300;
      for (std::size_t i = 0; i < items.size(); ++i)
        if (ready(i)) nearest = std::min(nearest, farCorner(items[i], at));
      const std::size_t got = schedule.next(at, [&](std::size_t i) { return farCorner(items[i], at); });
      ASSERT_LT(got, items.size());
      ASSERT_TRUE(ready(got)) << "handed out before a shallower item within reach";
      EXPECT_DOUBLE_EQ(farCorner(items[got], at), nearest);
      for (std::size_t j = 0; j < items.size(); ++j)
        if (!taken[j] && j != got && items[got].depth < items[j].depth && withinReach(items[got], items[j], reach))
          ++waiting_pairs;
      taken[got] = true;
      at = items[got].hi;
    }
    EXPECT_EQ(schedule.next(at, [&](std::size_t i) { return farCorner(items[i], at); }), items.size());
  }
  EXPECT_GT(waiting_pairs, 100);  // the rule was exercised, not vacuous
}

// The first hand-out is the first ready item in the given order; items of one depth never wait for each other.
TEST(TopDownSchedule, FirstIsTheFirstReadyAndOneDepthNeverWaits) {
  std::vector<ScheduledItem> items{{1, {0, 0}, {10, 10}}, {0, {5, 5}, {20, 20}}, {0, {0, 0}, {10, 10}}};
  TopDownSchedule schedule(items, 5);
  EXPECT_EQ(schedule.first(), 1u);  // item 0 waits for both depth-0 items over it
  EXPECT_EQ(schedule.first(), 2u);
  EXPECT_EQ(schedule.first(), 0u);
  EXPECT_EQ(schedule.first(), 3u);
}
