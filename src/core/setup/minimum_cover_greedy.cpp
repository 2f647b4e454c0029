// The minimum cover, part 3: greedy on the core (the first incumbent of the search), greedy set cover for
// comparison, 1-swaps that raise the bonus of a cover, and the checks coversAll and bonusEarned.
#include <algorithm>
#include <chrono>
#include <numeric>
#include <stdexcept>
#include <string>

#include "minimum_cover_internal.h"

namespace art2part {

using cover::Word;

namespace {

// The candidates as a bitset over candidate indices; throws for indices out of range.
std::vector<Word> candidateMask(const CoverProblem& p, const std::vector<int>& chosen) {
  std::vector<Word> mask(cover::wordsFor(p.candidates), 0);
  for (int r : chosen) {
    if (r < 0 || r >= p.candidates)
      throw std::invalid_argument("minimum cover: candidate " + std::to_string(r) + " out of range");
    cover::setBit(mask.data(), r);
  }
  return mask;
}

// Weight of the items a candidate earns that no other chosen candidate earns (what removing it loses), and of the
// items it would add (what taking it gains), from per item counts of chosen earners.
double weightWhere(const BitMatrix& bonus, const std::vector<double>& weight, int candidate,
                   const std::vector<int>& earners, int count) {
  double sum = 0;
  cover::forEachBit(bonus.row(candidate), bonus.wordsPerRow(), [&](int b) {
    if (earners[b] == count) sum += weight[b];
  });
  return sum;
}

// One improving swap (or the removal of a redundant candidate); false when there is none.
bool improveOnce(const cover::DistinctElements& elements, const BitMatrix& bonus, const std::vector<double>& weight,
                 std::vector<int>& chosen) {
  const BitMatrix& m = elements.coverers;
  const int candidates = m.columns(), cw = m.wordsPerRow();
  const int tail = candidates & 63;
  std::vector<Word> mask(cw, 0);
  for (int c : chosen) cover::setBit(mask.data(), c);
  std::vector<int> earners(bonus.columns(), 0);
  for (int c : chosen) cover::forEachBit(bonus.row(c), bonus.wordsPerRow(), [&](int b) { ++earners[b]; });
  // Per chosen candidate: the candidates covering every element only it covers (the AND of their coverer rows).
  std::vector<std::vector<Word>> replacing(chosen.size(), std::vector<Word>(cw, ~Word(0)));
  for (auto& r : replacing)
    if (tail && cw) r[cw - 1] = (Word(1) << tail) - 1;
  std::vector<int> index(candidates, -1);
  for (std::size_t i = 0; i < chosen.size(); ++i) index[chosen[i]] = static_cast<int>(i);
  for (int e = 0; e < m.rows(); ++e) {
    const Word* row = m.row(e);
    int count = 0, which = -1;
    for (int w = 0; w < cw && count < 2; ++w) {
      const Word bits = row[w] & mask[w];
      if (!bits) continue;
      count += cover::popcount64(bits);
      which = index[w * 64 + __builtin_ctzll(bits)];
    }
    if (count != 1) continue;
    for (int w = 0; w < cw; ++w) replacing[which][w] &= row[w];
  }
  int best_i = -1, best_r = -1;
  double best_gain = 1e-9;
  for (std::size_t i = 0; i < chosen.size(); ++i) {
    const int c = chosen[i];
    std::vector<Word>& r = replacing[i];
    cover::clearBit(r.data(), c);
    if (cover::intersects(r.data(), mask.data(), cw)) {  // another chosen candidate covers all c covers alone
      chosen.erase(chosen.begin() + i);
      return true;
    }
    const double lost = weightWhere(bonus, weight, c, earners, 1);
    cover::forEachBit(r.data(), cw, [&](int d) {
      double gained = weightWhere(bonus, weight, d, earners, 0);
      // Items c alone earned that d earns too stay earned.
      cover::forEachBit(bonus.row(d), bonus.wordsPerRow(), [&](int b) {
        if (earners[b] == 1 && cover::testBit(bonus.row(c), b)) gained += weight[b];
      });
      if (gained - lost > best_gain) {
        best_gain = gained - lost;
        best_i = static_cast<int>(i);
        best_r = d;
      }
    });
  }
  if (best_i < 0) return false;
  chosen[best_i] = best_r;
  return true;
}

}  // namespace

namespace cover {

namespace {

// Drops candidates whose elements all have another chosen coverer, least useful (fewest elements) first.
void removeRedundant(const CoreProblem& core, std::vector<int>& chosen) {
  const int ew = core.covers.wordsPerRow();
  std::vector<int> count(core.elements, 0);
  for (int c : chosen) forEachBit(core.covers.row(c), ew, [&](int e) { ++count[e]; });
  std::vector<int> order = chosen;
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    const int ca = popcount(core.covers.row(a), ew), cb = popcount(core.covers.row(b), ew);
    return ca != cb ? ca < cb : a > b;
  });
  for (int c : order) {
    bool redundant = true;
    forEachBit(core.covers.row(c), ew, [&](int e) { redundant = redundant && count[e] > 1; });
    if (!redundant) continue;
    forEachBit(core.covers.row(c), ew, [&](int e) { --count[e]; });
    chosen.erase(std::find(chosen.begin(), chosen.end(), c));
  }
}

}  // namespace

