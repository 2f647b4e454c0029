// Finishing benchmarks (issue 17): the whole plan (visibility, setups and those added for finishing, holes, roughing,
// finishing, verification) on the shared parts, with the figures the issue names, each judged by a simulation, not
// by the planner:
//   gouges and collisions   the tri-dexel verification of roughing and finishing together (its default lattice)
//   area within 0.05 mm     surfaceCoverage: the share of the surface some cutting pose comes within 0.05 mm of
//                           (scallops included), per surface type
//   scallops                probeScallops on the faces surface finishing made: windows at a twentieth of the ball's
//                           flat stepover, the share of windows within 1.1x the target and the 99 % quantile
//   plane and cylinder      probeScallops windows on the plane and cylinder faces finished (material left above
//                           the surface), the share within 0.01 mm
//   holes                   holes a library drill matches, and how many are drilled
//   tool loads              the most times one tool is loaded within one setup's finishing (1 is the figure)
//   time                    planning seconds per stage; machining estimate (roughing, finishing, tool changes)
//   bench_finishing [PART ...] [--level L] [--windows N] [--threads T]   (file names in shared/parts; default: all of
//   them; T: finishing's groups side by side, 0 = the hardware's)
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <limits>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "art2part/common/parallel.h"
#include "art2part/finishing/surface_finishing.h"
#include "art2part/plan/plan_part.h"
#include "art2part/simulation/scallop_probe.h"
#include "art2part/simulation/surface_coverage.h"
#include "bench_main.h"

using namespace art2part;

