// Cone thinning (thesis 4.1.3.1). The work per call is the depth of the directions that can end up in the skeleton:
// for each, the largest cosine to the directions just outside the cone (the rim, found through the cells' neighbour
// lists), given up as soon as it is too shallow. This runs once per voxel, tens of thousands of times per setup: a
// 40-degree cap at level 4 (~120 directions, a rim of ~60) takes ~10 us.
#include "art2part/roughing/cone_thinning.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>

#include "art2part/common/angles.h"

namespace art2part {

namespace {

std::size_t wordsOf(const DirectionSet& set) { return (static_cast<std::size_t>(set.size()) + 63) / 64; }

void put(Cone& c, int d) { c[d >> 6] |= std::uint64_t(1) << (d & 63); }
bool has(const Cone& c, int d) { return (c[d >> 6] >> (d & 63)) & 1u; }

bool isEmpty(const Cone& c) {
  return std::all_of(c.begin(), c.end(), [](std::uint64_t w) { return w == 0; });
}

// `c` laid out on the set's words: missing words are empty, bits at or beyond set.size() are cleared, so word-wise
// complements and intersections below never see directions that do not exist.
Cone fitted(const DirectionSet& set, const Cone& c) {
  Cone out(wordsOf(set), 0);
  std::copy_n(c.begin(), std::min(c.size(), out.size()), out.begin());
  if (set.size() % 64 != 0) out.back() &= (std::uint64_t(1) << (set.size() % 64)) - 1;
  return out;
}

Cone intersection(const Cone& a, const Cone& b) {  // both fitted
  Cone c(a.size());
  for (std::size_t w = 0; w < c.size(); ++w) c[w] = a[w] & b[w];
  return c;
}

template <class F>
void forEach(const Cone& c, F f) {
  for (std::size_t w = 0; w < c.size(); ++w)
    for (std::uint64_t bits = c[w]; bits != 0; bits &= bits - 1)
      f(static_cast<int>(64 * w) + __builtin_ctzll(bits));
}

// The width of one peeled layer: the mean spacing of the sampled directions (6.3 degrees at level 4).
double layerWidth(const DirectionSet& set) { return std::sqrt(4 * kPi / std::max(1, set.cellCount())); }

// The directions outside `region` (fitted) that touch it: representatives of cells sharing an edge or a corner with
// the cell of a region direction (direction c < cellCount() is cell c's own). Extra directions, beyond cellCount(),
// are few and all taken when outside. The nearest outside direction of a region direction is among these (checked
// against all outside directions in test_cone_thinning).
//
// The boundary is thus taken at the outside directions, up to one (uneven: 2.3 to 9.9 degrees at level 4) spacing
// beyond the region. Midpoints of inside/outside pairs, or the edges of the region's cells, were tried: on caps of
// 20 to 90 degrees about 200 axes they placed the access direction no better (mean 3.1 to 3.5 degrees off the axis,
// where the nearest sampled direction is itself up to 7 degrees off) at two to three times the work.
std::vector<Vec3> rim(const DirectionSet& set, const Cone& region) {
  Cone touched(region.size(), 0);
  forEach(region, [&](int d) {
    const int c = set.cell_of[d];
    put(touched, c);
    for (int n : set.edge_neighbours[c]) put(touched, n);
    for (int n : set.vertex_neighbours[c]) put(touched, n);
  });
  for (int e = set.cellCount(); e < set.size(); ++e) put(touched, e);
  for (std::size_t w = 0; w < touched.size(); ++w) touched[w] &= ~region[w];
  std::vector<Vec3> out;
  forEach(touched, [&](int o) { out.push_back(set.directions[o]); });
  return out;
}

// Directions of a last layer, each with its height above the layer's floor (radians).
struct Layer {
  std::vector<int> directions;
  std::vector<double> height;
};

// The last layer of `candidates` (a subset of `region`, both fitted) while `region` is peeled: the candidates whose
// depth in the region is within one layer width of the deepest candidate's. All of them (height 1) when the region
// has no outside and nothing is peeled.
Layer lastLayer(const DirectionSet& set, const Cone& region, const Cone& candidates) {
  Layer layer;
  const std::vector<Vec3> outside = rim(set, region);
  if (outside.empty()) {
    forEach(candidates, [&](int d) { layer.directions.push_back(d), layer.height.push_back(1.0); });
    return layer;
  }
  // Depths as cosines to the nearest outside direction (smaller is deeper). A candidate is dropped as soon as one
  // outside direction shows it too shallow for the layer of the deepest so far; the candidate nearest the
  // candidates' mean goes first, as it is likely deep (a cap's centre), so most of the others stop early.
  const double width = layerWidth(set);
  auto limitFor = [&](double deepest) {  // the largest cosine still in the layer
    const double floor_angle = std::acos(std::clamp(deepest, -1.0, 1.0)) - width;
    return floor_angle <= 0 ? 2.0 : std::cos(floor_angle) + 1e-12;
  };
  Vec3 mean = Vec3::Zero();
  forEach(candidates, [&](int d) { mean += set.directions[d]; });
  int first = -1;
  forEach(candidates, [&](int d) {
    if (first < 0 || set.directions[d].dot(mean) > set.directions[first].dot(mean)) first = d;
  });
  std::vector<int> dirs;
  std::vector<double> nearest;
  double deepest = 2.0, limit = 2.0;
  auto measure = [&](int d) {
    const Vec3& v = set.directions[d];
    double m = -1.0;
    for (const Vec3& o : outside)
      if ((m = std::max(m, v.dot(o))) > limit) return;
    dirs.push_back(d);
    nearest.push_back(m);
    if (m < deepest) deepest = m, limit = limitFor(m);
  };
  measure(first);
  forEach(candidates, [&](int d) {
    if (d != first) measure(d);
  });
  const double floor_angle = std::acos(std::clamp(deepest, -1.0, 1.0)) - width;
  for (std::size_t i = 0; i < dirs.size(); ++i)
    if (nearest[i] <= limit) {  // only the layer's few directions pay for an acos
      layer.directions.push_back(dirs[i]);
      layer.height.push_back(std::acos(std::clamp(nearest[i], -1.0, 1.0)) - floor_angle);
    }
  return layer;
}

Cone asCone(const DirectionSet& set, const Layer& layer) {
  Cone c(wordsOf(set), 0);
  for (int d : layer.directions) put(c, d);
  return c;
}

Layer skeleton(const DirectionSet& set, const Cone& cone, const Cone* secondary) {
  const Cone region = fitted(set, cone);
  const Cone kept = secondary ? intersection(region, fitted(set, *secondary)) : region;
  if (isEmpty(kept)) return {};
  return lastLayer(set, region, kept);
}

}  // namespace

Cone thinCone(const DirectionSet& set, const Cone& cone) { return asCone(set, skeleton(set, cone, nullptr)); }

// "Stop just before the intersection of the shrinking region with the secondary region vanishes": the layers are
// those of the primary, the last one taken among the directions the secondary also holds.
Cone restrictedThinning(const DirectionSet& set, const Cone& primary, const Cone& secondary) {
  return asCone(set, skeleton(set, primary, &secondary));
}

Cone reachCone(const DirectionSet& set, const Vec3& axis, double max_tilt_deg) {
  if (!(axis.norm() > 0)) throw std::invalid_argument("reachCone: zero axis");
  const Vec3 a = axis.normalized();
  const double cos_limit = std::cos(max_tilt_deg * kPi / 180) - 1e-12;
  Cone c(wordsOf(set), 0);
  for (int d = 0; d < set.size(); ++d)
    if (set.directions[d].dot(a) >= cos_limit) put(c, d);
  return c;
}

// The mean is weighted by each member's height above the layer's floor: on caps of 20 to 90 degrees about 200 axes
// this put the access direction at most 7.9 degrees off the axis against 12.2 for the plain mean (mean error 3.1
// against 3.5; the nearest sampled direction is itself up to 7.2 degrees off). A zero mean (the whole sphere) gives
// the first member.
int accessDirection(const DirectionSet& set, const Cone& cone, const Cone* reach) {
  const Layer layer = skeleton(set, cone, reach);
  Vec3 mean = Vec3::Zero();
  for (std::size_t i = 0; i < layer.directions.size(); ++i)
    mean += (layer.height[i] + 1e-9) * set.directions[layer.directions[i]];
  int best = -1;
  double best_dot = -HUGE_VAL;
  for (int d : layer.directions) {
    const double dot = set.directions[d].dot(mean);
    if (dot > best_dot) best_dot = dot, best = d;
  }
  return best;
}

// Cells are counted once, as in coneSolidAngle: a representative counts its cell; an extra direction counts its
// cell only when the representative is not in the intersection (and once however many extras share it).
double intersectionSolidAngle(const DirectionSet& set, const Cone& a, const Cone& b) {
  const Cone both = intersection(fitted(set, a), fitted(set, b));
  double area = 0.0;
  std::vector<int> extra_cells;
  forEach(both, [&](int d) {
    if (d < set.cellCount())
      area += set.cell_area[d];
    else if (!has(both, set.cell_of[d]))
      extra_cells.push_back(set.cell_of[d]);
  });
  std::sort(extra_cells.begin(), extra_cells.end());
  extra_cells.erase(std::unique(extra_cells.begin(), extra_cells.end()), extra_cells.end());
  for (int c : extra_cells) area += set.cell_area[c];
  return area;
}

}  // namespace art2part
