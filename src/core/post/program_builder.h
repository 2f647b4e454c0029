// Internal to the post: the step-by-step builder of a MachineProgram that the 3+2 and 5-axis planners share.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "art2part/common/angles.h"
#include "art2part/post/machine_program.h"

namespace art2part::post_detail {

constexpr double kDegree = kPi / 180;

// Consecutive toolpath points [begin, end).
struct PointRun {
  int begin = 0, end = 0;
};

// "toolpaths.csv line 19 (op 3, setup 1, tool 'ball6')" for point `row` (0-based).
std::string describePoint(const Toolpath& path, int row);

// The setup's points split where the tool changes.
std::vector<PointRun> toolRuns(const Toolpath& path, PointRun setup_run);

ToolPose poseOf(const CutterLocation& point);

// Appends steps to the program's last setup, tracking where the joints are and which tool is in the spindle. Every
// step's joints are checked against the machine's travel (a violation is a bug upstream: it throws).
class ProgramBuilder {
 public:
  ProgramBuilder(MachineProgram& program, const Toolpath& path, std::map<std::string, int> tool_numbers);

  const Machine& machine() const { return program_.machine; }
  const PostOptions& options() const { return program_.options; }
  const Toolpath& path() const { return path_; }
  const JointPosition& current() const { return current_; }
  const PostTool& toolOf(int row) const;  // the tool of toolpath point `row`
  Placement placementFor(int row) const;  // the setup's fixture and the tool of point `row`

  void beginSetup(int setup);
  void retract(bool always = false);  // G53 G0 Z up to the safe height, unless there (or always)
  void changeTool(int tool_number);                     // (call retract() first)
  void positionRotaries(const JointPosition& target);  // up to the safe height, then the rotaries alone
  // To `target` from above: rotaries (at the safe height), X Y, then Z down (rapid, or at the plunge feed).
  void approach(const JointPosition& target, MoveKind move, int row);
  void moveTo(ProgramStep step);  // a Move; dropped when the joints do not change
  // Drilling cycles: the cycle's index in the setup, and its steps (kept even when they do not move: rs274 makes them).
  int addCycle(const DrillCycle& cycle);
  void cycleStep(ProgramStep step, int cycle);
  void note(const std::string& comment);  // a comment printed before the next step
  double feedFor(int from_row, int to_row) const;  // the tool's feed, or its plunge feed down the axis

 private:
  SetupProgram& setup() { return program_.setups.back(); }
  void append(ProgramStep step);
  JointPosition atSafeHeight(JointPosition joints) const;

  MachineProgram& program_;
  const Toolpath& path_;
  std::map<std::string, int> tool_numbers_;
  JointPosition current_;
  int tool_ = 0;
  std::string note_;
};

// The linear joints that put the tip at a part-frame point with the rotaries held: tip(lin) = origin + map * lin.
// With the rotaries fixed the tip is an affine (rigid) function of the linear joints, so one 3x3 solve is exact.
class FixedOrientation {
 public:
  FixedOrientation(const Machine& machine, const Placement& placement, const JointPosition& rotaries);
  JointPosition jointsFor(const Vec3& tip) const;

 private:
  JointPosition rotaries_;
  Vec3 origin_;
  Eigen::Matrix3d inverse_;
};

// 3+2: when the points from `row` on are a drilling run (machine_program.h), appends its canned cycle's steps and
// returns the first row after it; else returns `row` and appends nothing.
int planDrillingCycle(ProgramBuilder& builder, const FixedOrientation& orientation, PointRun run, int row);

// The planners: append the steps of one setup's points (retracts, tool changes, approaches and moves).
void planThreePlusTwo(ProgramBuilder& builder, PointRun setup_run);
void planFiveAxis(ProgramBuilder& builder, PointRun setup_run);

// Largest angle (rad) between the tool axis of a point in the run and that of its first point, and the point.
double axisSpread(const Toolpath& path, PointRun run, int* widest_row = nullptr);

}  // namespace art2part::post_detail
