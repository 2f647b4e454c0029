// TopDownSchedule against a plain reading of its rule: on random boxes at random depths, with one reach for every pair
// or a reach per pair, every item is handed out once; no item comes before a shallower one whose box lies within the
// reach (checked over all pairs, not the schedule's sweep); and each hand-out is the nearest of the items ready at that
// moment by the caller's distance (found by scanning them all, without the box bound the schedule prunes with).
// shortenedOrder (ordered_tour.h) on the schedule's orders: it keeps the rule (the same plain reading), never lengthens
// the travel, and no single move of a run it tries is left that would shorten it (every move tried by brute force).
#include "art2part/geometry/top_down_schedule.h"
#include "art2part/geometry/ordered_tour.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <limits>
#include <optional>
#include <stdexcept>

using namespace art2part;
using Eigen::Vector2d;

namespace {

bool withinReach(const ScheduledItem& a, const ScheduledItem& b, double reach) {
  return !((a.lo.array() > b.hi.array() + reach).any() || (b.lo.array() > a.hi.array() + reach).any());
}

// A reach per pair as roughing gives one: wider the farther the shallower item lies above the deeper (a body widening
// up the tool), `base` at one depth apart.
double depthReach(const ScheduledItem& shallower, const ScheduledItem& deeper, double base) {
  return base * (0.5 + 0.5 * std::abs(deeper.depth - shallower.depth));
}
constexpr double kMostDepths = 5;  // depths 0 to 4: the widest depthReach is base x (0.5 + 0.5 x 4)

// The distance a caller might give: to the box's far corner from the tool (never less than the box's distance).
double farCorner(const ScheduledItem& item, const Vector2d& at) {
  return (item.lo - at).cwiseAbs().cwiseMax((item.hi - at).cwiseAbs()).norm();
}

}  // namespace

class TopDownScheduleReach : public testing::TestWithParam<bool> {};  // true: a reach per pair (depthReach)

TEST_P(TopDownScheduleReach, EveryItemComesAfterTheShallowerOnesWithinReachAndIsTheNearestReady) {
  const bool per_pair = GetParam();
  std::mt19937 random(11);
  std::uniform_real_distribution<double> unit(0, 1);
  int waiting_pairs = 0;
  for (int trial = 0; trial < 40; ++trial) {
    SCOPED_TRACE(trial);
    std::vector<ScheduledItem> items(5 + random() % 60);
    for (ScheduledItem& item : items) {
      item.depth = static_cast<double>(random() % static_cast<int>(kMostDepths));
      item.lo = Vector2d(200 * unit(random), 200 * unit(random));
      item.hi = item.lo + Vector2d(40 * unit(random), 10 * unit(random));
    }
    const double base = 15 * unit(random);
    const double most = per_pair ? base * (0.5 + 0.5 * (kMostDepths - 1)) : base;
    auto reach = [&](const ScheduledItem& shallower, const ScheduledItem& deeper) {
      return per_pair ? depthReach(shallower, deeper, base) : base;
    };
    TopDownSchedule schedule = per_pair ? TopDownSchedule(items, most, reach) : TopDownSchedule(items, base);
    std::vector<bool> taken(items.size(), false);
    Vector2d at(100, 100);
    auto ready = [&](std::size_t i) {
      if (taken[i]) return false;
      for (std::size_t j = 0; j < items.size(); ++j)
        if (!taken[j] && items[j].depth < items[i].depth && withinReach(items[i], items[j], reach(items[j], items[i])))
          return false;
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
        if (!taken[j] && j != got && items[got].depth < items[j].depth &&
            withinReach(items[got], items[j], reach(items[got], items[j])))
          ++waiting_pairs;
      taken[got] = true;
      at = items[got].hi;
    }
    EXPECT_EQ(schedule.next(at, [&](std::size_t i) { return farCorner(items[i], at); }), items.size());
  }
  EXPECT_GT(waiting_pairs, 100);  // the rule was exercised, not vacuous
}

INSTANTIATE_TEST_SUITE_P(OneOrPerPair, TopDownScheduleReach, testing::Bool());

// The first hand-out is the first ready item in the given order; items of one depth never wait for each other.
TEST(TopDownSchedule, FirstIsTheFirstReadyAndOneDepthNeverWaits) {
  std::vector<ScheduledItem> items{{1, {0, 0}, {10, 10}}, {0, {5, 5}, {20, 20}}, {0, {0, 0}, {10, 10}}};
  TopDownSchedule schedule(items, 5);
  EXPECT_EQ(schedule.first(), 1u);  // item 0 waits for both depth-0 items over it
  EXPECT_EQ(schedule.first(), 2u);
  EXPECT_EQ(schedule.first(), 0u);
  EXPECT_EQ(schedule.first(), 3u);
}

