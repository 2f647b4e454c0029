#include "art2part/geometry/top_down_schedule.h"

#include <algorithm>
#include <limits>
#include <numeric>

namespace art2part {

TopDownSchedule::TopDownSchedule(std::vector<ScheduledItem> items, double reach)
    : TopDownSchedule(std::move(items), reach, [reach](const ScheduledItem&, const ScheduledItem&) { return reach; }) {}

TopDownSchedule::TopDownSchedule(std::vector<ScheduledItem> items, double most_reach, const ScheduleReach& pair_reach)
    : items_(std::move(items)), waiting_(items_.size(), 0), unblocks_(items_.size()), taken_(items_.size(), false) {
  const double reach = most_reach;
  std::vector<std::size_t> by_x(items_.size());
  std::iota(by_x.begin(), by_x.end(), std::size_t{0});
  std::sort(by_x.begin(), by_x.end(),
            [this](std::size_t a, std::size_t b) { return items_[a].lo.x() < items_[b].lo.x(); });
  for (std::size_t i = 0; i < by_x.size(); ++i) {
    const ScheduledItem& a = items_[by_x[i]];
    // Sorted by lo.x: once an item starts beyond a's reach along x, every later one does too.
    for (std::size_t j = i + 1; j < by_x.size() && items_[by_x[j]].lo.x() <= a.hi.x() + reach; ++j) {
      const ScheduledItem& b = items_[by_x[j]];
      if (a.depth == b.depth || b.lo.y() > a.hi.y() + reach || a.lo.y() > b.hi.y() + reach) continue;
      const std::size_t upper = a.depth < b.depth ? by_x[i] : by_x[j], lower = a.depth < b.depth ? by_x[j] : by_x[i];
      const double r = std::min(reach, pair_reach(items_[upper], items_[lower]));
      if (b.lo.x() > a.hi.x() + r || a.lo.x() > b.hi.x() + r || b.lo.y() > a.hi.y() + r || a.lo.y() > b.hi.y() + r)
        continue;
      unblocks_[upper].push_back(lower);
      ++waiting_[lower];
    }
  }
}

std::vector<std::vector<std::size_t>> TopDownSchedule::waitsFor() const {
  std::vector<std::vector<std::size_t>> waits(items_.size());
  for (std::size_t upper = 0; upper < unblocks_.size(); ++upper)
    for (std::size_t lower : unblocks_[upper]) waits[lower].push_back(upper);
  return waits;
}

void TopDownSchedule::take(std::size_t i) {
  taken_[i] = true;
  for (std::size_t b : unblocks_[i]) --waiting_[b];
}

std::size_t TopDownSchedule::first() {
  for (std::size_t i = 0; i < items_.size(); ++i)
    if (!taken_[i] && waiting_[i] == 0) {
      take(i);
      return i;
    }
  return items_.size();
}

std::size_t TopDownSchedule::next(const Eigen::Vector2d& at, const std::function<double(std::size_t)>& distance) {
  std::size_t best = items_.size();
  double nearest = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < items_.size(); ++i) {
    if (taken_[i] || waiting_[i] > 0) continue;
    const Eigen::Vector2d outside = (items_[i].lo - at).cwiseMax(at - items_[i].hi).cwiseMax(Eigen::Vector2d::Zero());
    if (outside.norm() > nearest) continue;
    const double d = distance(i);
    if (d < nearest || (d == nearest && items_[i].depth > items_[best].depth)) best = i, nearest = d;
  }
  if (best < items_.size()) take(best);
  return best;
}

}  // namespace art2part
