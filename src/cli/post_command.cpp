// art2part post DIR --machine FILE [--out DIR2] [--mode 3+2|5axis|auto] [--tolerance MM] [--blend-tolerance MM]
//                   [--rate HZ] [--name NAME]
// Reads DIR/toolpaths.csv and DIR/tools.json (and DIR/plan.json's setups, when there: each setup's part placed where
// the machine's travel reaches it, fixture_placement.h) and writes, into DIR2 (default DIR): program.ngc (every setup, M0
// between them), setup_<k>.ngc, tool.tbl (mm, LinuxCNC), tool_rs274.tbl (inches, the stand-alone rs274) and
// trajectory.csv (time, then the joints in mm and degrees at --rate samples per second).
#include <filesystem>
#include <iostream>

#include "arguments.h"
#include "art2part/post/fixture_placement.h"
#include "art2part/post/joint_trajectory.h"
#include "art2part/post/machine_program.h"
#include "art2part/post/post_files.h"
#include "commands.h"

namespace art2part {

namespace {

PostOptions postOptionsFrom(const Arguments& a) {
  PostOptions options;
  options.mode = parsePostMode(a.value("mode", postModeName(options.mode)));
  options.chordal_tolerance = a.number("tolerance", options.chordal_tolerance);
  if (!(options.chordal_tolerance > 0)) throw UsageError("--tolerance must be a positive number of mm");
  return options;
}

// The part's name for the headers: --name, else the plan folder's name.
std::string partName(const Arguments& a, const std::string& dir) {
  if (a.has("name")) return a.value("name");
  std::error_code error;
  const std::filesystem::path full = std::filesystem::weakly_canonical(dir, error);
  const std::string name = (error ? std::filesystem::path(dir) : full).filename().string();
  return name.empty() ? "part" : name;
}

}  // namespace

int runPost(const std::vector<std::string>& args) {
  const Arguments a(args, {}, {"machine", "out", "mode", "tolerance", "blend-tolerance", "rate", "name"});
  const std::string dir = a.requirePositional(1, "one plan folder: art2part post DIR --machine FILE");
  if (!a.has("machine")) throw UsageError("post needs --machine FILE (a machine of config/machines/)");
  PostOptions options = postOptionsFrom(a);
  TrajectoryOptions trajectory_options;
  trajectory_options.blend_tolerance = a.number("blend-tolerance", trajectory_options.blend_tolerance);
  const double rate = a.number("rate", 100);
  if (!(trajectory_options.blend_tolerance > 0) || !(rate > 0))
    throw UsageError("--blend-tolerance and --rate must be positive");

  const Machine machine = loadMachine(a.value("machine"));
  const Toolpath path = readToolpathsCsv(dir + "/toolpaths.csv");
  const std::vector<Tool> tools = readToolsJson(dir + "/tools.json");
  // Each setup where the machine reaches it: the plan's placement, else the search (fixture_placement.h); a folder
  // without plan.json keeps the machine file's fixtures.
  const FixturePlan placement = placeSetups(machine, path, tools, clampingsFromPlanFolder(dir, machine), options);
  if (!placement.allReachable()) throw InputError(placement.unreachableText());
  options.fixtures = placement.fixtures();
  const MachineProgram program = buildMachineProgram(machine, path, tools, partName(a, dir), options);
  const JointTrajectory trajectory = parameterizeTrajectory(machine, programWaypoints(program), trajectory_options);
  const PostFiles files = writePostFiles(program, trajectory, rate, a.value("out", dir));

  std::cout << "post: " << program.setups.size() << " setup(s), mode " << postModeName(program.mode) << ", "
            << program.tools.size() << " tool(s), " << program.stepCount() << " steps on " << machine.name
            << "; trajectory " << trajectory.duration() << " s\n  " << files.job_program << "\n";
  for (const SetupPlacement& p : placement.setups) std::cout << "  fixture: " << placementText(machine, p) << "\n";
  for (const std::string& file : files.setup_programs) std::cout << "  " << file << "\n";
  std::cout << "  " << files.tool_table << "\n  " << files.rs274_tool_table << "\n  " << files.trajectory << "\n";
  return 0;
}

}  // namespace art2part
