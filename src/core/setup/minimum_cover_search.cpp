// The minimum cover, part 2: the exact branch and bound on the cyclic core. The objective is
// lexicographic: fewest candidates, then (with the bonus) most bonus weight among the covers of that size.
//
// Depth first, branching on the uncovered element with the fewest allowed coverers; later branches of a node exclude
// the candidates of the earlier ones, so the subtrees partition the covers, and a branch dominated by an earlier one
// (covers no more, earns no more) is skipped. The size bound is the larger of a greedy packing (uncovered elements
// with pairwise disjoint coverer sets) and a dual solution of the covering LP; the size search adds the Lagrangian
// bound with reduced-cost fixing and its greedy heuristic (minimum_cover_bound.cpp), and decides the last two
// candidates exactly. The bonus bound counts the most the remaining slots can earn. A node is tight when its packing
// fills every slot: then each slot takes a candidate of its own packed element, which narrows the candidates (and
// propagates through elements that only one packed element's candidates cover), gives a stronger bonus bound (the LP
// dual over the packed elements' choice sets), and passes on to the children, which skip their own bounds.
#include <algorithm>
#include <chrono>
#include <climits>
#include <cmath>
#include <functional>

#include "minimum_cover_internal.h"

namespace art2part::cover {

namespace {

bool betterBonus(double bonus, double best) { return bonus > best + 1e-9 * std::max(1.0, std::abs(best)); }

// A Lagrangian bound above `budget` by more than this is taken as above it (sizes are whole numbers; the bound's
// rounding error is far smaller).
constexpr double kBoundTolerance = 1e-6;

class BranchAndBound {
 public:
  BranchAndBound(const CoreProblem& core, bool use_bonus, double time_limit_s, const std::function<bool()>& keep_going)
      : core_(core),
        keep_going_(keep_going),
        use_bonus_(use_bonus),
        cw_(core.coverers.wordsPerRow()),
        ew_(core.covers.wordsPerRow()),
        bw_(core.earns.wordsPerRow()),
        lagrangian_(!use_bonus),
        lagrange_(core) {
    if (std::isfinite(time_limit_s)) {
      has_deadline_ = true;
      deadline_ = std::chrono::steady_clock::now() +
                  std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                      std::chrono::duration<double>(time_limit_s));
    }
    if (use_bonus_) findDominators();
    effective_.assign(cw_, 0);
    row_count_.assign(core.candidates, 0);
    marginal_.assign(core.candidates, 0);
    slack_.assign(core.candidates, 0);
    used_.assign(cw_, 0);
    relevant_.assign(cw_, 0);
    items_.assign(bw_, 0);
    restricted_.assign(cw_, 0);
    if (use_bonus_) {
      item_earners_ = core.earns.transposed();
      items_by_weight_.resize(core.bonus_items);
      for (int b = 0; b < core.bonus_items; ++b) items_by_weight_[b] = b;
      std::stable_sort(items_by_weight_.begin(), items_by_weight_.end(),
                       [&](int a, int b) { return core.weight[a] > core.weight[b]; });
      set_of_.assign(core.candidates, -1);
      alpha_of_.assign(core.candidates, 0);
    }
  }

  CoreSolution run(const SearchStart& start) {
    best_ = start.chosen;
    best_size_ = start.size;
    best_bonus_ = use_bonus_ ? start.bonus : 0;
    size_is_minimal_ = start.size_is_minimal;
    const int depths = best_size_ + 2;
    uncovered_.assign(static_cast<std::size_t>(depths) * ew_, 0);
    allowed_.assign(static_cast<std::size_t>(depths) * cw_, 0);
    earned_.assign(static_cast<std::size_t>(depths) * bw_, 0);
    branches_.resize(depths);
    packings_.assign(depths, {});
    relaxed_.assign(depths, 0);
    for (int e = 0; e < core_.elements; ++e) setBit(uncovered(0), e);
    for (int c = 0; c < core_.candidates; ++c) setBit(allowed(0), c);
    if (lagrangian_) {
      multipliers_.assign(static_cast<std::size_t>(depths) * core_.elements, 0.0);
      narrowed_.assign(static_cast<std::size_t>(depths) * cw_, 0);
      long long nonzeros = 0;
      for (int e = 0; e < core_.elements; ++e) nonzeros += popcount(core_.coverers.row(e), cw_);
      std::vector<int> cover;  // the root's bound, long optimised, and the better incumbent its heuristic finds
      if (nonzeros <= kLagrangianNonzeros)
        lagrange_.optimiseRoot(uncovered(0), allowed(0), multipliers(0), best_size_, [this] { return pastDeadline(); },
                               cover);
      recordExtension(0, cover);
    }
    search(0, 0.0);
    CoreSolution out;
    out.chosen = best_;
    std::sort(out.chosen.begin(), out.chosen.end());
    out.bonus = coreBonus(core_, out.chosen);
    out.complete = !timed_out_;
    out.improved = improved_;
    out.nodes = nodes_;
    return out;
  }