double coreBonus(const CoreProblem& core, const std::vector<int>& chosen) {
  std::vector<Word> earned(core.earns.wordsPerRow(), 0);
  double bonus = 0;
  for (int c : chosen) {
    bonus += freshBonus(core, core.earns.row(c), earned.data());
    for (int w = 0; w < core.earns.wordsPerRow(); ++w) earned[w] |= core.earns.row(c)[w];
  }
  return bonus;
}

CoreSolution greedyCoreCover(const CoreProblem& core, bool use_bonus) {
  const int ew = core.covers.wordsPerRow(), bw = core.earns.wordsPerRow();
  std::vector<Word> uncovered(ew, 0), earned(bw, 0);
  for (int e = 0; e < core.elements; ++e) setBit(uncovered.data(), e);
  CoreSolution out;
  int left = core.elements;
  while (left > 0) {
    int best = -1, best_count = 0;
    double best_bonus = 0;
    for (int c = 0; c < core.candidates; ++c) {
      const int count = popcountAnd(core.covers.row(c), uncovered.data(), ew);
      if (count == 0 || count < best_count) continue;
      const double bonus = use_bonus ? freshBonus(core, core.earns.row(c), earned.data()) : 0.0;
      if (count > best_count || bonus > best_bonus) {
        best = c;
        best_count = count;
        best_bonus = bonus;
      }
    }
    out.chosen.push_back(best);  // every core element has a coverer, so best >= 0
    for (int w = 0; w < ew; ++w) uncovered[w] &= ~core.covers.row(best)[w];
    for (int w = 0; w < bw; ++w) earned[w] |= core.earns.row(best)[w];
    left -= best_count;
  }
  removeRedundant(core, out.chosen);
  std::sort(out.chosen.begin(), out.chosen.end());
  out.bonus = use_bonus ? coreBonus(core, out.chosen) : 0.0;
  return out;
}

}  // namespace cover

std::vector<int> cover::improveBonusBySwaps(const DistinctElements& elements, const BitMatrix& bonus,
                                            const std::vector<double>& weight, std::vector<int> chosen) {
  // Each step raises the bonus or shrinks the cover; the cap only guards against rounding ping-pong.
  for (int step = 0; step < 1000 && improveOnce(elements, bonus, weight, chosen); ++step) {
  }
  std::sort(chosen.begin(), chosen.end());
  return chosen;
}

