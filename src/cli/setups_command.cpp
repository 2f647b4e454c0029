// art2part setups PART [--mode 3axis|5axis] [--tilt DEG] [--time-limit S] [--no-pp] [--json] plus the visibility
// options (--level L, --sphere, --backend, --no-special, --no-side, --resolution, --samples, --threads) and
// --units U, --tolerance MM: the same directions and matrix `art2part visibility` writes for the same options.
#include <iostream>

#include "arguments.h"
#include "art2part/setup/setup_report.h"
#include "art2part/visibility/analysis.h"
#include "commands.h"
#include "terminal_progress.h"

namespace art2part {

const std::set<std::string>& setupFlags() {
  static const std::set<std::string> flags{"no-special", "no-side", "no-pp"};
  return flags;
}

const std::set<std::string>& setupValueOptions() {
  static const std::set<std::string> options{"mode",       "tilt",    "time-limit", "level",   "sphere", "backend",
                                             "resolution", "samples", "threads",    "units",   "tolerance"};
  return options;
}

SetupOptions setupOptionsFrom(const Arguments& a) {
  SetupOptions options;
  options.mode = parseMachineMode(a.value("mode", machineModeName(options.mode)));
  options.max_tilt_deg = a.number("tilt", options.max_tilt_deg);
  options.time_limit_s = a.number("time-limit", options.time_limit_s);
  options.parallel_perpendicular = !a.flag("no-pp");
  // Checked here as well as by planSetups, so a wrong value fails before the visibility analysis runs.
  if (!(options.max_tilt_deg > 0.0 && options.max_tilt_deg <= 180.0))
    throw UsageError("--tilt is an angle in (0, 180] degrees");
  if (!(options.time_limit_s >= 0.0)) throw UsageError("--time-limit must be at least 0 seconds");
  return options;
}

int runSetups(const std::vector<std::string>& args) {
  std::set<std::string> flags = setupFlags();
  flags.insert("json");
  const Arguments a(args, flags, setupValueOptions());
  const std::string path = a.requirePositional(1, "one part file: art2part setups PART");
  const SetupOptions setup_options = setupOptionsFrom(a);
  const VisibilityOptions visibility_options = visibilityOptionsFrom(a);
  const Part part = loadPart(path, loadOptionsFrom(a));
  const VisibilityResult visibility = analyseVisibility(part, visibility_options);
  const ProgressSink progress = terminalProgress();
  const SetupPlan plan = planSetups(part, visibility, setup_options, progress);
  endTerminalProgress(progress);
  if (a.flag("json")) {
    nlohmann::json j = setupPlanJson(plan, visibility.directions);
    j["part"] = path;
    j["triangles"] = part.mesh.triangleCount();
    j["directions"] = visibility.directions.size();
    j["level"] = visibility_options.level;
    std::cout << j.dump() << "\n";
  } else {
    std::cout << "part:         " << path << " (" << part.mesh.triangleCount() << " triangles, "
              << visibility.directions.size() << " directions)\n"
              << setupPlanText(part, plan, visibility.directions);
  }
  return 0;
}

}  // namespace art2part
