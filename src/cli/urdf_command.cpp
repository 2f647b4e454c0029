// art2part urdf --machine FILE [--setup K] [--out FILE.urdf]
// The URDF of a machine (config/machines/*.yaml), with the part frame at the fixture of setup K (default: the
// machine's default fixture), on stdout or into --out. launch/machine.launch loads it as robot_description.
#include <fstream>
#include <iostream>

#include "arguments.h"
#include "art2part/kinematics/machine.h"
#include "art2part/kinematics/machine_urdf.h"
#include "commands.h"

namespace art2part {

int runUrdf(const std::vector<std::string>& args) {
  const Arguments a(args, {}, {"machine", "setup", "out"});
  if (!a.positional().empty()) throw UsageError("urdf takes no positional argument: art2part urdf --machine FILE");
  if (!a.has("machine")) throw UsageError("urdf needs --machine FILE (a machine of config/machines/)");
  UrdfOptions options;
  options.setup = a.integer("setup", -1);
  const std::string text = machineUrdf(loadMachine(a.value("machine")), options);
  if (!a.has("out")) {
    std::cout << text;
    return 0;
  }
  std::ofstream file(a.value("out"), std::ios::binary);
  if (!(file << text)) throw InputError("cannot write " + a.value("out"));
  return 0;
}

}  // namespace art2part
