// The minimum cover, part 1: checking the problem, merging identical elements, the Quine-McCluskey style reduction
// (essential candidates, row dominance under the multi-valued order, column dominance) down to the cyclic core, and
// putting the answer together. The exact search on the core is in minimum_cover_search.cpp.
#include "art2part/setup/minimum_cover.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <numeric>
#include <stdexcept>
#include <string>

#include "minimum_cover_internal.h"

namespace art2part {

using cover::Word;

namespace {

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

Word hashRow(const Word* row, int words) {
  Word h = 0x9E3779B97F4A7C15ull;
  for (int w = 0; w < words; ++w) {
    Word x = row[w] + 0x9E3779B97F4A7C15ull + (h << 6) + (h >> 2);
    x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
    x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
    h ^= x ^ (x >> 31);
  }
  return h;
}

}  // namespace

void cover::validateProblem(const CoverProblem& p) {
  if (p.candidates < 0) throw std::invalid_argument("minimum cover: negative candidate count");
  if (p.coverers.columns() != p.candidates)
    throw std::invalid_argument("minimum cover: coverers has " + std::to_string(p.coverers.columns()) +
                                " columns for " + std::to_string(p.candidates) + " candidates");
  if (p.earners.rows() != static_cast<int>(p.bonus_weight.size()))
    throw std::invalid_argument("minimum cover: " + std::to_string(p.earners.rows()) + " bonus items but " +
                                std::to_string(p.bonus_weight.size()) + " bonus weights");
  if (p.earners.rows() > 0 && p.earners.columns() != p.candidates)
    throw std::invalid_argument("minimum cover: earners has " + std::to_string(p.earners.columns()) +
                                " columns for " + std::to_string(p.candidates) + " candidates");
  for (double w : p.bonus_weight)
    if (!(w >= 0) || !std::isfinite(w))
      throw std::invalid_argument("minimum cover: bonus weights must be finite and not negative");
}

// ---- identical elements ---------------------------------------------------------------------------------------------

// Hashing each row (16 words for 1024 candidates) into an open-addressing table: linear in the matrix size.
cover::DistinctElements cover::mergeIdenticalElements(const BitMatrix& coverers) {
  const int elements = coverers.rows(), words = coverers.wordsPerRow();
  const int tail = coverers.columns() & 63;
  const Word last_mask = tail ? (Word(1) << tail) - 1 : ~Word(0);
  DistinctElements out;
  std::size_t capacity = 16;
  while (capacity < 2 * static_cast<std::size_t>(elements) + 1) capacity <<= 1;
  std::vector<int> slots(capacity, -1);  // distinct element index, -1 empty
  std::vector<Word> hashes;              // per distinct element
  std::vector<Word> rows;                // the distinct rows, padding bits cleared
  std::vector<Word> row(words);
  for (int e = 0; e < elements; ++e) {
    std::copy(coverers.row(e), coverers.row(e) + words, row.begin());
    if (words) row[words - 1] &= last_mask;
    if (isZero(row.data(), words)) {
      out.uncoverable.push_back(e);
      continue;
    }
    const Word h = hashRow(row.data(), words);
    for (std::size_t s = h & (capacity - 1);; s = (s + 1) & (capacity - 1)) {
      const int d = slots[s];
      if (d < 0) {
        slots[s] = static_cast<int>(hashes.size());
        hashes.push_back(h);
        rows.insert(rows.end(), row.begin(), row.end());
        out.multiplicity.push_back(1);
        break;
      }
      if (hashes[d] == h &&
          std::memcmp(&rows[static_cast<std::size_t>(d) * words], row.data(), sizeof(Word) * words) == 0) {
        ++out.multiplicity[d];
        break;
      }
    }
  }
  out.coverers = BitMatrix(static_cast<int>(hashes.size()), coverers.columns());
  if (words)
    for (std::size_t d = 0; d < hashes.size(); ++d)
      std::copy(&rows[d * words], &rows[d * words] + words, out.coverers.row(static_cast<int>(d)));
  return out;
}

namespace {

// ---- the reduction --------------------------------------------------------------------------------------------------

struct Reduction {
  int candidate_words = 0, bonus_words = 0;
  BitMatrix elements;              // distinct element x candidate, kept masked to the live candidates
  std::vector<int> live_elements;  // distinct elements still to cover, ascending
  std::vector<Word> live;          // candidates still in play
  BitMatrix bonus;                 // candidate x bonus item (no columns when the bonus is ignored)
  std::vector<Word> earned;        // bonus items earned by the essential candidates
  std::vector<int> chosen;         // essential candidates
};

// bonus: candidate x bonus item, no columns when the bonus is ignored.
Reduction startReduction(const cover::DistinctElements& distinct, const BitMatrix& bonus, int& empty_candidates) {
  Reduction r;
  const int candidates = distinct.coverers.columns();
  r.candidate_words = cover::wordsFor(candidates);
  r.elements = distinct.coverers;
  r.live_elements.resize(r.elements.rows());
  std::iota(r.live_elements.begin(), r.live_elements.end(), 0);
  // Empty candidates: in no element's coverer set.
  r.live.assign(r.candidate_words, 0);
  for (int e = 0; e < r.elements.rows(); ++e)
    for (int w = 0; w < r.candidate_words; ++w) r.live[w] |= r.elements.row(e)[w];
  empty_candidates = candidates - cover::popcount(r.live.data(), r.candidate_words);
  r.bonus = bonus;
  r.bonus_words = r.bonus.wordsPerRow();
  r.earned.assign(r.bonus_words, 0);
  return r;
}

void takeCandidate(Reduction& r, int c) {
  r.chosen.push_back(c);
  const Word* b = r.bonus.row(c);
  for (int w = 0; w < r.bonus_words; ++w) r.earned[w] |= b[w];
  cover::clearBit(r.live.data(), c);
}

// Elements with a single coverer left: that candidate is in every cover. Returns how many were taken.
int essentialCandidates(Reduction& r) {
  const int cw = r.candidate_words;
  std::vector<Word> essential(cw, 0);
  int taken = 0;
  for (int e : r.live_elements) {
    const Word* row = r.elements.row(e);
    if (cover::popcount(row, cw) != 1) continue;
    for (int w = 0; w < cw; ++w)
      if (row[w]) {
        const int c = w * 64 + __builtin_ctzll(row[w]);
        if (!cover::testBit(essential.data(), c)) {
          cover::setBit(essential.data(), c);
          ++taken;
        }
        break;
      }
  }
  if (!taken) return 0;
  cover::forEachBit(essential.data(), cw, [&](int c) { takeCandidate(r, c); });
  // Everything an essential candidate covers is done; no other element has it as a coverer.
  std::vector<int> left;
  left.reserve(r.live_elements.size());
  for (int e : r.live_elements)
    if (!cover::intersects(r.elements.row(e), essential.data(), cw)) left.push_back(e);
  r.live_elements.swap(left);
  return taken;
}

// Element q goes when another element p has a coverer set inside q's: whatever covers p covers q. Identical sets
// were merged, so inclusions are strict. Sorting by set size, each element is tested only against the minimal ones
// kept so far. Returns how many went.
int removeDominatedColumns(Reduction& r) {
  const int cw = r.candidate_words;
  std::vector<std::pair<int, int>> by_size;  // (coverers, element)
  by_size.reserve(r.live_elements.size());
  for (int e : r.live_elements) by_size.emplace_back(cover::popcount(r.elements.row(e), cw), e);
  std::sort(by_size.begin(), by_size.end());
  std::vector<int> kept;
  for (const auto& [size, q] : by_size) {
    const Word* rq = r.elements.row(q);
    bool dominated = false;
    for (int p : kept)
      if (cover::isSubset(r.elements.row(p), rq, cw)) {
        dominated = true;
        break;
      }
    if (!dominated) kept.push_back(q);
  }
  const int removed = static_cast<int>(r.live_elements.size() - kept.size());
  std::sort(kept.begin(), kept.end());
  r.live_elements.swap(kept);
  return removed;
}

// Candidate i goes when another live candidate j covers every element i still covers and earns every bonus item i
// would still earn (dominance under the multi-valued order 0 < 1 < 2); of exactly equal candidates the lowest index
// stays. Candidates that no longer cover anything go too. Returns how many went.
int removeDominatedRows(Reduction& r) {
  const int cw = r.candidate_words, bw = r.bonus_words;
  const int m = static_cast<int>(r.live_elements.size());
  const int ew = cover::wordsFor(m);
  const int candidates = r.elements.columns();
  // Candidate rows over the live elements, and the bonus each would still add.
  BitMatrix rows(candidates, m);
  for (int k = 0; k < m; ++k)
    cover::forEachBit(r.elements.row(r.live_elements[k]), cw, [&](int c) { rows.set(c, k); });
  BitMatrix fresh(candidates, bw * 64);
  std::vector<std::pair<int, int>> order;  // (-covered, candidate): most covering first
  std::vector<int> covered(candidates, 0), fresh_count(candidates, 0);
  std::vector<Word> gone(cw, 0);
  int removed = 0;
  cover::forEachBit(r.live.data(), cw, [&](int c) {
    covered[c] = cover::popcount(rows.row(c), ew);
    if (covered[c] == 0) {
      cover::setBit(gone.data(), c);
      ++removed;
      return;
    }
    for (int w = 0; w < bw; ++w) fresh.row(c)[w] = r.bonus.row(c)[w] & ~r.earned[w];
    fresh_count[c] = cover::popcount(fresh.row(c), bw);
    order.emplace_back(-covered[c], c);
  });
  std::sort(order.begin(), order.end());
  for (const auto& [neg, i] : order) {
    const Word* ri = rows.row(i);
    const Word* bi = fresh.row(i);
    for (const auto& [neg_j, j] : order) {
      if (-neg_j < covered[i]) break;  // j covers fewer: cannot hold i's elements
      if (j == i || fresh_count[j] < fresh_count[i]) continue;
      if (!cover::isSubset(ri, rows.row(j), ew) || !cover::isSubset(bi, fresh.row(j), bw)) continue;
      const bool equal = covered[j] == covered[i] && fresh_count[j] == fresh_count[i];
      if (equal && j > i) continue;  // of equal candidates the lowest index stays
      cover::setBit(gone.data(), i);
      ++removed;
      break;
    }
  }
  if (!removed) return 0;
  for (int w = 0; w < cw; ++w) r.live[w] &= ~gone[w];
  for (int e : r.live_elements) {
    Word* row = r.elements.row(e);
    for (int w = 0; w < cw; ++w) row[w] &= r.live[w];
  }
  return removed;
}

// What is left after the reduction, renumbered densely.
cover::CoreProblem cyclicCore(const Reduction& r, const CoverProblem& p) {
  cover::CoreProblem core;
  const int cw = r.candidate_words;
  std::vector<int> index(p.candidates, -1);
  cover::forEachBit(r.live.data(), cw, [&](int c) {
    index[c] = static_cast<int>(core.original.size());
    core.original.push_back(c);
  });
  core.candidates = static_cast<int>(core.original.size());
  core.elements = static_cast<int>(r.live_elements.size());
  core.coverers = BitMatrix(core.elements, core.candidates);
  for (int k = 0; k < core.elements; ++k)
    cover::forEachBit(r.elements.row(r.live_elements[k]), cw, [&](int c) { core.coverers.set(k, index[c]); });
  core.covers = core.coverers.transposed();
  // Bonus items still to earn that some core candidate earns.
  std::vector<int> item_index(r.bonus_words * 64, -1);
  for (int c : core.original)
    for (int w = 0; w < r.bonus_words; ++w)
      for (Word bits = r.bonus.row(c)[w] & ~r.earned[w]; bits; bits &= bits - 1) {
        const int b = w * 64 + __builtin_ctzll(bits);
        if (item_index[b] < 0) {
          item_index[b] = core.bonus_items++;
          core.weight.push_back(p.bonus_weight[b]);
        }
      }
  core.earns = BitMatrix(core.candidates, core.bonus_items);
  for (int k = 0; k < core.candidates; ++k) {
    const int c = core.original[k];
    for (int w = 0; w < r.bonus_words; ++w)
      for (Word bits = r.bonus.row(c)[w] & ~r.earned[w]; bits; bits &= bits - 1)
        core.earns.set(k, item_index[w * 64 + __builtin_ctzll(bits)]);
  }
  return core;
}

// The whole reduction, repeated until nothing changes, and the cyclic core it leaves.
struct Reduced {
  Reduction state;
  cover::CoreProblem core;
  int empty_candidates = 0, essential = 0, dominated_candidates = 0, dominated_elements = 0, rounds = 0;
};

Reduced reduce(const CoverProblem& p, const cover::DistinctElements& distinct, const BitMatrix& bonus) {
  Reduced out;
  Reduction& r = out.state;
  r = startReduction(distinct, bonus, out.empty_candidates);
  while (!r.live_elements.empty()) {
    ++out.rounds;
    const int essential = essentialCandidates(r);
    out.essential += essential;
    if (r.live_elements.empty()) break;
    const int columns = removeDominatedColumns(r);
    out.dominated_elements += columns;
    const int rows = removeDominatedRows(r);
    out.dominated_candidates += rows;
    if (essential + columns + rows == 0) break;
  }
  out.core = cyclicCore(r, p);
  return out;
}

std::vector<int> withCore(std::vector<int> chosen, const cover::CoreProblem& core, const std::vector<int>& picked) {
  for (int k : picked) chosen.push_back(core.original[k]);
  std::sort(chosen.begin(), chosen.end());
  return chosen;
}

// The time left of a budget started at `start`; infinite stays infinite.
double timeLeft(double limit_s, std::chrono::steady_clock::time_point start) {
  if (!std::isfinite(limit_s)) return limit_s;
  return std::max(0.0, limit_s - secondsSince(start));
}

}  // namespace

// ---- the minimum cover ----------------------------------------------------------------------------------------------

// Two searches when the bonus counts. First the fewest candidates, on the core of the plain reduction (row dominance
// without the bonus is far stronger, so that core is small). Then, with that size as the target, the most bonus on
// the core of the reduction under the multi-valued order, starting from the first cover improved by swaps. The
// second search proves both the size and the bonus when it finishes; when it runs out of time the size stays proven
// by the first.
CoverResult minimumCover(const CoverProblem& problem, const CoverOptions& options) {
  cover::validateProblem(problem);
  if (std::isnan(options.time_limit_s) || options.time_limit_s < 0)
    throw std::invalid_argument("minimum cover: time limit must not be negative");
  auto start = std::chrono::steady_clock::now();
  CoverResult result;
  CoverStats& stats = result.stats;
  stats.elements = problem.coverers.rows();
  stats.candidates = problem.candidates;

  const cover::DistinctElements distinct = cover::mergeIdenticalElements(problem.coverers);
  result.uncoverable = distinct.uncoverable;
  stats.uncoverable = static_cast<int>(result.uncoverable.size());
  stats.distinct_elements = distinct.coverers.rows();

  // ---- the fewest candidates
  const Reduced size = reduce(problem, distinct, BitMatrix(problem.candidates, 0));
  stats.empty_candidates = size.empty_candidates;
  stats.essential = size.essential;
  stats.dominated_candidates = size.dominated_candidates;
  stats.dominated_elements = size.dominated_elements;
  stats.reduction_rounds = size.rounds;
  stats.core_candidates = size.core.candidates;
  stats.core_elements = size.core.elements;
  stats.seconds_reduce = secondsSince(start);

  start = std::chrono::steady_clock::now();
  const double limit = options.time_limit_s;
  std::vector<int> chosen = size.state.chosen;
  bool size_proven = true;
  if (size.core.elements > 0) {
    cover::CoreSolution solution = cover::greedyCoreCover(size.core, false);
    if (limit > 0) {
      cover::SearchStart from{static_cast<int>(solution.chosen.size()), 0.0, solution.chosen};
      solution = cover::branchAndBound(size.core, from, false, limit, options.keep_going);
    }
    size_proven = solution.complete;
    stats.search_nodes = solution.nodes;
    chosen = withCore(std::move(chosen), size.core, solution.chosen);
  }
  std::sort(chosen.begin(), chosen.end());
  stats.seconds_search = secondsSince(start);

  bool has_bonus = false;
  for (double w : problem.bonus_weight) has_bonus = has_bonus || w > 0;
  result.stopped = options.keep_going && !options.keep_going();
  if (!options.use_bonus || !has_bonus || result.stopped) {
    result.chosen = std::move(chosen);
    result.proven_minimal = size_proven;
    result.bonus_proven_best = size_proven && (options.use_bonus || !has_bonus);
    result.bonus = bonusEarned(problem, result.chosen);
    return result;
  }

  // ---- the most bonus among the covers of that size
  auto reduce_start = std::chrono::steady_clock::now();
  BitMatrix bonus = problem.earners.transposed();  // candidate x item; items of no weight left out of dominance
  for (int b = 0; b < problem.earners.rows(); ++b)
    if (problem.bonus_weight[b] <= 0)
      for (int c = 0; c < problem.candidates; ++c) bonus.reset(c, b);
  const Reduced multi = reduce(problem, distinct, bonus);
  stats.bonus_core_candidates = multi.core.candidates;
  stats.bonus_core_elements = multi.core.elements;
  chosen = cover::improveBonusBySwaps(distinct, bonus, problem.bonus_weight, std::move(chosen));
  stats.seconds_reduce += secondsSince(reduce_start);

  auto search_start = std::chrono::steady_clock::now();
  bool bonus_proven = false;
  if (multi.core.elements == 0) {
    // The reduction under the multi-valued order is exact for (size, bonus): its essential candidates are the answer.
    chosen = multi.state.chosen;
    bonus_proven = true;
  } else if (timeLeft(limit, start) > 0) {
    const int target = static_cast<int>(chosen.size() - multi.state.chosen.size());
    const double to_beat = bonusEarned(problem, chosen) - bonusEarned(problem, multi.state.chosen);
    if (target > 0) {
      const cover::SearchStart from{target, to_beat, {}, size_proven};
      const cover::CoreSolution solution =
          cover::branchAndBound(multi.core, from, true, timeLeft(limit, start), options.keep_going);
      stats.search_nodes += solution.nodes;
      if (solution.improved) chosen = withCore(multi.state.chosen, multi.core, solution.chosen);
      bonus_proven = solution.complete;
    }
  }
  if (!bonus_proven) chosen = cover::improveBonusBySwaps(distinct, bonus, problem.bonus_weight, std::move(chosen));
  stats.seconds_search += secondsSince(search_start);

  result.stopped = options.keep_going && !options.keep_going();
  result.chosen = std::move(chosen);
  std::sort(result.chosen.begin(), result.chosen.end());
  result.proven_minimal = size_proven || bonus_proven;
  result.bonus_proven_best = bonus_proven;
  result.bonus = bonusEarned(problem, result.chosen);
  return result;
}

}  // namespace art2part