namespace {

// Whether `order` puts every item after the shallower ones within the reach (a plain reading, all pairs).
bool keepsTheRule(const std::vector<ScheduledItem>& items, const std::vector<std::size_t>& order, double reach) {
  std::vector<bool> done(items.size(), false);
  for (std::size_t i : order) {
    for (std::size_t j = 0; j < items.size(); ++j)
      if (!done[j] && items[j].depth < items[i].depth && withinReach(items[i], items[j], reach)) return false;
    done[i] = true;
  }
  return true;
}

// The travel of `order`, summed here (not by tourTravel).
double travelOf(const std::vector<TourStop>& stops, const std::vector<std::size_t>& order) {
  double travel = 0;
  for (std::size_t k = 1; k < order.size(); ++k) {
    const Eigen::Vector3d d = stops[order[k]].entry - stops[order[k - 1]].exit;
    travel += std::sqrt(d.x() * d.x() + d.y() * d.y() + d.z() * d.z());
  }
  return travel;
}

}  // namespace

TEST(OrderedTour, ShortensTheScheduleOrderKeepingItsRuleUntilNoRunMoveHelps) {
  std::mt19937 random(5);
  std::uniform_real_distribution<double> unit(0, 1);
  double before = 0, after = 0;
  int moves_tried = 0;
  for (int trial = 0; trial < 25; ++trial) {
    SCOPED_TRACE(trial);
    std::vector<ScheduledItem> items(4 + random() % 30);
    std::vector<TourStop> stops;
    for (ScheduledItem& item : items) {
      item.depth = static_cast<double>(random() % 4);
      item.lo = Vector2d(150 * unit(random), 150 * unit(random));
      item.hi = item.lo + Vector2d(30 * unit(random), 12 * unit(random));
      auto inBox = [&]() {
        const Vector2d p = item.lo + (item.hi - item.lo).cwiseProduct(Vector2d(unit(random), unit(random)));
        return Eigen::Vector3d(p.x(), p.y(), -5 * item.depth);
      };
      stops.push_back({inBox(), inBox()});
    }
    const double reach = 20 * unit(random);
    TopDownSchedule schedule(items, reach);
    std::vector<std::size_t> order;
    Vector2d at(0, 0);
    for (std::size_t k = 0; k < items.size(); ++k) {
      order.push_back(schedule.next(at, [&](std::size_t i) { return farCorner(items[i], at); }));
      at = stops[order.back()].exit.head<2>();
    }
    const std::vector<std::size_t> shorter = shortenedOrder(stops, order, schedule.waitsFor());
    std::vector<std::size_t> sorted = shorter;
    std::sort(sorted.begin(), sorted.end());
    for (std::size_t i = 0; i < sorted.size(); ++i) ASSERT_EQ(sorted[i], i) << "not a permutation";
    EXPECT_TRUE(keepsTheRule(items, shorter, reach));
    const double travel = travelOf(stops, shorter);
    EXPECT_NEAR(tourTravel(stops, shorter), travel, 1e-9);
    EXPECT_LE(travel, travelOf(stops, order) + 1e-9);
    before += travelOf(stops, order);
    after += travel;
    // Every run of up to kOrOptRun stops moved to every other gap: none that keeps the rule is shorter by more than
    // kOrOptGainMm.
    const std::size_t n = shorter.size();
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t length = 1; length <= kOrOptRun && i + length <= n; ++length)
        for (std::size_t gap = 0; gap <= n - length; ++gap) {
          std::vector<std::size_t> rest(shorter.begin(), shorter.begin() + static_cast<std::ptrdiff_t>(i));
          rest.insert(rest.end(), shorter.begin() + static_cast<std::ptrdiff_t>(i + length), shorter.end());
          std::vector<std::size_t> moved = rest;
          moved.insert(moved.begin() + static_cast<std::ptrdiff_t>(gap),
                       shorter.begin() + static_cast<std::ptrdiff_t>(i),
                       shorter.begin() + static_cast<std::ptrdiff_t>(i + length));
          if (moved == shorter || !keepsTheRule(items, moved, reach)) continue;
          ++moves_tried;
          EXPECT_GE(travelOf(stops, moved), travel - kOrOptGainMm - 1e-9) << "a run move left that shortens it";
        }
  }
  EXPECT_GT(moves_tried, 1000);
  EXPECT_LT(after, 0.95 * before);  // nearest first leaves stops behind that or-opt picks up on the way
}

// A stop left behind on a line is moved to where it lies on the way, but no earlier than the stop it waits for.
TEST(OrderedTour, AStopLeftBehindGoesOnTheWayAfterTheStopItWaitsFor) {
  std::vector<TourStop> stops;
  for (const double x : {0.0, 10.0, 20.0, 30.0, 40.0, 15.0})
    stops.push_back({Eigen::Vector3d(x, 0, 0), Eigen::Vector3d(x, 0, 0)});
  std::vector<std::vector<std::size_t>> waits(stops.size());
  const std::vector<std::size_t> order{0, 1, 2, 3, 4, 5};
  EXPECT_EQ(shortenedOrder(stops, order, waits), (std::vector<std::size_t>{0, 1, 5, 2, 3, 4}));
  waits[5] = {2};  // the stop at 15 must come after the one at 20
  EXPECT_EQ(shortenedOrder(stops, order, waits), (std::vector<std::size_t>{0, 1, 2, 5, 3, 4}));
}