 private:
  struct Branch {
    int candidate, covered;
    double bonus;
    bool dominated;
    double cost;  // Lagrangian reduced cost (size search), 0 otherwise
  };

  // What the Lagrangian stage of a node leaves: its bound, the element to branch on, and a candidate every better
  // cover below takes (-1: none).
  struct LagrangianNode {
    double bound = 0;
    int branch_element = -1, must_take = -1;
  };

  Word* uncovered(int depth) { return uncovered_.data() + static_cast<std::size_t>(depth) * ew_; }
  Word* allowed(int depth) { return allowed_.data() + static_cast<std::size_t>(depth) * cw_; }
  Word* earned(int depth) { return earned_.data() + static_cast<std::size_t>(depth) * bw_; }
  double* multipliers(int depth) { return multipliers_.data() + static_cast<std::size_t>(depth) * core_.elements; }
  Word* narrowed(int depth) { return narrowed_.data() + static_cast<std::size_t>(depth) * cw_; }

  bool pastDeadline() {
    if ((has_deadline_ && std::chrono::steady_clock::now() > deadline_) || (keep_going_ && !keep_going_()))
      timed_out_ = true;
    return timed_out_;
  }
  bool outOfTime() { return timed_out_ || ((nodes_ & 15) == 1 && pastDeadline()); }

  void record(int size, double bonus) {
    if (size < best_size_ || (use_bonus_ && size == best_size_ && betterBonus(bonus, best_bonus_))) {
      best_.assign(stack_.begin(), stack_.end());
      improved_ = true;
      best_size_ = size;
      best_bonus_ = bonus;
    }
  }

  // The uncovered elements, fewest coverers in A first: the order of the packing and of the dual ascent.
  void orderUncovered(const Word* U, const Word* A) {
    order_.clear();
    forEachBit(U, ew_, [&](int e) { order_.emplace_back(popcountAnd(core_.coverers.row(e), A, cw_), e); });
    std::sort(order_.begin(), order_.end());
  }

  // Greedy packing of uncovered elements whose allowed coverer sets are pairwise disjoint: each needs its own
  // candidate. Stops once it exceeds `enough`.
  int packingBound(const Word* A, int enough, std::vector<int>& packed_) {
    std::fill(used_.begin(), used_.end(), 0);
    packed_.clear();
    int packed = 0;
    for (const auto& [count, e] : order_) {
      const Word* row = core_.coverers.row(e);
      bool disjoint = true;
      for (int w = 0; w < cw_ && disjoint; ++w) disjoint = (row[w] & A[w] & used_[w]) == 0;
      if (!disjoint) continue;
      for (int w = 0; w < cw_; ++w) used_[w] |= row[w] & A[w];
      packed_.push_back(e);
      if (++packed > enough) break;
    }
    return packed;
  }

  // A feasible solution of the dual of the covering LP (a weight y_e per uncovered element, at most 1 summed over
  // the elements of any candidate): its total bounds the cover size from below. Start from y_e = 1 / (most
  // uncovered elements any coverer of e covers), which the largest row bound |U| / max|c| is the uniform case of,
  // then raise each y_e, fewest coverers first, by the least slack among its coverers. Needs row_count_.
  double dualBound(const Word* A) {
    double total = 0;
    forEachBit(relevant_.data(), cw_, [&](int c) { slack_[c] = 1.0; });
    for (const auto& [count, e] : order_) {
      const Word* row = core_.coverers.row(e);
      int most = 0;
      forEachCommonBit(row, A, cw_, [&](int c) { most = std::max(most, row_count_[c]); });
      const double y = 1.0 / most;
      total += y;
      forEachCommonBit(row, A, cw_, [&](int c) { slack_[c] -= y; });
    }
    for (const auto& [count, e] : order_) {
      const Word* row = core_.coverers.row(e);
      double raise = 1.0;
      forEachCommonBit(row, A, cw_, [&](int c) { raise = std::min(raise, slack_[c]); });
      if (raise <= 1e-12) continue;
      total += raise;
      forEachCommonBit(row, A, cw_, [&](int c) { slack_[c] -= raise; });
    }
    return total;
  }

