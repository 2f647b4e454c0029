// Checkpoints of the verification's sweep (sweep_checkpoints.h).
#include "sweep_checkpoints.h"

#include <algorithm>
#include <cstring>
#include <string>

namespace art2part::sweep_checkpoints {

namespace {

// FNV-1a, 64 bits: a hash of bytes fed in order.
class Hash {
 public:
  explicit Hash(std::uint64_t seed = 1469598103934665603ull) : h_(seed) {}
  void bytes(const void* data, std::size_t n) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < n; ++i) h_ = (h_ ^ p[i]) * 1099511628211ull;
  }
  void number(double v) { bytes(&v, sizeof v); }
  void integer(std::int64_t v) { bytes(&v, sizeof v); }
  void text(const std::string& s) {
    integer(static_cast<std::int64_t>(s.size()));
    bytes(s.data(), s.size());
  }
  void vec(const Vec3& v) {
    for (int i = 0; i < 3; ++i) number(v[i]);
  }
  void mesh(const Mesh& m) {
    integer(static_cast<std::int64_t>(m.vertices.size()));
    for (const Vec3& v : m.vertices) vec(v);
    integer(static_cast<std::int64_t>(m.triangles.size()));
    for (const auto& t : m.triangles) bytes(t.data(), sizeof(t[0]) * t.size());
  }
  void row(const CutterLocation& r) {
    integer(r.op);
    integer(r.setup);
    text(r.tool);
    integer(static_cast<int>(r.move));
    vec(r.tip);
    vec(r.axis);
  }
  std::uint64_t value() const { return h_; }

 private:
  std::uint64_t h_;
};

}  // namespace

std::uint64_t inputsKey(const DexelLattice& lattice, const Mesh& part, const Mesh* stock_mesh,
                        const VerifyOptions& options) {
  Hash h;
  h.vec(lattice.box.min);
  h.vec(lattice.box.max);
  h.vec(lattice.spacing);
  h.mesh(part);
  h.integer(stock_mesh ? 1 : 0);
  if (stock_mesh) h.mesh(*stock_mesh);
  for (double v : {options.tolerance, options.step_fraction, options.tool_chord_mm}) h.number(v);
  h.integer(options.cusp_step ? 1 : 0);
  return h.value();
}

std::vector<std::uint64_t> prefixKeys(const Toolpath& path, const std::vector<int>& rows, std::uint64_t inputs,
                                      const std::vector<Tool>& tools) {
  std::map<std::string, std::uint64_t> shapes;  // by id: the hash of the tool's shape
  for (const Tool& t : tools) {
    Hash h;
    h.integer(static_cast<int>(t.type));
    for (double v : {t.diameter, t.corner_radius, t.point_angle_deg, t.flute_length, t.shank_diameter, t.stickout})
      h.number(v);
    for (const HolderStep& step : t.holder) {
      h.number(step.diameter);
      h.number(step.length);
    }
    shapes[t.id] = h.value();
  }
  std::vector<std::uint64_t> keys;
  Hash h(inputs);
  std::size_t next = 0;
  for (int row : rows) {
    for (; next < static_cast<std::size_t>(row) && next < path.size(); ++next) {
      h.row(path[next]);
      const auto shape = shapes.find(path[next].tool);
      h.integer(static_cast<std::int64_t>(shape == shapes.end() ? 0 : shape->second));
    }
    keys.push_back(h.value());
  }
  return keys;
}

std::vector<int> checkpointRows(const Toolpath& path, int count) {
  std::vector<int> changes;  // rows where the setup changes
  for (std::size_t r = 1; r < path.size(); ++r)
    if (path[r].setup != path[r - 1].setup) changes.push_back(static_cast<int>(r));
  if (static_cast<int>(changes.size()) <= count) return changes;
  std::vector<int> rows;
  for (int k = 1; k <= count && !changes.empty(); ++k) {
    const double share = static_cast<double>(path.size()) * k / (count + 1);
    auto it = std::upper_bound(changes.begin(), changes.end(), share);
    if (it == changes.begin()) continue;
    const int row = *std::prev(it);
    if (rows.empty() || rows.back() != row) rows.push_back(row);
  }
  return rows;
}

int resumable(const std::vector<SweepCheckpoint>& from, const Toolpath& path, std::uint64_t inputs,
              const std::vector<Tool>& tools) {
  std::vector<int> rows;
  for (const SweepCheckpoint& c : from) rows.push_back(std::min<int>(c.row, static_cast<int>(path.size())));
  std::vector<int> order(from.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return rows[a] < rows[b]; });
  std::vector<int> sorted;
  for (int i : order) sorted.push_back(rows[i]);
  const std::vector<std::uint64_t> keys = prefixKeys(path, sorted, inputs, tools);
  for (std::size_t k = order.size(); k-- > 0;) {
    const SweepCheckpoint& c = from[order[k]];
    if (c.row <= 0 || c.row >= static_cast<int>(path.size())) continue;
    if (keys[k] == c.key && toolPlacedAt(path, c.row)) return order[k];
  }
  return -1;
}

void addSweep(SweepResult& into, const SweepResult& piece) {
  for (const auto& [row, finding] : piece.findings) into.findings[row] = finding;
  for (const auto& [op, swept] : piece.by_op) {
    OperationSweep& o = into.by_op[op];
    o.removed_mm3 += swept.removed_mm3;
    if (swept.deepest_level_cut_mm > o.deepest_level_cut_mm) {
      o.deepest_level_cut_mm = swept.deepest_level_cut_mm;
      o.deepest_level_cut_row = swept.deepest_level_cut_row;
    }
    std::vector<double>& bins = o.level_cut_by_height_mm3;
    if (bins.size() < swept.level_cut_by_height_mm3.size()) bins.resize(swept.level_cut_by_height_mm3.size(), 0.0);
    for (std::size_t b = 0; b < swept.level_cut_by_height_mm3.size(); ++b) bins[b] += swept.level_cut_by_height_mm3[b];
  }
  into.poses += piece.poses;
  into.seconds += piece.seconds;
  into.cancelled = into.cancelled || piece.cancelled;
}

}  // namespace art2part::sweep_checkpoints
