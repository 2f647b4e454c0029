// An order of stops, each entered at one point and left at another (a piece of a roughing level is entered where its
// first pass starts and left where its last cut ends), made shorter by or-opt: a run of up to kOrOptRun consecutive
// stops moved to the gap where it adds the least travel, while every stop stays after the stops it waits for
// (TopDownSchedule's rule: the shallower ones within reach), until no such move shortens the travel by more than
// kOrOptGainMm. The travel between two stops: straight from the first's exit to the second's entry; none before the
// first stop or after the last (the tool comes from, and goes to, the clearance plane).
// Why: a nearest-neighbour order (TopDownSchedule::next) leaves stops behind that it must come back for later; moving
// them to where they lie on the way removes most of those trips (issue 19: nearest neighbour, then an improvement).
// Why or-opt and not 2-opt: reversing a stretch would reverse each stop in it, whose entry and exit are not symmetric,
// and would put deeper stops before the shallower ones over them.
// Cost: per sweep, every run against every gap (quadratic in the stops), at most kOrOptSweeps sweeps.
#pragma once

#include <cstddef>
#include <optional>
#include <vector>

#include <Eigen/Core>

namespace art2part {

constexpr std::size_t kOrOptRun = 3;   // the longest run of consecutive stops moved at once
constexpr double kOrOptGainMm = 1e-3;  // a move must shorten the travel by more than this
constexpr int kOrOptSweeps = 30;       // sweeps over every run at most
constexpr std::size_t kExactTourStops = 12;  // leastTravelOrder: the most stops ordered exactly

struct TourStop {
  Eigen::Vector3d entry = Eigen::Vector3d::Zero();  // where the stop is entered
  Eigen::Vector3d exit = Eigen::Vector3d::Zero();   // where it is left
};

// The travel of visiting `stops` in `order` (indices into stops), as above.
double tourTravel(const std::vector<TourStop>& stops, const std::vector<std::size_t>& order);

// `order` (a permutation of the stops' indices in which every stop comes after those it waits for) shortened as
// above. `waits_for[i]`: the stops that must come before stop i. Throws std::invalid_argument when `order` is not
// such a permutation or waits_for's size is not the stops'.
std::vector<std::size_t> shortenedOrder(const std::vector<TourStop>& stops, std::vector<std::size_t> order,
                                        const std::vector<std::vector<std::size_t>>& waits_for);

// The order of `stops` (no stop waiting for another) with the least travel from `start`, where the tool is before the
// first stop (none: wherever the first stop is entered, as tourTravel counts). Exact for up to kExactTourStops stops
// (Held-Karp: the shortest path through every subset ending at each stop, 2^n n^2 steps); beyond that the
// nearest-neighbour order from `start` (or from each stop in turn, without one), shortened by or-opt as above: the
// shortest of those. Ties go to the order given (0, 1, ...), so stops with no travel to gain keep their places.
// Used for a setup's operations with one tool (finishing.cpp): a handful of stops, each entered and left over the
// clearance plane.
std::vector<std::size_t> leastTravelOrder(const std::vector<TourStop>& stops,
                                          const std::optional<Eigen::Vector3d>& start);

}  // namespace art2part