  // Upper bound on the bonus the next `slots` candidates can add, from the candidates in `relevant_`. The largest
  // `slots` marginal bonuses; no more than all the items they could still earn together; and, as each packed element
  // needs a candidate of its own, the best marginal among each packed element's coverers plus the largest marginals
  // for the slots left over.
  double bonusBound(int slots, const Word* A, const Word* E, const std::vector<int>& packed_) {
    top_.clear();
    std::fill(items_.begin(), items_.end(), 0);
    forEachBit(relevant_.data(), cw_, [&](int c) {
      top_.push_back(marginal_[c]);
      const Word* earns = core_.earns.row(c);
      for (int w = 0; w < bw_; ++w) items_[w] |= earns[w];
    });
    const int k = std::min<int>(slots, static_cast<int>(top_.size()));
    std::partial_sort(top_.begin(), top_.begin() + k, top_.end(), std::greater<double>());
    double sum = 0;
    for (int i = 0; i < k; ++i) sum += top_[i];
    const int packed = std::min<int>(slots, static_cast<int>(packed_.size()));
    double by_packing = 0;
    for (int i = 0; i < packed; ++i) {
      double most = 0;
      const Word* row = core_.coverers.row(packed_[i]);
      for (int w = 0; w < cw_; ++w)
        for (Word bits = row[w] & A[w]; bits; bits &= bits - 1)
          most = std::max(most, marginal_[w * 64 + __builtin_ctzll(bits)]);
      by_packing += most;
    }
    for (int i = 0; i < k - packed; ++i) by_packing += top_[i];
    return std::min({sum, by_packing, freshBonus(core_, items_.data(), E)});
  }

  // When the packing fills every slot, each candidate still to choose covers exactly one packed element, one per
  // packed element: the others can go. Then an uncovered element whose coverers all serve the same packed element
  // narrows that element's choice to them, until nothing changes. Returns the candidates left in restricted_, or
  // nullptr when some uncovered element has none of them. (The packing was made over the size bound's candidates,
  // but it holds over all of A: a candidate left out there covers no more than its dominator, which is in.)
  const Word* tightCandidates(const Word* U, const Word* A, const std::vector<int>& packed_) {
    const int k = static_cast<int>(packed_.size());
    choices_.resize(static_cast<std::size_t>(k) * cw_);
    auto choice = [&](int i) { return choices_.data() + static_cast<std::size_t>(i) * cw_; };
    for (int i = 0; i < k; ++i) {
      const Word* row = core_.coverers.row(packed_[i]);
      for (int w = 0; w < cw_; ++w) choice(i)[w] = row[w] & A[w];
    }
    for (bool changed = true; changed;) {
      changed = false;
      bool dead = false;
      forEachBit(U, ew_, [&](int e) {
        if (dead) return;
        const Word* row = core_.coverers.row(e);
        int only = -1, count = 0;
        for (int i = 0; i < k && count < 2; ++i)
          if (intersects(row, choice(i), cw_)) only = i, ++count;
        if (count == 0) dead = true;
        if (count != 1) return;
        Word* c = choice(only);
        for (int w = 0; w < cw_; ++w) {
          changed = changed || (c[w] & ~row[w]) != 0;
          c[w] &= row[w];
        }
      });
      if (dead) return nullptr;
    }
    std::fill(restricted_.begin(), restricted_.end(), 0);
    for (int i = 0; i < k; ++i)
      for (int w = 0; w < cw_; ++w) restricted_[w] |= choice(i)[w];
    return restricted_.data();
  }

