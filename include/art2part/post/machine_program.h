// The post's model of a job: toolpaths.csv points turned into joint moves of one machine, setup by setup, with the
// tool changes, safe retracts and rotary repositions a controller needs. The G-code writer (gcode.h) prints it and the
// time parameterization (joint_trajectory.h) times it, so both describe the same motion.
//
// Two ways to run a job (PostMode):
//   3+2     the rotaries are positioned once per setup (at the safe height), then the tool moves in X Y Z only: every
//           point of a setup must share one tool axis. A 3-axis mill is the case with no rotaries: there each setup's
//           axis must lie along the spindle once the part is fixtured (its fixture in the machine file or in
//           PostOptions::fixtures), otherwise the post refuses it.
//   5-axis  the joints follow every point: inverse kinematics per point, each solved from the one before
//           (inverseKinematicsPath: C unwound, never jumping a turn; a singular pose takes the C of the next regular
//           one), and every move subdivided until the tip of the linearly interpolated joints stays within
//           chordal_tolerance of the straight CL segment and the tool axis within axis_tolerance_deg of the
//           interpolated (slerp) CL axis. Where the axis reaches the singularity in one plane and leaves it in
//           another, C turns in place at the singular pose (tip and axis held, subdivided likewise): no lift.
//
// Coordinates: every move is in joint coordinates. LinuxCNC runs the programs under identity kinematics (M429 on the
// simulated xyzac-trt / xyzbc-trt machines, their start-up mode) with G43 active, so the program's X Y Z are the joints'
// X Y Z minus the tool length in Z (on a table-table machine or a 3-axis mill that is the tool tip in machine
// coordinates) and A/B C are the rotary joints in degrees. Work offsets G54 and G92 must be zero (the programs set G54
// to zero and cancel G92).
//
// Drilling (3+2 and 3-axis only): a drill's run in toolpaths.csv of a rapid to a point (the R plane), a feed straight
// down the tool axis, a rapid back up to that point, reached from straight above it or across at its height (the
// cycle's own first move, X Y at the height it starts from), becomes one canned cycle: G81,
// or G83 pecking Q = the drill's max_stepdown (its diameter when 0) when the feed is longer than peck_ratio x its
// diameter; G98 when the next point is a rapid straight back up to where the cycle began (over the R plane), G99
// otherwise. The program's steps are the cycle's motion exactly as rs274ngc expands it (the XY move at the start Z,
// even of zero length, the Z move to R, the feed, G83's pecks: back to R, down again to 0.254 mm above the last depth,
// the retract), each tagged with the cycle, so the trajectory times what the controller runs. 5-axis mode keeps G0/G1.
//
// Safety: before every tool change and every rotary reposition the spindle goes up to the safe height (G53 G0 Z, the
// gauge point retract_z in machine coordinates), the rotaries turn up there, then X Y, then Z down to the first point.
// A 5-axis rapid that the joints cannot follow continuously (the pose needs the other IK branch) is made the same way.
// A pose no branch reaches, a feed move that would need a branch flip, a tool not in tools.json, a setup whose points
// come in two separate runs: each throws InputError naming the toolpaths.csv line, the op, the setup and the reason.
#pragma once

#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "art2part/kinematics/inverse_kinematics.h"
#include "art2part/kinematics/machine.h"
#include "art2part/tooling/tool.h"
#include "art2part/tooling/toolpath.h"

