#include "art2part/simulation/stock_mesh.h"

#include <cstdio>

#include "art2part/render/annotate.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <unordered_map>

#include "art2part/render/palette.h"
#include "art2part/render/picture.h"

namespace art2part {

namespace {

using Index3 = std::array<int, 3>;

// Occupancy sampled at every `step`-th lattice point, with one empty layer around (sample indices -1 and n).
class SampleGrid {
 public:
  SampleGrid(const Stock& stock, int step) : stock_(stock), step_(step) {
    for (int k = 0; k < 3; ++k) n_[k] = (stock.lattice.cells[k] - 1) / step + 1;
    occupied_.assign(static_cast<std::size_t>(n_[0] + 2) * (n_[1] + 2) * (n_[2] + 2), 0);
    for (int b = 0; b < n_[1]; ++b)
      for (int a = 0; a < n_[0]; ++a) {
        const SpanList& spans = stock.ray(2, stock.lattice.rayIndex(2, a * step, b * step));
        for (int c = 0; c < n_[2]; ++c) occupied_[slot({a, b, c})] = spansContain(spans, coordinate(2, c));
      }
  }

  const std::array<int, 3>& size() const { return n_; }
  bool inside(const Index3& s) const {
    for (int k = 0; k < 3; ++k)
      if (s[k] < -1 || s[k] > n_[k]) return false;
    return occupied_[slot(s)] != 0;
  }
  double coordinate(int axis, int s) const { return stock_.lattice.coordinate(axis, s * step_); }
  Vec3 point(const Index3& s) const { return Vec3(coordinate(0, s[0]), coordinate(1, s[1]), coordinate(2, s[2])); }

  // Where the material boundary crosses the edge from sample s to s + e_axis (one end inside, one outside), read
  // from the ray of that family through both.
  Vec3 crossing(const Index3& s, int axis) const {
    Index3 e = s;
    ++e[axis];
    const double t0 = coordinate(axis, s[axis]), t1 = coordinate(axis, e[axis]);
    const int u = DexelLattice::uAxis(axis), v = DexelLattice::vAxis(axis);
    Vec3 p = point(s);
    p[axis] = 0.5 * (t0 + t1);
    const SpanList& spans = stock_.ray(axis, stock_.lattice.rayIndex(axis, s[u] * step_, s[v] * step_));
    const bool from_inside = inside(s);
    for (const Span& span : spans) {
      const double t = from_inside ? span.hi : span.lo;
      if (t >= t0 && t <= t1) {
        p[axis] = t;
        break;
      }
    }
    return p;
  }

 private:
  std::size_t slot(const Index3& s) const {
    return (static_cast<std::size_t>(s[2] + 1) * (n_[1] + 2) + (s[1] + 1)) * (n_[0] + 2) + (s[0] + 1);
  }

  const Stock& stock_;
  int step_;
  std::array<int, 3> n_{};
  std::vector<std::uint8_t> occupied_;
};

class SurfaceNets {
 public:
  explicit SurfaceNets(const SampleGrid& grid) : grid_(grid) {}

  Mesh run() {
    const auto& n = grid_.size();
    for (int axis = 0; axis < 3; ++axis)
      for (int c = -1; c <= n[2]; ++c)
        for (int b = -1; b <= n[1]; ++b)
          for (int a = -1; a <= n[0]; ++a) {
            Index3 s{a, b, c}, e{a, b, c};
            if (++e[axis] > n[axis]) continue;
            const bool lower = grid_.inside(s);
            if (lower != grid_.inside(e)) addQuad(s, axis, lower);
          }
    return std::move(mesh_);
  }

 private:
  // The four cells around the edge from s along `axis`, wound so the face looks out of the material.
  void addQuad(const Index3& s, int axis, bool material_below) {
    const int u = DexelLattice::uAxis(axis), v = DexelLattice::vAxis(axis);
    Index3 c10 = s, c11 = s, c01 = s;
    --c10[u];
    --c11[u];
    --c11[v];
    --c01[v];
    int q[4] = {vertex(s), vertex(c10), vertex(c11), vertex(c01)};
    if (!material_below) std::swap(q[1], q[3]);
    mesh_.triangles.push_back({q[0], q[1], q[2]});
    mesh_.triangles.push_back({q[0], q[2], q[3]});
  }

