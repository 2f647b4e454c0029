// The minimum cover against an independent integer program (GLPK) on random matrices, the reduction rules on small
// hand-made matrices, the time limit, bad input, and a large instance shaped like a real visibility matrix.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <stdexcept>
#include <vector>

#include "art2part/setup/minimum_cover.h"
#include "cover_ilp.h"

namespace art2part {
namespace {

// rows[e] = the candidates covering element e.
CoverProblem makeProblem(int candidates, const std::vector<std::vector<int>>& rows,
                         const std::vector<std::vector<int>>& earners = {}, const std::vector<double>& weights = {}) {
  CoverProblem p;
  p.candidates = candidates;
  p.coverers = BitMatrix(static_cast<int>(rows.size()), candidates);
  for (std::size_t e = 0; e < rows.size(); ++e)
    for (int r : rows[e]) p.coverers.set(static_cast<int>(e), r);
  p.earners = BitMatrix(static_cast<int>(earners.size()), candidates);
  for (std::size_t b = 0; b < earners.size(); ++b)
    for (int r : earners[b]) p.earners.set(static_cast<int>(b), r);
  p.bonus_weight = weights;
  return p;
}

bool contains(const std::vector<int>& v, int x) { return std::find(v.begin(), v.end(), x) != v.end(); }

// A random matrix of varied size and density, with some empty candidates, uncoverable and repeated elements, and
// (in about half) random bonus items.
CoverProblem randomProblem(std::mt19937& rng) {
  auto uniform = [&](int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng); };
  auto chance = [&](double p) { return std::uniform_real_distribution<double>(0, 1)(rng) < p; };
  // Up to 300 elements, fewer with many candidates: GLPK takes seconds on some 60 x 300 matrices, and the test has a
  // time budget.
  const int candidates = uniform(3, 60), elements = uniform(5, std::min(300, std::max(40, 6000 / candidates)));
  const double density = std::vector<double>{0.02, 0.05, 0.1, 0.2, 0.4, 0.6}[uniform(0, 5)];
  std::vector<char> empty(candidates, 0);
  if (chance(0.4))
    for (int k = uniform(1, 3); k > 0; --k) empty[uniform(0, candidates - 1)] = 1;
  const double uncoverable = chance(0.3) ? 0.05 : 0.0, repeat = chance(0.5) ? 0.3 : 0.0;
  std::vector<std::vector<int>> rows;
  for (int e = 0; e < elements; ++e) {
    if (!rows.empty() && chance(repeat)) {
      rows.push_back(rows[uniform(0, static_cast<int>(rows.size()) - 1)]);
      continue;
    }
    std::vector<int> row;
    if (!chance(uncoverable)) {
      for (int r = 0; r < candidates; ++r)
        if (!empty[r] && chance(density)) row.push_back(r);
      // Mostly coverable: sparse rows would otherwise leave too many elements without a coverer.
      if (row.empty() && !chance(0.1)) {
        const int r = uniform(0, candidates - 1);
        if (!empty[r]) row.push_back(r);
      }
    }
    rows.push_back(row);
  }
  std::vector<std::vector<int>> earners;
  std::vector<double> weights;
  if (chance(0.5)) {
    const int items = uniform(1, 12);
    for (int b = 0; b < items; ++b) {
      std::vector<int> row;
      const double p = std::uniform_real_distribution<double>(0.02, 0.3)(rng);
      for (int r = 0; r < candidates; ++r)
        if (chance(p)) row.push_back(r);
      earners.push_back(row);
      weights.push_back(std::uniform_real_distribution<double>(0.1, 10.0)(rng));
    }
  }
  return makeProblem(candidates, rows, earners, weights);
}

std::vector<int> uncoverableElements(const CoverProblem& p) {
  std::vector<int> out;
  for (int e = 0; e < p.coverers.rows(); ++e)
    if (p.coverers.rowCount(e) == 0) out.push_back(e);
  return out;
}

void expectValidResult(const CoverProblem& p, const CoverResult& result) {
  EXPECT_TRUE(coversAll(p, result.chosen));
  EXPECT_TRUE(std::is_sorted(result.chosen.begin(), result.chosen.end()));
  EXPECT_TRUE(std::adjacent_find(result.chosen.begin(), result.chosen.end()) == result.chosen.end());
  EXPECT_EQ(result.uncoverable, uncoverableElements(p));
  EXPECT_EQ(result.stats.uncoverable, static_cast<int>(result.uncoverable.size()));
  EXPECT_NEAR(result.bonus, bonusEarned(p, result.chosen), 1e-9);
}

TEST(MinimumCover, MatchesTheIntegerProgramOnRandomMatrices) {
  std::mt19937 rng(20240611);
  const int instances = 1000;
  int greedy_worse = 0, with_core = 0, with_bonus = 0, with_bonus_core = 0;
  int largest_core_candidates = 0, largest_core_elements = 0;
  long long nodes = 0;
  double seconds_cover = 0, seconds_ilp = 0, slowest = 0;
  auto since = [](std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
  };
  for (int i = 0; i < instances; ++i) {
    const CoverProblem p = randomProblem(rng);
    SCOPED_TRACE("instance " + std::to_string(i));
    auto start = std::chrono::steady_clock::now();
    const int optimum = test::ilpMinimumCoverSize(p);
    seconds_ilp += since(start);
    ASSERT_GE(optimum, 0);

    CoverOptions plain;
    plain.use_bonus = false;
    start = std::chrono::steady_clock::now();
    const CoverResult size_only = minimumCover(p, plain);
    const CoverResult result = minimumCover(p);
    const double seconds = since(start);
    seconds_cover += seconds;
    slowest = std::max(slowest, seconds);
    expectValidResult(p, size_only);
    EXPECT_EQ(static_cast<int>(size_only.chosen.size()), optimum);
    EXPECT_TRUE(size_only.proven_minimal);

    expectValidResult(p, result);
    EXPECT_EQ(static_cast<int>(result.chosen.size()), optimum);
    EXPECT_TRUE(result.proven_minimal);
    EXPECT_TRUE(result.bonus_proven_best);
    if (p.earners.rows() > 0) {
      ++with_bonus;
      start = std::chrono::steady_clock::now();
      const double best = test::ilpBestBonus(p, optimum);
      seconds_ilp += since(start);
      ASSERT_FALSE(std::isnan(best));
      EXPECT_NEAR(result.bonus, best, 1e-6);
    }
    if (result.stats.core_elements > 0) ++with_core;
    if (result.stats.bonus_core_elements > 0) ++with_bonus_core;
    largest_core_candidates = std::max(largest_core_candidates, result.stats.core_candidates);
    largest_core_elements = std::max(largest_core_elements, result.stats.core_elements);
    nodes += result.stats.search_nodes;

    // No time to search: still a cover, minimal only when it says so.
    CoverOptions no_time;
    no_time.time_limit_s = 0;
    const CoverResult quick = minimumCover(p, no_time);
    expectValidResult(p, quick);
    EXPECT_GE(static_cast<int>(quick.chosen.size()), optimum);
    if (quick.proven_minimal) {
      EXPECT_EQ(static_cast<int>(quick.chosen.size()), optimum);
    }
    if (quick.bonus_proven_best && p.earners.rows() > 0) {
      EXPECT_NEAR(quick.bonus, result.bonus, 1e-6);
    }

    const CoverResult greedy = greedyCover(p);
    expectValidResult(p, greedy);
    EXPECT_GE(static_cast<int>(greedy.chosen.size()), optimum);
    if (static_cast<int>(greedy.chosen.size()) > optimum) ++greedy_worse;
  }
  std::printf("%d random matrices (%d with bonus items): greedy worse than the optimum in %d; cyclic core in %d "
              "(largest %d x %d), bonus core in %d; %lld search nodes; minimumCover %.2f s (slowest %.3f s), "
              "GLPK %.2f s\n",
              instances, with_bonus, greedy_worse, with_core, largest_core_candidates, largest_core_elements,
              with_bonus_core, nodes, seconds_cover, slowest, seconds_ilp);
  EXPECT_GT(with_core, 0);
}

TEST(MinimumCover, TakesTheEssentialCandidate) {
  // Element 2 is covered by candidate 2 alone.
  const CoverProblem p = makeProblem(4, {{0, 1}, {1, 3}, {2}, {0, 3}});
  const CoverResult result = minimumCover(p);
  EXPECT_TRUE(contains(result.chosen, 2));
  EXPECT_GE(result.stats.essential, 1);
  EXPECT_EQ(static_cast<int>(result.chosen.size()), test::ilpMinimumCoverSize(p));
  EXPECT_TRUE(coversAll(p, result.chosen));
}

TEST(MinimumCover, DropsDominatedRows) {
  // Candidate 0 covers {e0}, candidate 1 covers {e0, e1}, candidate 2 covers {e1, e2}, candidate 3 covers {e2}.
  const CoverProblem p = makeProblem(4, {{0, 1}, {1, 2}, {2, 3}});
  const CoverResult result = minimumCover(p);
  EXPECT_EQ(result.chosen, (std::vector<int>{1, 2}));
  EXPECT_GE(result.stats.dominated_candidates, 2);
  EXPECT_TRUE(result.proven_minimal);
}

TEST(MinimumCover, KeepsARowThatEarnsMoreBonus) {
  // Candidate 0 covers less than candidate 1 but alone earns a flat face: under the multi-valued order it is not
  // dominated (candidate 1 is, once the essential candidate 2 has covered e1), and {0, 2} beats {1, 2} on bonus.
  const CoverProblem p = makeProblem(3, {{0, 1}, {1, 2}, {2}}, {{0}}, {5.0});
  const CoverResult result = minimumCover(p);
  EXPECT_EQ(result.chosen, (std::vector<int>{0, 2}));
  EXPECT_DOUBLE_EQ(result.bonus, 5.0);
  EXPECT_TRUE(result.bonus_proven_best);
  CoverOptions plain;
  plain.use_bonus = false;
  const CoverResult size_only = minimumCover(p, plain);
  EXPECT_EQ(size_only.chosen.size(), 2u);
  EXPECT_TRUE(size_only.proven_minimal);
  EXPECT_FALSE(size_only.bonus_proven_best);  // the bonus was not looked at
}

TEST(MinimumCover, EqualCandidatesKeepTheLowestIndex) {
  const CoverProblem p = makeProblem(3, {{0, 2}, {0, 2}, {1}});
  CoverOptions plain;
  plain.use_bonus = false;
  const CoverResult result = minimumCover(p, plain);
  EXPECT_EQ(result.chosen, (std::vector<int>{0, 1}));
  EXPECT_EQ(result.stats.distinct_elements, 2);
}

TEST(MinimumCover, SolvesACyclicCore) {
  // Three candidates, each covering two of three elements in a cycle: nothing reduces, two are needed.
  const CoverProblem p = makeProblem(3, {{0, 1}, {1, 2}, {0, 2}});
  const CoverResult result = minimumCover(p);
  EXPECT_EQ(result.chosen.size(), 2u);
  EXPECT_TRUE(coversAll(p, result.chosen));
  EXPECT_TRUE(result.proven_minimal);
  EXPECT_EQ(result.stats.core_candidates, 3);
  EXPECT_EQ(result.stats.core_elements, 3);
  EXPECT_EQ(result.stats.essential, 0);
  EXPECT_EQ(result.stats.dominated_candidates, 0);
  EXPECT_EQ(result.stats.dominated_elements, 0);
  EXPECT_GT(result.stats.search_nodes, 0);
}

TEST(MinimumCover, ReportsUncoverableElementsAndEmptyCandidates) {
  const CoverProblem p = makeProblem(4, {{}, {0}, {1}, {}, {0, 1}});
  const CoverResult result = minimumCover(p);
  EXPECT_EQ(result.uncoverable, (std::vector<int>{0, 3}));
  EXPECT_EQ(result.chosen, (std::vector<int>{0, 1}));
  EXPECT_EQ(result.stats.empty_candidates, 2);
  EXPECT_EQ(result.stats.elements, 5);
  EXPECT_EQ(result.stats.distinct_elements, 3);
  EXPECT_TRUE(result.proven_minimal);
}

TEST(MinimumCover, EmptyProblems) {
  const CoverResult none = minimumCover(makeProblem(0, {}));
  EXPECT_TRUE(none.chosen.empty());
  EXPECT_TRUE(none.proven_minimal);
  const CoverResult blind = minimumCover(makeProblem(0, {{}, {}}));
  EXPECT_EQ(blind.uncoverable, (std::vector<int>{0, 1}));
  EXPECT_TRUE(blind.chosen.empty());
}

// A random matrix whose cyclic core is not empty.
CoverProblem hardProblem(std::mt19937& rng, int candidates, int elements, double density) {
  std::bernoulli_distribution bit(density);
  std::vector<std::vector<int>> rows(elements);
  for (auto& row : rows) {
    while (row.size() < 2) {
      row.clear();
      for (int r = 0; r < candidates; ++r)
        if (bit(rng)) row.push_back(r);
    }
  }
  return makeProblem(candidates, rows);
}

TEST(MinimumCover, NoTimeMeansGreedyOnTheCore) {
  std::mt19937 rng(7);
  const CoverProblem p = hardProblem(rng, 40, 200, 0.08);
  CoverOptions options;
  options.time_limit_s = 0;
  const CoverResult quick = minimumCover(p, options);
  ASSERT_GT(quick.stats.core_elements, 0);
  EXPECT_TRUE(coversAll(p, quick.chosen));
  EXPECT_FALSE(quick.proven_minimal);
  EXPECT_FALSE(quick.bonus_proven_best);
  EXPECT_EQ(quick.stats.search_nodes, 0);
  const CoverResult exact = minimumCover(p);
  EXPECT_TRUE(exact.proven_minimal);
  EXPECT_LE(exact.chosen.size(), quick.chosen.size());
  EXPECT_EQ(static_cast<int>(exact.chosen.size()), test::ilpMinimumCoverSize(p));
}

TEST(MinimumCover, TheBonusSearchNeedsTimeButTheSizeDoesNot) {
  // Candidate 3 covers everything; 0, 1 and 2 each cover two elements and earn a face. The plain reduction leaves
  // nothing (3 dominates the others), the multi-valued one a core: with no time the size is proven, the bonus not.
  const CoverProblem p = makeProblem(4, {{0, 1, 3}, {1, 2, 3}, {0, 2, 3}}, {{0}, {1}, {2}}, {1.0, 2.0, 3.0});
  CoverOptions options;
  options.time_limit_s = 0;
  const CoverResult quick = minimumCover(p, options);
  EXPECT_EQ(quick.chosen, (std::vector<int>{3}));
  EXPECT_TRUE(quick.proven_minimal);
  EXPECT_FALSE(quick.bonus_proven_best);
  EXPECT_EQ(quick.stats.core_elements, 0);
  EXPECT_EQ(quick.stats.bonus_core_candidates, 4);
  EXPECT_EQ(quick.stats.bonus_core_elements, 3);
  const CoverResult exact = minimumCover(p);
  EXPECT_EQ(exact.chosen, (std::vector<int>{3}));
  EXPECT_TRUE(exact.proven_minimal);
  EXPECT_TRUE(exact.bonus_proven_best);
  EXPECT_DOUBLE_EQ(exact.bonus, 0.0);
}

TEST(MinimumCover, RejectsMismatchedInput) {
  CoverProblem p = makeProblem(4, {{0}, {1, 2}});
  p.candidates = 5;
  EXPECT_THROW(minimumCover(p), std::invalid_argument);
  EXPECT_THROW(greedyCover(p), std::invalid_argument);
  EXPECT_THROW(coversAll(p, {0}), std::invalid_argument);

  CoverProblem weights = makeProblem(4, {{0}, {1, 2}}, {{0}, {1}}, {1.0});
  EXPECT_THROW(minimumCover(weights), std::invalid_argument);
  EXPECT_THROW(bonusEarned(weights, {0}), std::invalid_argument);

  CoverProblem earners = makeProblem(4, {{0}, {1, 2}}, {{0}}, {1.0});
  earners.earners = BitMatrix(1, 3);
  EXPECT_THROW(minimumCover(earners), std::invalid_argument);

  const CoverProblem good = makeProblem(4, {{0}, {1, 2}});
  EXPECT_THROW(coversAll(good, {4}), std::invalid_argument);
  CoverOptions negative;
  negative.time_limit_s = -1;
  EXPECT_THROW(minimumCover(good, negative), std::invalid_argument);
}

// ---- a large instance shaped like real data ------------------------------------------------------------------------

struct Vec {
  double x, y, z;
};
double dot(const Vec& a, const Vec& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

Vec randomUnit(std::mt19937& rng) {
  std::normal_distribution<double> n(0, 1);
  for (;;) {
    Vec v{n(rng), n(rng), n(rng)};
    const double len = std::sqrt(dot(v, v));
    if (len > 1e-9) return {v.x / len, v.y / len, v.z / len};
  }
}

// 20000 triangles x 1024 directions from 300 distinct cones: mostly wide caps (faces open to a half space), some
// narrower caps cut by a second one (walls, pockets), a few narrow ones (deep pockets); a few triangles no direction
// sees. 40 flat faces as bonus items, earned like setup_plan's square faces: within 10 degrees of the face normal or
// of the face plane.
CoverProblem coneProblem(std::mt19937& rng) {
  const int directions = 1024, triangles = 20000, cones = 300, faces = 40;
  auto radians = [](double degrees) { return degrees * 3.14159265358979323846 / 180; };
  std::vector<Vec> dirs(directions);
  for (auto& d : dirs) d = randomUnit(rng);
  std::uniform_real_distribution<double> unit(0, 1);
  std::vector<std::vector<int>> cone_rows(cones);
  for (auto& row : cone_rows)
    while (row.empty()) {
      const Vec a = randomUnit(rng), b = randomUnit(rng);
      const double kind = unit(rng);
      double half = 0, cut = -2.0;  // half-angle of the cap around a; cos of the cap around b (none: -2)
      if (kind < 0.6) {
        half = radians(60 + 30 * unit(rng));
      } else if (kind < 0.95) {
        half = radians(25 + 35 * unit(rng));
        cut = std::cos(radians(70 + 20 * unit(rng)));
      } else {
        half = radians(8 + 17 * unit(rng));
      }
      for (int d = 0; d < directions; ++d)
        if (dot(dirs[d], a) >= std::cos(half) && dot(dirs[d], b) >= cut) row.push_back(d);
    }
  std::vector<std::vector<int>> rows(triangles);
  std::uniform_int_distribution<int> pick(0, cones - 1);
  for (int t = 0; t < triangles; ++t)
    if (unit(rng) > 0.002) rows[t] = cone_rows[pick(rng)];
  std::vector<std::vector<int>> earners(faces);
  std::vector<double> weights(faces);
  for (int f = 0; f < faces; ++f) {
    const Vec n = randomUnit(rng);
    for (int d = 0; d < directions; ++d) {
      const double c = dot(dirs[d], n);
      if (c >= std::cos(radians(10)) || (c >= 0 && c < std::sin(radians(10)))) earners[f].push_back(d);
    }
    weights[f] = 10 + 1000 * unit(rng);
  }
  return makeProblem(directions, rows, earners, weights);
}

TEST(MinimumCover, SolvesALargeConeInstance) {
  std::mt19937 rng(99);
  const CoverProblem p = coneProblem(rng);
  const auto greedy_start = std::chrono::steady_clock::now();
  const CoverResult greedy = greedyCover(p);
  const double greedy_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - greedy_start).count();
  for (bool use_bonus : {false, true}) {
    CoverOptions options;
    options.use_bonus = use_bonus;
    const auto start = std::chrono::steady_clock::now();
    const CoverResult result = minimumCover(p, options);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_TRUE(coversAll(p, result.chosen));
    EXPECT_TRUE(result.proven_minimal);
    EXPECT_EQ(result.bonus_proven_best, use_bonus);
    EXPECT_GE(greedy.chosen.size(), result.chosen.size());
    const CoverStats& s = result.stats;
    EXPECT_EQ(s.uncoverable, static_cast<int>(uncoverableElements(p).size()));
    std::printf("cone instance %d x %d, bonus %s: %zu setups (greedy %zu in %.3f s), bonus %.1f, %.3f s (reduce %.3f, "
                "search %.3f); %d distinct, %d uncoverable, %d empty, %d essential, %d dominated rows, %d dominated "
                "columns, %d rounds, core %d x %d, bonus core %d x %d, %lld nodes\n",
                s.elements, s.candidates, use_bonus ? "on" : "off", result.chosen.size(), greedy.chosen.size(),
                greedy_seconds, result.bonus, seconds, s.seconds_reduce, s.seconds_search, s.distinct_elements,
                s.uncoverable, s.empty_candidates, s.essential, s.dominated_candidates, s.dominated_elements,
                s.reduction_rounds, s.core_candidates, s.core_elements, s.bonus_core_candidates, s.bonus_core_elements,
                s.search_nodes);
  }
}

}  // namespace
}  // namespace art2part
