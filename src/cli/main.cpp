// art2part: the pipeline without ROS. `art2part help` lists the commands.
#include <iostream>

#include "arguments.h"
#include "art2part/geometry/mesh.h"
#include "commands.h"

namespace {

const char* kUsage =
    "usage: art2part COMMAND ...\n"
    "  info PART [--json] [--units mm|in|m] [--tolerance MM]   what the part is: triangles, faces, box, volume\n"
    "  render PART --out FILE.png [--width W] [--height H] [--units U]   a shaded picture (OSMesa), faces coloured\n"
    "  visibility PART --out DIR [--picture CONES.png] [--level L] [--sphere tetrahedron|icosahedron] [--backend ray|render]\n              [--no-special] [--no-side] [--resolution PX]\n"
    "             [--samples N] [--threads N]   visibility cones: DIR/mesh.stl, directions.csv, visibility.bits\n";

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  if (args.empty() || args[0] == "help" || args[0] == "--help" || args[0] == "-h") {
    std::cout << kUsage;
    return args.empty() ? 2 : 0;
  }
  const std::string command = args[0];
  args.erase(args.begin());
  try {
    if (command == "info") return art2part::runInfo(args);
    if (command == "render") return art2part::runRender(args);
    if (command == "visibility") return art2part::runVisibility(args);
    throw art2part::UsageError("unknown command '" + command + "'");
  } catch (const art2part::UsageError& e) {
    std::cerr << "art2part: " << e.what() << "\n" << kUsage;
    return 2;
  } catch (const art2part::InputError& e) {
    std::cerr << "art2part: error: " << e.what() << "\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "art2part: internal error: " << e.what() << "\n";
    return 3;
  }
}
