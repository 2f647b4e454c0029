// The cell supervisor's requests in core terms: a plan_part goal checked and turned into PlanOptions, the machine it
// names resolved in the package's machine folder, and the plan folders under the output root named and listed (the
// folders themselves: cell_folders.h). Plain functions, so the checks are tested without a node.
#pragma once

#include <map>
#include <string>
#include <vector>

#include <art2part/PlanPartAction.h>

#include "art2part/plan/plan_part.h"

namespace art2part {

// What the supervisor reads from its parameters (config/cell.yaml).
struct SupervisorConfig {
  std::string tools;                      // the tool library (tools.yaml)
  std::string machines_dir;               // config/machines: goal.machine names a file here
  std::string machine_3axis = "vmc_3axis";   // the machine when a 3-axis goal names none
  std::string machine_5axis = "trunnion_5axis"; // ... and a 5-axis one
  int max_queue = 4;                      // goals waiting beyond the one running; more are rejected
  std::map<std::string, double> stage_timeouts;  // s per stage ("visibility", "roughing", ...); a stage running longer
                                                 // fails the goal naming it; a stage not listed: default_timeout
  double default_timeout = 1800;
};

// The options of a goal, checked: mode, scallop (metres, 0..1 mm), roughing_only. Throws InputError with the reason.
PlanOptions planOptionsFrom(const PlanPartGoal& goal);

// The machine file a goal names (a bare name, no path: "vmc_3axis" or "vmc_3axis.yaml"), or the default for its mode.
// Throws InputError for a name with a path in it or one the folder does not hold.
std::string machineFileFor(const PlanPartGoal& goal, const SupervisorConfig& config);

// A fresh folder name for a plan of `part_source`: its stem and the UTC time, e.g. "ctc01_20261126-083012", made
// unique under `root` with a suffix.
std::string newPlanFolderName(const std::string& root, const std::string& part_source);

// A plan folder name as get_plan takes it: one path component, no "..". Throws InputError otherwise.
void checkPlanName(const std::string& name);

// The plan folders under root (those holding plan.json), newest first.
std::vector<std::string> listPlanFolders(const std::string& root);

}  // namespace art2part
