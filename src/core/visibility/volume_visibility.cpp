// Volume visibility (thesis 3.2.5): the delta volume as voxels and, per voxel, the directions it is reachable from.
#include "art2part/visibility/volume_visibility.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <thread>
#include <unordered_map>
#include <utility>

#include "art2part/common/parallel.h"
#include "volume_visibility_height_map.h"

namespace art2part {

namespace {

using volume::HeightMap;

constexpr int kWordBits = 64;

int threadCount(int requested, int work) {
  const int hw = static_cast<int>(std::thread::hardware_concurrency());
  const int threads = requested > 0 ? requested : std::max(1, hw);
  return std::clamp(threads, 1, std::max(1, work));
}


// ---- inside / outside -------------------------------------------------------------------------------------------

// A crossing of a column's +z ray with the surface: +1 entering the part (face looking down), -1 leaving.
struct Crossing {
  float z;
  int sign;
  bool operator<(const Crossing& o) const { return z < o.z; }
};

// Column centres are nudged off the voxel lattice by an irrational-looking fraction of a voxel: meshes of
// axis-aligned parts put triangle edges (box diagonals, shared edges) exactly through lattice points, where a ray
// would count a crossing twice or not at all.
Eigen::Vector2d columnNudge(double voxel) { return voxel * Eigen::Vector2d(1.234567e-4, 2.718281e-4); }

void addCrossings(const Mesh& mesh, int t, const VoxelGrid& g, std::vector<std::vector<Crossing>>& columns) {
  const Vec3 &a = mesh.corner(t, 0), &b = mesh.corner(t, 1), &c = mesh.corner(t, 2);
  const double area2 = (b.x() - a.x()) * (c.y() - a.y()) - (c.x() - a.x()) * (b.y() - a.y());
  if (area2 == 0) return;  // vertical: a z ray never crosses it
  const Eigen::Vector2d nudge = columnNudge(g.voxel);
  auto column = [&](double x, double nudge_x) { return (x - g.origin.x() - nudge_x) / g.voxel - 0.5; };
  const int i0 = std::max(0, static_cast<int>(std::ceil(column(std::min({a.x(), b.x(), c.x()}), nudge.x()))));
  const int i1 = std::min(g.nx - 1, static_cast<int>(std::floor(column(std::max({a.x(), b.x(), c.x()}), nudge.x()))));
  auto row = [&](double y) { return (y - g.origin.y() - nudge.y()) / g.voxel - 0.5; };
  const int j0 = std::max(0, static_cast<int>(std::ceil(row(std::min({a.y(), b.y(), c.y()})))));
  const int j1 = std::min(g.ny - 1, static_cast<int>(std::floor(row(std::max({a.y(), b.y(), c.y()})))));
  const int sign = area2 > 0 ? -1 : 1;  // counter-clockwise from above: normal up, the ray leaves
  for (int j = j0; j <= j1; ++j)
    for (int i = i0; i <= i1; ++i) {
      const double x = g.origin.x() + (i + 0.5) * g.voxel + nudge.x();
      const double y = g.origin.y() + (j + 0.5) * g.voxel + nudge.y();
      // Barycentric coordinates; inside when all share the sign of the area.
      const double wa = ((b.x() - x) * (c.y() - y) - (c.x() - x) * (b.y() - y)) / area2;
      const double wb = ((c.x() - x) * (a.y() - y) - (a.x() - x) * (c.y() - y)) / area2;
      const double wc = 1.0 - wa - wb;
      if (wa < 0 || wb < 0 || wc < 0) continue;
      columns[std::size_t(j) * g.nx + i].push_back({float(wa * a.z() + wb * b.z() + wc * c.z()), sign});
    }
}

// ---- per-chunk reachability words ------------------------------------------------------------------------------

// Bit b of word(v) = voxel v sees direction chunk_start + b. One row of voxels along x at a time, so the
// projections advance by constant steps.
void rowWords(const VoxelGrid& g, const std::vector<char>& outside, const std::vector<HeightMap>& maps,
              double tolerance, int j, int k, std::uint64_t* words) {
  const int base = g.index(0, j, k);
  std::fill(words + base, words + base + g.nx, 0);
  const Vec3 first = g.centre(0, j, k);
  for (std::size_t m = 0; m < maps.size(); ++m) {
    const HeightMap& map = maps[m];
    const std::uint64_t bit = std::uint64_t(1) << m;
    const double du = g.voxel * map.e1.x() * map.inv_pixel, dv = g.voxel * map.e2.x() * map.inv_pixel;
    const double dh = g.voxel * map.d.x();
    double u = (first.dot(map.e1) - map.u0) * map.inv_pixel, v = (first.dot(map.e2) - map.v0) * map.inv_pixel;
    double h = first.dot(map.d) + tolerance;
    for (int i = 0; i < g.nx; ++i, u += du, v += dv, h += dh) {
      if (!outside[base + i]) continue;
      const int pu = std::clamp(static_cast<int>(u), 0, map.w - 1);
      const int pv = std::clamp(static_cast<int>(v), 0, map.h - 1);
      if (h >= map.height[std::size_t(pv) * map.w + pu]) words[base + i] |= bit;
    }
  }
}

// Cones are interned 64 directions at a time: after chunk c a voxel's id names the distinct prefix (its bits for
// directions [0, 64 (c+1))), and the prefix table of chunk c maps (previous id, new word) to the next id. The
// full cone is never held per voxel, only the final table of distinct ones.
struct Prefix {
  std::uint32_t parent;
  std::uint64_t word;
  bool operator==(const Prefix& o) const { return parent == o.parent && word == o.word; }
};
struct PrefixHash {
  std::size_t operator()(const Prefix& p) const {
    return std::hash<std::uint64_t>()(p.word * 0x9E3779B97F4A7C15ull ^ (std::uint64_t(p.parent) << 17 | p.parent));
  }
};

// Serial on purpose: ids are handed out in voxel order, so the result does not depend on the thread count.
std::vector<Prefix> internChunk(const std::vector<std::uint64_t>& words, std::vector<std::uint32_t>& ids) {
  std::vector<Prefix> table;
  std::unordered_map<Prefix, std::uint32_t, PrefixHash> index;
  Prefix last{VolumeVisibility::kInsidePart, 0};
  std::uint32_t last_id = 0;
  for (std::size_t v = 0; v < ids.size(); ++v) {
    if (ids[v] == VolumeVisibility::kInsidePart) continue;
    const Prefix key{ids[v], words[v]};
    if (!(key == last)) {  // neighbours along x mostly repeat the key: skip the hash
      auto found = index.emplace(key, static_cast<std::uint32_t>(table.size()));
      if (found.second) table.push_back(key);
      last = key, last_id = found.first->second;
    }
    ids[v] = last_id;
  }
  return table;
}

// Walks each final id back through the prefix tables to spell out its cone, into the flat table.
std::vector<std::uint64_t> spellCones(const std::vector<std::vector<Prefix>>& tables) {
  if (tables.empty()) return {};
  const std::size_t n = tables.back().size(), words = tables.size();
  std::vector<std::uint64_t> cones(n * words, 0);
  for (std::size_t id = 0; id < n; ++id) {
    std::uint32_t at = static_cast<std::uint32_t>(id);
    for (std::size_t c = words; c-- > 0;) {
      cones[id * words + c] = tables[c][at].word;
      at = tables[c][at].parent;
    }
  }
  return cones;
}

void buildMaps(const Mesh& mesh, const Box& stock, const std::vector<Vec3>& directions, std::size_t start,
               double pixel, int threads, std::vector<HeightMap>& maps) {
  const int count = static_cast<int>(std::min<std::size_t>(kWordBits, directions.size() - start));
  maps.resize(count);
  parallelFor(std::min(threads, count), std::min(threads, count), [&](int t) {
    for (int m = t; m < count; m += threads) {
      maps[m].reset(directions[start + m], stock, pixel);
      maps[m].rasteriseMesh(mesh);
    }
  });
}

void chunkWords(const VoxelGrid& g, const std::vector<char>& outside, const std::vector<HeightMap>& maps,
                double tolerance, int threads, std::vector<std::uint64_t>& words) {
  const int rows = g.ny * g.nz;
  parallelFor(threads, threads, [&](int t) {
    for (int r = t * rows / threads; r < (t + 1) * rows / threads; ++r)
      rowWords(g, outside, maps, tolerance, r % g.ny, r / g.ny, words.data());
  });
}

}  // namespace

int VoxelGrid::voxelAt(const Vec3& p) const {
  const Vec3 f = (p - origin) / voxel;
  const int i = static_cast<int>(std::floor(f.x())), j = static_cast<int>(std::floor(f.y())),
            k = static_cast<int>(std::floor(f.z()));
  if (i < 0 || j < 0 || k < 0 || i >= nx || j >= ny || k >= nz) return -1;
  return index(i, j, k);
}

std::size_t VolumeVisibility::deltaVoxels() const {
  return static_cast<std::size_t>(
      std::count_if(cone_of_voxel.begin(), cone_of_voxel.end(), [](std::uint32_t c) { return c != kInsidePart; }));
}

std::size_t VolumeVisibility::bytes() const {
  return cone_of_voxel.size() * sizeof(std::uint32_t) + cone_words.size() * sizeof(std::uint64_t);
}

VoxelGrid stockGrid(const Mesh& mesh, const VolumeVisibilityOptions& options) {
  if (!(options.voxel_size > 0)) throw InputError("volume visibility: voxel size must be positive");
  const Box box = boundingBox(mesh);
  if (box.empty()) throw InputError("volume visibility: the mesh is empty");
  const Vec3 size = box.size() + Vec3::Constant(2 * std::max(0.0, options.margin));
  const Eigen::Array3d n = (size / options.voxel_size).array().ceil().max(1.0);
  const double count = n.prod();
  if (count > options.max_voxels) {
    std::ostringstream msg;
    msg << "volume visibility: voxel size " << options.voxel_size << " mm gives " << n.x() << " x " << n.y() << " x "
        << n.z() << " = " << count << " voxels over the " << size.x() << " x " << size.y() << " x " << size.z()
        << " mm stock, more than " << options.max_voxels << "; use a larger voxel size";
    throw InputError(msg.str());
  }
  VoxelGrid g;
  g.voxel = options.voxel_size;
  g.nx = static_cast<int>(n.x()), g.ny = static_cast<int>(n.y()), g.nz = static_cast<int>(n.z());
  g.origin = box.center() - 0.5 * options.voxel_size * Vec3(n.x(), n.y(), n.z());
  return g;
}

std::vector<char> voxelsOutsidePart(const Mesh& mesh, const VoxelGrid& g) {
  std::vector<std::vector<Crossing>> columns(static_cast<std::size_t>(g.nx) * g.ny);
  for (int t = 0; t < mesh.triangleCount(); ++t) addCrossings(mesh, t, g, columns);
  std::vector<char> outside(g.size(), 1);
  for (int j = 0; j < g.ny; ++j)
    for (int i = 0; i < g.nx; ++i) {
      auto& col = columns[std::size_t(j) * g.nx + i];
      std::sort(col.begin(), col.end());
      // Winding number below each voxel centre; non-zero is inside whichever way the mesh is oriented.
      int winding = 0;
      std::size_t next = 0;
      for (int k = 0; k < g.nz; ++k) {
        const double z = g.origin.z() + (k + 0.5) * g.voxel;
        while (next < col.size() && col[next].z < z) winding += col[next++].sign;
        if (winding != 0) outside[g.index(i, j, k)] = 0;
      }
    }
  return outside;
}

VolumeVisibility volumeVisibility(const Mesh& mesh, const std::vector<Vec3>& directions,
                                  const VolumeVisibilityOptions& options) {
  VolumeVisibility result;
  result.grid = stockGrid(mesh, options);
  result.directions = static_cast<int>(directions.size());
  const VoxelGrid& g = result.grid;
  const std::vector<char> outside = voxelsOutsidePart(mesh, g);
  result.cone_of_voxel.assign(g.size(), 0);
  for (std::size_t v = 0; v < g.size(); ++v)
    if (!outside[v]) result.cone_of_voxel[v] = VolumeVisibility::kInsidePart;

  const double tolerance = options.tolerance >= 0 ? options.tolerance : 1e-3 * g.voxel;
  const double pixel = g.voxel * (options.pixel_ratio > 0 ? options.pixel_ratio : 0.5);
  const int threads = threadCount(options.threads, g.ny * g.nz);
  Box stock;
  stock.extend(g.origin);
  stock.extend(g.origin + g.voxel * Vec3(g.nx, g.ny, g.nz));

  std::vector<HeightMap> maps;
  std::vector<std::uint64_t> words(g.size());
  std::vector<std::vector<Prefix>> tables;
  for (std::size_t start = 0; start < directions.size(); start += kWordBits) {
    buildMaps(mesh, stock, directions, start, pixel, threads, maps);
    chunkWords(g, outside, maps, tolerance, threads, words);
    tables.push_back(internChunk(words, result.cone_of_voxel));
  }
  result.words_per_cone = static_cast<int>(tables.size());
  result.cone_words = spellCones(tables);
  return result;
}

}  // namespace art2part
