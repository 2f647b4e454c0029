// Verification speed (issue 5): a 10^5-move raster of a 6 mm flat end mill over a real part scaled to 100 mm, swept
// through a tri-dexel stock at 0.2 mm. The raster follows the part (drop-cutter heights read from the part's own z
// dexels, widened by a cell so the flat bottom never dips beside a wall), so the path cuts real stock and should
// verify clean. Prints moves, resolution, dexels, poses, seconds and moves per second.
//   bench_simulation [PART] [--threads N] [--lines N (of 1000 moves; 100)]
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <string>
#include <thread>

#include "art2part/geometry/part.h"
#include "art2part/simulation/mesh_dexels.h"
#include "art2part/simulation/verify.h"
#include "bench_main.h"

using namespace art2part;

namespace {

const char* const kUsage =
    "bench_simulation [PART] [--threads N] [--lines N]\n"
    "  PART: a path, default shared/parts/nist_ctc_01_asme1_rd.stp; --lines: lines of 1000 moves, default 100\n";
constexpr double kResolution = 0.2;
constexpr double kMargin = 2.0;
constexpr double kPartSize = 100.0;
constexpr int kPointsPerLine = 1000;  // by 100 lines: 10^5 moves

double since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

Tool flatSix() {
  Tool t;
  t.id = "flat6";
  t.diameter = 6;
  t.flute_length = 30;
  t.shank_diameter = 6;
  t.stickout = 45;
  t.holder = {{32, 40}, {50, 30}};
  return t;
}

// The part's top along every z ray of the lattice (-infinity where the ray misses it).
class HeightMap {
 public:
  HeightMap(const Mesh& mesh, const DexelLattice& lattice) : lattice_(lattice), dexels_(mesh, lattice) {}

  // The lowest a flat end mill of this radius can sit at (x, y) without its bottom entering the part.
  double dropFlat(double x, double y, double radius, double floor) const {
    const double reach = radius + lattice_.spacing.head<2>().norm();
    const auto is = lattice_.indexRange(0, x - reach, x + reach), js = lattice_.indexRange(1, y - reach, y + reach);
    double z = floor;
    for (int j = js[0]; j <= js[1]; ++j)
      for (int i = is[0]; i <= is[1]; ++i) {
        const double dx = lattice_.coordinate(0, i) - x, dy = lattice_.coordinate(1, j) - y;
        if (dx * dx + dy * dy > reach * reach) continue;
        const int ray = lattice_.rayIndex(2, i, j);
        if (dexels_.begin(2, ray) != dexels_.end(2, ray)) z = std::max(z, (dexels_.end(2, ray) - 1)->hi);
      }
    return z;
  }

 private:
  DexelLattice lattice_;
  MeshDexels dexels_;
};

Toolpath raster(const Mesh& part, const Tool& tool, int lines) {
  const Box box = boundingBox(part);
  const DexelLattice lattice = DexelLattice::over(stockBox(box, kMargin), kResolution);
  const HeightMap heights(part, lattice);
  const double r = 0.5 * tool.diameter, safe = box.max.z() + kMargin + 5;
  Toolpath path;
  for (int line = 0; line < lines; ++line) {
    const double y = box.min.y() - r + (box.size().y() + 2 * r) * line / std::max(lines - 1, 1);
    for (int k = 0; k < kPointsPerLine; ++k) {
      const double f = static_cast<double>(line % 2 ? kPointsPerLine - 1 - k : k) / (kPointsPerLine - 1);
      const double x = box.min.x() - r + (box.size().x() + 2 * r) * f;
      CutterLocation c;
      c.tool = tool.id;
      c.move = line == 0 && k == 0 ? MoveKind::Rapid : MoveKind::Feed;
      c.tip = Vec3(x, y, line == 0 && k == 0 ? safe : heights.dropFlat(x, y, r, box.min.z()));
      path.push_back(c);
    }
  }
  return path;
}

int benchMain(const std::vector<std::string>& args) {
  const Arguments a(args, {}, {"threads", "lines"});
  const std::vector<std::string>& p = positionalAtMost(a, 1);
  const std::string file = p.empty() ? std::string(ART2PART_SHARED_PARTS) + "/nist_ctc_01_asme1_rd.stp" : p[0];
  const int threads = atLeast(a.integer("threads", 0), 0, "--threads");
  const int lines = atLeast(a.integer("lines", 100), 1, "--lines");
  Part part = loadPart(file);
  const Box box = boundingBox(part.mesh);
  scaleMesh(part.mesh, kPartSize / box.size().maxCoeff());
  const Tool tool = flatSix();
  auto start = std::chrono::steady_clock::now();
  const Toolpath path = raster(part.mesh, tool, lines);
  const double seconds_path = since(start);

  VerifyOptions options;
  options.resolution = kResolution;
  options.stock_margin = kMargin;
  options.threads = threads;
  const std::clock_t cpu = std::clock();
  const VerificationReport r = verifyToolpath(part.mesh, part.triangle_face, path, {tool}, options);
  const double cpu_seconds = static_cast<double>(std::clock() - cpu) / CLOCKS_PER_SEC;
  const Vec3 size = boundingBox(part.mesh).size();
  std::printf("part:        %s scaled to %.1f x %.1f x %.1f mm, %d triangles\n", file.c_str(), size.x(), size.y(),
              size.z(), part.mesh.triangleCount());
  std::printf("path:        %d moves (raster, 6 mm flat end mill), %lld poses, %.2f s to make\n", r.moves,
              static_cast<long long>(r.poses), seconds_path);
  std::printf("resolution:  %.3f mm, %lld dexels (%.3f x %.3f x %.3f mm cells)\n", r.resolution_mm,
              static_cast<long long>(r.dexels), r.spacing.x(), r.spacing.y(), r.spacing.z());
  std::printf("sweep:       %.2f s, %.0f moves/s, %.0f poses/s\n", r.seconds_sweep, r.moves_per_second,
              r.poses / std::max(r.seconds_sweep, 1e-9));
  std::printf("total:       %.2f s (dexelize + sweep + leftover), %.2f s of CPU over %u threads\n", r.seconds_total,
              cpu_seconds, threads > 0 ? threads : std::thread::hardware_concurrency());
  std::printf("result:      %d gouges (worst %.4f mm), %d collisions, removed %.0f mm3, leftover %.0f mm3 (max %.2f mm, "
              "%d regions)\n",
              r.gouges, r.worst_gouge_mm, r.collisions, r.removed_volume_mm3, r.leftover_volume_mm3, r.leftover_max_mm,
              r.region_count);
  return 0;
}

}  // namespace

int main(int argc, char** argv) { return runBench(argc, argv, kUsage, benchMain); }
