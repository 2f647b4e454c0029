// Internal to the minimum cover: word-level bitset helpers and the cyclic core handed from the reduction
// (minimum_cover.cpp) to the exact search (minimum_cover_search.cpp).
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "art2part/setup/minimum_cover.h"
#include "art2part/visibility/visibility_map.h"

namespace art2part::cover {

using Word = std::uint64_t;

inline int wordsFor(int bits) { return (bits + 63) / 64; }

// Bits set in a word. The build targets plain x86-64, which has no POPCNT instruction: there __builtin_popcountll
// is a call into libgcc (a byte table), which the search spends a fifth of its time in; the inline bit count below is
// several times faster. With -mpopcnt (or -march=native) the instruction is used.
inline int popcount64(Word x) {
#ifdef __POPCNT__
  return __builtin_popcountll(x);
#else
  x = x - ((x >> 1) & 0x5555555555555555ull);
  x = (x & 0x3333333333333333ull) + ((x >> 2) & 0x3333333333333333ull);
  x = (x + (x >> 4)) & 0x0F0F0F0F0F0F0F0Full;
  return static_cast<int>((x * 0x0101010101010101ull) >> 56);
#endif
}

inline int popcount(const Word* a, int words) {
  int count = 0;
  for (int w = 0; w < words; ++w) count += popcount64(a[w]);
  return count;
}

inline int popcountAnd(const Word* a, const Word* b, int words) {
  int count = 0;
  for (int w = 0; w < words; ++w) count += popcount64(a[w] & b[w]);
  return count;
}

inline bool isZero(const Word* a, int words) {
  for (int w = 0; w < words; ++w)
    if (a[w]) return false;
  return true;
}

// a is a subset of b.
inline bool isSubset(const Word* a, const Word* b, int words) {
  for (int w = 0; w < words; ++w)
    if (a[w] & ~b[w]) return false;
  return true;
}

inline bool intersects(const Word* a, const Word* b, int words) {
  for (int w = 0; w < words; ++w)
    if (a[w] & b[w]) return true;
  return false;
}

inline bool testBit(const Word* a, int bit) { return (a[bit >> 6] >> (bit & 63)) & 1u; }
inline void setBit(Word* a, int bit) { a[bit >> 6] |= Word(1) << (bit & 63); }
inline void clearBit(Word* a, int bit) { a[bit >> 6] &= ~(Word(1) << (bit & 63)); }

// f(index) for every set bit, ascending.
template <class F>
inline void forEachBit(const Word* a, int words, F&& f) {
  for (int w = 0; w < words; ++w)
    for (Word bits = a[w]; bits != 0; bits &= bits - 1) f(w * 64 + __builtin_ctzll(bits));
}

// f(index) for every bit set in both a and b, ascending.
template <class F>
inline void forEachCommonBit(const Word* a, const Word* b, int words, F&& f) {
  for (int w = 0; w < words; ++w)
    for (Word bits = a[w] & b[w]; bits != 0; bits &= bits - 1) f(w * 64 + __builtin_ctzll(bits));
}

// The cyclic core: what the reduction could not decide. Candidates, elements and bonus items renumbered densely;
// bonus items are only those no essential candidate has earned yet (none when the bonus is ignored).
struct CoreProblem {
  int candidates = 0, elements = 0, bonus_items = 0;
  BitMatrix coverers;           // element x candidate
  BitMatrix covers;             // candidate x element (the transpose)
  BitMatrix earns;              // candidate x bonus item
  std::vector<double> weight;   // per bonus item
  std::vector<int> original;    // core candidate -> problem candidate
};

struct CoreSolution {
  std::vector<int> chosen;  // core candidate indices, ascending
  double bonus = 0;         // weight of the core bonus items the chosen candidates earn
  bool complete = false;    // the search ran to the end: optimal for the (size, bonus) order
  bool improved = false;    // the search found a better cover than the one it started from
  long long nodes = 0;
};

// What the search starts from: a cover of `size` candidates earning `bonus`. `chosen` may be empty when that cover
// is known only outside the core; the search then reports a core cover only if it beats it (improved).
struct SearchStart {
  int size = 0;
  double bonus = 0;
  std::vector<int> chosen;
  bool size_is_minimal = false;  // no smaller cover exists (proven before): only more bonus is looked for
};

// Bonus weight of the items in `items` not yet in `earned`.
inline double freshBonus(const CoreProblem& core, const Word* items, const Word* earned) {
  double bonus = 0;
  const int bw = core.earns.wordsPerRow();
  for (int w = 0; w < bw; ++w)
    for (Word bits = items[w] & ~earned[w]; bits; bits &= bits - 1)
      bonus += core.weight[w * 64 + __builtin_ctzll(bits)];
  return bonus;
}

// Sum of the weights of the core bonus items earned by `chosen`.
double coreBonus(const CoreProblem& core, const std::vector<int>& chosen);

// Greedy on the core (most uncovered elements, then most new bonus, then lowest index), redundant candidates
// removed afterwards: the first upper bound of the search, and the answer when there is no time to search.
CoreSolution greedyCoreCover(const CoreProblem& core, bool use_bonus);

// Exact branch and bound for (fewest candidates, then most bonus when use_bonus), starting from `start` as the
// incumbent. time_limit_s: wall clock for the search (infinite: none); when it runs out, or `keep_going` (when not
// empty) says to stop, the incumbent is returned incomplete.
CoreSolution branchAndBound(const CoreProblem& core, const SearchStart& start, bool use_bonus, double time_limit_s,
                            const std::function<bool()>& keep_going = {});

// ---- the Lagrangian relaxation (minimum_cover_bound.cpp) -----------------------------------------------------------

// How far one subgradient optimisation goes.
struct SubgradientPlan {
  int iterations = 0;       // evaluations at most
  double step = 1.0;        // the Polyak step factor at the start
  double least_step = 0.0;  // stop when the factor, halved, falls below it
  int window = 20;          // evaluations without a better bound before the factor is halved
  double goal = 0;          // stop once the bound exceeds it (the node can go)
  double upper = 0;         // the size the step aims at (the incumbent's)
};

// The Lagrangian bound of the subproblem "cover the elements U with candidates of A": see minimum_cover_bound.cpp.
class LagrangianBound {
 public:
  explicit LagrangianBound(const CoreProblem& core);
  // Subgradient optimisation from the multipliers u (one per core element; only those of U are read and written),
  // which end at the best found. Returns that bound; reducedCost then gives the reduced costs there, for A.
  double optimise(const Word* U, const Word* A, double* u, const SubgradientPlan& plan);
  double reducedCost(int candidate) const { return best_cost_[candidate]; }
  double lastStep() const { return last_step_; }  // the step factor the last optimise ended with
  // A cover of U by candidates of A, guided by the reduced costs of the last optimise; empty when it needs more than
  // `limit` candidates or A cannot cover U.
  std::vector<int> greedyCover(const Word* U, const Word* A, int limit) const;
  // Reduced-cost fixing after the last optimise, for covers at most `room` above its bound: into `narrowed` the
  // candidates of A a cover with them may hold (reduced cost <= room); returns one every such cover holds (-1: none).
  int fixByReducedCost(const Word* A, double room, Word* narrowed) const;
  // The root: from a dual solution, rounds of subgradient optimisation, each followed by the greedy cover, until the
  // bound shows that no cover is smaller than `incumbent` candidates, the step factor runs out or past_deadline().
  // `cover` receives the smallest cover found below `incumbent` (empty: none). Returns the bound.
  double optimiseRoot(const Word* U, const Word* A, double* u, int incumbent,
                      const std::function<bool()>& past_deadline, std::vector<int>& cover);

