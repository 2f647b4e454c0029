// Work at depths handed out one item at a time, in an order a cutter can take it down a pocket: an item is ready
// once every shallower item whose x-y box lies within `reach` of its box has been handed out (a reach the same for
// every pair, or given per pair); among the ready items,
// the one nearest the tool by the caller's distance. Roughing's level pieces (PieceSchedule, operation_moves.h) and
// planar finishing's wall stretches (cutWalls, finishing_moves.h) are scheduled by it.
// Why: what a cut above leaves within the reach of a cut below is what the cut below was planned for only once the
// cut above is done; cuts further apart do not meet, so the tool may finish one pocket before it crosses to the next
// instead of crossing the part at every level.
// Cost: the waiting pairs are found by a sweep over the boxes sorted along x (the pairs within reach along x, not all
// n^2); each hand-out scans the ready items, measuring only those whose box is nearer than the best so far (the box's
// distance bounds the caller's from below).
#pragma once

#include <functional>
#include <vector>

#include <Eigen/Core>

namespace art2part {

struct ScheduledItem {
  double depth = 0;        // larger is deeper; items of one depth never wait for each other
  Eigen::Vector2d lo, hi;  // the item's x-y box (lo <= hi)
};

// How far apart the boxes of a shallower item and a deeper one may lie for the deeper one to wait (a body widening
// up the tool reaches farther round items far above it).
using ScheduleReach = std::function<double(const ScheduledItem& shallower, const ScheduledItem& deeper)>;

class TopDownSchedule {
 public:
  TopDownSchedule(std::vector<ScheduledItem> items, double reach);
  // With the reach given per pair, never more than `most_reach`.
  TopDownSchedule(std::vector<ScheduledItem> items, double most_reach, const ScheduleReach& reach);
  std::size_t size() const { return items_.size(); }
  // Per item: the shallower items within reach, which it waits for (whatever has been taken).
  std::vector<std::vector<std::size_t>> waitsFor() const;

  // The first ready item in the given order, now taken; size() once every item is taken.
  std::size_t first();
  // The ready item nearest the tool at `at` by `distance(i)`, now taken; at a tie, the deeper one (down the pocket the
  // tool is in). `distance(i)` must never be less than the x-y distance from `at` to item i's box. size() once every
  // item is taken.
  std::size_t next(const Eigen::Vector2d& at, const std::function<double(std::size_t)>& distance);

 private:
  void take(std::size_t i);
  std::vector<ScheduledItem> items_;
  std::vector<std::size_t> waiting_;               // per item: shallower items within reach not taken yet
  std::vector<std::vector<std::size_t>> unblocks_;  // per item: deeper items within reach
  std::vector<bool> taken_;
};

}  // namespace art2part
