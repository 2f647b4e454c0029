// Or-opt under precedence (ordered_tour.h).
#include "art2part/geometry/ordered_tour.h"

#include <algorithm>
#include <limits>
#include <stdexcept>

namespace art2part {

namespace {

constexpr std::size_t kNone = std::numeric_limits<std::size_t>::max();

class TourShortener {
 public:
  TourShortener(const std::vector<TourStop>& stops, std::vector<std::size_t> order,
                const std::vector<std::vector<std::size_t>>& waits_for)
      : stops_(stops), order_(std::move(order)), waits_for_(waits_for), before_(stops.size()), pos_(stops.size()) {
    for (std::size_t i = 0; i < waits_for_.size(); ++i)
      for (std::size_t w : waits_for_[i]) before_[w].push_back(i);
    place();
  }

  // One sweep: every run of every length moved to its best gap where that shortens the travel. Whether any moved.
  bool sweep() {
    bool moved = false;
    for (std::size_t i = 0; i < order_.size(); ++i)
      for (std::size_t length = 1; length <= kOrOptRun && i + length <= order_.size(); ++length)
        if (moveRun(i, length)) {
          moved = true;
          break;
        }
    return moved;
  }

  std::vector<std::size_t> take() { return std::move(order_); }

 private:
  double hop(std::size_t from, std::size_t to) const {
    if (from == kNone || to == kNone) return 0.0;
    return (stops_[from].exit - stops_[to].entry).norm();
  }
  std::size_t at(std::size_t gap_side) const { return gap_side < order_.size() ? order_[gap_side] : kNone; }

  void place() {
    for (std::size_t i = 0; i < order_.size(); ++i) pos_[order_[i]] = i;
  }

  // The run order_[i, i + length) moved to the gap where it adds least, when that shortens the travel.
  bool moveRun(std::size_t i, std::size_t length) {
    const std::size_t n = order_.size(), end = i + length;
    const std::size_t first = order_[i], last = order_[end - 1];
    const std::size_t prev = i > 0 ? order_[i - 1] : kNone, next = at(end);
    const double saved = hop(prev, first) + hop(last, next) - hop(prev, next);
    if (saved <= kOrOptGainMm) return false;
    // The gaps the run may go to: after every stop one of its stops waits for, before every stop waiting for one.
    std::size_t lo = 0, hi = n;
    for (std::size_t k = i; k < end; ++k) {
      for (std::size_t w : waits_for_[order_[k]])
        if (pos_[w] < i) lo = std::max(lo, pos_[w] + 1);
      for (std::size_t b : before_[order_[k]])
        if (pos_[b] >= end) hi = std::min(hi, pos_[b]);
    }
    // Gap g lies between order_[g - 1] and order_[g]; g in [i, end] leaves the run where it is.
    double best = saved - kOrOptGainMm;
    std::size_t best_gap = kNone;
    auto weigh = [&](std::size_t g) {
      const std::size_t a = g > 0 ? order_[g - 1] : kNone, b = at(g);
      const double added = hop(a, first) + hop(last, b) - hop(a, b);
      if (added < best) best = added, best_gap = g;
    };
    for (std::size_t g = lo; g < i; ++g) weigh(g);
    for (std::size_t g = end + 1; g <= hi; ++g) weigh(g);
    if (best_gap == kNone) return false;
    const auto it = [this](std::size_t k) { return order_.begin() + static_cast<std::ptrdiff_t>(k); };
    if (best_gap < i)
      std::rotate(it(best_gap), it(i), it(end));
    else
      std::rotate(it(i), it(end), it(best_gap));
    place();
    return true;
  }

  const std::vector<TourStop>& stops_;
  std::vector<std::size_t> order_;
  const std::vector<std::vector<std::size_t>>& waits_for_;
  std::vector<std::vector<std::size_t>> before_;  // per stop: the stops waiting for it
  std::vector<std::size_t> pos_;                  // per stop: its place in order_
};

void checkOrder(std::size_t stops, const std::vector<std::size_t>& order,
                const std::vector<std::vector<std::size_t>>& waits_for) {
  if (waits_for.size() != stops) throw std::invalid_argument("shortenedOrder: waits_for is not one list per stop");
  if (order.size() != stops) throw std::invalid_argument("shortenedOrder: the order is not a permutation of the stops");
  std::vector<bool> seen(stops, false);
  for (std::size_t s : order) {
    if (s >= stops || seen[s])
      throw std::invalid_argument("shortenedOrder: the order is not a permutation of the stops");
    for (std::size_t w : waits_for[s])
      if (w >= stops || !seen[w]) throw std::invalid_argument("shortenedOrder: a stop comes before one it waits for");
    seen[s] = true;
  }
}

}  // namespace

double tourTravel(const std::vector<TourStop>& stops, const std::vector<std::size_t>& order) {
  double travel = 0;
  for (std::size_t k = 1; k < order.size(); ++k) travel += (stops[order[k - 1]].exit - stops[order[k]].entry).norm();
  return travel;
}

std::vector<std::size_t> shortenedOrder(const std::vector<TourStop>& stops, std::vector<std::size_t> order,
                                        const std::vector<std::vector<std::size_t>>& waits_for) {
  checkOrder(stops.size(), order, waits_for);
  TourShortener shortener(stops, std::move(order), waits_for);
  for (int k = 0; k < kOrOptSweeps && shortener.sweep(); ++k) {
  }
  return shortener.take();
}

}  // namespace art2part
