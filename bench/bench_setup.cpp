// Setup planning benchmarks (issue 4): on every shared part at one sphere level (4 by default: 1024 directions and
// the special ones), the time of the reach matrix and of the minimum cover (reduction, search) for 3- and 5-axis, the
// size of the problem (distinct cones, the cyclic core), the setups found beside greedy set cover, and how far the
// 3-axis setup directions are from the part's face normals and cylinder axes. The 122k-triangle STL at level 4 is the
// "100k triangles x 1024 directions" figure; the target is reach + cover within 1 s there.
//   bench_setup [LEVEL [PART]]   (PART a file name in shared/parts)
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <unordered_set>

#include "art2part/setup/setup_plan.h"
#include "bench_main.h"

using namespace art2part;

namespace {

const char* const kUsage = "bench_setup [LEVEL [PART]]   (sphere level, default 4; PART a file name in shared/parts)\n";
const std::string kParts = ART2PART_SHARED_PARTS;
constexpr double kPi = 3.14159265358979323846;

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

int distinctRows(const BitMatrix& m) {
  std::unordered_set<std::string> rows;
  const std::size_t bytes = sizeof(std::uint64_t) * m.wordsPerRow();
  for (int r = 0; r < m.rows(); ++r) rows.emplace(reinterpret_cast<const char*>(m.row(r)), bytes);
  return static_cast<int>(rows.size());
}

// Degrees from d to the nearest plane normal or cylinder (cone) axis of the part, either sense.
double degreesToNearestFeature(const Part& part, const Vec3& d) {
  double best = 1.0e9;
  for (const Face& f : part.faces) {
    const bool plane = f.type == SurfaceType::Plane && f.normal.norm() > 0.5;
    const bool axial = (f.type == SurfaceType::Cylinder || f.type == SurfaceType::Cone) && f.axis.norm() > 0.5;
    if (f.area <= 0.0 || (!plane && !axial)) continue;
    const Vec3 v = (plane ? f.normal : f.axis).normalized();
    best = std::min(best, std::acos(std::min(1.0, std::abs(v.dot(d)))) * 180.0 / kPi);
  }
  return best;
}

double maxDegreesToFeature(const Part& part, const SetupPlan& plan, const DirectionSet& directions) {
  double worst = 0.0;
  for (const Setup& s : plan.setups)
    worst = std::max(worst, degreesToNearestFeature(part, directions.directions[s.direction]));
  return worst;
}

void benchPart(const std::string& name, int level) {
  const Part part = loadPart(kParts + "/" + name);
  VisibilityOptions options;
  options.level = level;
  auto start = std::chrono::steady_clock::now();
  const VisibilityResult visibility = analyseVisibility(part, options);
  const double seconds_visibility = secondsSince(start);
  const int cones = distinctRows(visibility.map.bits);
  SetupOptions three;
  const SetupPlan a = planSetups(part, visibility, three);
  SetupOptions five;
  five.mode = MachineMode::FiveAxis;
  const SetupPlan b = planSetups(part, visibility, five);
  std::printf("%-46s %7d %5d %6.1f %7d | 3ax %6.3f %6.3f (%5.3f %6.3f) %4dx%-5d %2d %2d %-3s %5.2f | 5ax %6.3f %6.3f "
              "%4dx%-5d %2d %2d %-3s\n",
              name.c_str(), part.mesh.triangleCount(), visibility.directions.size(), seconds_visibility, cones,
              a.seconds_reach, a.seconds_cover, a.cover.seconds_reduce, a.cover.seconds_search,
              a.cover.core_candidates, a.cover.core_elements, static_cast<int>(a.setups.size()), a.greedy_setups,
              a.proven_minimal ? "yes" : "no", maxDegreesToFeature(part, a, visibility.directions), b.seconds_reach,
              b.seconds_cover, b.cover.core_candidates, b.cover.core_elements, static_cast<int>(b.setups.size()),
              b.greedy_setups, b.proven_minimal ? "yes" : "no");
}

int benchMain(const std::vector<std::string>& args) {
  const Arguments a(args, {}, {});
  const std::vector<std::string>& p = positionalAtMost(a, 2);
  const int level = p.size() > 0 ? atLeast(parseInteger(p[0], "LEVEL"), 0, "LEVEL") : 4;
  const std::string only = p.size() > 1 ? p[1] : "";
  const char* parts[] = {"nist_ctc_01_asme1_rd.stp", "nist_ctc_02_asme1_rc.stp", "ANC101.stp", "featuretype.STEP",
                         "ktoolcav.stl", "mount_rush.stl", "Ailette001Solid-nohole-decimated-smoothed.stl",
                         "nist_ctc_02_asme1_rc_fine_tess.stl"};
  if (!only.empty()) requireOneOf(only, parts);
  std::printf("setups at sphere level %d; seconds; core = cyclic core (candidates x elements) of the plain minimum cover; "
              "setups, greedy, proven; angle = max degrees from a 3-axis setup direction to a plane normal or axis\n",
              level);
  std::printf("%-46s %7s %5s %6s %7s | 3ax %6s %6s (%5s %6s) %10s %2s %2s %-3s %5s | 5ax %6s %6s %10s %2s %2s %-3s\n",
              "part", "tri", "dir", "vis", "cones", "reach", "cover", "red", "search", "core", "n", "gr", "pr",
              "angle", "reach", "cover", "core", "n", "gr", "pr");
  for (const char* name : parts)
    if (only.empty() || only == name) benchPart(name, level);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  std::setvbuf(stdout, nullptr, _IOLBF, 0);  // figures appear as they are measured, also into a file
  return runBench(argc, argv, kUsage, benchMain);
}