namespace art2part {

enum class PostMode {
  Auto,          // 3+2 when every setup has one tool axis (always on a 3-axis mill), else 5-axis
  ThreePlusTwo,  // "3+2"
  FiveAxis,      // "5axis"
};
PostMode parsePostMode(const std::string& text);  // auto | 3+2 | 5axis; throws InputError
const char* postModeName(PostMode mode);

struct PostOptions {
  PostMode mode = PostMode::Auto;
  double chordal_tolerance = 0.005;       // mm: 5-axis moves: tip of the interpolated joints to the CL segment
  double axis_tolerance_deg = 0.1;        // deg: 5-axis moves: tool axis of the interpolated joints to the CL axis
  double same_axis_tolerance_deg = 0.01;  // deg: 3+2: the tool axes of one setup must agree within this
  // Safe height: the gauge point's machine Z (G53 Z) for retracts. NaN: the Z joint's maximum minus retract_margin
  // (a margin keeps rounding from touching the soft limit).
  double retract_z = std::numeric_limits<double>::quiet_NaN();
  double retract_margin = 1.0;  // mm
  // A feed move heading down the tool axis steeper than this (deg from the axis) is a plunge: tool plunge_mm_min.
  double plunge_angle_deg = 45;
  bool drilling_cycles = true;  // 3+2: drilling runs become G81 / G83 (see above); false: G0 / G1 throughout
  double peck_ratio = 3.0;      // a drilling feed longer than this many drill diameters is pecked (G83)
  std::map<int, FixturePose> fixtures;  // per setup: where the part sits, overriding the machine file's
  // Set: post only the points of the setup with this index (none when no setup has it: the input is checked, nothing
  // posted). The placement search (fixture_placement.h) checks setups one by one.
  std::optional<int> only_setup;
  std::vector<std::string> preamble;    // G-code lines after the modal set-up, e.g. "M429" on the LinuxCNC sim
  IkOptions ik;
};

// A tool as the controller knows it: its number (T, H and pocket) and its length offset.
struct PostTool {
  int number = 0;
  Tool tool;
  double length = 0;  // gauge line to tip: toolLength(tool) (stickout + holder), mm
};

enum class StepKind {
  Move,        // G0 / G1 in joint coordinates
  Retract,     // G53 G0 Z retract_z: only Z moves
  ToolChange,  // coolant and spindle off, T M6, G43 H, spindle and coolant on
};

struct ProgramStep {
  StepKind kind = StepKind::Move;
  MoveKind move = MoveKind::Rapid;  // Move: G0 (rapid) or G1 (feed)
  JointPosition joints;             // Move, Retract: where the joints end (mm, rad)
  double feed_mm_min = 0;           // Move, feed: the tip's feed relative to the part
  double tip_length = 0;            // Move: mm the tip travels relative to the part (the CL segment's share)
  int tool = 0;                     // ToolChange: PostTool::number
  int row = -1;                     // the toolpaths.csv point (0-based) the move heads for; -1: retract, approach
  bool at_row = false;              // the move ends on that point (else on a subdivision point before it)
  std::string comment;              // printed before the step when not empty
  int cycle = -1;                   // >= 0: a step of SetupProgram::cycles[cycle] (printed as the cycle's one line)
};

// A canned drilling cycle (G81 / G83) at one hole; the steps tagged with it are its motion.
struct DrillCycle {
  JointPosition bottom;             // the joints at the hole's bottom: the cycle's X Y Z
  double r_z = 0;                   // the joint Z of the R plane
  double clear_z = 0;               // the joint Z it retracts to: where it began (G98) or the R plane (G99)
  bool retract_to_start = true;     // G98 (else G99)
  double peck = 0;                  // G83's Q, mm; 0: G81
  double feed_mm_min = 0;
};

struct SetupProgram {
  int setup = 0;  // toolpaths.csv's setup index
  FixturePose fixture;
  std::vector<ProgramStep> steps;  // begins with a retract and a tool change, ends with a retract
  std::vector<int> tools;          // tool numbers in the order they are used
  std::vector<DrillCycle> cycles;  // the canned cycles the steps refer to, in order
};

struct MachineProgram {
  Machine machine;
  std::string part_name;
  PostMode mode = PostMode::ThreePlusTwo;  // resolved: never Auto
  PostOptions options;
  double retract_z = 0;           // resolved safe height (gauge point, machine Z)
  JointPosition start;            // where the machine is when the job begins (home, inside the travel)
  std::vector<PostTool> tools;    // numbered 1.. in the order of first use
  std::vector<SetupProgram> setups;  // in the order of toolpaths.csv

  const PostTool& tool(int number) const;  // throws std::out_of_range
  int stepCount() const;
};

// The whole job. `tools` is tools.json (every tool id of the path must be there); `part_name` goes in the headers.
MachineProgram buildMachineProgram(const Machine& machine, const Toolpath& path, const std::vector<Tool>& tools,
                                   const std::string& part_name, const PostOptions& options = {});

// The program X Y Z (G-code under identity kinematics with G43 of a tool of `tool_length`): the joints' X Y Z minus
// the tool length in Z.
Vec3 programXyz(const JointPosition& joints, double tool_length);

}  // namespace art2part
