// The minimum cover, part 4: the Lagrangian relaxation of the covering problem on the cyclic core, the size bound of
// the exact search (minimum_cover_search.cpp), and the primal heuristic it guides. After J. E. Beasley, "A
// Lagrangian heuristic for set-covering problems" (Naval Research Logistics 37, 1990) and A. Caprara, M. Fischetti,
// P. Toth, "A heuristic method for the set covering problem" (Operations Research 47, 1999).
//
// Relaxing each element's covering constraint (some coverer chosen) with a multiplier u_i >= 0 leaves
//   L(u) = sum of u_i + sum over candidates of min(0, c_j),   c_j = 1 - sum of u_i over the elements j covers,
// a lower bound on the size of every cover for every u >= 0. Subgradient optimisation raises it towards the bound of
// the linear relaxation: with x_j = 1 where c_j < 0, g_i = 1 - (chosen candidates covering i) is a subgradient. The
// reduced costs c_j bound further: a cover with candidate j has at least L + c_j candidates when c_j >= 0, a cover
// without it at least L - c_j when c_j < 0.
//
// Also here: the exact end of the size search, a cover by at most two candidates (smallCover).
#include <algorithm>
#include <cmath>

#include "minimum_cover_internal.h"

namespace art2part::cover {

LagrangianBound::LagrangianBound(const CoreProblem& core)
    : core_(core),
      cw_(core.coverers.wordsPerRow()),
      cost_(core.candidates, 0.0),
      best_cost_(core.candidates, 0.0),
      subgradient_(core.elements, 0.0),
      best_u_(core.elements, 0.0),
      chosen_(cw_, 0) {}

// L(u) over the subproblem: cover U with candidates of A. Fills cost_ (for A) and chosen_ (c_j < 0).
double LagrangianBound::evaluate(const Word* U, const Word* A, const double* u) {
  forEachBit(A, cw_, [&](int j) { cost_[j] = 1.0; });
  double bound = 0;
  forEachBit(U, wordsFor(core_.elements), [&](int i) {
    const double ui = u[i];
    if (ui <= 0) return;
    bound += ui;
    const Word* row = core_.coverers.row(i);
    forEachCommonBit(row, A, cw_, [&](int j) { cost_[j] -= ui; });
  });
  std::fill(chosen_.begin(), chosen_.end(), 0);
  forEachBit(A, cw_, [&](int j) {
    if (cost_[j] < 0) {
      bound += cost_[j];
      setBit(chosen_.data(), j);
    }
  });
  return bound;
}

// The projected subgradient at the last evaluation into subgradient_ (on U); returns its squared norm.
double LagrangianBound::computeSubgradient(const Word* U, const double* u) {
  double norm = 0;
  forEachBit(U, wordsFor(core_.elements), [&](int i) {
    double g = 1.0 - popcountAnd(core_.coverers.row(i), chosen_.data(), cw_);
    if (g < 0 && u[i] <= 0) g = 0;  // u_i stays at 0: no move along it
    subgradient_[i] = g;
    norm += g * g;
  });
  return norm;
}

double LagrangianBound::optimise(const Word* U, const Word* A, double* u, const SubgradientPlan& plan) {
  const int ew = wordsFor(core_.elements);
  double best = -1.0, factor = plan.step;
  // Beasley's step rule: the factor is halved whenever the best bound has not risen for a window of evaluations.
  // (Caprara, Fischetti and Toth's rule, which halves it when the bound swings by more than 1 % over a window,
  // halved it on every window here from the start: at factor 0.006 the bound crept up by 0.1 per 50 steps.)
  int stalled = 0;
  for (int iteration = 0;; ++iteration) {
    const double bound = evaluate(U, A, u);
    if (bound > best + 1e-6) {
      best = bound;
      stalled = 0;
      forEachBit(U, ew, [&](int i) { best_u_[i] = u[i]; });
      forEachBit(A, cw_, [&](int j) { best_cost_[j] = cost_[j]; });
    } else if (++stalled >= plan.window) {
      factor *= 0.5;
      stalled = 0;
      if (factor < plan.least_step) break;
    }
    if (best > plan.goal || iteration + 1 >= plan.iterations) break;
    const double norm = computeSubgradient(U, u);
    if (norm <= 0) break;  // x(u) covers every element, exactly where u_i > 0: u is optimal
    const double step = factor * std::max(plan.upper - bound, 1e-3) / norm;
    forEachBit(U, ew, [&](int i) { u[i] = std::max(0.0, u[i] + step * subgradient_[i]); });
  }
  forEachBit(U, ew, [&](int i) { u[i] = best_u_[i]; });
  last_step_ = factor;
  return best;
}

namespace {

// Drops candidates whose elements of U all have another chosen coverer, largest reduced cost first.
void dropRedundant(const CoreProblem& core, const Word* U, const std::vector<double>& cost, std::vector<int>& chosen) {
  const int ew = core.covers.wordsPerRow();
  std::vector<int> count(core.elements, 0);
  for (int j : chosen) {
    const Word* row = core.covers.row(j);
    for (int w = 0; w < ew; ++w)
      for (Word bits = row[w] & U[w]; bits; bits &= bits - 1) ++count[w * 64 + __builtin_ctzll(bits)];
  }
  std::vector<int> order = chosen;
  std::sort(order.begin(), order.end(), [&](int a, int b) { return cost[a] != cost[b] ? cost[a] > cost[b] : a > b; });
  for (int j : order) {
    const Word* row = core.covers.row(j);
    bool redundant = true;
    for (int w = 0; w < ew && redundant; ++w)
      for (Word bits = row[w] & U[w]; bits && redundant; bits &= bits - 1)
        redundant = count[w * 64 + __builtin_ctzll(bits)] > 1;
    if (!redundant) continue;
    for (int w = 0; w < ew; ++w)
      for (Word bits = row[w] & U[w]; bits; bits &= bits - 1) --count[w * 64 + __builtin_ctzll(bits)];
    chosen.erase(std::find(chosen.begin(), chosen.end(), j));
  }
}

}  // namespace

std::vector<int> LagrangianBound::greedyCover(const Word* U, const Word* A, int limit) const {
  const int ew = core_.covers.wordsPerRow();
  std::vector<Word> left(U, U + ew);
  std::vector<int> chosen;
  while (!isZero(left.data(), ew)) {
    // Caprara-Fischetti-Toth score: c_j / mu_j when c_j > 0, c_j * mu_j otherwise (mu_j: newly covered elements).
    int pick = -1;
    double pick_score = 0;
    forEachBit(A, cw_, [&](int j) {
      const int mu = popcountAnd(core_.covers.row(j), left.data(), ew);
      if (mu == 0) return;
      const double c = best_cost_[j];
      const double score = c > 0 ? c / mu : c * mu;
      if (pick < 0 || score < pick_score) pick = j, pick_score = score;
    });
    if (pick < 0) return {};  // A cannot cover U
    chosen.push_back(pick);
    const Word* row = core_.covers.row(pick);
    for (int w = 0; w < ew; ++w) left[w] &= ~row[w];
  }
  dropRedundant(core_, U, best_cost_, chosen);
  if (static_cast<int>(chosen.size()) > limit) return {};
  return chosen;
}

double LagrangianBound::optimiseRoot(const Word* U, const Word* A, double* u, int incumbent,
                                     const std::function<bool()>& past_deadline, std::vector<int>& cover) {
  // Beasley's start (factor 1, halved after 50 steps without progress), in rounds of 100 steps. A step costs a pass
  // over the nonzeros: some 1e8 of them in all at most (a tenth of a second), so 40 rounds on mount_rush's core.
  constexpr double kLeastStep = 0.002, kTolerance = 1e-6, kWork = 1e8;
  long long nonzeros = 0;
  forEachBit(U, wordsFor(core_.elements), [&](int i) { nonzeros += popcountAnd(core_.coverers.row(i), A, cw_); });
  const int rounds = static_cast<int>(std::clamp(kWork / (100.0 * std::max(1LL, nonzeros)), 1.0, 40.0));
  dualStart(core_, U, A, u);
  cover.clear();
  SubgradientPlan plan;
  plan.iterations = 100;
  plan.step = 1.0;
  plan.least_step = kLeastStep;
  plan.window = 50;
  double bound = 0;
  for (int round = 0; round < rounds && !past_deadline(); ++round) {
    plan.goal = incumbent - 1 + kTolerance;
    plan.upper = incumbent;
    bound = optimise(U, A, u, plan);
    plan.step = lastStep();
    std::vector<int> found = greedyCover(U, A, incumbent - 1);
    if (!found.empty()) {
      incumbent = static_cast<int>(found.size());
      cover.swap(found);
    }
    if (bound > incumbent - 1 + kTolerance || plan.step < kLeastStep) break;
  }
  return bound;
}

int LagrangianBound::fixByReducedCost(const Word* A, double room, Word* narrowed) const {
  std::copy(A, A + cw_, narrowed);
  int must_take = -1;
  forEachBit(A, cw_, [&](int j) {
    const double cost = best_cost_[j];
    if (cost > room) clearBit(narrowed, j);
    else if (-cost > room && must_take < 0) must_take = j;
  });
  return must_take;
}

namespace {

// The allowed candidates covering every element of U into `found`; false when there is none. The intersection of
// the elements' coverer sets is empty after a few elements in most nodes.
bool coveringAll(const CoreProblem& core, const Word* U, const Word* A, std::vector<Word>& found) {
  const int cw = core.coverers.wordsPerRow(), ew = core.covers.wordsPerRow();
  found.assign(A, A + cw);
  bool any = true;
  for (int w = 0; w < ew && any; ++w)
    for (Word bits = U[w]; bits && any; bits &= bits - 1) {
      const Word* row = core.coverers.row(w * 64 + __builtin_ctzll(bits));
      any = false;
      for (int x = 0; x < cw; ++x) any = (found[x] &= row[x]) != 0 || any;
    }
  return any;
}

int firstBit(const std::vector<Word>& a) {
  for (std::size_t w = 0; w < a.size(); ++w)
    if (a[w]) return static_cast<int>(w) * 64 + __builtin_ctzll(a[w]);
  return -1;
}

}  // namespace

std::vector<int> smallCover(const CoreProblem& core, const Word* U, const Word* A, int room) {
  if (room <= 0) return {};
  const int cw = core.coverers.wordsPerRow(), ew = core.covers.wordsPerRow();
  std::vector<Word> found;
  if (coveringAll(core, U, A, found)) return {firstBit(found)};
  if (room == 1) return {};
  int element = -1, fewest = 0;
  forEachBit(U, ew, [&](int e) {
    const int count = popcountAnd(core.coverers.row(e), A, cw);
    if (element < 0 || count < fewest) element = e, fewest = count;
  });
  std::vector<Word> rest(ew);
  const Word* row = core.coverers.row(element);
  for (int w = 0; w < cw; ++w)
    for (Word bits = row[w] & A[w]; bits; bits &= bits - 1) {
      const int c = w * 64 + __builtin_ctzll(bits);
      const Word* covers = core.covers.row(c);
      for (int x = 0; x < ew; ++x) rest[x] = U[x] & ~covers[x];
      if (coveringAll(core, rest.data(), A, found)) return {c, firstBit(found)};
    }
  return {};
}

void dualStart(const CoreProblem& core, const Word* U, const Word* A, double* u) {
  // u_i = 1 / (most elements of U any allowed coverer of i covers): no reduced cost below 0, L(u) = sum u_i.
  const int cw = core.coverers.wordsPerRow(), ew = core.covers.wordsPerRow();
  std::vector<int> size(core.candidates, 0);
  forEachBit(A, cw, [&](int j) { size[j] = popcountAnd(core.covers.row(j), U, ew); });
  forEachBit(U, ew, [&](int i) {
    int most = 1;
    const Word* row = core.coverers.row(i);
    forEachCommonBit(row, A, cw, [&](int j) { most = std::max(most, size[j]); });
    u[i] = 1.0 / most;
  });
}

}  // namespace art2part::cover