TEST(OrderedTour, RejectsAnOrderThatIsNoPermutationOrBreaksTheRule) {
  const std::vector<TourStop> stops(3);
  const std::vector<std::vector<std::size_t>> waits{{}, {0}, {}};
  EXPECT_THROW(shortenedOrder(stops, {0, 1}, waits), std::invalid_argument);
  EXPECT_THROW(shortenedOrder(stops, {0, 1, 1}, waits), std::invalid_argument);
  EXPECT_THROW(shortenedOrder(stops, {1, 0, 2}, waits), std::invalid_argument);
  EXPECT_THROW(shortenedOrder(stops, {0, 1, 2}, {{}, {0}}), std::invalid_argument);
  EXPECT_NO_THROW(shortenedOrder(stops, {2, 0, 1}, waits));
}

namespace {

// The least travel over every order of `stops` from `start` (none: from the first entry), by trying them all.
double bruteForceLeast(const std::vector<TourStop>& stops, const std::optional<Eigen::Vector3d>& start) {
  std::vector<std::size_t> order(stops.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  double least = std::numeric_limits<double>::infinity();
  do {
    double travel = tourTravel(stops, order);
    if (start) travel += (*start - stops[order.front()].entry).norm();
    least = std::min(least, travel);
  } while (std::next_permutation(order.begin(), order.end()));
  return least;
}

double travelFromStart(const std::vector<TourStop>& stops, const std::vector<std::size_t>& order,
                       const std::optional<Eigen::Vector3d>& start) {
  double travel = tourTravel(stops, order);
  if (start && !order.empty()) travel += (*start - stops[order.front()].entry).norm();
  return travel;
}

bool isPermutation(std::vector<std::size_t> order, std::size_t n) {
  std::sort(order.begin(), order.end());
  for (std::size_t i = 0; i < order.size(); ++i)
    if (order[i] != i) return false;
  return order.size() == n;
}

}  // namespace

// A setup's operations with one tool: the order found travels as little as the best of every order (exact up to
// kExactTourStops stops), from where the tool is or from anywhere.
TEST(LeastTravelOrder, MatchesEveryOrderTriedOnRandomStops) {
  std::mt19937 rng(19);
  std::uniform_real_distribution<double> coord(-100, 100);
  auto point = [&] { return Eigen::Vector3d(coord(rng), coord(rng), coord(rng) / 10); };
  for (int trial = 0; trial < 60; ++trial) {
    const std::size_t n = 1 + trial % 7;
    std::vector<TourStop> stops(n);
    for (TourStop& s : stops) s = {point(), point()};
    std::optional<Eigen::Vector3d> start;
    if (trial % 2) start = point();
    const std::vector<std::size_t> order = leastTravelOrder(stops, start);
    ASSERT_TRUE(isPermutation(order, n)) << "trial " << trial;
    EXPECT_NEAR(travelFromStart(stops, order, start), bruteForceLeast(stops, start), 1e-6) << "trial " << trial;
  }
}

// Beyond kExactTourStops: never longer than the order given, nor than nearest neighbour from the start.
TEST(LeastTravelOrder, ManyStopsTravelNoMoreThanTheGivenOrNearestOrder) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> coord(-100, 100);
  auto point = [&] { return Eigen::Vector3d(coord(rng), coord(rng), 0); };
  for (int trial = 0; trial < 10; ++trial) {
    const std::size_t n = kExactTourStops + 1 + static_cast<std::size_t>(trial) * 3;
    std::vector<TourStop> stops(n);
    for (TourStop& s : stops) {
      s.entry = point();
      s.exit = s.entry + Eigen::Vector3d(coord(rng) / 20, coord(rng) / 20, 0);
    }
    const Eigen::Vector3d start = point();
    const std::vector<std::size_t> order = leastTravelOrder(stops, start);
    ASSERT_TRUE(isPermutation(order, n));
    std::vector<std::size_t> given(n), nearest;
    for (std::size_t i = 0; i < n; ++i) given[i] = i;
    std::vector<bool> used(n, false);
    Eigen::Vector3d at = start;
    for (std::size_t k = 0; k < n; ++k) {
      std::size_t pick = n;
      for (std::size_t i = 0; i < n; ++i)
        if (!used[i] && (pick == n || (at - stops[i].entry).norm() < (at - stops[pick].entry).norm())) pick = i;
      used[pick] = true, nearest.push_back(pick), at = stops[pick].exit;
    }
    const double found = travelFromStart(stops, order, start);
    EXPECT_LE(found, travelFromStart(stops, given, start) + 1e-9);
    EXPECT_LE(found, travelFromStart(stops, nearest, start) + 1e-6);
  }
}

// Stops with nothing to gain keep their places.
TEST(LeastTravelOrder, KeepsTheGivenOrderWhenNoneIsShorter) {
  std::vector<TourStop> stops(4);
  for (TourStop& s : stops) s = {Eigen::Vector3d(1, 2, 3), Eigen::Vector3d(1, 2, 3)};
  EXPECT_EQ(leastTravelOrder(stops, std::nullopt), (std::vector<std::size_t>{0, 1, 2, 3}));
  EXPECT_TRUE(leastTravelOrder({}, Eigen::Vector3d::Zero()).empty());
}