  // The vertex of the cell whose lowest corner is sample c: the mean of the crossings on its twelve edges.
  int vertex(const Index3& c) {
    const std::int64_t key = (static_cast<std::int64_t>(c[2] + 1) * 65536 + (c[1] + 1)) * 65536 + (c[0] + 1);
    const auto found = vertices_.find(key);
    if (found != vertices_.end()) return found->second;
    Vec3 sum = Vec3::Zero();
    int count = 0;
    for (int axis = 0; axis < 3; ++axis)
      for (int corner = 0; corner < 4; ++corner) {
        Index3 s = c;
        s[DexelLattice::uAxis(axis)] += corner & 1;
        s[DexelLattice::vAxis(axis)] += corner >> 1;
        Index3 e = s;
        ++e[axis];
        if (grid_.inside(s) == grid_.inside(e)) continue;
        sum += grid_.crossing(s, axis);
        ++count;
      }
    const int index = static_cast<int>(mesh_.vertices.size());
    mesh_.vertices.push_back(count > 0 ? Vec3(sum / count) : grid_.point(c));
    vertices_.emplace(key, index);
    return index;
  }

  const SampleGrid& grid_;
  Mesh mesh_;
  std::unordered_map<std::int64_t, int> vertices_;
};

bool stockContainsNear(const Stock& stock, const Vec3& p) {
  const DexelLattice& lattice = stock.lattice;
  const double fx = (p.x() - lattice.box.min.x()) / lattice.spacing.x();
  const double fy = (p.y() - lattice.box.min.y()) / lattice.spacing.y();
  if (fx < 0 || fy < 0 || fx >= lattice.cells[0] || fy >= lattice.cells[1]) return false;
  return spansContain(stock.ray(2, lattice.rayIndex(2, static_cast<int>(fx), static_cast<int>(fy))), p.z());
}

// Signed distance of a triangle of the stock's mesh to the part: + stock left, - a gouge. Contouring rounds the
// stock's sharp edges by up to half a cell, so a triangle inside the part only counts as a gouge when the material
// just outside it, towards the air, is part material the tool removed; otherwise it lies on the part (0).
double deviation(const Mesh& mesh, int t, const Stock& stock, const MeshDexels& part, const PartDistance& distance) {
  const Vec3 c = triangleCentroid(mesh, t);
  const double d = distance.distance(c);
  if (!part.containsNear(c)) return d;
  const Vec3 probe = c + 0.5 * std::min(d, stock.lattice.minSpacing()) * triangleNormal(mesh, t);
  return part.containsNear(probe) && !stockContainsNear(stock, probe) ? -d : 0.0;
}

}  // namespace

StockMesh remainingStockMesh(const Stock& stock, const MeshDexels& part, const PartDistance& part_distance,
                             int max_cells) {
  const int longest = *std::max_element(stock.lattice.cells.begin(), stock.lattice.cells.end());
  const int step = std::max(1, (longest + std::max(max_cells, 1) - 1) / std::max(max_cells, 1));
  const SampleGrid grid(stock, step);
  StockMesh out;
  out.mesh = SurfaceNets(grid).run();
  out.deviation.resize(out.mesh.triangles.size());
  for (int t = 0; t < out.mesh.triangleCount(); ++t) out.deviation[t] = deviation(out.mesh, t, stock, part, part_distance);
  return out;
}

std::vector<std::array<unsigned char, 3>> deviationColours(const std::vector<double>& deviation, double scale,
                                                           double tolerance) {
  std::vector<std::array<unsigned char, 3>> colours;
  colours.reserve(deviation.size());
  for (double d : deviation) {
    const Rgb c = d < -tolerance ? Rgb{0.9f, 0.1f, 0.1f} : rampColour(std::max(d, 0.0) / std::max(scale, 1e-9));
    colours.push_back({static_cast<unsigned char>(255 * c[0]), static_cast<unsigned char>(255 * c[1]),
                       static_cast<unsigned char>(255 * c[2])});
  }
  return colours;
}

void writeDeviationPicture(const StockMesh& stock_mesh, double scale, double tolerance, const std::string& path,
                           const std::string& title) {
  if (stock_mesh.mesh.triangles.empty()) throw InputError("no stock is left to draw in " + path);
  PictureOptions options;
  options.triangle_colours = deviationColours(stock_mesh.deviation, scale, tolerance);
  ColourScale legend;
  legend.caption = "stock above the part";
  legend.unit = "mm";
  legend.low = 0;
  legend.high = scale;
  legend.colour = [scale](double v) { return rampColour(v / std::max(scale, 1e-9)); };
  char gouge[80];
  std::snprintf(gouge, sizeof gouge, "gouge deeper than %.3g mm", tolerance);
  legend.extra = {{Rgb{0.9f, 0.1f, 0.1f}, gouge}};
  const Image image = withScale(renderPicture(stock_mesh.mesh, options), title, legend);
  try {
    writePng(image, path);
  } catch (const std::runtime_error& e) {
    throw InputError(e.what());
  }
}

}  // namespace art2part