 private:
  double evaluate(const Word* U, const Word* A, const double* u);
  double computeSubgradient(const Word* U, const double* u);

  const CoreProblem& core_;
  const int cw_;
  std::vector<double> cost_, best_cost_;  // per candidate, valid on A
  std::vector<double> subgradient_, best_u_;  // per element, valid on U
  std::vector<Word> chosen_;  // candidates with negative reduced cost
  double last_step_ = 0;
};

// A cover of U by at most `room` (up to 2) candidates of A, a single one when one suffices; empty when there is none.
// Exact: of two, one covers the element with the fewest allowed coverers and the other the rest. The size search
// ends here when a smaller cover may add only two candidates more, where most of its nodes lie.
std::vector<int> smallCover(const CoreProblem& core, const Word* U, const Word* A, int room);

// Multipliers with no negative reduced cost, where the bound is their sum: u_i = 1 / (most elements of U that an
// allowed coverer of i covers). The start of the root's subgradient optimisation.
void dualStart(const CoreProblem& core, const Word* U, const Word* A, double* u);

// ---- shared by minimum_cover.cpp and minimum_cover_greedy.cpp -------------------------------------------------------

// Throws std::invalid_argument when the matrices do not match or a weight is negative.
void validateProblem(const CoverProblem& p);

// One row per distinct nonempty coverer set, with how many elements share it; elements without coverers aside.
struct DistinctElements {
  BitMatrix coverers;              // distinct element x candidate
  std::vector<int> multiplicity;   // elements per distinct element
  std::vector<int> uncoverable;    // original element indices, ascending
};
DistinctElements mergeIdenticalElements(const BitMatrix& coverers);

// 1-swaps on a cover: replace a chosen candidate by one that covers every element only it covered, as long as
// that raises the bonus (and drop a chosen candidate that has become redundant). `bonus`: candidate x bonus item.
std::vector<int> improveBonusBySwaps(const DistinctElements& elements, const BitMatrix& bonus,
                                     const std::vector<double>& weight, std::vector<int> chosen);

}  // namespace art2part::cover
