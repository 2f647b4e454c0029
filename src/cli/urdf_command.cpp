// art2part urdf --machine FILE [--setup K] [--plan DIR] [--out FILE.urdf]
// The URDF of a machine (config/machines/*.yaml), with the part frame at the fixture of setup K (default: the
// machine's default fixture), on stdout or into --out. With --plan, the fixture is the one DIR/plan.json records for
// setup K on this machine (where `plan` or the bridge placed it). launch/machine.launch loads it as robot_description.
#include <fstream>
#include <iostream>

#include "arguments.h"
#include "art2part/kinematics/machine.h"
#include "art2part/kinematics/machine_urdf.h"
#include "art2part/plan/plan_folder.h"
#include "art2part/post/fixture_placement.h"
#include "commands.h"

namespace art2part {

int runUrdf(const std::vector<std::string>& args) {
  const Arguments a(args, {}, {"machine", "setup", "plan", "out"});
  if (!a.positional().empty()) throw UsageError("urdf takes no positional argument: art2part urdf --machine FILE");
  if (!a.has("machine")) throw UsageError("urdf needs --machine FILE (a machine of config/machines/)");
  const Machine machine = loadMachine(a.value("machine"));
  UrdfOptions options;
  options.setup = a.integer("setup", -1);
  const std::string plan_dir = a.value("plan");  // empty: none (a launch file's default)
  if (!plan_dir.empty()) {
    if (options.setup < 0) throw UsageError("urdf --plan DIR needs --setup K (a setup of DIR/plan.json)");
    const nlohmann::json plan = readPlanJson(plan_dir);
    if (plan.is_null()) throw InputError("'" + plan_dir + "' has no plan.json");
    options.fixture = recordedFixture(plan, options.setup, machine.name);
  }
  const std::string text = machineUrdf(machine, options);
  if (!a.has("out")) {
    std::cout << text;
    return 0;
  }
  std::ofstream file(a.value("out"), std::ios::binary);
  if (!(file << text)) throw InputError("cannot write " + a.value("out"));
  return 0;
}

}  // namespace art2part
