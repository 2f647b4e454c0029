// art2part plan PART --out DIR [--mode 3axis|5axis] [--tilt DEG] [--level L] [--time-limit S] [--no-pp]
//                    [--tools FILE] [--tool ID] [--allowance MM] [--stepdown MM] [--no-rest] [--no-reach] [--whole-stock]
//                    [--no-stay-down] [--adaptive] [--machine FILE]
//                    [--verify-resolution MM] [--roughing 3axis|5axis] [--no-finish] [--scallop MM]
//                    plus the visibility options: the pipeline without ROS (planPart, plan_part.h). Part -> visibility
// -> setups -> holes -> roughing -> finishing -> verification -> post. --roughing 5axis (the default with --mode 5axis) adds 5-axis voxel roughing after each
// setup's 3-axis operations and posts for the default 5-axis machine (config/machines/trunnion_5axis.yaml) unless --machine says; each setup's
// part is placed on the machine's table where its travel reaches the whole setup (fixture_placement.h), recorded in
// plan.json's setups[k].fixture. Writes DIR/plan.json, toolpaths.csv, tools.json, mesh.stl, program.ngc (with setup_<k>.ngc,
// tool tables, trajectory.csv), setups.png, remaining.png (the stock left, coloured by its thickness) and the
// visibility contract files (directions.csv, visibility.bits).
#include <algorithm>
#include <chrono>
#include <iostream>
#include <string>

#include "arguments.h"
#include "art2part/plan/plan_folder.h"
#include "art2part/plan/plan_json.h"
#include "art2part/plan/plan_part.h"
#include "art2part/roughing/roughing.h"
#include "art2part/setup/setup_report.h"
#include "art2part/simulation/verify.h"
#include "commands.h"
#include "terminal_progress.h"

#ifndef ART2PART_CONFIG_DIR
#define ART2PART_CONFIG_DIR "config"
#endif

namespace art2part {
namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

RoughingOptions roughingOptionsFrom(const Arguments& a) {
  RoughingOptions options;
  options.allowance = a.number("allowance", options.allowance);
  options.levels.stepdown = a.number("stepdown", options.levels.stepdown);
  options.clearing.tool = a.value("tool", "");
  options.rest.enabled = !a.flag("no-rest");
  options.rest.reach = !a.flag("no-reach");
  options.stock.in_process = !a.flag("whole-stock");
  options.clearing.stay_down = !a.flag("no-stay-down");
  if (a.flag("adaptive")) options.clearing.strategy = RoughingOptions::Clearing::Strategy::Engagement;
  if (!(options.allowance >= 0) || !(options.levels.stepdown >= 0))
    throw UsageError("--allowance and --stepdown must not be negative");
  // 5-axis voxel roughing after the 3-axis operations: asked for, or implied by 5-axis setups.
  const std::string roughing = a.value("roughing", a.value("mode", "3axis") == "5axis" ? "5axis" : "3axis");
  if (roughing != "3axis" && roughing != "5axis") throw UsageError("--roughing is 3axis or 5axis");
  options.five_axis.enabled = roughing == "5axis";
  return options;
}

}  // namespace

