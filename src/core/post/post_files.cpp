// The files of `art2part post`: program.ngc, setup_<k>.ngc, tool.tbl, tool_rs274.tbl, trajectory.csv.
#include "art2part/post/post_files.h"

#include <filesystem>
#include <fstream>

#include "art2part/post/gcode.h"

namespace art2part {

namespace {

std::string writeText(const std::string& dir, const std::string& name, const std::string& text) {
  const std::string path = (std::filesystem::path(dir) / name).string();
  std::ofstream file(path, std::ios::binary);
  file << text;
  if (!file) throw InputError("cannot write " + path);
  return path;
}

}  // namespace

PostFiles writePostFiles(const MachineProgram& program, const JointTrajectory& trajectory, double rate_hz,
                         const std::string& dir) {
  std::error_code error;
  std::filesystem::create_directories(dir, error);
  if (error) throw InputError("cannot create folder " + dir + ": " + error.message());
  PostFiles files;
  files.job_program = writeText(dir, "program.ngc", jobProgramText(program));
  for (size_t i = 0; i < program.setups.size(); ++i) {
    const std::string name = "setup_" + std::to_string(program.setups[i].setup) + ".ngc";
    files.setup_programs.push_back(writeText(dir, name, setupProgramText(program, static_cast<int>(i))));
  }
  files.tool_table = writeText(dir, "tool.tbl", toolTableText(program, ToolTableUnits::Millimetres));
  files.rs274_tool_table = writeText(dir, "tool_rs274.tbl", toolTableText(program, ToolTableUnits::Inches));
  files.trajectory = (std::filesystem::path(dir) / "trajectory.csv").string();
  writeTrajectoryCsv(trajectory, rate_hz, files.trajectory);
  return files;
}

}  // namespace art2part
