// Surface finishing benchmarks (issue 17, item 5). Two tables:
//  1. the drop-cutter on the 122k-triangle CTC-02 mesh with a 6 mm ball, one thread: drops in raster order (rows along
//     x, 0.3 mm apart along them) over the part's box and at random points of it; drops per second.
//  2. 3-axis finishing (6 mm ball in its shrink-fit holder, 0.01 mm scallop) of the free-form faces (spheres, tori,
//     cones whose axis is not the direction, mesh regions) of the shared mesh parts from +z, and of CTC-02 from +x
//     too; and of every face of CTC-02 from +z (the whole side, what an OpenCAMLib raster does in 11-76 minutes):
//     faces, drops, drops/s, raster rows, waterline levels and contours, CL points, retracts, spacings, the planner's
//     areas, seconds. With --verify each path is simulated against the part itself as the stock (so any removal is a
//     gouge and any touch of the shank or holder a collision).
//   bench_surface_finishing [PART] [--verify]   (a file name in shared/parts, or "all")
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "art2part/finishing/drop_cutter.h"
#include "art2part/finishing/surface_finishing.h"
#include "art2part/roughing/shadow.h"
#include "art2part/simulation/verify.h"
#include "bench_main.h"

using namespace art2part;

namespace {

const char* const kUsage =
    "bench_surface_finishing [PART] [--verify]   (a file name in shared/parts, or \"all\")\n";
const std::string kParts = ART2PART_SHARED_PARTS;
const std::string kCtc02 = "nist_ctc_02_asme1_rc_fine_tess.stl";

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// The library's ball6: a 6 mm ball end mill in a shrink-fit chuck (config/tools.yaml).
Tool ball6() {
  Tool t;
  t.id = "ball6";
  t.type = ToolType::Ball;
  t.diameter = 6;
  t.corner_radius = 3;
  t.flute_length = 12;
  t.shank_diameter = 6;
  t.stickout = 30;
  t.holder = {{23, 12}, {25, 13}, {27, 13}, {44, 42}, {63, 16}};
  return t;
}

Part load(const std::string& name) {
  LoadOptions options;
  if (name == "ktoolcav.stl") options.unit = LengthUnit::Inch;  // the file is in inches
  return loadPart(kParts + "/" + name, options);
}

void benchDrops() {
  const Part part = load(kCtc02);
  const Tool tool = ball6();
  const SetupFrame frame = setupFrame(part, Vec3::UnitZ());
  const std::vector<Vec3> v = toFrame(part.mesh.vertices, frame);
  auto start = std::chrono::steady_clock::now();
  const DropCutter cutter(v, part.mesh.triangles, tool);
  const double build = secondsSince(start);
  const Box b = cutter.bounds();
  const double floor = b.min.z() - 10;
  double sum = 0;
  long raster = 0;
  start = std::chrono::steady_clock::now();
  for (double y = b.min.y(); y <= b.max.y(); y += 2.0)
    for (double x = b.min.x(); x <= b.max.x(); x += 0.3, ++raster) sum += cutter.drop(x, y, floor);
  const double raster_s = secondsSince(start);
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> ux(b.min.x(), b.max.x()), uy(b.min.y(), b.max.y());
  const long random = 1000000;
  long touching = 0;
  start = std::chrono::steady_clock::now();
  for (long k = 0; k < random; ++k) {
    const double z = cutter.drop(ux(rng), uy(rng), floor);
    touching += z > floor;
    sum += z;
  }
  const double random_s = secondsSince(start);
  std::printf("drop-cutter, %s, %d triangles, ball 6 mm, 1 thread: built in %.3f s (%ld cell entries)\n",
              kCtc02.c_str(), part.mesh.triangleCount(), build, cutter.binnedEntries());
  std::printf("  raster order: %ld drops in %.3f s = %.2f M/s\n", raster, raster_s, raster / raster_s / 1e6);
  std::printf("  random:       %ld drops (%ld on the part) in %.3f s = %.2f M/s   (checksum %.0f)\n\n", random,
              touching, random_s, random / random_s / 1e6, sum);
}

bool freeForm(const Face& f, const Vec3& dir) {
  switch (f.type) {
    case SurfaceType::Plane:
    case SurfaceType::Cylinder: return false;
    case SurfaceType::Cone: return std::abs(f.axis.dot(dir)) < 0.999;
    default: return true;
  }
}

void benchFinishing(const std::string& name, const Part& part, const Vec3& dir, const char* dir_name, bool all_faces,
                    bool verify) {
  std::vector<int> faces;
  for (int f = 0; f < static_cast<int>(part.faces.size()); ++f)
    if (all_faces || freeForm(part.faces[f], dir)) faces.push_back(f);
  double area = 0;
  for (int f : faces) area += part.faces[f].area;
  if (faces.empty()) {
    std::printf("%-30s %-3s no free-form faces\n", name.c_str(), dir_name);
    return;
  }
  const Tool tool = ball6();
  SurfaceFinishingOptions options;
  const SurfaceFinishingResult r = finishSurfaces3Axis(part, faces, setupFrame(part, dir), tool, 0, options);
  std::printf("%-30s %-3s %5zu %8.0f %9ld %6.2f %6d %5d %6d %8zu %5d  %5.3f %5.3f %5.3f %8.0f %7.0f %8.0f %6.2f %6.2f %6.2f %7.2f\n",
              (name + (all_faces ? " (all)" : "")).c_str(), dir_name, faces.size(), area, r.drops,
              r.drops / std::max(r.seconds, 1e-9) / 1e6, r.raster_passes, r.waterline_levels, r.waterline_contours,
              r.path.size(), r.retracts, r.stepover_mm, r.raster_stepover_mm, r.height_step_mm, r.planned_area_mm2,
              r.skipped_area_mm2, r.unreached_area_mm2, r.seconds_map, r.seconds_raster, r.seconds_waterline, r.seconds);
  std::fflush(stdout);
  if (verify && !r.path.empty()) {
    VerifyOptions vo;
    vo.stock_mesh = &part.mesh;  // the part as the stock: any removal gouges, any touch of the body collides
    const VerificationReport report = verifyToolpath(part.mesh, part.triangle_face, r.path, {tool}, vo);
    std::printf("    verified at %.3f mm: %d gouges (worst %.4f mm), %d collisions (worst %.3f mm), %.1f s\n",
                report.resolution_mm, report.gouges, report.worst_gouge_mm, report.collisions,
                report.worst_collision_mm, report.seconds_total);
  }
}

int benchMain(const std::vector<std::string>& args) {
  const Arguments a(args, {"verify"}, {});
  const std::vector<std::string>& p = positionalAtMost(a, 1);
  const std::string only = p.empty() ? "all" : p[0];
  const bool verify = a.flag("verify");
  const std::vector<std::string> parts = {"mount_rush.stl", "Ailette001Solid-nohole-decimated-smoothed.stl",
                                          "ktoolcav.stl", kCtc02};
  if (only != "all") requireOneOf(only, parts);
  if (only == "all" || only == kCtc02) benchDrops();
  std::printf("3-axis surface finishing, ball 6 mm, scallop 0.01 mm, chordal 0.005 mm, hardware threads\n");
  std::printf("%-30s %-3s %5s %8s %9s %6s %6s %5s %6s %8s %5s  %5s %5s %5s %8s %7s %8s %6s %6s %6s %7s\n", "part",
              "dir", "faces", "area", "drops", "M/s", "rows", "levls", "contrs", "points", "retr", "step", "row", "level",
              "planned", "skipped", "unreach", "map s", "rast s", "wl s", "total s");
  for (const std::string& name : parts) {
    if (only != "all" && only != name) continue;
    const Part part = load(name);
    benchFinishing(name, part, Vec3::UnitZ(), "+z", false, verify);
    if (name == kCtc02) {
      benchFinishing(name, part, Vec3::UnitX(), "+x", false, verify);
      benchFinishing(name, part, Vec3::UnitZ(), "+z", true, verify);
    }
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) { return runBench(argc, argv, kUsage, benchMain); }
