// The plan folder of the file contract (docs/contracts.md): what `art2part plan`, the cell supervisor and the stage
// nodes write, and what `art2part verify`, `art2part post` and the controller bridge read. One writer and one reader,
// so every producer writes the same files and every consumer reads them the same way.
//
// A plan folder holds: plan.json (the plan, its figures and timings), toolpaths.csv and tools.json (the path and its
// tools), mesh.stl (the triangles the path refers to), directions.csv and visibility.bits (the visibility files),
// setups.png, setup_<k>.png and remaining.png (pictures), setup_sheet.html (setup_sheet.h), and with a machine program.ngc, setup_<k>.ngc, the tool tables and
// trajectory.csv.
#pragma once

#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "art2part/kinematics/machine.h"
#include "art2part/plan/plan_part.h"
#include "art2part/post/fixture_placement.h"
#include "art2part/post/machine_program.h"
#include "art2part/tooling/tool.h"

namespace art2part {

// Every setup clamps the part anew, facing up on `machine`'s table: the setup frame along the table's axes, the middle
// of the roughing stock's bottom (in that frame) on the table point (clampFacingUp); writePlanFolder places each setup
// from its clamping where the machine's travel reaches it (placeSetups).
std::map<int, Clamping> setupClampings(const Machine& machine, const Part& part, const SetupPlan& plan,
                                       const RoughingOptions& roughing);

// How the plan becomes a program for a machine.
struct PlanProgramOptions {
  bool write = true;        // false: no program (plan.json says why not)
  Machine machine;          // the machine the program is for
  PostOptions post;         // its mode and tolerances (the fixtures come from the placement)
  std::map<int, Clamping> clampings;  // per setup (setupClampings); a setup without one keeps the machine's fixture
  double trajectory_rate_hz = 50;  // samples per second of trajectory.csv
};

struct PlanFolderOptions {
  bool pictures = true;     // setups.png and, when the plan was verified, remaining.png (OSMesa renders)
  bool remaining_picture = true;  // false: remaining.png comes from where the simulation ran (the verification node)
  bool visibility_files = true;  // directions.csv and visibility.bits
  PlanProgramOptions program;
};

// What writing the folder found: plan.json as written, and whether the machine could run the plan.
struct WrittenPlan {
  nlohmann::json plan;          // plan.json's content
  bool program_written = false;
  std::string program_error;    // why not (a machine whose travel the part exceeds, say): a finding, not a failure
  FixturePlan placement;        // where each setup's part sits on the machine (plan.json setups[k].fixture)
  double write_seconds = 0, post_seconds = 0;
};

// Writes the whole folder (created when missing). `extra_timings` (stage, seconds) go into plan.json's timings before
// write and post (the CLI's load time). Throws InputError when a file cannot be written.
WrittenPlan writePlanFolder(const std::string& dir, const Part& part, const PlanResult& plan,
                            const PlanFolderOptions& options,
                            const std::vector<std::pair<std::string, double>>& extra_timings = {});

// toolpaths.csv and tools.json alone (a stage node's output_dir). Throws InputError when they cannot be written.
void writeToolpathFiles(const std::string& dir, const Toolpath& path, const std::vector<Tool>& tools);

// What a consumer of a plan folder reads.
struct PlanFolder {
  std::string dir;
  Toolpath toolpath;               // toolpaths.csv
  std::vector<Tool> tools;         // tools.json
  std::string mesh_path;           // dir/mesh.stl, empty when the folder has none
  nlohmann::json plan;             // plan.json, null when the folder has none (a stage node's output)
};

// Reads toolpaths.csv and tools.json (required) and plan.json (when present). Throws InputError naming the folder and
// the file that is missing or malformed.
PlanFolder readPlanFolder(const std::string& dir);

// dir/plan.json alone (what a list of plans needs, without the path): null when the folder has none. Throws
// InputError when it is not JSON.
nlohmann::json readPlanJson(const std::string& dir);

// The short summary of plan.json a supervisor returns: setups, operations, faces by status, verification, time.
nlohmann::json planSummary(const nlohmann::json& plan);

}  // namespace art2part
