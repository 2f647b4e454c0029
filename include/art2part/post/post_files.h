// What `art2part post` writes into a folder: the job program, one program per setup, the tool tables and the
// trajectory.
#pragma once

#include <string>
#include <vector>

#include "art2part/post/joint_trajectory.h"
#include "art2part/post/machine_program.h"

namespace art2part {

struct PostFiles {
  std::string job_program;                  // program.ngc: every setup in order, M0 between them
  std::vector<std::string> setup_programs;  // setup_<k>.ngc, k = toolpaths.csv's setup index
  std::string tool_table;                   // tool.tbl: mm, for LinuxCNC
  std::string rs274_tool_table;             // tool_rs274.tbl: inches, for the stand-alone rs274 interpreter
  std::string trajectory;                   // trajectory.csv
};

// Writes the files into `dir` (created when missing). Throws InputError when a file cannot be written.
PostFiles writePostFiles(const MachineProgram& program, const JointTrajectory& trajectory, double rate_hz,
                         const std::string& dir);

}  // namespace art2part