CoverResult greedyCover(const CoverProblem& problem) {
  cover::validateProblem(problem);
  const auto start = std::chrono::steady_clock::now();
  CoverResult result;
  CoverStats& stats = result.stats;
  stats.elements = problem.coverers.rows();
  stats.candidates = problem.candidates;
  cover::DistinctElements distinct = cover::mergeIdenticalElements(problem.coverers);
  result.uncoverable = std::move(distinct.uncoverable);
  stats.uncoverable = static_cast<int>(result.uncoverable.size());
  stats.distinct_elements = distinct.coverers.rows();

  const int cw = cover::wordsFor(problem.candidates);
  const BitMatrix bonus = problem.earners.rows() > 0 ? problem.earners.transposed() : BitMatrix(problem.candidates, 0);
  const int bw = bonus.wordsPerRow();
  std::vector<Word> earned(bw, 0);
  std::vector<char> covered(distinct.coverers.rows(), 0);
  std::vector<long long> gain(problem.candidates);
  std::vector<Word> used(cw, 0);
  for (int e = 0; e < distinct.coverers.rows(); ++e)
    for (int w = 0; w < cw; ++w) used[w] |= distinct.coverers.row(e)[w];
  stats.empty_candidates = problem.candidates - cover::popcount(used.data(), cw);

  long long left = std::accumulate(distinct.multiplicity.begin(), distinct.multiplicity.end(), 0LL);
  while (left > 0) {
    // Elements (with their multiplicity) each candidate would newly cover.
    std::fill(gain.begin(), gain.end(), 0);
    for (int e = 0; e < distinct.coverers.rows(); ++e)
      if (!covered[e])
        cover::forEachBit(distinct.coverers.row(e), cw, [&](int c) { gain[c] += distinct.multiplicity[e]; });
    int best = -1;
    double best_bonus = -1;
    for (int c = 0; c < problem.candidates; ++c) {
      if (gain[c] == 0 || (best >= 0 && gain[c] < gain[best])) continue;
      double b = 0;
      for (int w = 0; w < bw; ++w)
        for (Word bits = bonus.row(c)[w] & ~earned[w]; bits; bits &= bits - 1)
          b += problem.bonus_weight[w * 64 + __builtin_ctzll(bits)];
      if (best < 0 || gain[c] > gain[best] || b > best_bonus) {
        best = c;
        best_bonus = b;
      }
    }
    result.chosen.push_back(best);
    for (int w = 0; w < bw; ++w) earned[w] |= bonus.row(best)[w];
    for (int e = 0; e < distinct.coverers.rows(); ++e)
      if (!covered[e] && cover::testBit(distinct.coverers.row(e), best)) {
        covered[e] = 1;
        left -= distinct.multiplicity[e];
      }
  }
  std::sort(result.chosen.begin(), result.chosen.end());
  result.bonus = bonusEarned(problem, result.chosen);
  stats.seconds_search = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

bool coversAll(const CoverProblem& problem, const std::vector<int>& chosen) {
  cover::validateProblem(problem);
  const std::vector<Word> mask = candidateMask(problem, chosen);
  const int words = problem.coverers.wordsPerRow();
  const int tail = problem.candidates & 63;
  const Word last_mask = tail ? (Word(1) << tail) - 1 : ~Word(0);
  for (int e = 0; e < problem.coverers.rows(); ++e) {
    const Word* row = problem.coverers.row(e);
    bool coverable = false, covered = false;
    for (int w = 0; w < words; ++w) {
      const Word bits = w == words - 1 ? row[w] & last_mask : row[w];
      coverable |= bits != 0;
      covered |= (bits & mask[w]) != 0;
    }
    if (coverable && !covered) return false;
  }
  return true;
}

double bonusEarned(const CoverProblem& problem, const std::vector<int>& chosen) {
  cover::validateProblem(problem);
  const std::vector<Word> mask = candidateMask(problem, chosen);
  double bonus = 0;
  for (int b = 0; b < problem.earners.rows(); ++b)
    if (cover::intersects(problem.earners.row(b), mask.data(), problem.earners.wordsPerRow()))
      bonus += problem.bonus_weight[b];
  return bonus;
}

}  // namespace art2part
