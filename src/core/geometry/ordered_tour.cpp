// Or-opt under precedence (ordered_tour.h).
#include "art2part/geometry/ordered_tour.h"

#include <algorithm>
#include <limits>
#include <numeric>
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

// The travel of `order` from `start` (none: from its first entry).
double travelFrom(const std::vector<TourStop>& stops, const std::vector<std::size_t>& order,
                  const std::optional<Eigen::Vector3d>& start) {
  double travel = tourTravel(stops, order);
  if (start && !order.empty()) travel += (*start - stops[order.front()].entry).norm();
  return travel;
}

// Held-Karp: best[set][last] the least travel visiting `set` (a bit per stop), ending at `last`.
std::vector<std::size_t> exactOrder(const std::vector<TourStop>& stops, const std::optional<Eigen::Vector3d>& start) {
  const std::size_t n = stops.size();
  const std::size_t sets = std::size_t{1} << n;
  constexpr double kInf = std::numeric_limits<double>::infinity();
  std::vector<double> best(sets * n, kInf);
  std::vector<std::size_t> came(sets * n, kNone);
  for (std::size_t i = 0; i < n; ++i)
    best[(std::size_t{1} << i) * n + i] = start ? (*start - stops[i].entry).norm() : 0;
  for (std::size_t set = 1; set < sets; ++set)
    for (std::size_t last = 0; last < n; ++last) {
      const double here = best[set * n + last];
      if (!(set >> last & 1) || here == kInf) continue;
      for (std::size_t next = 0; next < n; ++next) {
        if (set >> next & 1) continue;
        const std::size_t to = (set | std::size_t{1} << next) * n + next;
        const double travel = here + (stops[last].exit - stops[next].entry).norm();
        if (travel < best[to] - 1e-9) best[to] = travel, came[to] = last;
      }
    }
  std::size_t set = sets - 1, last = 0;
  for (std::size_t i = 1; i < n; ++i)
    if (best[set * n + i] < best[set * n + last] - 1e-9) last = i;
  std::vector<std::size_t> order;
  while (last != kNone) {
    order.push_back(last);
    const std::size_t before = came[set * n + last];
    set &= ~(std::size_t{1} << last);
    last = before;
  }
  std::reverse(order.begin(), order.end());
  return order;
}

// Nearest neighbour from `start`, or from stop `first` when there is none.
std::vector<std::size_t> nearestOrder(const std::vector<TourStop>& stops, const std::optional<Eigen::Vector3d>& start,
                                      std::size_t first) {
  std::vector<bool> done(stops.size(), false);
  std::vector<std::size_t> order;
  Eigen::Vector3d at = start ? *start : stops[first].entry;
  while (order.size() < stops.size()) {
    std::size_t pick = kNone;
    double least = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < stops.size(); ++i)
      if (!done[i] && (at - stops[i].entry).norm() < least - 1e-9) least = (at - stops[i].entry).norm(), pick = i;
    done[pick] = true;
    order.push_back(pick);
    at = stops[pick].exit;
  }
  return order;
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

std::vector<std::size_t> leastTravelOrder(const std::vector<TourStop>& stops,
                                          const std::optional<Eigen::Vector3d>& start) {
  std::vector<std::size_t> given(stops.size());
  std::iota(given.begin(), given.end(), std::size_t{0});
  if (stops.size() < 2) return given;
  std::vector<std::size_t> best = stops.size() <= kExactTourStops ? exactOrder(stops, start) : given;
  if (stops.size() > kExactTourStops) {
    // With a start, or-opt runs over the start as a stop of its own that every other waits for.
    std::vector<TourStop> with_start;
    std::vector<std::vector<std::size_t>> waits_for(stops.size());
    if (start) {
      with_start.push_back({*start, *start});
      with_start.insert(with_start.end(), stops.begin(), stops.end());
      waits_for.assign(with_start.size(), {0});
      waits_for[0].clear();
    }
    const std::size_t tries = start ? 1 : stops.size();
    for (std::size_t first = 0; first < tries; ++first) {
      std::vector<std::size_t> order = nearestOrder(stops, start, first);
      if (start) {
        for (std::size_t& i : order) ++i;
        order.insert(order.begin(), 0);
        order = shortenedOrder(with_start, std::move(order), waits_for);
        order.erase(order.begin());
        for (std::size_t& i : order) --i;
      } else {
        order = shortenedOrder(stops, std::move(order), waits_for);
      }
      if (travelFrom(stops, order, start) < travelFrom(stops, best, start) - kOrOptGainMm) best = std::move(order);
    }
  }
  // The order given unless the one found is shorter (Held-Karp's ties are broken by index, not by the given order).
  if (travelFrom(stops, best, start) < travelFrom(stops, given, start) - kOrOptGainMm) return best;
  return given;
}

}  // namespace art2part
