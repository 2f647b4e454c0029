// What each setup direction can reach (setup_plan.h reachMatrix): in 3-axis the visibility map itself; in 5-axis a
// triangle is reached from setup direction s when its visibility cone meets the cap of directions within the tilt of
// s. Identical cones are merged first (a 100k-triangle part has far fewer distinct cones), each distinct cone is
// tested against every cap word by word, and the rows are scattered back.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <thread>
#include <unordered_map>

#include "art2part/common/angles.h"
#include "art2part/common/parallel.h"

#include "setup_internal.h"

namespace art2part {
namespace {

// Hash and equality of BitMatrix rows by row index, so identical cones meet in one map entry.
struct RowHash {
  const BitMatrix* m;
  std::size_t operator()(int r) const {
    std::uint64_t h = 1469598103934665603ull;
    const std::uint64_t* w = m->row(r);
    for (int i = 0; i < m->wordsPerRow(); ++i) {
      h ^= w[i] + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2);
      h *= 1099511628211ull;
    }
    return static_cast<std::size_t>(h ^ (h >> 29));
  }
};

struct RowEqual {
  const BitMatrix* m;
  bool operator()(int a, int b) const {
    return std::memcmp(m->row(a), m->row(b), sizeof(std::uint64_t) * m->wordsPerRow()) == 0;
  }
};

struct DistinctRows {
  std::vector<int> representative;  // one row per distinct content
  std::vector<int> index_of;        // per row: its distinct content
};

DistinctRows distinctRows(const BitMatrix& m) {
  DistinctRows out;
  out.index_of.resize(m.rows());
  std::unordered_map<int, int, RowHash, RowEqual> seen(static_cast<std::size_t>(m.rows()) / 4 + 16, RowHash{&m},
                                                       RowEqual{&m});
  for (int r = 0; r < m.rows(); ++r) {
    const auto inserted = seen.emplace(r, static_cast<int>(out.representative.size()));
    if (inserted.second) out.representative.push_back(r);
    out.index_of[r] = inserted.first->second;
  }
  return out;
}

// caps.row(s): the directions within the tilt of direction s (the cap is symmetric: d is in s's cap when s is in d's).
BitMatrix tiltCaps(const std::vector<Vec3>& directions, double tilt_deg) {
  const int D = static_cast<int>(directions.size());
  const double min_cos = std::cos(tilt_deg * kPi / 180.0) - 1e-12;
  BitMatrix caps(D, D);
  for (int s = 0; s < D; ++s)
    for (int d = s; d < D; ++d)
      if (directions[s].dot(directions[d]) >= min_cos) {
        caps.set(s, d);
        caps.set(d, s);
      }
  return caps;
}

bool meets(const std::uint64_t* a, const std::uint64_t* b, const std::vector<int>& words) {
  for (int w : words)
    if (a[w] & b[w]) return true;
  return false;
}

// Rows [begin, end) of `reach`: distinct cone u reaches s when it meets s's cap.
void reachOfCones(const BitMatrix& bits, const std::vector<int>& representative, const BitMatrix& caps,
                  BitMatrix& reach, int begin, int end) {
  std::vector<int> words;
  for (int u = begin; u < end; ++u) {
    const std::uint64_t* cone = bits.row(representative[u]);
    words.clear();
    for (int w = 0; w < bits.wordsPerRow(); ++w)
      if (cone[w]) words.push_back(w);
    if (words.empty()) continue;
    std::uint64_t* out = reach.row(u);
    for (int s = 0; s < caps.rows(); ++s)
      if (meets(cone, caps.row(s), words)) out[s >> 6] |= std::uint64_t(1) << (s & 63);
  }
}

// The reach of every distinct cone, spread over the hardware threads (rows are whole words: no sharing).
BitMatrix distinctReach(const BitMatrix& bits, const std::vector<int>& representative, const BitMatrix& caps) {
  const int U = static_cast<int>(representative.size());
  BitMatrix reach(U, caps.rows());
  const int threads = std::clamp(static_cast<int>(std::thread::hardware_concurrency()), 1, std::max(1, U / 256));
  parallelFor(threads, threads,
              [&](int i) { reachOfCones(bits, representative, caps, reach, U * i / threads, U * (i + 1) / threads); });
  return reach;
}

}  // namespace

BitMatrix reachMatrix(const VisibilityResult& visibility, const SetupOptions& options) {
  const BitMatrix& bits = visibility.map.bits;
  if (bits.columns() != visibility.directions.size())
    throw InputError("the visibility map has " + std::to_string(bits.columns()) + " directions, the direction set " +
                     std::to_string(visibility.directions.size()));
  if (!(options.max_tilt_deg > 0.0 && options.max_tilt_deg <= 180.0))
    throw InputError("the 5-axis tilt must be in (0, 180] degrees, not " + std::to_string(options.max_tilt_deg));
  if (options.mode == MachineMode::ThreeAxis) return bits;
  const DistinctRows cones = distinctRows(bits);
  const BitMatrix caps = tiltCaps(visibility.directions.directions, options.max_tilt_deg);
  const BitMatrix distinct = distinctReach(bits, cones.representative, caps);
  BitMatrix reach(bits.rows(), bits.columns());
  const std::size_t bytes = sizeof(std::uint64_t) * bits.wordsPerRow();
  for (int t = 0; t < bits.rows(); ++t) std::memcpy(reach.row(t), distinct.row(cones.index_of[t]), bytes);
  return reach;
}

}  // namespace art2part
