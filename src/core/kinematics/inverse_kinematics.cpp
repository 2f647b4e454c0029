// Inverse kinematics: tool tip and axis in the part frame -> joints, with branch choice, C unwinding and the
// singularity held.
#include "art2part/kinematics/inverse_kinematics.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "rotary_axes.h"

namespace art2part {

using namespace kinematics_detail;

namespace {

constexpr double kDegree = kPi / 180;

// The pose in the table frame, checked and with a unit axis; false for NaN or a zero axis.
bool poseInTable(const Placement& placement, const ToolPose& pose, ToolPose& in_table) {
  const double length = pose.axis.norm();
  if (!pose.tip.allFinite() || !pose.axis.allFinite() || !(length > 1e-12)) return false;
  in_table.tip = placement.fixture.pointToTable(pose.tip);
  in_table.axis = placement.fixture.directionToTable(pose.axis / length);
  return true;
}

// The angle + 2 pi k nearest the previous value inside the joint's travel; when no turn is inside, the nearest turn
// (which the limit check then reports).
double unwound(const Joint& joint, double angle, double previous, double tolerance) {
  if (auto inside = nearestTurn(angle, previous, joint.min - tolerance, joint.max + tolerance)) return *inside;
  return nearestTurn(angle, previous);
}

// The rotary solutions (tilt, C) that give the axis: both branches, or the one with C held when singular.
struct RotarySolutions {
  std::vector<std::pair<double, double>> angles;
  bool held = false;
  double axis_error = 0;
};

bool alongRotaryAxis(const Vec3& axis_in_table, const IkOptions& options) {
  return std::hypot(axis_in_table.x(), axis_in_table.y()) <= std::sin(options.axis_tolerance);
}

RotarySolutions rotarySolutions(const Machine& machine, const Vec3& axis, const JointPosition& previous,
                                const IkOptions& options) {
  RotarySolutions solutions;
  if (alongRotaryAxis(axis, options)) {
    // Axis along the C axis (either way): any C does; keep the one we have, inside its travel.
    const double rotary = unwound(machine.rotaryJoint(), previous.rotary, previous.rotary, options.limit_tolerance);
    const double tilt = tiltWithRotaryHeld(machine.kind, axis, rotary);
    solutions.angles.push_back({tilt, rotary});
    solutions.held = true;
    solutions.axis_error = angleBetween(axis, toolAxisOf(machine.kind, tilt, rotary));
    return solutions;
  }
  double tilt = 0, rotary = 0;
  rotaryAnglesOf(machine.kind, axis, tilt, rotary);
  solutions.angles.push_back({tilt, rotary});
  solutions.angles.push_back({-tilt, rotary + kPi});
  return solutions;
}

// Candidate joint positions for a pose in the table frame, each rotary angle at the turn nearest `previous` (inside
// the travel when limited). Empty for an axis a 3-axis machine cannot take.
std::vector<JointPosition> candidates(const Machine& machine, double tool_length, const ToolPose& in_table,
                                      const JointPosition& previous, const IkOptions& options, bool limited,
                                      RotarySolutions& rotaries) {
  std::vector<JointPosition> result;
  if (!machine.fiveAxis()) {
    rotaries.axis_error = angleBetween(in_table.axis, Vec3::UnitZ());
    if (rotaries.axis_error > options.axis_tolerance) return result;
    JointPosition joints;
    joints.linear = linearJointsFor(machine, tool_length, in_table.tip, 0, 0);
    result.push_back(joints);
    return result;
  }
  rotaries = rotarySolutions(machine, in_table.axis, previous, options);
  for (const auto& [tilt, rotary] : rotaries.angles) {
    JointPosition joints;
    if (limited) {
      joints.tilt = unwound(machine.tiltJoint(), tilt, previous.tilt, options.limit_tolerance);
      joints.rotary = unwound(machine.rotaryJoint(), rotary, previous.rotary, options.limit_tolerance);
    } else {
      joints.tilt = nearestTurn(tilt, previous.tilt);
      joints.rotary = nearestTurn(rotary, previous.rotary);
    }
    joints.linear = linearJointsFor(machine, tool_length, in_table.tip, joints.tilt, joints.rotary);
    result.push_back(joints);
  }
  return result;
}

// How long the rotaries take to get from one position to the other at full speed, and how far they turn.
double rotaryMoveTime(const Machine& machine, const JointPosition& from, const JointPosition& to) {
  if (!machine.fiveAxis()) return 0;
  return std::max(std::abs(to.tilt - from.tilt) / machine.tiltJoint().max_velocity,
                  std::abs(to.rotary - from.rotary) / machine.rotaryJoint().max_velocity);
}

double rotaryMoveAngle(const JointPosition& from, const JointPosition& to) {
  return std::abs(to.tilt - from.tilt) + std::abs(to.rotary - from.rotary);
}

bool nearer(const Machine& machine, const JointPosition& previous, const JointPosition& a, const JointPosition& b) {
  const double time_a = rotaryMoveTime(machine, previous, a), time_b = rotaryMoveTime(machine, previous, b);
  const double slack = 1e-12 * std::max(1.0, std::max(time_a, time_b));
  if (std::abs(time_a - time_b) > slack) return time_a < time_b;
  return rotaryMoveAngle(previous, a) < rotaryMoveAngle(previous, b) - 1e-12;
}

std::string describeRotaries(const Machine& machine, const JointPosition& joints) {
  char text[96];
  std::snprintf(text, sizeof text, "%s %.4f %s %.4f", machine.tiltJoint().name.c_str(), joints.tilt / kDegree,
                machine.rotaryJoint().name.c_str(), joints.rotary / kDegree);
  return text;
}

std::string describeAxis(const Vec3& axis) {
  char text[96];
  std::snprintf(text, sizeof text, "(%.6f, %.6f, %.6f)", axis.x(), axis.y(), axis.z());
  return text;
}

}  // namespace

IkSolution inverseKinematics(const Machine& machine, const Placement& placement, const ToolPose& pose,
                             const JointPosition& previous, const IkOptions& options) {
  IkSolution solution;
  solution.joints = previous;
  ToolPose in_table;
  if (!poseInTable(placement, pose, in_table)) {
    solution.status = IkStatus::InvalidPose;
    solution.reason = "tool pose has NaN or a zero-length axis: tip " + describeAxis(pose.tip) + " axis " +
                      describeAxis(pose.axis);
    return solution;
  }

  RotarySolutions rotaries;
  const std::vector<JointPosition> found =
      candidates(machine, placement.tool_length, in_table, previous, options, true, rotaries);
  solution.rotary_held = rotaries.held;
  solution.axis_error = rotaries.axis_error;
  if (found.empty()) {
    char text[200];
    std::snprintf(text, sizeof text,
                  "tool axis %s (part frame) is %.4f deg from the spindle axis; a 3-axis machine cannot tilt the tool",
                  describeAxis(pose.axis).c_str(), rotaries.axis_error / kDegree);
    solution.status = IkStatus::AxisUnreachable;
    solution.reason = text;
    solution.joints.linear = linearJointsFor(machine, placement.tool_length, in_table.tip, 0, 0);
    return solution;
  }

  const JointPosition* best_inside = nullptr;
  const JointPosition* best_any = nullptr;
  std::string why_not;
  for (const JointPosition& joints : found) {
    if (!best_any || nearer(machine, previous, joints, *best_any)) best_any = &joints;
    const std::string violation = limitViolation(machine, joints, options.limit_tolerance);
    if (violation.empty()) {
      if (!best_inside || nearer(machine, previous, joints, *best_inside)) best_inside = &joints;
    } else {
      if (!why_not.empty()) why_not += "; ";
      why_not += machine.fiveAxis() ? describeRotaries(machine, joints) + ": " + violation : violation;
    }
  }
  if (best_inside) {
    solution.joints = *best_inside;
    return solution;
  }
  solution.status = IkStatus::OutsideLimits;
  solution.joints = *best_any;
  solution.reason = "no solution inside the joint limits (" + why_not + ")";
  return solution;
}

std::vector<JointPosition> inverseKinematicsBranches(const Machine& machine, const Placement& placement,
                                                     const ToolPose& pose, const JointPosition& previous,
                                                     const IkOptions& options) {
  ToolPose in_table;
  if (!poseInTable(placement, pose, in_table)) return {};
  RotarySolutions rotaries;
  return candidates(machine, placement.tool_length, in_table, previous, options, false, rotaries);
}

bool singularPose(const Machine& machine, const Placement& placement, const ToolPose& pose, const IkOptions& options) {
  ToolPose in_table;
  return machine.fiveAxis() && poseInTable(placement, pose, in_table) && alongRotaryAxis(in_table.axis, options);
}

std::vector<IkSolution> inverseKinematicsPath(const Machine& machine, const Placement& placement,
                                              const std::vector<ToolPose>& poses, const JointPosition& start,
                                              const IkOptions& options) {
  const int count = static_cast<int>(poses.size());
  // The first pose at or after each that is not singular (count when none).
  std::vector<int> next_regular(count + 1, count);
  for (int i = count - 1; i >= 0; --i)
    next_regular[i] = singularPose(machine, placement, poses[i], options) ? next_regular[i + 1] : i;
  std::vector<IkSolution> solutions;
  solutions.reserve(poses.size());
  JointPosition previous = start;
  int looked_at = -1;         // the regular pose a run of singular poses took its C from
  double looked_rotary = 0;   // and that C
  for (int i = 0; i < count; ++i) {
    JointPosition from = previous;
    const int regular = next_regular[i];
    if (regular != i && regular < count) {
      // Singular: C is free. Take the C the next regular pose needs from here (its branch nearest the joints before
      // the singularity), so that pose follows without a flip; a whole run of singular poses shares it.
      if (looked_at != regular) {
        const IkSolution ahead = inverseKinematics(machine, placement, poses[regular], previous, options);
        looked_at = regular;
        looked_rotary = ahead.ok() ? ahead.joints.rotary : previous.rotary;
      }
      from.rotary = looked_rotary;
    }
    solutions.push_back(inverseKinematics(machine, placement, poses[i], from, options));
    if (solutions.back().ok()) previous = solutions.back().joints;
  }
  return solutions;
}

}  // namespace art2part
