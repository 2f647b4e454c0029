// Visibility benchmarks (issue 3): speed of both backends beside the naive 1024 x 1024 OSMesa loop, linear scaling
// in triangles and directions, and the agreement of the backends on every shared part.
//   bench_visibility [speed|scaling|accuracy [PART [LEVEL]]|all]   (default all; PART a file name in shared/parts)
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>

#include "art2part/geometry/part.h"
#include "art2part/visibility/analysis.h"
#include "art2part/visibility/cones.h"

using namespace art2part;

namespace {

const std::string kParts = ART2PART_SHARED_PARTS;
constexpr double kPi = 3.14159265358979323846;

double secondsOf(const std::function<void()>& work) {
  const auto start = std::chrono::steady_clock::now();
  work();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void printRate(const char* what, int triangles, int directions, double seconds) {
  const double pairs = static_cast<double>(triangles) * directions;
  std::printf("  %-34s %7d tri x %5d dir  %8.2f s  %12.0f pairs/s\n", what, triangles, directions, seconds,
              pairs / seconds);
}

void speed() {
  std::printf("speed: 100k-triangle part x 1024 directions (level 4), 2 threads unless said\n");
  const Part part = loadPart(kParts + "/nist_ctc_02_asme1_rc_fine_tess.stl");
  const DirectionSet set = sampleSphere(4);
  const int T = part.mesh.triangleCount(), D = set.size();
  double s = secondsOf([&] { rayVisibility(part.mesh, set.directions, withEdgeRefinement()); });
  printRate("ray, 4 samples + edges [default]", T, D, s);
  s = secondsOf([&] { rayVisibility(part.mesh, set.directions); });
  printRate("ray (Embree), 4 samples", T, D, s);
  RayVisibilityOptions one;
  one.samples_per_triangle = 1;
  s = secondsOf([&] { rayVisibility(part.mesh, set.directions, one); });
  printRate("ray (Embree), 1 sample", T, D, s);
  RenderVisibilityOptions render;
  s = secondsOf([&] { renderVisibility(part.mesh, set.directions, render); });
  printRate("render (OSMesa ids), auto resolution", T, D, s);
  // The naive loop: 1024 x 1024 per view, one context. Timed on 64 directions; the rate is what counts.
  RenderVisibilityOptions naive;
  naive.resolution = 1024;
  naive.threads = 1;
  const std::vector<Vec3> some(set.directions.begin(), set.directions.begin() + 64);
  s = secondsOf([&] { renderVisibility(part.mesh, some, naive); });
  printRate("naive render 1024x1024, 1 thread", T, 64, s);
  std::printf("  naive loop extrapolated to %d directions: %.1f s\n", D, s * D / 64.0);
}

void scaling() {
  std::printf("scaling: triangles (STEP tessellated finer) and directions (sphere level), default ray backend\n");
  const DirectionSet set = sampleSphere(4);
  for (double tolerance : {2.0, 0.5, 0.15}) {
    LoadOptions load;
    load.chordal_tolerance = tolerance;
    const Part part = loadPart(kParts + "/nist_ctc_02_asme1_rc.stp", load);
    const double s = secondsOf([&] { rayVisibility(part.mesh, set.directions, withEdgeRefinement()); });
    printRate(("CTC 2, chordal " + std::to_string(tolerance).substr(0, 4) + " mm").c_str(),
              part.mesh.triangleCount(), set.size(), s);
  }
  const Part part = loadPart(kParts + "/nist_ctc_02_asme1_rc_fine_tess.stl");
  for (int level : {3, 4, 5}) {
    const DirectionSet dirs = sampleSphere(level);
    const double s = secondsOf([&] { rayVisibility(part.mesh, dirs.directions, withEdgeRefinement()); });
    printRate(("fine tessellation, level " + std::to_string(level)).c_str(), part.mesh.triangleCount(), dirs.size(), s);
  }
}

void accuracy(const std::string& only, int level) {
  std::printf("accuracy: ray vs render at level 4 with special directions, no side correction; pairs within 2 deg of "
              "grazing left out; lost = seen by a dense ray reference (16 samples) from some direction, by the "
              "backend from none\n");
  const char* parts[] = {"nist_ctc_01_asme1_rd.stp", "nist_ctc_02_asme1_rc.stp", "ANC101.stp", "featuretype.STEP",
                         "ktoolcav.stl", "mount_rush.stl", "Ailette001Solid-nohole-decimated-smoothed.stl",
                         "nist_ctc_02_asme1_rc_fine_tess.stl"};
  const double grazing = std::sin(2.0 * kPi / 180.0);
  for (const char* name : parts) {
    if (!only.empty() && only != name) continue;
    const Part part = loadPart(kParts + "/" + name);
    VisibilityOptions options;
    options.level = level;
    options.side_correction = false;
    const VisibilityResult ray = analyseVisibility(part, options);
    options.backend = VisibilityBackend::Render;
    const VisibilityResult render = analyseVisibility(part, options);
    RayVisibilityOptions dense;
    dense.samples_per_triangle = 16;
    const VisibilityMap reference = rayVisibility(part.mesh, ray.directions.directions, dense);
    long long compared = 0, ray_only = 0, render_only = 0;
    for (int t = 0; t < part.mesh.triangleCount(); ++t) {
      const Vec3 n = triangleNormal(part.mesh, t);
      for (int d = 0; d < ray.map.directions(); ++d) {
        if (std::abs(n.dot(ray.directions.directions[d])) < grazing) continue;
        ++compared;
        const bool a = ray.map.bits.get(t, d), b = render.map.bits.get(t, d);
        ray_only += a && !b;
        render_only += b && !a;
      }
    }
    int lost_ray = 0, lost_render = 0;
    for (int t = 0; t < part.mesh.triangleCount(); ++t) {
      if (reference.bits.rowCount(t) == 0) continue;
      lost_ray += ray.map.bits.rowCount(t) == 0;
      lost_render += render.map.bits.rowCount(t) == 0;
    }
    std::printf("  %-46s %7d tri %5d dir  agreement %.5f  (ray only %lld, render only %lld)  lost: ray %d, render %d\n",
                name, part.mesh.triangleCount(), ray.map.directions(),
                1.0 - static_cast<double>(ray_only + render_only) / compared, ray_only, render_only, lost_ray,
                lost_render);
  }
}

}  // namespace

int main(int argc, char** argv) {
  std::setvbuf(stdout, nullptr, _IOLBF, 0);  // figures appear as they are measured, also into a file
  const std::string what = argc > 1 ? argv[1] : "all";
  try {
    if (what == "speed" || what == "all") speed();
    if (what == "scaling" || what == "all") scaling();
    if (what == "accuracy" || what == "all") accuracy(argc > 2 ? argv[2] : "", argc > 3 ? std::stoi(argv[3]) : 4);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_visibility: %s\n", e.what());
    return 1;
  }
  return 0;
}
