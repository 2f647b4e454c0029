// Volume visibility benchmark (issue 3 item 5): grid size, delta volume, time and memory of the interned cones on
// shared parts, beside a plain bitset per voxel.
//   bench_volume_visibility [PART VOXEL_MM [LEVEL]]   (default: ANC101 at 2 mm and CTC 1 at 4 mm, level 4)
#include <chrono>
#include <cstdio>
#include <string>

#include "art2part/geometry/part.h"
#include "art2part/sphere/direction_set.h"
#include "art2part/visibility/volume_visibility.h"
#include "bench_main.h"

using namespace art2part;

namespace {

const char* const kUsage =
    "bench_volume_visibility [PART VOXEL_MM [LEVEL]]\n"
    "  PART a file name in shared/parts; default: ANC101 at 2 mm and CTC 1 at 4 mm, level 4\n";
const std::string kParts = ART2PART_SHARED_PARTS;

void run(const std::string& file, double voxel, int level) {
  const Part part = loadPart(kParts + "/" + file);
  const DirectionSet set = sampleSphere(level);
  VolumeVisibilityOptions options;
  options.voxel_size = voxel;
  options.threads = 2;
  const auto start = std::chrono::steady_clock::now();
  const VolumeVisibility vv = volumeVisibility(part.mesh, set.directions, options);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const Vec3 size = boundingBox(part.mesh).size();
  const double mb = 1.0 / (1 << 20);
  const double dense = double(vv.grid.size()) * vv.words_per_cone * 8;
  std::printf("%s (%.0f x %.0f x %.0f mm, %d triangles), voxel %.1f mm\n", file.c_str(), size.x(), size.y(),
              size.z(), part.mesh.triangleCount(), voxel);
  std::printf("  grid %d x %d x %d = %zu voxels, delta volume %zu, directions %d, %.2f s (2 threads)\n", vv.grid.nx,
              vv.grid.ny, vv.grid.nz, vv.grid.size(), vv.deltaVoxels(), set.size(), seconds);
  std::printf("  distinct cones %zu (%.1f%% of delta voxels), %.1f MB (index %.1f + cones %.1f); bitset per voxel "
              "%.1f MB\n",
              vv.coneCount(), 100.0 * vv.coneCount() / std::max<std::size_t>(1, vv.deltaVoxels()), vv.bytes() * mb,
              vv.cone_of_voxel.size() * 4 * mb, vv.cone_words.size() * 8 * mb, dense * mb);
}

int benchMain(const std::vector<std::string>& args) {
  const Arguments a(args, {}, {});
  const std::vector<std::string>& p = positionalAtMost(a, 3);
  if (p.size() == 1) throw UsageError("PART needs VOXEL_MM");
  if (p.size() >= 2) {
    const double voxel = positive(parseNumber(p[1], "VOXEL_MM"), "VOXEL_MM");
    const int level = p.size() > 2 ? atLeast(parseInteger(p[2], "LEVEL"), 0, "LEVEL") : 4;
    requireFile(kParts + "/" + p[0]);
    run(p[0], voxel, level);
    return 0;
  }
  run("ANC101.stp", 2.0, 4);
  run("nist_ctc_01_asme1_rd.stp", 4.0, 4);
  return 0;
}

}  // namespace

int main(int argc, char** argv) { return runBench(argc, argv, kUsage, benchMain); }
