// Sampling the Gaussian sphere: how even the cells are (largest / smallest area) for both bases, what a set costs
// to build, and how fast directions are located in it.
#include <chrono>
#include <cstdio>
#include <random>

#include "art2part/sphere/direction_set.h"
#include "bench_main.h"

using namespace art2part;

namespace {

const char* const kUsage = "bench_sphere   (no arguments)\n";

double secondsToBuild(int level, SphereBase base, int repeats) {
  const auto start = std::chrono::steady_clock::now();
  int cells = 0;
  for (int i = 0; i < repeats; ++i) cells += sampleSphere(level, base).cellCount();
  const std::chrono::duration<double> elapsed = std::chrono::steady_clock::now() - start;
  return cells > 0 ? elapsed.count() / repeats : 0.0;
}

double secondsPerLookup(const DirectionSet& set, int count) {
  std::mt19937 rng(1);
  std::normal_distribution<double> g;
  std::vector<Vec3> dirs;
  for (int i = 0; i < count; ++i) dirs.push_back(Vec3(g(rng), g(rng), g(rng)).normalized());
  const auto start = std::chrono::steady_clock::now();
  long long sum = 0;
  for (const Vec3& d : dirs) sum += cellContaining(set, d);
  const std::chrono::duration<double> elapsed = std::chrono::steady_clock::now() - start;
  return sum >= 0 ? elapsed.count() / count : 0.0;
}

const char* name(SphereBase base) { return base == SphereBase::Tetrahedron ? "tetrahedron" : "icosahedron"; }

int benchMain(const std::vector<std::string>& args) {
  positionalAtMost(Arguments(args, {}, {}), 0);  // no arguments: any is a usage mistake
  std::printf("cell area ratio (largest / smallest)\n%-6s %22s %22s\n", "level", "tetrahedron (cells)",
              "icosahedron (cells)");
  for (int level = 0; level <= 7; ++level) {
    const DirectionSet t = sampleSphere(level, SphereBase::Tetrahedron);
    const DirectionSet i = sampleSphere(level, SphereBase::Icosahedron);
    std::printf("%-6d %12.3f (%7d) %12.3f (%7d)\n", level, cellAreaRatio(t), t.cellCount(), cellAreaRatio(i),
                i.cellCount());
  }
  std::printf("\nbuild time\n");
  for (SphereBase base : {SphereBase::Tetrahedron, SphereBase::Icosahedron})
    for (int level : {4, 7})
      std::printf("%-12s level %d: %8.3f ms\n", name(base), level, 1e3 * secondsToBuild(level, base, level < 7 ? 50 : 5));
  std::printf("\ncellContaining (random directions)\n");
  for (SphereBase base : {SphereBase::Tetrahedron, SphereBase::Icosahedron})
    for (int level : {4, 7}) {
      const DirectionSet set = sampleSphere(level, base);
      std::printf("%-12s level %d: %8.3f us per lookup\n", name(base), level, 1e6 * secondsPerLookup(set, 100000));
    }
  return 0;
}

}  // namespace

int main(int argc, char** argv) { return runBench(argc, argv, kUsage, benchMain); }
