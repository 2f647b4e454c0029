// Roughing benchmarks (issue 6). Two tables:
//  1. one setup (from +z, the part's own frame) at a 1 mm step-down with the tool the planner chooses, on every shared
//     part: triangles, levels, rings of the centre regions (machinable contours, offset), seconds, contours/s,
//     cutting and rapid length. The 122k-triangle STL is the "100k triangles, 1 mm, at most 5 s" figure.
//  2. the whole stage as `art2part plan` runs it (visibility at level 3, 3-axis setups, roughing with the tools' own
//     step-downs and rest passes), judged by the verification: gouges, collisions, stock removed, leftover; once
//     3-axis and once with 5-axis voxel roughing after each setup's 3-axis operations (the same setups), side by side.
//   bench_roughing [PART] [--one-setup]   (a file name in shared/parts, or "all"; --one-setup: table 1 only)
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include "art2part/roughing/roughing.h"
#include "art2part/simulation/verify.h"
#include "art2part/visibility/analysis.h"
#include "bench_main.h"

using namespace art2part;

namespace {

const char* const kUsage =
    "bench_roughing [PART] [--one-setup]   (a file name in shared/parts, or \"all\"; --one-setup: table 1 only)\n";
const std::string kParts = ART2PART_SHARED_PARTS;
const std::string kTools = std::string(ART2PART_SOURCE_DIR) + "/config/tools.yaml";
const char* kAll[] = {"nist_ctc_01_asme1_rd.stp", "nist_ctc_02_asme1_rc.stp", "nist_ctc_02_asme1_rc_fine_tess.stl",
                      "ANC101.stp", "featuretype.STEP", "ktoolcav.stl", "mount_rush.stl",
                      "Ailette001Solid-nohole-decimated-smoothed.stl"};

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void benchOneSetup(const std::string& name, const Part& part, const ToolLibrary& library) {
  Setup setup;
  setup.frame = setupFrame(part, Vec3::UnitZ());
  RoughingOptions options;
  options.levels.stepdown = 1.0;
  options.rest.enabled = false;
  auto start = std::chrono::steady_clock::now();
  const Tool* tool = chooseRoughingTool(part, setup, roughingTools(library), options);
  const double choose = secondsSince(start);
  if (!tool) {
    std::printf("%-46s no tool reaches\n", name.c_str());
    return;
  }
  start = std::chrono::steady_clock::now();
  const RoughingOperation op = roughSetup(part, setup, 0, *tool, options).operation;
  const double seconds = secondsSince(start);
  int rings = 0;
  for (const RoughingLevel& l : op.levels) rings += l.rings;
  std::printf("%-46s %7d %-8s %5zu %7d %7.2f %7.2f %9.0f %10.0f %9.0f %8zu\n", name.c_str(), part.mesh.triangleCount(),
              tool->id.c_str(), op.levels.size(), rings, choose, seconds, rings / std::max(seconds, 1e-9), op.feed_mm,
              op.rapid_mm, op.path.size());
}

void benchPlan(const std::string& name, const Part& part, const SetupPlan& setups, const ToolLibrary& library,
               bool five_axis) {
  RoughingOptions options;
  options.five_axis.enabled = five_axis;
  auto start = std::chrono::steady_clock::now();
  const RoughingPlan plan = planRoughing(part, setups, library, options);
  const double seconds = secondsSince(start);
  Toolpath path;
  std::vector<Tool> tools;
  double feed = 0, estimate = 0;
  std::string used;
  for (const RoughingOperation& op : plan.operations) {
    path.insert(path.end(), op.path.begin(), op.path.end());
    tools.push_back(*library.find(op.tool));
    feed += op.feed_mm;
    estimate += op.seconds;
    used += (used.empty() ? "" : ",") + op.tool;
  }
  if (path.empty()) {
    std::printf("%-46s no roughing\n", name.c_str());
    return;
  }
  const VerificationReport report = verifyToolpath(part.mesh, part.triangle_face, path, tools);
  const double material = report.stock_volume_mm3 - report.part_volume_mm3;
  std::printf("%-40s %-5s %3zu %3zu %7.1f %9.0f %7.0f %3d %3d %6.1f%% %9.0f %6.2f  %s\n", name.c_str(),
              five_axis ? "5axis" : "3axis", setups.setups.size(),
              plan.operations.size(), seconds, feed, estimate, report.gouges, report.collisions,
              100.0 * report.removed_volume_mm3 / std::max(material, 1e-9), report.leftover_volume_mm3,
              report.leftover_max_mm, used.c_str());
}

int benchMain(const std::vector<std::string>& args) {
  const Arguments a(args, {"one-setup"}, {});
  std::vector<std::string> parts = positionalAtMost(a, 1);
  if (parts.empty() || parts[0] == "all") parts.assign(std::begin(kAll), std::end(kAll));
  for (const std::string& name : parts) requireFile(kParts + "/" + name);
  const bool one_setup = a.flag("one-setup");
  const ToolLibrary library = loadToolLibrary(kTools);
  std::vector<Part> loaded;
  for (const std::string& name : parts) loaded.push_back(loadPart(kParts + "/" + name));

  std::printf("one setup from +z, 1 mm step-down, the chosen tool, no rest pass\n");
  std::printf("%-46s %7s %-8s %5s %7s %7s %7s %9s %10s %9s %8s\n", "part", "tris", "tool", "levels", "rings",
              "choose", "rough s", "rings/s", "cut mm", "rapid mm", "points");
  for (std::size_t i = 0; i < parts.size(); ++i) benchOneSetup(parts[i], loaded[i], library);

  if (one_setup) return 0;
  std::printf("\nthe stage: level-3 visibility, 3-axis setups, roughing + rest passes, verified\n");
  std::printf("%-40s %-5s %3s %3s %7s %9s %7s %3s %3s %7s %9s %6s  %s\n", "part", "mode", "set", "ops", "plan s",
              "cut mm", "est s", "gou", "col", "removed", "left mm3", "max", "tools");
  for (std::size_t i = 0; i < parts.size(); ++i) {
    VisibilityOptions visibility_options;
    visibility_options.level = 3;
    const SetupPlan setups = planSetups(loaded[i], analyseVisibility(loaded[i], visibility_options));
    for (bool five_axis : {false, true}) benchPlan(parts[i], loaded[i], setups, library, five_axis);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  return runBench(argc, argv, kUsage, benchMain);
}