  // At a tight node the candidates to choose are one from each packed element's choice set (choices_), and the
  // bonus they add is bounded by the dual of the linear relaxation: for any split of each fresh item's weight into a
  // part alpha counted per candidate and the rest counted once, sum(w - alpha) over the items they could earn plus,
  // per choice set, the largest alpha total of one candidate. alpha = w everywhere is the by-packing bound, alpha = 0
  // the union bound; here each item, heaviest first, goes to alpha = w when that lowers the bound.
  double tightBonusBound(const Word* E, const std::vector<int>& packed_) {
    const int k = static_cast<int>(packed_.size());
    std::fill(restricted_.begin(), restricted_.end(), 0);
    for (int i = 0; i < k; ++i) {
      const Word* choice = choices_.data() + static_cast<std::size_t>(i) * cw_;
      forEachBit(choice, cw_, [&](int c) {
        set_of_[c] = i;
        alpha_of_[c] = 0;
      });
      for (int w = 0; w < cw_; ++w) restricted_[w] |= choice[w];
    }
    set_best_.assign(k, 0.0);
    set_raise_.assign(k, -1.0);
    double bound = 0;
    for (int b : items_by_weight_) {
      if (testBit(E, b)) continue;
      const Word* earners = item_earners_.row(b);
      if (!intersects(earners, restricted_.data(), cw_)) continue;
      const double w = core_.weight[b];
      bound += w;
      // Raising alpha_b to w: each choice set's best may grow.
      touched_.clear();
      for (int x = 0; x < cw_; ++x)
        for (Word bits = earners[x] & restricted_[x]; bits; bits &= bits - 1) {
          const int c = x * 64 + __builtin_ctzll(bits), i = set_of_[c];
          if (set_raise_[i] < 0) touched_.push_back(i);
          set_raise_[i] = std::max(set_raise_[i], alpha_of_[c] + w);
        }
      double increase = 0;
      for (int i : touched_) increase += std::max(0.0, set_raise_[i] - set_best_[i]);
      if (increase < w) {
        bound -= w - increase;
        for (int i : touched_) set_best_[i] = std::max(set_best_[i], set_raise_[i]);
        for (int x = 0; x < cw_; ++x)
          for (Word bits = earners[x] & restricted_[x]; bits; bits &= bits - 1)
            alpha_of_[x * 64 + __builtin_ctzll(bits)] += w;
      }
      for (int i : touched_) set_raise_[i] = -1.0;
    }
    return bound;
  }

