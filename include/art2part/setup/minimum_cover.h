// The minimum cover of the visibility matrix (thesis 3.3.1): the fewest rows (directions, setups) whose union covers
// every coverable column (triangle), found by Quine-McCluskey style reduction to the cyclic core and an exact branch
// and bound on the core. With the parallel-perpendicular bias (3.3.2): among the covers of minimum size, the one that
// earns most bonus weight (flat faces seen whole and square: the "2" entries of the multi-valued matrix).
//
// Plain data, no geometry: setup_plan.h builds the problem from a visibility result.
#pragma once

#include <functional>
#include <vector>

#include "art2part/visibility/visibility_map.h"

namespace art2part {

struct CoverProblem {
  int candidates = 0;  // rows of the thesis' matrix: the directions
  // One row per element (column of the thesis' matrix: a triangle), bit r set when candidate r covers it. This is
  // the visibility map's own layout (triangle x direction), so no transpose is needed. columns() == candidates.
  BitMatrix coverers;
  // One row per bonus item (a flat face), bit r set when candidate r earns it: the element value 2 of the
  // multi-valued matrix for every triangle of that face. May have no rows (plain minimum cover).
  BitMatrix earners;
  std::vector<double> bonus_weight;  // per bonus item, > 0 (the face's area)
};

struct CoverOptions {
  double time_limit_s = 5.0;  // for the search on the cyclic core; after it the best cover found is returned
  bool use_bonus = true;      // false: minimum size only, bonus ignored (ties broken by row index)
  // Asked at the search's time checks (every few nodes); false stops the search as running out of time does, and
  // minimumCover returns the best cover found without a second search (CoverResult::stopped). Empty: never stops.
  std::function<bool()> keep_going;
};

struct CoverStats {
  int elements = 0, candidates = 0;
  int uncoverable = 0;              // elements with no coverer
  int distinct_elements = 0;        // after merging elements with identical coverer sets
  int empty_candidates = 0;         // candidates that cover nothing
  int essential = 0;                // candidates taken because an element has no other coverer
  int dominated_candidates = 0;     // rows removed by row dominance
  int dominated_elements = 0;       // columns removed by column dominance
  int reduction_rounds = 0;
  int core_candidates = 0, core_elements = 0;  // the cyclic core left for the search (0 x 0: none)
  // With the bonus, the counts above are those of the plain reduction the size search runs on; the bonus search runs
  // on the core of the reduction under the multi-valued order (weaker row dominance, so a larger core).
  int bonus_core_candidates = 0, bonus_core_elements = 0;
  long long search_nodes = 0;               // both searches
  double seconds_reduce = 0, seconds_search = 0;
};

struct CoverResult {
  std::vector<int> chosen;          // candidate indices, ascending
  std::vector<int> uncoverable;     // element indices no candidate covers (unmachinable triangles)
  bool proven_minimal = false;      // the search finished: no smaller cover exists
  bool bonus_proven_best = false;   // ... and no cover of the same size earns more bonus
  double bonus = 0;                 // bonus weight earned by the chosen candidates
  bool stopped = false;             // CoverOptions::keep_going said to stop: the best cover found so far
  CoverStats stats;
};

// Reduction (empty rows, uncoverable columns, identical columns, essential rows, row dominance under the
// multi-valued order, column dominance, repeated until nothing changes) and branch and bound on the cyclic core.
// With the bonus, two searches share options.time_limit_s: the fewest candidates on the core of the plain reduction,
// then the most bonus at that size on the core of the multi-valued one. When time runs out in the second the size
// stays proven (proven_minimal) and the cover is the best found (bonus_proven_best false).
// Throws std::invalid_argument when the matrices do not match (coverers.columns() != candidates, ...), a bonus weight
// is negative or not finite, or the time limit is negative.
CoverResult minimumCover(const CoverProblem& problem, const CoverOptions& options = {});

// Greedy set cover (most newly covered elements first; ties by bonus): the classic approximation, for comparison.
CoverResult greedyCover(const CoverProblem& problem);

// True when every coverable element has a coverer among `chosen`. Both throw std::invalid_argument for a candidate
// index out of range (and for a problem minimumCover would reject).
bool coversAll(const CoverProblem& problem, const std::vector<int>& chosen);
// The bonus weight the candidates earn together.
double bonusEarned(const CoverProblem& problem, const std::vector<int>& chosen);

}  // namespace art2part
