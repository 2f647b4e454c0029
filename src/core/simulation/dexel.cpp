#include "art2part/simulation/dexel.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace art2part {

DexelLattice DexelLattice::over(const Box& box, double resolution, std::int64_t max_rays) {
  if (box.empty() || !(box.size().minCoeff() > 0.0)) throw InputError("simulation: the stock box is empty");
  if (!(resolution > 0.0) || !std::isfinite(resolution))
    throw InputError("simulation: the resolution must be a positive number of mm");
  DexelLattice lattice;
  lattice.box = box;
  for (int k = 0; k < 3; ++k) {
    const double cells = std::ceil(box.size()[k] / resolution - 1e-9);
    if (cells > 1e6) throw InputError("simulation: resolution " + std::to_string(resolution) + " mm is too fine");
    lattice.cells[k] = std::max(1, static_cast<int>(cells));
    lattice.spacing[k] = box.size()[k] / lattice.cells[k];
  }
  if (lattice.totalRays() > max_rays)
    throw InputError("simulation: resolution " + std::to_string(resolution) + " mm makes " +
                     std::to_string(lattice.totalRays()) + " dexels, more than " + std::to_string(max_rays) +
                     ": choose a coarser one");
  return lattice;
}

std::int64_t DexelLattice::totalRays() const {
  std::int64_t total = 0;
  for (int k = 0; k < 3; ++k) total += static_cast<std::int64_t>(cells[uAxis(k)]) * cells[vAxis(k)];
  return total;
}

Vec3 DexelLattice::rayOrigin(int axis, int iu, int iv) const {
  Vec3 origin = Vec3::Zero();
  origin[uAxis(axis)] = coordinate(uAxis(axis), iu);
  origin[vAxis(axis)] = coordinate(vAxis(axis), iv);
  return origin;
}

std::array<int, 2> DexelLattice::indexRange(int axis, double lo, double hi) const {
  const double first = std::ceil((lo - box.min[axis]) / spacing[axis] - 0.5);
  const double last = std::floor((hi - box.min[axis]) / spacing[axis] - 0.5);
  const int n = cells[axis];
  return {static_cast<int>(std::max(first, 0.0)), static_cast<int>(std::min(last, n - 1.0))};
}

void subtractSpan(SpanList& spans, Span cut, SpanList* removed) {
  if (spans.empty() || cut.hi <= spans.front().lo || cut.lo >= spans.back().hi) return;
  if (spans.size() == 1 && (cut.lo <= spans[0].lo || cut.hi >= spans[0].hi)) {  // trims one end or all of it
    Span& s = spans[0];
    if (removed) removed->push_back({std::max(s.lo, cut.lo), std::min(s.hi, cut.hi)});
    if (cut.lo <= s.lo && cut.hi >= s.hi) spans.clear();
    else if (cut.lo <= s.lo) s.lo = cut.hi;
    else s.hi = cut.lo;
    return;
  }
  auto it = std::lower_bound(spans.begin(), spans.end(), cut.lo, [](const Span& s, double t) { return s.hi <= t; });
  while (it != spans.end() && it->lo < cut.hi) {
    const Span s = *it;
    if (removed) removed->push_back({std::max(s.lo, cut.lo), std::min(s.hi, cut.hi)});
    if (s.lo < cut.lo && s.hi > cut.hi) {  // the cut splits the span
      it->hi = cut.lo;
      spans.insert(it + 1, Span{cut.hi, s.hi});
      return;
    }
    if (s.lo < cut.lo) {
      it->hi = cut.lo;
      ++it;
    } else if (s.hi > cut.hi) {
      it->lo = cut.hi;
      return;
    } else {
      it = spans.erase(it);
    }
  }
}

void addSpan(SpanList& spans, Span add) {
  auto first = std::lower_bound(spans.begin(), spans.end(), add.lo, [](const Span& s, double t) { return s.hi < t; });
  auto last = first;
  while (last != spans.end() && last->lo <= add.hi) {
    add.lo = std::min(add.lo, last->lo);
    add.hi = std::max(add.hi, last->hi);
    ++last;
  }
  first = spans.erase(first, last);
  spans.insert(first, add);
}

bool spansContain(const SpanList& spans, double t) {
  for (const Span& s : spans) {
    if (t < s.lo) return false;
    if (t <= s.hi) return true;
  }
  return false;
}

double totalLength(const SpanList& spans) {
  double sum = 0;
  for (const Span& s : spans) sum += s.length();
  return sum;
}

SpanList spanDifference(const SpanList& a, const SpanList& b) {
  SpanList out;
  std::size_t j = 0;
  for (Span s : a) {
    while (j < b.size() && b[j].hi <= s.lo) ++j;
    std::size_t k = j;
    while (k < b.size() && b[k].lo < s.hi) {
      if (b[k].lo > s.lo) out.push_back({s.lo, b[k].lo});
      s.lo = std::max(s.lo, b[k].hi);
      ++k;
    }
    if (s.lo < s.hi) out.push_back(s);
  }
  return out;
}

}  // namespace art2part