  // With the bonus the core keeps candidates that cover less than another but earn other items. For the size bound
  // they do not count while a candidate covering all they cover is allowed: swapping gives a cover no larger.
  // dominator_[c]: one candidate covering every core element c covers, itself dominated by none; -1 if none.
  void findDominators() {
    dominator_.assign(core_.candidates, -1);
    std::vector<int> order(core_.candidates), count(core_.candidates);
    for (int c = 0; c < core_.candidates; ++c) {
      order[c] = c;
      count[c] = popcount(core_.covers.row(c), ew_);
    }
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return count[a] > count[b]; });
    std::vector<int> maximal;
    for (int c : order) {
      for (int d : maximal)
        if (isSubset(core_.covers.row(c), core_.covers.row(d), ew_)) {
          dominator_[c] = d;
          break;
        }
      if (dominator_[c] < 0) maximal.push_back(c);
    }
  }

  // The allowed candidates that count for the size bound.
  const Word* effectiveCandidates(const Word* A) {
    if (!use_bonus_) return A;
    std::copy(A, A + cw_, effective_.begin());
    forEachBit(A, cw_, [&](int c) {
      if (dominator_[c] >= 0 && testBit(A, dominator_[c])) clearBit(effective_.data(), c);
    });
    return effective_.data();
  }

  // A branch is not worth taking when an earlier one covers every uncovered element it covers and earns every
  // fresh item it earns: swapping it for the earlier one in any cover of its subtree gives a cover, no larger and
  // earning no less, that an earlier subtree holds (the earliest branch candidate in it decides which).
  void skipDominated(std::vector<Branch>& branches, const Word* U, const Word* E) {
    for (std::size_t i = 1; i < branches.size(); ++i) {
      const Word* ci = core_.covers.row(branches[i].candidate);
      const Word* bi = core_.earns.row(branches[i].candidate);
      for (std::size_t j = 0; j < i && !branches[i].dominated; ++j) {
        if (branches[j].dominated) continue;
        const Word* cj = core_.covers.row(branches[j].candidate);
        bool inside = true;
        for (int w = 0; w < ew_ && inside; ++w) inside = (ci[w] & U[w] & ~cj[w]) == 0;
        if (use_bonus_) {
          const Word* bj = core_.earns.row(branches[j].candidate);
          for (int w = 0; w < bw_ && inside; ++w) inside = (bi[w] & ~E[w] & ~bj[w]) == 0;
        }
        branches[i].dominated = inside;
      }
    }
  }

  // One node: the covers that extend the chosen stack_ with candidates from A, covering U.
  void search(int depth, double bonus) {
    ++nodes_;
    if (outOfTime()) return;
    const Word* U = uncovered(depth);
    const Word* A = allowed(depth);  // narrowed at tight nodes
    const Word* E = earned(depth);
    const int left = popcount(U, ew_);
    if (left == 0) {
      record(depth, bonus);
      return;
    }
    int slots = best_size_ - depth;  // candidates that may still be added without a worse size
    if (slots <= 0) return;
    if (!use_bonus_ && slots <= 3) {  // a smaller cover adds at most two: decided directly, without bounds
      recordExtension(depth, smallCover(core_, U, A, slots - 1));
      return;
    }
    std::vector<int>& packed = packings_[depth];

    // A packing that fills every slot, inherited from a tight parent, keeps the node tight: skip the bounds.
    int lower = slots, branch_element = -1;
    const bool inherited = static_cast<int>(packed.size()) == slots;
    if (!inherited) {
      branch_element = boundNode(U, A, slots, packed, lower);
      if (branch_element < 0 || lower > slots) return;
    }
    const bool tight = static_cast<int>(packed.size()) == slots;
    if (lower == slots || size_is_minimal_) {  // no smaller cover below: only more bonus at the same size counts
      if (!use_bonus_) return;
      if (tight) {
        A = tightCandidates(U, A, packed);
        if (!A) return;
        std::copy(A, A + cw_, relevant_.begin());
        branch_element = fewestCoverers(U, A);
        if (!betterBonus(bonus + tightBonusBound(E, packed), best_bonus_)) return;
      }
      forEachBit(relevant_.data(), cw_, [&](int c) { marginal_[c] = freshBonus(core_, core_.earns.row(c), E); });
      if (!betterBonus(bonus + bonusBound(slots, A, E, packed), best_bonus_)) return;
    }
    LagrangianNode relaxed;
    relaxed_[depth] = lagrangian_ && node_nonzeros_ <= kLagrangianNonzeros;
    if (relaxed_[depth]) {
      if (!lagrangianNode(depth, U, A, relaxed)) return;
      A = narrowed(depth);
      branch_element = relaxed.branch_element;
      slots = best_size_ - depth;  // the heuristic may have found a better cover
    }

    std::vector<Branch>& branches = branches_[depth];
    branches.clear();
    auto addBranch = [&](int c) {
      branches.push_back({c, popcountAnd(core_.covers.row(c), U, ew_),
                          use_bonus_ ? freshBonus(core_, core_.earns.row(c), E) : 0.0, false,
                          relaxed_[depth] ? lagrange_.reducedCost(c) : 0.0});
    };
    if (relaxed.must_take >= 0)
      addBranch(relaxed.must_take);  // every better cover below takes it: the only branch
    else
      forEachBit(core_.coverers.row(branch_element), cw_, [&](int c) {
        if (testBit(A, c)) addBranch(c);
      });
    // Least reduced cost first in the size search, most bonus first in the bonus search (good covers early prune
    // most), then most newly covered.
    const bool bonus_first = use_bonus_;
    std::sort(branches.begin(), branches.end(), [bonus_first](const Branch& a, const Branch& b) {
      if (bonus_first && a.bonus != b.bonus) return a.bonus > b.bonus;
      if (a.cost != b.cost) return a.cost < b.cost;
      if (a.covered != b.covered) return a.covered > b.covered;
      if (a.bonus != b.bonus) return a.bonus > b.bonus;
      return a.candidate < b.candidate;
    });
    skipDominated(branches, U, E);

    if (slots == 1) {  // one candidate must cover everything left: the first such is the best (sorted by bonus)
      for (const Branch& b : branches)
        if (b.covered == left && !b.dominated) {
          stack_.push_back(b.candidate);
          record(depth + 1, bonus + b.bonus);
          stack_.pop_back();
          return;
        }
      return;
    }

    Word* U2 = uncovered(depth + 1);
    Word* A2 = allowed(depth + 1);
    Word* E2 = earned(depth + 1);
    std::copy(A, A + cw_, A2);
    for (const Branch& b : branches) {
      // Later branches exclude the earlier candidates of this element: the subtrees partition the covers.
      clearBit(A2, b.candidate);
      if (b.dominated) continue;
      const Word* covers = core_.covers.row(b.candidate);
      for (int w = 0; w < ew_; ++w) U2[w] = U[w] & ~covers[w];
      const Word* earns = core_.earns.row(b.candidate);
      for (int w = 0; w < bw_; ++w) E2[w] = E[w] | earns[w];
      // Tight: the candidate serves exactly one packed element; the others still fill the child's slots.
      std::vector<int>& child_packed = packings_[depth + 1];
      child_packed.clear();
      if (tight)
        for (int p : packed)
          if (!testBit(covers, p)) child_packed.push_back(p);
      stack_.push_back(b.candidate);
      search(depth + 1, bonus + b.bonus);
      stack_.pop_back();
      if (timed_out_) return;
      if (lower > best_size_ - depth) return;  // the incumbent improved past what this node can offer
      if (lower == best_size_ - depth && !use_bonus_) return;
      if (relaxed_[depth] && relaxed.bound > best_size_ - 1 - depth + kBoundTolerance) return;
    }
  }

  // `cover` (of the node's U) after the chosen stack, recorded when that is better.
  void recordExtension(int depth, const std::vector<int>& cover) {
    if (cover.empty()) return;
    stack_.insert(stack_.end(), cover.begin(), cover.end());
    record(depth + static_cast<int>(cover.size()), 0.0);
    stack_.resize(depth);
  }

  // ---- the Lagrangian stage of the size search ----

  // The node's Lagrangian bound, warm started from the parent's multipliers; the heuristic; then the allowed
  // candidates narrowed by reduced cost into narrowed(depth): out when every cover taking one is too large, and a
  // must-take when every cover without one is. False when no better cover lies below.
  bool lagrangianNode(int depth, const Word* U, const Word* A, LagrangianNode& out) {
    double* u = multipliers(depth);
    if (depth > 0 && relaxed_[depth - 1]) {
      const double* parent = multipliers(depth - 1);
      forEachBit(U, ew_, [&](int i) { u[i] = parent[i]; });
    } else if (depth > 0) {
      dualStart(core_, U, A, u);
    }
    SubgradientPlan plan;
    plan.iterations = kNodeIterations;
    plan.step = kNodeStep;
    plan.least_step = kNodeStep / 16;
    plan.window = kNodeWindow;
    plan.goal = best_size_ - 1 - depth + kBoundTolerance;
    plan.upper = best_size_ - depth;
    out.bound = lagrange_.optimise(U, A, u, plan);
    if (out.bound > best_size_ - 1 - depth + kBoundTolerance) return false;
    recordExtension(depth, lagrange_.greedyCover(U, A, best_size_ - 1 - depth));
    const double room = best_size_ - 1 - depth - out.bound + kBoundTolerance;  // what a reduced cost may add
    if (room < 0) return false;
    Word* N = narrowed(depth);
    out.must_take = lagrange_.fixByReducedCost(A, room, N);
    out.branch_element = fewestCoverers(U, N);
    return out.branch_element >= 0 && popcountAnd(core_.coverers.row(out.branch_element), N, cw_) > 0;
  }

  // The size bound of a node: max(packing, dual) over the candidates that count for it (packing into `packed`).
  // Returns the uncovered element with the fewest allowed coverers, or -1 when one has none; fills relevant_ (the
  // allowed candidates covering something uncovered) and their row_count_.
  int boundNode(const Word* U, const Word* A, int slots, std::vector<int>& packed, int& lower) {
    int branch_element = -1, fewest = INT_MAX;
    std::fill(relevant_.begin(), relevant_.end(), 0);
    bool dead_end = false;
    node_nonzeros_ = 0;
    forEachBit(U, ew_, [&](int e) {
      if (dead_end) return;
      const Word* row = core_.coverers.row(e);
      const int count = popcountAnd(row, A, cw_);
      node_nonzeros_ += count;
      if (count == 0) dead_end = true;
      if (count < fewest) {
        fewest = count;
        branch_element = e;
      }
      for (int w = 0; w < cw_; ++w) relevant_[w] |= row[w] & A[w];
    });
    if (dead_end) return -1;
    forEachBit(relevant_.data(), cw_, [&](int c) { row_count_[c] = popcountAnd(core_.covers.row(c), U, ew_); });
    const Word* sized = effectiveCandidates(A);
    orderUncovered(U, sized);
    lower = packingBound(sized, slots, packed);
    // Three candidates before the exact finish, the dual bound (a pass over every coverer bit, 1.1 million on a
    // blade's core) prunes seldom: skipping it there halved the size search on the blade.
    if (lower < slots && (use_bonus_ || slots > 4))
      lower = std::max(lower, static_cast<int>(std::ceil(dualBound(sized) - 1e-9)));
    return branch_element;
  }

  int fewestCoverers(const Word* U, const Word* A) {
    int element = -1, fewest = INT_MAX;
    forEachBit(U, ew_, [&](int e) {
      const int count = popcountAnd(core_.coverers.row(e), A, cw_);
      if (count < fewest) {
        fewest = count;
        element = e;
      }
    });
    return element;
  }

  // A subgradient step costs a pass over the node's matrix. On dense cores (a blade's: 1.1 million nonzeros, 4899
  // elements of some 200 coverers each) a few dozen steps cost more than thousands of combinatorial nodes, and the
  // bound stays far below the optimum anyway (linear relaxation 4.5 for 6 there): the relaxation runs at a node only
  // when its matrix has at most this many nonzeros.
  static constexpr long long kLagrangianNonzeros = 200000;
  // Below the root, a few subgradient steps from the parent's multipliers.
  static constexpr int kNodeIterations = 15, kNodeWindow = 5;
  static constexpr double kNodeStep = 0.2;

  const CoreProblem& core_;
  const std::function<bool()>& keep_going_;
  const bool use_bonus_;
  const int cw_, ew_, bw_;
  const bool lagrangian_;  // the size search bounds by the Lagrangian relaxation and narrows by reduced costs
  LagrangianBound lagrange_;
  std::vector<double> multipliers_;  // per depth, one per core element
  std::vector<Word> narrowed_;       // per depth: the allowed candidates after reduced-cost fixing
  std::vector<char> relaxed_;        // per depth: the node ran the Lagrangian stage (its multipliers are current)
  long long node_nonzeros_ = 0;      // of the last boundNode: coverer bits of U's elements within A
  bool has_deadline_ = false, timed_out_ = false, improved_ = false, size_is_minimal_ = false;
  std::chrono::steady_clock::time_point deadline_;
  long long nodes_ = 0;

  std::vector<std::pair<int, int>> order_;  // (coverers, element), scratch
  std::vector<Word> uncovered_, allowed_, earned_;  // per depth
  std::vector<std::vector<Branch>> branches_;       // per depth
  std::vector<int> stack_;
  // Scratch, valid within one node until it recurses.
  std::vector<std::vector<int>> packings_;         // per depth: the packing of the node (inherited when tight)
  std::vector<int> row_count_, dominator_;
  BitMatrix item_earners_;  // bonus item x candidate
  std::vector<int> items_by_weight_, set_of_, touched_;
  std::vector<double> alpha_of_, set_best_, set_raise_;
  std::vector<double> marginal_, top_, slack_;
  std::vector<Word> used_, relevant_, items_, effective_, restricted_, choices_;

  std::vector<int> best_;
  int best_size_ = 0;
  double best_bonus_ = 0;
};

}  // namespace

CoreSolution branchAndBound(const CoreProblem& core, const SearchStart& start, bool use_bonus, double time_limit_s,
                            const std::function<bool()>& keep_going) {
  BranchAndBound search(core, use_bonus, time_limit_s, keep_going);
  return search.run(start);
}

}  // namespace art2part::cover
