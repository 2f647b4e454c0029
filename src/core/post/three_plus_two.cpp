// 3+2 setups: the rotaries positioned once (the IK branch that keeps every point of the setup inside the travel,
// nearest the joints before), then X Y Z moves only. With the rotaries fixed, the tip in the part frame is an affine
// (rigid) function of the linear joints, so each point's joints come from one 3x3 solve, exact to rounding.
#include <cmath>
#include <cstdio>
#include <limits>

#include "program_builder.h"

namespace art2part::post_detail {

FixedOrientation::FixedOrientation(const Machine& machine, const Placement& placement, const JointPosition& rotaries)
    : rotaries_(rotaries) {
  JointPosition joints = rotaries;
  joints.linear = Vec3::Zero();
  origin_ = forwardKinematics(machine, placement, joints).tip;
  Eigen::Matrix3d map;
  for (int c = 0; c < 3; ++c) {
    joints.linear = Vec3::Unit(c);
    map.col(c) = forwardKinematics(machine, placement, joints).tip - origin_;
  }
  inverse_ = map.inverse();
}

JointPosition FixedOrientation::jointsFor(const Vec3& tip) const {
  JointPosition joints = rotaries_;
  joints.linear = inverse_ * (tip - origin_);
  return joints;
}

namespace {

// The setup's one tool axis, or an error naming the two points that disagree.
void requireOneAxis(const ProgramBuilder& builder, PointRun run) {
  int widest_row = run.begin;
  const double spread = axisSpread(builder.path(), run, &widest_row);
  if (spread <= builder.options().same_axis_tolerance_deg * kDegree) return;
  char text[160];
  std::snprintf(text, sizeof text, "the tool axis differs by %.4f deg from that of line %d", spread / kDegree,
                run.begin + 2);
  throw InputError(describePoint(builder.path(), widest_row) + ": setup " +
                   std::to_string(builder.path()[run.begin].setup) + " is not a 3+2 setup: " + text +
                   " (one axis per setup; post it with --mode 5axis)");
}

// A 3-axis mill: every axis along the spindle once the part is fixtured.
void requireSpindleAxis(const ProgramBuilder& builder, PointRun run) {
  for (int row = run.begin; row < run.end; ++row) {
    const IkSolution solution = inverseKinematics(builder.machine(), builder.placementFor(row),
                                                  poseOf(builder.path()[row]), builder.current(), builder.options().ik);
    if (solution.status == IkStatus::AxisUnreachable || solution.status == IkStatus::InvalidPose)
      throw InputError(describePoint(builder.path(), row) + ": " + solution.reason + " (machine " +
                       builder.machine().name + " machines only setups whose tool axis is along its spindle once " +
                       "the part is fixtured: give setup " + std::to_string(builder.path()[row].setup) +
                       " a fixture that turns its axis up)");
  }
}

// The first limit violation of the run's points with the rotaries of `candidate`; empty when all fit.
std::string violationWith(const ProgramBuilder& builder, PointRun run, const JointPosition& candidate, int& row_out) {
  // The candidate's rotaries (its linear joints are recomputed per point below).
  JointPosition rotaries_only = candidate;
  rotaries_only.linear = builder.current().linear;
  const std::string rotary_violation =
      limitViolation(builder.machine(), rotaries_only, builder.options().ik.limit_tolerance);
  if (!rotary_violation.empty()) {
    row_out = run.begin;
    return rotary_violation;
  }
  for (const PointRun& tools : toolRuns(builder.path(), run)) {
    const FixedOrientation orientation(builder.machine(), builder.placementFor(tools.begin), candidate);
    for (int row = tools.begin; row < tools.end; ++row) {
      const std::string violation = limitViolation(builder.machine(), orientation.jointsFor(builder.path()[row].tip),
                                                   builder.options().ik.limit_tolerance);
      if (!violation.empty()) {
        row_out = row;
        return violation;
      }
    }
  }
  return "";
}

double rotaryMoveTime(const Machine& machine, const JointPosition& from, const JointPosition& to) {
  if (!machine.fiveAxis()) return 0;
  return std::max(std::abs(to.tilt - from.tilt) / machine.tiltJoint().max_velocity,
                  std::abs(to.rotary - from.rotary) / machine.rotaryJoint().max_velocity);
}

// The rotaries for the setup: among the IK branches of its first point (C at the turn nearest the joints before, or
// the turns either side of it), the quickest to reach of those that keep every point inside the travel.
JointPosition setupOrientation(const ProgramBuilder& builder, PointRun run) {
  const Machine& machine = builder.machine();
  std::vector<JointPosition> branches = inverseKinematicsBranches(
      machine, builder.placementFor(run.begin), poseOf(builder.path()[run.begin]), builder.current(),
      builder.options().ik);
  const size_t nearest_turns = branches.size();
  for (size_t b = 0; b < nearest_turns && machine.fiveAxis(); ++b)
    for (double turn : {-2 * kPi, 2 * kPi}) {  // when the nearest turn of C leaves its travel, the next may not
      JointPosition other = branches[b];
      other.rotary += turn;
      branches.push_back(other);
    }
  const JointPosition* best = nullptr;
  std::string why_not;
  int why_row = run.begin;
  for (const JointPosition& branch : branches) {
    int row = run.begin;
    const std::string violation = violationWith(builder, run, branch, row);
    if (violation.empty()) {
      if (!best || rotaryMoveTime(machine, builder.current(), branch) <
                       rotaryMoveTime(machine, builder.current(), *best))
        best = &branch;
    } else if (why_not.empty()) {
      why_not = violation;
      why_row = row;
    }
  }
  if (best) return *best;
  if (branches.empty()) throw InputError(describePoint(builder.path(), run.begin) + ": the tool axis is unreachable");
  throw InputError(describePoint(builder.path(), why_row) + ": no orientation of setup " +
                   std::to_string(builder.path()[run.begin].setup) + " keeps every point inside the travel of " +
                   machine.name + " (" + why_not + ")");
}

}  // namespace

void planThreePlusTwo(ProgramBuilder& builder, PointRun setup_run) {
  if (!builder.machine().fiveAxis()) requireSpindleAxis(builder, setup_run);
  requireOneAxis(builder, setup_run);
  const JointPosition rotaries = setupOrientation(builder, setup_run);
  const Toolpath& path = builder.path();
  for (const PointRun& run : toolRuns(path, setup_run)) {
    const FixedOrientation orientation(builder.machine(), builder.placementFor(run.begin), rotaries);
    builder.retract();
    builder.changeTool(builder.toolOf(run.begin).number);
    builder.note("op " + std::to_string(path[run.begin].op));
    builder.approach(orientation.jointsFor(path[run.begin].tip), path[run.begin].move, run.begin);
    for (int row = run.begin + 1; row < run.end; ++row) {
      const int after_cycle = planDrillingCycle(builder, orientation, run, row);
      if (after_cycle > row) {
        row = after_cycle - 1;
        continue;
      }
      ProgramStep step;
      step.move = path[row].move;
      step.joints = orientation.jointsFor(path[row].tip);
      step.row = row;
      step.at_row = true;
      step.tip_length = (path[row].tip - path[row - 1].tip).norm();
      if (step.move == MoveKind::Feed) step.feed_mm_min = builder.feedFor(row - 1, row);
      if (path[row].op != path[row - 1].op) step.comment = "op " + std::to_string(path[row].op);
      builder.moveTo(step);
    }
  }
}

}  // namespace art2part::post_detail
