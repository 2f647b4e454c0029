// The post's program model: tools numbered, points grouped by setup and tool, the mode resolved, and the builder
// that appends retracts, tool changes, approaches and moves.
#include "art2part/post/machine_program.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>

#include "program_builder.h"

namespace art2part {

using namespace post_detail;

PostMode parsePostMode(const std::string& text) {
  for (PostMode mode : {PostMode::Auto, PostMode::ThreePlusTwo, PostMode::FiveAxis})
    if (text == postModeName(mode)) return mode;
  throw InputError("unknown post mode '" + text + "' (expected 3+2, 5axis or auto)");
}

const char* postModeName(PostMode mode) {
  switch (mode) {
    case PostMode::Auto: return "auto";
    case PostMode::ThreePlusTwo: return "3+2";
    case PostMode::FiveAxis: return "5axis";
  }
  return "";
}

Vec3 programXyz(const JointPosition& joints, double tool_length) {
  return joints.linear - tool_length * Vec3::UnitZ();
}

const PostTool& MachineProgram::tool(int number) const {
  for (const PostTool& tool : tools)
    if (tool.number == number) return tool;
  throw std::out_of_range("no tool T" + std::to_string(number) + " in the program");
}

int MachineProgram::stepCount() const {
  int count = 0;
  for (const SetupProgram& setup : setups) count += static_cast<int>(setup.steps.size());
  return count;
}

namespace post_detail {

std::string describePoint(const Toolpath& path, int row) {
  const CutterLocation& point = path.at(row);
  return "toolpaths.csv line " + std::to_string(row + 2) + " (op " + std::to_string(point.op) + ", setup " +
         std::to_string(point.setup) + ", tool '" + point.tool + "')";
}

std::vector<PointRun> toolRuns(const Toolpath& path, PointRun setup_run) {
  std::vector<PointRun> runs;
  for (int row = setup_run.begin; row < setup_run.end; ++row) {
    if (runs.empty() || path[row].tool != path[row - 1].tool) runs.push_back({row, row});
    runs.back().end = row + 1;
  }
  return runs;
}

ToolPose poseOf(const CutterLocation& point) {
  ToolPose pose;
  pose.tip = point.tip;
  pose.axis = point.axis;
  return pose;
}

double axisSpread(const Toolpath& path, PointRun run, int* widest_row) {
  double widest = 0;
  for (int row = run.begin; row < run.end; ++row) {
    const double angle = angleBetween(path[run.begin].axis, path[row].axis);
    if (angle > widest) {
      widest = angle;
      if (widest_row) *widest_row = row;
    }
  }
  return widest;
}

// ---- ProgramBuilder ------------------------------------------------------------------------------------------------

ProgramBuilder::ProgramBuilder(MachineProgram& program, const Toolpath& path, std::map<std::string, int> tool_numbers)
    : program_(program), path_(path), tool_numbers_(std::move(tool_numbers)), current_(program.start) {}

const PostTool& ProgramBuilder::toolOf(int row) const { return program_.tool(tool_numbers_.at(path_.at(row).tool)); }

Placement ProgramBuilder::placementFor(int row) const {
  Placement placement;
  placement.fixture = program_.setups.back().fixture;
  placement.tool_length = toolOf(row).length;
  return placement;
}

void ProgramBuilder::beginSetup(int setup_index) {
  SetupProgram setup;
  setup.setup = setup_index;
  const auto given = program_.options.fixtures.find(setup_index);
  setup.fixture =
      given != program_.options.fixtures.end() ? given->second : fixtureForSetup(program_.machine, setup_index);
  program_.setups.push_back(setup);
}

void ProgramBuilder::append(ProgramStep step) {
  if (step.kind != StepKind::ToolChange) {
    const std::string violation = limitViolation(machine(), step.joints, options().ik.limit_tolerance);
    if (!violation.empty())
      throw InputError("post: a move leaves the joint travel (" + violation + ")" +
                       (step.row >= 0 ? " near " + describePoint(path_, step.row) : std::string()));
    current_ = step.joints;
  }
  if (!note_.empty()) step.comment = step.comment.empty() ? note_ : note_ + ", " + step.comment;
  note_.clear();
  setup().steps.push_back(std::move(step));
}

JointPosition ProgramBuilder::atSafeHeight(JointPosition joints) const {
  joints.linear.z() = program_.retract_z;
  return joints;
}

void ProgramBuilder::retract(bool always) {
  if (!always && current_.linear.z() == program_.retract_z) return;
  ProgramStep step;
  step.kind = StepKind::Retract;
  step.joints = atSafeHeight(current_);
  append(step);
}

void ProgramBuilder::changeTool(int tool_number) {
  ProgramStep step;
  step.kind = StepKind::ToolChange;
  step.tool = tool_number;
  step.joints = current_;
  const PostTool& tool = program_.tool(tool_number);
  step.comment = "T" + std::to_string(tool_number) + ": " + tool.tool.id;
  append(step);
  tool_ = tool_number;
  SetupProgram& here = setup();
  if (std::find(here.tools.begin(), here.tools.end(), tool_number) == here.tools.end())
    here.tools.push_back(tool_number);
}

void ProgramBuilder::positionRotaries(const JointPosition& target) {
  if (!machine().fiveAxis()) return;
  if (target.tilt == current_.tilt && target.rotary == current_.rotary) return;
  retract();
  ProgramStep step;
  step.joints = current_;
  step.joints.tilt = target.tilt;
  step.joints.rotary = target.rotary;
  step.comment = "rotaries";
  moveTo(step);
}

void ProgramBuilder::approach(const JointPosition& target, MoveKind move, int row) {
  positionRotaries(target);
  if (current_.linear.z() != program_.retract_z) retract();
  ProgramStep above;
  above.joints = atSafeHeight(target);
  moveTo(above);
  ProgramStep down;
  down.move = move;
  down.joints = target;
  down.row = row;
  down.at_row = true;
  down.tip_length = std::abs(program_.retract_z - target.linear.z());
  if (move == MoveKind::Feed) down.feed_mm_min = toolOf(row).tool.plunge_mm_min;
  moveTo(down);
}

int ProgramBuilder::addCycle(const DrillCycle& cycle) {
  setup().cycles.push_back(cycle);
  return static_cast<int>(setup().cycles.size()) - 1;
}

void ProgramBuilder::cycleStep(ProgramStep step, int cycle) {
  step.kind = StepKind::Move;
  step.cycle = cycle;
  append(step);
}

void ProgramBuilder::note(const std::string& comment) {
  note_ = note_.empty() ? comment : note_ + ", " + comment;
}

void ProgramBuilder::moveTo(ProgramStep step) {
  step.kind = StepKind::Move;
  const bool still = (step.joints.linear - current_.linear).cwiseAbs().maxCoeff() < 1e-9 &&
                     std::abs(step.joints.tilt - current_.tilt) < 1e-12 &&
                     std::abs(step.joints.rotary - current_.rotary) < 1e-12;
  if (still) return;
  append(step);
}

double ProgramBuilder::feedFor(int from_row, int to_row) const {
  const Tool& tool = toolOf(to_row).tool;
  const Vec3 along = path_[to_row].tip - path_[from_row].tip;
  const double length = along.norm();
  if (length > 0 && -along.dot(path_[to_row].axis) >= length * std::cos(options().plunge_angle_deg * kDegree))
    return tool.plunge_mm_min;
  return tool.feed_mm_min;
}

}  // namespace post_detail

namespace {

// Tools numbered 1.. in the order the path first uses them; every id must be in tools.json.
std::map<std::string, int> numberTools(const Toolpath& path, const std::vector<Tool>& tools,
                                       std::vector<PostTool>& numbered) {
  std::map<std::string, int> numbers;
  for (int row = 0; row < static_cast<int>(path.size()); ++row) {
    const std::string& id = path[row].tool;
    if (numbers.count(id)) continue;
    const auto found = std::find_if(tools.begin(), tools.end(), [&](const Tool& tool) { return tool.id == id; });
    if (found == tools.end()) throw InputError(describePoint(path, row) + ": tool '" + id + "' is not in tools.json");
    if (!(found->feed_mm_min > 0) || !(found->plunge_mm_min > 0) || !(found->spindle_rpm > 0))
      throw InputError("tools.json: tool '" + id + "' needs positive feed_mm_min, plunge_mm_min and spindle_rpm");
    PostTool tool;
    tool.number = static_cast<int>(numbered.size()) + 1;
    tool.tool = *found;
    tool.length = toolLength(*found);
    numbered.push_back(tool);
    numbers[id] = tool.number;
  }
  return numbers;
}

// Consecutive points of one setup; a setup that comes back after another is an error (re-fixturing twice).
std::vector<PointRun> setupRuns(const Toolpath& path) {
  std::vector<PointRun> runs;
  std::set<int> seen;
  for (int row = 0; row < static_cast<int>(path.size()); ++row) {
    if (row == 0 || path[row].setup != path[row - 1].setup) {
      if (!seen.insert(path[row].setup).second)
        throw InputError(describePoint(path, row) + ": setup " + std::to_string(path[row].setup) +
                         " comes back after another setup; the points of a setup must be consecutive");
      runs.push_back({row, row});
    }
    runs.back().end = row + 1;
  }
  return runs;
}

PostMode resolveMode(const Machine& machine, const Toolpath& path, const std::vector<PointRun>& runs,
                     const PostOptions& options) {
  if (!machine.fiveAxis()) {
    if (options.mode == PostMode::FiveAxis)
      throw InputError("machine " + machine.name + " (" + machine.source +
                       ") is a 3-axis mill: 5-axis programs need a 5-axis machine");
    return PostMode::ThreePlusTwo;
  }
  if (options.mode != PostMode::Auto) return options.mode;
  for (const PointRun& run : runs)
    if (axisSpread(path, run) > options.same_axis_tolerance_deg * kDegree) return PostMode::FiveAxis;
  return PostMode::ThreePlusTwo;
}

double resolveRetractZ(const Machine& machine, const PostOptions& options) {
  const Joint& z = machine.joints.at(2);
  const double retract = std::isnan(options.retract_z) ? z.max - options.retract_margin : options.retract_z;
  if (!z.within(retract))
    throw InputError("safe height Z " + std::to_string(retract) + " mm lies outside the Z travel of machine " +
                     machine.name);
  return retract;
}

// Home (all joints 0), moved inside the travel.
JointPosition startPosition(const Machine& machine) {
  std::vector<double> values(machine.jointCount(), 0.0);
  for (int j = 0; j < machine.jointCount(); ++j)
    values[j] = std::clamp(0.0, machine.joints[j].min, machine.joints[j].max);
  return jointPositionFromVector(machine, values);
}

}  // namespace

MachineProgram buildMachineProgram(const Machine& machine, const Toolpath& path, const std::vector<Tool>& tools,
                                   const std::string& part_name, const PostOptions& options) {
  if (path.empty()) throw InputError("toolpaths.csv has no points: nothing to post");
  if (!(options.chordal_tolerance > 0) || !(options.axis_tolerance_deg > 0))
    throw InputError("post: the chordal and axis tolerances must be positive");
  MachineProgram program;
  program.machine = machine;
  program.part_name = part_name;
  program.options = options;
  program.retract_z = resolveRetractZ(machine, options);
  program.start = startPosition(machine);
  std::map<std::string, int> numbers = numberTools(path, tools, program.tools);
  const std::vector<PointRun> runs = setupRuns(path);
  program.mode = resolveMode(machine, path, runs, options);

  ProgramBuilder builder(program, path, std::move(numbers));
  for (const PointRun& run : runs) {
    if (options.only_setup && path[run.begin].setup != *options.only_setup) continue;
    builder.beginSetup(path[run.begin].setup);
    builder.retract(true);  // a setup's own program starts wherever the machine is
    if (program.mode == PostMode::ThreePlusTwo) {
      planThreePlusTwo(builder, run);
    } else {
      planFiveAxis(builder, run);
    }
    builder.retract();
  }
  return program;
}

}  // namespace art2part
