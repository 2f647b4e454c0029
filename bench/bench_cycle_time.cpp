// Cycle-time bench (issue 19): the whole plan as `art2part plan` makes it (default options, 3-axis, on the default
// machine config/machines/vmc_3axis.yaml), timed by the cycle-time model (post/cycle_time.h) and judged by the
// simulation: per operation its time (cutting, rapid, tool change), the volume it removed, material per minute, its
// bound (that volume at its tool's library rate) and the ratio; per part the roughing time against the sum of its
// operations' bounds and the rapid length against the cutting length (the figures: at most 1.5x and 0.3x).
//   bench_cycle_time [PART ...] [--no-finish] [--adaptive] [--no-stay-down] [--no-reach]   (file names in shared/parts,
//   or "all"; default featuretype.STEP; --adaptive: constant-engagement main passes; --no-stay-down: every link over
//   the clearance plane; --no-reach: no reach pass with the main tool's long twin; all as the CLI's)
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include "art2part/kinematics/machine.h"
#include "art2part/plan/plan_figures.h"
#include "bench_main.h"

using namespace art2part;

namespace {

const char* const kUsage =
    "bench_cycle_time [PART ...] [--no-finish] [--adaptive] [--no-stay-down] [--no-reach]\n"
    "  PART: a file name in shared/parts, or \"all\"; default featuretype.STEP\n"
    "  --adaptive: constant-engagement main passes; --no-stay-down: every link over the clearance plane;\n"
    "  --no-reach: no reach pass with the main tool's long twin; all as the CLI's\n";
const std::string kParts = ART2PART_SHARED_PARTS;
const std::string kConfig = std::string(ART2PART_SOURCE_DIR) + "/config";
const char* kAll[] = {"nist_ctc_01_asme1_rd.stp", "nist_ctc_02_asme1_rc.stp", "ANC101.stp", "featuretype.STEP",
                      "ktoolcav.stl", "mount_rush.stl", "Ailette001Solid-nohole-decimated-smoothed.stl"};

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

double ratio(double a, double b) { return b > 0 ? a / b : 0.0; }

// time / bound, or "-" without one (a bound under kLeastBoundSeconds).
std::string ratioText(double ratio) {
  if (ratio <= 0) return "-";
  char text[32];
  std::snprintf(text, sizeof text, ratio > 999 ? ">999" : "%.2f", ratio);
  return text;
}

void printOperation(const PlanOperation& op, const OperationFigures& f) {
  std::printf("  %3d %2d %-16s %-9s %8.0f %7.0f %5.0f %8.1f %8.1f %9.1f %8.1f %7.0f %6s%s\n", op.index, op.setup,
              op.kind.c_str(), op.tool.c_str(), f.time.cutting_s, f.time.rapid_s, f.time.tool_change_s,
              f.time.cutting_mm / 1000, f.time.rapid_mm / 1000, f.removed_mm3 / 1000, f.mm3_per_min / 1000, f.bound_s,
              ratioText(f.bound_ratio).c_str(), f.useless ? "  USELESS" : "");
}

void benchPart(const std::string& name, const ToolLibrary& library, const Machine& machine, bool finish,
               const RoughingOptions& roughing) {
  const Part part = loadPart(kParts + "/" + name);
  PlanOptions options;
  options.roughing = roughing;
  options.finish = finish;
  options.verification.stock_margin = options.roughing.stock.margin;
  const auto start = std::chrono::steady_clock::now();
  const PlanResult plan = planPart(part, library, options);
  const double plan_seconds = secondsSince(start);
  const PlanFigures figures = planFigures(plan, machine);
  std::printf("\n%s: %zu setups, %zu operations, planned in %.1f s, verification %s (%d gouges, %d collisions)\n",
              name.c_str(), plan.setups.setups.size(), plan.operations.size(), plan_seconds,
              plan.verification.passed() ? "passed" : "FAILED", plan.verification.gouges,
              plan.verification.collisions);
  std::printf("  %3s %2s %-16s %-9s %8s %7s %5s %8s %8s %9s %8s %7s %6s\n", "op", "su", "kind", "tool", "cut s",
              "rapid s", "tc s", "cut m", "rapid m", "rem cm3", "cm3/min", "bound s", "ratio");
  for (std::size_t i = 0; i < plan.operations.size(); ++i) printOperation(plan.operations[i], figures.operations[i]);
  for (const DroppedOperation& d : plan.roughing.dropped)
    if (d.simulated)
      std::printf("  dropped: setup %d %s %s, removed %.1f cm3 in %.0f s (planner's estimate)\n", d.setup, d.kind.c_str(),
                  d.tool.c_str(), d.removed_mm3 / 1000, d.seconds);
  if (plan.useless.kept > 0)
    std::printf("  %d of %d useless roughing operations kept: %s\n", plan.useless.kept, plan.useless.found,
                plan.useless.kept_why.c_str());
  double old_roughing = 0;  // the planners' own estimates (feed and rapid lengths at constant rates)
  for (const RoughingOperation& op : plan.roughing.operations) old_roughing += op.seconds;
  const CycleTime& r = figures.roughing;
  const CycleTime& t = figures.time.total;
  std::printf("  roughing:  %.0f s (%.2f h) = cutting %.0f + rapid %.0f + tool change %.0f s; bound %.0f s (%.2f h); "
              "ratio %.2f; rapid/cutting length %.2f (%.0f m / %.0f m); removed %.0f cm3\n",
              r.total_s(), r.total_s() / 3600, r.cutting_s, r.rapid_s, r.tool_change_s, figures.roughing_bound_s,
              figures.roughing_bound_s / 3600, ratio(r.total_s(), figures.roughing_bound_s),
              ratio(r.rapid_mm, r.cutting_mm), r.rapid_mm / 1000, r.cutting_mm / 1000,
              figures.roughing_removed_mm3 / 1000);
  std::printf("  finishing: %.0f s = cutting %.0f + rapid %.0f + tool change %.0f s; rapid/cutting length %.2f\n",
              figures.finishing.total_s(), figures.finishing.cutting_s, figures.finishing.rapid_s,
              figures.finishing.tool_change_s, ratio(figures.finishing.rapid_mm, figures.finishing.cutting_mm));
  std::printf("  part:      %.0f s (%.2f h) = cutting %.0f + rapid %.0f + %d tool changes %.0f + %d setup changes %.0f s;"
              " rapid/cutting length %.2f; old estimate %.0f s (roughing %.0f + finishing %.0f)\n",
              t.total_s(), t.total_s() / 3600, t.cutting_s, t.rapid_s, t.tool_changes, t.tool_change_s,
              t.setup_changes, t.setup_change_s, ratio(t.rapid_mm, t.cutting_mm),
              old_roughing + plan.finishing.seconds, old_roughing, plan.finishing.seconds);
}

int benchMain(const std::vector<std::string>& args) {
  const Arguments a(args, {"no-finish", "adaptive", "no-stay-down", "no-reach"}, {});
  std::vector<std::string> parts;
  for (const std::string& arg : a.positional()) {
    if (arg == "all") parts.assign(std::begin(kAll), std::end(kAll));
    else parts.push_back(arg);
  }
  if (parts.empty()) parts.push_back("featuretype.STEP");
  for (const std::string& name : parts) requireFile(kParts + "/" + name);
  const bool finish = !a.flag("no-finish");
  RoughingOptions roughing;
  if (a.flag("adaptive")) roughing.clearing.strategy = RoughingOptions::Clearing::Strategy::Engagement;
  if (a.flag("no-stay-down")) roughing.clearing.stay_down = false;
  if (a.flag("no-reach")) roughing.rest.reach = false;
  const ToolLibrary library = loadToolLibrary(kConfig + "/tools.yaml");
  const Machine machine = loadMachine(kConfig + "/machines/vmc_3axis.yaml");
  std::printf("cycle time on %s; bound = removed volume at the tool's library rate (max_stepdown x max_stepover x "
              "feed); ratio = time / bound\n", machine.name.c_str());
  for (const std::string& name : parts) benchPart(name, library, machine, finish, roughing);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  return runBench(argc, argv, kUsage, benchMain);
}