namespace {

const char* const kUsage =
    "bench_finishing [PART ...] [--level L] [--windows N] [--threads T]   (file names in shared/parts; default: all of "
    "them)\n";
const std::string kParts = ART2PART_SHARED_PARTS;
const std::string kTools = std::string(ART2PART_SOURCE_DIR) + "/config/tools.yaml";
const char* kAll[] = {"featuretype.STEP", "ANC101.stp", "nist_ctc_01_asme1_rd.stp", "nist_ctc_02_asme1_rc.stp",
                      "ktoolcav.stl", "mount_rush.stl", "Ailette001Solid-nohole-decimated-smoothed.stl",
                      "nist_ctc_02_asme1_rc_fine_tess.stl"};

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

LoadOptions loadOptionsFor(const std::string& name) {
  LoadOptions options;
  if (name == "ktoolcav.stl") options.unit = LengthUnit::Inch;  // SOURCES.md: the cavity is modelled in inches
  return options;
}

// The largest number of loads of one tool within one setup's finishing.
int worstToolLoads(const FinishingPlan& plan) {
  std::map<std::pair<int, std::string>, int> loads;
  int setup = -1;
  std::string loaded;
  for (const FinishingOperation& op : plan.operations) {
    if (op.setup != setup || op.tool != loaded) ++loads[{op.setup, op.tool}];
    setup = op.setup;
    loaded = op.tool;
  }
  int worst = 0;
  for (const auto& [key, n] : loads) worst = std::max(worst, n);
  return worst;
}

// Faces finished by one kind of operation, and the ball of the surface operations (the largest one used).
std::vector<int> facesOf(const FinishingPlan& plan, const std::set<FinishingKind>& kinds) {
  std::set<int> faces;
  for (const FinishingOperation& op : plan.operations)
    if (kinds.count(op.kind)) faces.insert(op.faces.begin(), op.faces.end());
  return {faces.begin(), faces.end()};
}

void bench(const std::string& name, int level, int windows, int threads) {
  const ToolLibrary library = loadToolLibrary(kTools);
  auto start = std::chrono::steady_clock::now();
  const Part part = loadPart(kParts + "/" + name, loadOptionsFor(name));
  const double load = secondsSince(start);
  PlanOptions options;
  options.visibility.level = level;
  options.finishing.threads = threads;
  const PlanResult plan = planPart(part, library, options);
  std::map<std::string, double> t(plan.timings.begin(), plan.timings.end());
  int added = 0;
  for (const Setup& s : plan.setups.setups) added += s.for_finishing ? 1 : 0;
  std::printf("\n== %s: %d triangles, %zu faces, %zu setups (%d added for finishing), %zu roughing + %zu finishing "
              "operations, %zu points\n",
              name.c_str(), part.mesh.triangleCount(), part.faces.size(), plan.setups.setups.size(), added,
              plan.roughing.operations.size(), plan.finishing.operations.size(), plan.toolpath.size());
  std::printf("   seconds: load %.1f, visibility %.1f, setups %.1f, holes %.2f, roughing %.1f, finishing %.1f, "
              "verification %.1f; whole plan %.1f\n",
              load, t["visibility"], t["setups"], t["holes"], t["roughing"], t["finishing"], t["verification"],
              t["total"] + load);
  const VerificationReport& v = plan.verification;
  std::printf("   simulation (%.2f mm lattice): %d gouges (worst %.3f mm), %d collisions (worst %.3f mm), %.0f mm3 left "
              "beyond the tolerance\n",
              v.resolution_mm, v.gouges, v.worst_gouge_mm, v.collisions, v.worst_collision_mm, v.leftover_volume_mm3);
  std::map<std::string, int> status;
  for (const FaceFinish& f : plan.finishing.faces) ++status[faceStatusName(f.status)];
  std::printf("   faces: %d finished, %d partial, %d unmachinable; worst tool loads per setup %d; %d tool changes\n",
              status["finished"], status["partial"], status["unmachinable"], worstToolLoads(plan.finishing),
              plan.finishing.tool_changes);
  // Holes a library drill makes (their method), and those a drilling operation (not the spot) makes.
  std::set<int> drilled_faces;
  for (const FinishingOperation& op : plan.finishing.operations)
    if (op.kind == FinishingKind::Drill && op.note.empty()) drilled_faces.insert(op.faces.begin(), op.faces.end());
  int matched = 0, drilled = 0;
  for (std::size_t h = 0; h < plan.finishing.holes.size(); ++h) {
    if (plan.finishing.hole_methods[h].method != HoleMethod::Drill) continue;
    ++matched;
    const std::vector<int>& faces = plan.finishing.holes[h].bore_faces;
    drilled += !faces.empty() && std::all_of(faces.begin(), faces.end(), [&](int f) { return drilled_faces.count(f); });
  }
  std::printf("   holes: %zu found, %d a library drill makes, %d drilled\n", plan.finishing.holes.size(), matched,
              drilled);
  double roughing_s = 0;
  for (const RoughingOperation& op : plan.roughing.operations) roughing_s += op.seconds;
  std::printf("   machining estimate: roughing %.0f s, finishing %.0f s (tool changes included)\n", roughing_s,
              plan.finishing.seconds);

  start = std::chrono::steady_clock::now();
  const CoverageReport coverage = surfaceCoverage(part.mesh, part.triangle_face, part.faces, plan.toolpath, plan.tools);
  std::printf("   area within 0.05 mm: %.1f %% of %.0f mm2 (%.1f s, %lld pose queries)\n", 100 * coverage.share(),
              coverage.area_mm2, secondsSince(start), coverage.pose_queries);
  for (const TypeCoverage& tc : coverage.types)
    std::printf("      %-8s %6.1f %% of %10.0f mm2\n", surfaceTypeName(tc.type),
                100 * tc.covered_mm2 / std::max(tc.area_mm2, 1e-9), tc.area_mm2);

  // Scallops on what surface finishing made.
  const std::vector<int> surfaces = facesOf(plan.finishing, {FinishingKind::Surface3Axis, FinishingKind::Surface5Axis});
  const double target = options.finishing.surface.scallop;
  if (!surfaces.empty() && windows > 0) {
    double radius = 1e300;
    for (const FinishingOperation& op : plan.finishing.operations)
      if (op.kind == FinishingKind::Surface3Axis || op.kind == FinishingKind::Surface5Axis)
        radius = std::min(radius, library.find(op.tool)->diameter / 2);
    ScallopProbeOptions probe;
    probe.windows = windows;
    const double stepover = scallopStepover(radius, target, std::numeric_limits<double>::infinity());
    probe.pitch = stepover / 20;
    probe.half_width = std::max(stepover, 0.2);
    start = std::chrono::steady_clock::now();
    const ScallopReport s = probeScallops(part.mesh, part.triangle_face, surfaces, plan.toolpath, plan.tools, probe);
    std::printf("   scallop (target %.3f mm, %d of %d windows reached, pitch %.4f mm): %.1f %% within 1.1x, 99 %% "
                "quantile %.4f mm (%.1f s)\n",
                target, s.fullyReachedCount(), windows, probe.pitch, 100 * s.shareWithin(1.1 * target),
                s.quantile(0.99), secondsSince(start));
  }
  const std::vector<int> planar =
      facesOf(plan.finishing, {FinishingKind::FaceMill, FinishingKind::SideMill, FinishingKind::Contour});
  if (!planar.empty() && windows > 0) {
    ScallopProbeOptions probe;
    probe.windows = windows;
    probe.pitch = 0.05;
    probe.half_width = 1.0;
    const ScallopReport s = probeScallops(part.mesh, part.triangle_face, planar, plan.toolpath, plan.tools, probe);
    std::printf("   planes and cylinders finished: %.1f %% of %d reached windows within 0.01 mm of nominal, 99 %% "
                "quantile %.4f mm\n",
                100 * s.shareWithin(0.01), s.fullyReachedCount(), s.quantile(0.99));
  }
}

int benchMain(const std::vector<std::string>& args) {
  const Arguments a(args, {}, {"level", "windows", "threads"});
  const int level = atLeast(a.integer("level", 4), 0, "--level");
  const int windows = atLeast(a.integer("windows", 400), 0, "--windows");
  const int threads = atLeast(a.integer("threads", 0), 0, "--threads");
  std::vector<std::string> parts = a.positional();
  if (parts.empty()) parts.assign(std::begin(kAll), std::end(kAll));
  for (const std::string& name : parts) requireFile(kParts + "/" + name);
  std::printf("bench_finishing: whole plans at visibility level %d (issue 17's figures), finishing on %d threads\n",
              level, threadCount(threads));
  for (const std::string& name : parts) {
    try {
      bench(name, level, windows, threads);
    } catch (const std::exception& e) {  // one part's failure is its line of the report; the others still run
      std::printf("\n== %s: %s\n", name.c_str(), e.what());
    }
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) { return runBench(argc, argv, kUsage, benchMain); }
