// Tests and benches only: the minimum cover as an integer program solved by GLPK, independent of the reduction and
// branch and bound in src/core/setup. Link -lglpk.
#pragma once

#include <glpk.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <set>
#include <utility>
#include <vector>

#include "art2part/setup/minimum_cover.h"

namespace art2part::test {

namespace ilp_detail {

// The coverer sets of the coverable elements, each once, and none that contains another: such a constraint is
// implied by the smaller one (covering the smaller set covers it), so the integer program stays the same. Works on
// whole words so that real-sized matrices (1e5 elements x 1024 candidates) take milliseconds.
inline std::vector<std::vector<int>> coverConstraints(const CoverProblem& p) {
  using Row = std::vector<std::uint64_t>;
  const int words = p.coverers.wordsPerRow(), tail = p.candidates % 64;
  std::set<Row> distinct;
  for (int e = 0; e < p.coverers.rows(); ++e) {
    Row row(p.coverers.row(e), p.coverers.row(e) + words);
    if (tail) row.back() &= (std::uint64_t(1) << tail) - 1;
    bool any = false;
    for (std::uint64_t w : row) any = any || w != 0;
    if (any) distinct.insert(row);
  }
  auto bits = [](const Row& row) {
    int n = 0;
    for (std::uint64_t w : row) n += __builtin_popcountll(w);
    return n;
  };
  std::vector<std::pair<int, const Row*>> by_size;
  for (const Row& row : distinct) by_size.emplace_back(bits(row), &row);
  std::stable_sort(by_size.begin(), by_size.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<const Row*> kept;
  for (const auto& [size, row] : by_size) {
    bool implied = false;
    for (const Row* smaller : kept) {
      bool inside = true;
      for (int w = 0; w < words && inside; ++w) inside = ((*smaller)[w] & ~(*row)[w]) == 0;
      if (inside) {
        implied = true;
        break;
      }
    }
    if (!implied) kept.push_back(row);
  }
  std::vector<std::vector<int>> out;
  for (const Row* row : kept) {
    std::vector<int> coverers;
    for (int r = 0; r < p.candidates; ++r)
      if (((*row)[r / 64] >> (r % 64)) & 1u) coverers.push_back(r);
    out.push_back(std::move(coverers));
  }
  return out;
}

// Columns 1..candidates are x_r, then one y_b per bonus item when with_bonus. Rows: cover constraints, then (bonus)
// y_b - sum x_r <= 0 and sum x_r == size. Returns the x values (0/1) or an empty vector when GLPK finds no optimum.
inline std::vector<int> solve(const CoverProblem& p, const std::vector<std::vector<int>>& constraints,
                              bool with_bonus, int size) {
  glp_term_out(GLP_OFF);
  const int n = p.candidates, items = with_bonus ? p.earners.rows() : 0;
  glp_prob* lp = glp_create_prob();
  glp_set_obj_dir(lp, with_bonus ? GLP_MAX : GLP_MIN);
  glp_add_cols(lp, n + items);
  for (int j = 1; j <= n; ++j) {
    glp_set_col_kind(lp, j, GLP_BV);
    glp_set_obj_coef(lp, j, with_bonus ? 0.0 : 1.0);
  }
  for (int b = 0; b < items; ++b) {
    glp_set_col_kind(lp, n + 1 + b, GLP_BV);
    glp_set_obj_coef(lp, n + 1 + b, p.bonus_weight[b]);
  }
  std::vector<int> ia{0}, ja{0};
  std::vector<double> ar{0.0};
  auto entry = [&](int row, int col, double value) {
    ia.push_back(row);
    ja.push_back(col);
    ar.push_back(value);
  };
  int rows = 0;
  for (const auto& coverers : constraints) {
    ++rows;
    for (int r : coverers) entry(rows, r + 1, 1.0);
  }
  const int cover_rows = rows;
  for (int b = 0; b < items; ++b) {
    ++rows;
    entry(rows, n + 1 + b, 1.0);
    for (int r = 0; r < n; ++r)
      if (p.earners.get(b, r)) entry(rows, r + 1, -1.0);
  }
  const int bonus_rows = rows - cover_rows;
  if (with_bonus) {
    ++rows;
    for (int r = 0; r < n; ++r) entry(rows, r + 1, 1.0);
  }
  if (rows > 0) glp_add_rows(lp, rows);
  for (int i = 1; i <= cover_rows; ++i) glp_set_row_bnds(lp, i, GLP_LO, 1.0, 0.0);
  for (int i = cover_rows + 1; i <= cover_rows + bonus_rows; ++i) glp_set_row_bnds(lp, i, GLP_UP, 0.0, 0.0);
  if (with_bonus) glp_set_row_bnds(lp, rows, GLP_FX, size, size);
  glp_load_matrix(lp, static_cast<int>(ia.size()) - 1, ia.data(), ja.data(), ar.data());

  glp_iocp parm;
  glp_init_iocp(&parm);
  parm.presolve = GLP_ON;
  // Exact all the same; how GLPK gets there: preprocessing at the root only (at every node it took a quarter of
  // MinimalOnFreeFormParts) and Gomory cuts, which close a set cover's weak relaxation faster than branching.
  parm.pp_tech = GLP_PP_ROOT;
  parm.gmi_cuts = GLP_ON;
  parm.msg_lev = GLP_MSG_OFF;
  std::vector<int> x;
  if (glp_intopt(lp, &parm) == 0 && glp_mip_status(lp) == GLP_OPT)
    for (int j = 1; j <= n; ++j) x.push_back(glp_mip_col_val(lp, j) > 0.5 ? 1 : 0);
  glp_delete_prob(lp);
  return x;
}

// The matrices fit together (what minimumCover would otherwise reject).
inline bool consistent(const CoverProblem& p) {
  return p.candidates >= 0 && p.coverers.columns() == p.candidates &&
         p.earners.rows() == static_cast<int>(p.bonus_weight.size()) &&
         (p.earners.rows() == 0 || p.earners.columns() == p.candidates);
}

}  // namespace ilp_detail

// The fewest candidates covering every coverable element; -1 when the input is inconsistent or GLPK fails.
inline int ilpMinimumCoverSize(const CoverProblem& p) {
  if (!ilp_detail::consistent(p)) return -1;
  const auto constraints = ilp_detail::coverConstraints(p);
  if (constraints.empty()) return 0;
  const std::vector<int> x = ilp_detail::solve(p, constraints, false, 0);
  if (x.empty()) return -1;
  int size = 0;
  for (int v : x) size += v;
  return size;
}

// The most bonus weight a cover of exactly `size` candidates earns; NaN when there is none, the input is
// inconsistent or GLPK fails.
inline double ilpBestBonus(const CoverProblem& p, int size) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  if (!ilp_detail::consistent(p) || size < 0 || size > p.candidates) return nan;
  const auto constraints = ilp_detail::coverConstraints(p);
  if (p.candidates == 0) return constraints.empty() ? 0.0 : nan;
  const std::vector<int> x = ilp_detail::solve(p, constraints, true, size);
  if (x.empty()) return nan;
  // The bonus of the chosen x, summed exactly (the y values carry GLPK's integrality tolerance).
  double bonus = 0;
  for (int b = 0; b < p.earners.rows(); ++b)
    for (int r = 0; r < p.candidates; ++r)
      if (x[r] && p.earners.get(b, r)) {
        bonus += p.bonus_weight[b];
        break;
      }
  return bonus;
}

}  // namespace art2part::test
