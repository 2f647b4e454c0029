// The cell supervisor's request checks (supervisor_requests.h).
#include "supervisor_requests.h"

#include <algorithm>
#include <cctype>
#include <ctime>
#include <filesystem>

#include "art2part/common/request_limits.h"
#include "art2part/geometry/mesh.h"  // InputError

namespace art2part {

namespace {

namespace fs = std::filesystem;


}  // namespace

PlanOptions planOptionsFrom(const PlanPartGoal& goal) {
  PlanOptions options;
  if (!goal.mode.empty() && goal.mode != "3axis" && goal.mode != "5axis")
    throw InputError("mode is \"3axis\" or \"5axis\", not \"" + goal.mode + "\"");
  options.setups.mode = goal.mode == "5axis" ? MachineMode::FiveAxis : MachineMode::ThreeAxis;
  options.roughing.five_axis.enabled = goal.mode == "5axis";
  options.finish = !goal.roughing_only;
  checkedRequestValue(goal.scallop_m, request_limits::kScallop);
  if (goal.scallop_m > 0) options.finishing.surface.scallop = goal.scallop_m * 1000;
  return options;
}

std::string machineFileFor(const PlanPartGoal& goal, const SupervisorConfig& config) {
  std::string name = goal.machine.empty() ? (goal.mode == "5axis" ? config.machine_5axis : config.machine_3axis)
                                          : goal.machine;
  if (name.find('/') != std::string::npos || name == "." || name == ".." || name.empty())
    throw InputError("machine names a machine of the cell by name (e.g. vmc_3axis), not a path: '" + goal.machine + "'");
  if (fs::path(name).extension() != ".yaml") name += ".yaml";
  const fs::path file = fs::path(config.machines_dir) / name;
  if (!fs::is_regular_file(file)) {
    std::string known;
    std::error_code error;
    for (const auto& entry : fs::directory_iterator(config.machines_dir, error))
      if (entry.path().extension() == ".yaml") known += (known.empty() ? "" : ", ") + entry.path().stem().string();
    throw InputError("no machine '" + fs::path(name).stem().string() + "' in the cell (machines: " + known + ")");
  }
  return file.string();
}

std::string newPlanFolderName(const std::string& root, const std::string& part_source) {
  std::string stem = fs::path(part_source).stem().string();
  for (char& c : stem)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_')) c = '_';
  if (stem.empty()) stem = "part";
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  char stamp[32];
  std::strftime(stamp, sizeof stamp, "%Y%m%d-%H%M%S", &utc);
  const std::string base = stem + "_" + stamp;
  std::string name = base;
  for (int n = 2; fs::exists(fs::path(root) / name); ++n) name = base + "_" + std::to_string(n);
  return name;
}

void checkPlanName(const std::string& name) {
  if (name.empty() || name == "." || name == ".." || name.find('/') != std::string::npos)
    throw InputError("a plan is named by its folder under the output root (as list_plans gives it), not '" + name + "'");
}

std::vector<std::string> listPlanFolders(const std::string& root) {
  std::vector<std::pair<fs::file_time_type, std::string>> found;
  std::error_code error;
  for (const auto& entry : fs::directory_iterator(root, error))
    if (entry.is_directory() && fs::is_regular_file(entry.path() / "plan.json"))
      found.emplace_back(fs::last_write_time(entry.path() / "plan.json", error), entry.path().filename().string());
  std::sort(found.begin(), found.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  std::vector<std::string> names;
  for (auto& f : found) names.push_back(std::move(f.second));
  return names;
}

}  // namespace art2part
