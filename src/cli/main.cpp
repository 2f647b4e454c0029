// art2part: the pipeline without ROS. `art2part help` lists the commands.
#include <iostream>
#include <string>
#include <vector>

#include "arguments.h"
#include "art2part/geometry/mesh.h"
#include "commands.h"

namespace {

// Each command's usage, in the order `art2part help` lists them.
struct CommandUsage {
  const char* name;
  const char* text;
};

const CommandUsage kCommands[] = {
    {"info", "  info PART [--json] [--units mm|in|m] [--tolerance MM]   what the part is: triangles, faces, box, volume\n"},
    {"render", "  render PART --out FILE.png [--width W] [--height H] [--units U]   a shaded picture (OSMesa), faces coloured\n"},
    {"visibility",
     "  visibility PART --out DIR [--picture CONES.png] [--level L] [--sphere tetrahedron|icosahedron] [--backend ray|render]\n"
     "             [--no-special] [--no-side] [--resolution PX]\n"
     "             [--samples N] [--threads N]   visibility cones: DIR/mesh.stl, directions.csv, visibility.bits\n"},
    {"setups",
     "  setups PART [--mode 3axis|5axis] [--tilt DEG] [--time-limit S] [--no-pp] [--json] [visibility options]\n"
     "             the fewest setups (minimum cover of the visibility cones), their frames and what each machines\n"},
    {"plan",
     "  plan PART --out DIR [--mode 3axis|5axis] [--tilt DEG] [--level L] [...setups options] [--tools FILE]\n"
     "             [--tool ID] [--allowance MM] [--stepdown MM] [--no-rest] [--no-reach] [--whole-stock] [--no-stay-down]\n"
     "             [--adaptive] [--roughing 3axis|5axis] [--no-finish] [--scallop MM] [--machine FILE]\n"
     "             [--verify-resolution MM]   visibility, setups, holes,\n"
     "             roughing, finishing, verification and post: DIR/plan.json, toolpaths.csv, tools.json, mesh.stl,\n"
     "             program.ngc, setups.png, remaining.png and the visibility files (progress on a terminal)\n"},
    {"verify",
     "  verify DIR [--part FILE] [--resolution MM] [--tolerance MM] [--stock-margin MM] [--stock FILE]\n"
     "             [--picture FILE.png] [--stock-out FILE.stl] [--threads N] [--max-listed N]   simulate\n"
     "             DIR/toolpaths.csv: JSON report (each list at most N long, default 100), exit 1 on any gouge or collision\n"},
    {"post",
     "  post DIR --machine FILE [--out DIR2] [--mode 3+2|5axis|auto] [--tolerance MM] [--blend-tolerance MM]\n"
     "             [--rate HZ] [--name NAME]   G-code for LinuxCNC from DIR/toolpaths.csv and tools.json: program.ngc,\n"
     "             setup_<k>.ngc, tool.tbl, tool_rs274.tbl (inches) and trajectory.csv (time, joints in mm and deg)\n"},
    {"urdf",
     "  urdf --machine FILE [--setup K] [--plan DIR] [--out FILE.urdf]   the machine's URDF (m, rad) with the part\n"
     "             frame at the fixture of setup K (with --plan: the one DIR/plan.json records), for\n"
     "             robot_state_publisher\n"},
};

std::string usage() {
  std::string text = "usage: art2part COMMAND ...   (art2part COMMAND --help: that command alone)\n";
  for (const CommandUsage& c : kCommands) text += c.text;
  return text;
}

const char* commandUsage(const std::string& name) {
  for (const CommandUsage& c : kCommands)
    if (name == c.name) return c.text;
  return nullptr;
}

bool asksForHelp(const std::vector<std::string>& args) {
  for (const std::string& a : args)
    if (a == "--help" || a == "-h") return true;
  return false;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  if (args.empty() || args[0] == "help" || args[0] == "--help" || args[0] == "-h") {
    if (args.size() > 1 && commandUsage(args[1])) {
      std::cout << "usage: art2part" << commandUsage(args[1]);
      return 0;
    }
    std::cout << usage();
    return args.empty() ? 2 : 0;
  }
  const std::string command = args[0];
  args.erase(args.begin());
  if (commandUsage(command) && asksForHelp(args)) {
    std::cout << "usage: art2part" << commandUsage(command);
    return 0;
  }
  try {
    if (command == "info") return art2part::runInfo(args);
    if (command == "render") return art2part::runRender(args);
    if (command == "visibility") return art2part::runVisibility(args);
    if (command == "setups") return art2part::runSetups(args);
    if (command == "plan") return art2part::runPlan(args);
    if (command == "verify") return art2part::runVerify(args);
    if (command == "post") return art2part::runPost(args);
    if (command == "urdf") return art2part::runUrdf(args);
    throw art2part::UsageError("unknown command '" + command + "'");
  } catch (const art2part::UsageError& e) {
    const char* one = commandUsage(command);
    std::cerr << "art2part: " << e.what() << "\n" << (one ? "usage: art2part" + std::string(one) : usage());
    return 2;
  } catch (const art2part::InputError& e) {
    std::cerr << "art2part: error: " << e.what() << "\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "art2part: internal error: " << e.what() << "\n";
    return 3;
  }
}