int runPlan(const std::vector<std::string>& args) {
  std::set<std::string> options = setupValueOptions();
  for (const char* o : {"out", "tools", "tool", "allowance", "stepdown", "machine", "verify-resolution", "roughing",
                        "scallop"})
    options.insert(o);
  std::set<std::string> flags = setupFlags();
  for (const char* f : {"no-rest", "no-reach", "whole-stock", "no-finish", "no-stay-down", "adaptive"}) flags.insert(f);
  const Arguments a(args, flags, options);
  const std::string path = a.requirePositional(1, "one part file: art2part plan PART --out DIR");
  if (!a.has("out")) throw UsageError("plan needs --out DIR");
  const std::string out = a.value("out");
  PlanOptions plan_options;
  plan_options.setups = setupOptionsFrom(a);
  plan_options.visibility = visibilityOptionsFrom(a);
  plan_options.roughing = roughingOptionsFrom(a);
  plan_options.finish = !a.flag("no-finish");
  plan_options.finishing.surface.scallop = a.number("scallop", plan_options.finishing.surface.scallop);
  if (!(plan_options.finishing.surface.scallop > 0)) throw UsageError("--scallop must be positive (mm)");
  plan_options.verification.stock_margin = plan_options.roughing.stock.margin;
  plan_options.verification.resolution = a.number("verify-resolution", 0);
  const ToolLibrary library = loadToolLibrary(a.value("tools", std::string(ART2PART_CONFIG_DIR) + "/tools.yaml"));
  const std::string default_machine =
      plan_options.roughing.five_axis.enabled ? "trunnion_5axis.yaml" : "vmc_3axis.yaml";
  const Machine machine = loadMachine(a.value("machine", std::string(ART2PART_CONFIG_DIR) + "/machines/" + default_machine));

  auto start = Clock::now();
  const Part part = loadPart(path, loadOptionsFrom(a));
  const double load_seconds = secondsSince(start);
  const ProgressSink progress = terminalProgress();
  const PlanResult plan = planPart(part, library, plan_options, progress);
  endTerminalProgress(progress);

  PlanFolderOptions folder;
  folder.program.machine = machine;
  folder.program.clampings = setupClampings(machine, part, plan.setups, plan_options.roughing);
  const WrittenPlan written = writePlanFolder(out, part, plan, folder, {{"load", load_seconds}});
  if (!written.program_written)
    std::cerr << "art2part: no program for " << machine.name << ": " << written.program_error << "\n";
  const nlohmann::json& j = written.plan;
  std::cout << "timings:     ";
  for (const auto& [stage, seconds] : j["timings"].items()) std::cout << " " << stage << " " << seconds.get<double>() << " s";
  std::cout << "\n";

  std::cout << "part:         " << path << " (" << part.mesh.triangleCount() << " triangles, "
            << plan.visibility.directions.size() << " directions)\n"
            << setupPlanText(part, plan.setups, plan.visibility.directions);
  for (const SetupPlacement& p : written.placement.setups)
    std::cout << "fixture:      " << placementText(machine, p) << "\n";
  const RoughingPlan& roughing = plan.roughing;
  if (roughing.closed_open_mesh_edges > 0)
    std::cout << "solid:        the mesh is open (" << roughing.closed_open_mesh_edges
              << " boundary edges): roughed and simulated as the solid between it and a floor on its open side\n";
  if (roughing.region_failures > 0 || roughing.direct_levels > 0)
    std::cout << "warning:      " << roughing.region_failures << " polygon operations failed, " << roughing.direct_levels
              << " levels took the shadow directly (the grown forbidden region missed part of it)\n";
  int drilled = 0;
  for (const HoleMachining& m : plan.hole_methods) drilled += m.method == HoleMethod::Drill ? 1 : 0;
  if (!plan.holes.empty())
    std::cout << "holes:        " << plan.holes.size() << " found, " << drilled << " drilled, kept out of roughing\n";
  for (const nlohmann::json& op : j["operations"])
    std::cout << "operation " << op["index"].get<int>() << ":  " << op["kind"].get<std::string>() << ", setup "
              << op["setup"].get<int>() << ", tool " << op["tool"].get<std::string>() << ", " << op["points"].get<long>()
              << " points, " << static_cast<long>(op["length_mm"].get<double>()) << " mm cutting, ~"
              << static_cast<long>(op["time_s"].get<double>()) << " s\n";
  if (plan_options.finish) {
    const auto& by = j["finishing"]["faces_by_status"];
    std::cout << "faces:        " << by.value("finished", 0) << " finished, " << by.value("partial", 0) << " partial, "
              << by.value("unmachinable", 0) << " unmachinable (plan.json faces says why); " << plan.finishing.tool_changes
              << " tool changes in finishing\n";
  }
  if (plan.verified) {
    const VerificationReport& report = plan.verification;
    std::cout << "verification: " << (report.passed() ? "" : "FAILED: ") << report.gouges << " gouges, " << report.collisions
              << " collisions, " << static_cast<long>(report.removed_volume_mm3) << " of "
              << static_cast<long>(report.stock_volume_mm3 - report.part_volume_mm3) << " mm3 of stock removed, "
              << static_cast<long>(report.leftover_volume_mm3) << " mm3 left beyond the tolerance\n"
              << "              " << j["verification"]["what_is_left"].get<std::string>() << "\n";
  }
  std::cout << "wrote:        " << out << "/{plan.json,toolpaths.csv,tools.json,mesh.stl,"
            << (written.program_written ? "program.ngc," : "") << "setups.png,remaining.png,directions.csv,"
            << "visibility.bits}\n";
  // A plan the simulation rejects is still written (plan.json says passed: false, and why); the exit status is for
  // errors in the input. `art2part verify DIR` exits 1 on any gouge or collision.
  return 0;
}

}  // namespace art2part
