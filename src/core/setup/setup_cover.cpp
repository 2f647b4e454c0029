// Choosing the setups from the cover problem: the fewest setups first (the proof of minimality comes from the plain
// minimum cover, which the reduction handles far better than the multi-valued one), then special directions (3.2.2:
// face normals, axes, edges; what a machinist picks first), then the parallel-perpendicular bonus (3.3.2).
#include <algorithm>
#include <chrono>
#include <cmath>

#include "setup_internal.h"

namespace art2part::setup_detail {
namespace {

using Word = std::uint64_t;

// The problem with only the special directions as candidates (the others cover and earn nothing).
CoverProblem specialOnly(const CoverProblem& problem, const std::vector<char>& special) {
  CoverProblem restricted = problem;
  std::vector<Word> mask(problem.coverers.wordsPerRow(), 0);
  for (int d = 0; d < static_cast<int>(special.size()) && d < problem.candidates; ++d)
    if (special[d]) mask[d >> 6] |= Word(1) << (d & 63);
  for (BitMatrix* m : {&restricted.coverers, &restricted.earners})
    for (int r = 0; r < m->rows(); ++r)
      for (int w = 0; w < m->wordsPerRow(); ++w) m->row(r)[w] &= mask[w];
  return restricted;
}

bool isSpecial(const std::vector<char>& special, int d) {
  return d < static_cast<int>(special.size()) && special[d] != 0;
}

// 1-swaps on a cover of fixed size: replace one chosen direction by another that covers every element only it
// covered, when that raises (number of special directions, bonus) lexicographically.
class SwapSearch {
 public:
  SwapSearch(const CoverProblem& problem, const std::vector<char>& special) : problem_(problem), special_(special) {}

  std::vector<int> improve(std::vector<int> chosen) const {
    for (int round = 0; round < 4 * static_cast<int>(chosen.size()) + 4; ++round)
      if (!improveOnce(chosen)) break;
    std::sort(chosen.begin(), chosen.end());
    return chosen;
  }

 private:
  // Per chosen direction: the candidates that cover every element it alone covers (among the chosen), itself
  // included: the AND of those elements' coverer rows.
  std::vector<std::vector<Word>> replacements(const std::vector<int>& chosen) const {
    const BitMatrix& m = problem_.coverers;
    const int words = m.wordsPerRow();
    std::vector<std::vector<Word>> out(chosen.size(), std::vector<Word>(words, ~Word(0)));
    for (int e = 0; e < m.rows(); ++e) {
      int count = 0, which = -1;
      for (int i = 0; i < static_cast<int>(chosen.size()) && count < 2; ++i)
        if (m.get(e, chosen[i])) ++count, which = i;
      if (count != 1) continue;
      const Word* row = m.row(e);
      for (int w = 0; w < words; ++w) out[which][w] &= row[w];
    }
    return out;
  }

  bool improveOnce(std::vector<int>& chosen) const {
    const std::vector<std::vector<Word>> replacing = replacements(chosen);
    int best_i = -1, best_d = -1, best_special = 0;
    double best_bonus = bonusEarned(problem_, chosen);
    for (int i = 0; i < static_cast<int>(chosen.size()); ++i)
      for (int d = 0; d < problem_.candidates; ++d) {
        if (!((replacing[i][d >> 6] >> (d & 63)) & 1u)) continue;
        const int gain = isSpecial(special_, d) - isSpecial(special_, chosen[i]);
        if (gain < best_special || std::find(chosen.begin(), chosen.end(), d) != chosen.end()) continue;
        std::vector<int> swapped = chosen;
        swapped[i] = d;
        const double b = bonusEarned(problem_, swapped);
        if (gain > best_special || b > best_bonus + 1e-9 * (1.0 + std::abs(best_bonus)))
          best_i = i, best_d = d, best_special = gain, best_bonus = b;
      }
    if (best_i < 0) return false;
    chosen[best_i] = best_d;
    return true;
  }

  const CoverProblem& problem_;
  const std::vector<char>& special_;
};

}  // namespace

CoverResult chooseSetups(const CoverProblem& problem, const std::vector<char>& special, const SetupOptions& options,
                         const std::function<bool()>& keep_going) {
  CoverOptions size_only;
  size_only.time_limit_s = options.time_limit_s;
  size_only.use_bonus = false;
  size_only.keep_going = keep_going;
  const auto start = std::chrono::steady_clock::now();
  CoverResult smallest = minimumCover(problem, size_only);
  if (smallest.stopped) return smallest;
  // The special directions' search has what the plain one left of the time limit (a tenth of it at least).
  const double spent = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  CoverOptions with_bonus = size_only;
  with_bonus.use_bonus = options.parallel_perpendicular;
  with_bonus.time_limit_s = std::max(0.1 * options.time_limit_s, options.time_limit_s - spent);
  CoverResult from_special = minimumCover(specialOnly(problem, special), with_bonus);
  if (from_special.uncoverable.size() == smallest.uncoverable.size() &&
      from_special.chosen.size() <= smallest.chosen.size()) {
    // Minimal when the plain search proved that size; the bonus is the best among covers of special directions.
    from_special.proven_minimal = smallest.proven_minimal && from_special.chosen.size() == smallest.chosen.size();
    from_special.bonus_proven_best = from_special.bonus_proven_best && from_special.proven_minimal;
    from_special.stats = smallest.stats;
    return from_special;
  }
  smallest.chosen = SwapSearch(problem, special).improve(std::move(smallest.chosen));
  smallest.bonus = bonusEarned(problem, smallest.chosen);
  smallest.bonus_proven_best = false;
  return smallest;
}

}  // namespace art2part::setup_detail
