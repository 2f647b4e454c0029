// Forward kinematics: joints -> tool tip and axis (machine, table and part frames).
#include <cmath>

#include "art2part/kinematics/inverse_kinematics.h"
#include "rotary_axes.h"

namespace art2part {

using namespace kinematics_detail;

Placement placementFor(const Machine& machine, int setup, double tool_length) {
  Placement placement;
  placement.fixture = fixtureForSetup(machine, setup);
  placement.tool_length = tool_length;
  return placement;
}

double angleBetween(const Vec3& a, const Vec3& b) { return std::atan2(a.cross(b).norm(), a.dot(b)); }

ToolPose toolPoseInMachine(const Machine& machine, double tool_length, const JointPosition& joints) {
  ToolPose pose;
  const Vec3 z = Vec3::UnitZ();
  if (machine.kind == MachineKind::HeadBC) {
    const double pivot = machine.geometry.pivot_length;
    pose.axis = toolAxisOf(machine.kind, joints.tilt, joints.rotary);
    pose.tip = joints.linear + pivot * z - (pivot + tool_length) * pose.axis;
  } else {  // the spindle does not tilt
    pose.axis = z;
    pose.tip = joints.linear - tool_length * z;
  }
  return pose;
}

ToolPose toolPoseInTable(const Machine& machine, double tool_length, const JointPosition& joints) {
  const ToolPose in_machine = toolPoseInMachine(machine, tool_length, joints);
  if (machine.kind != MachineKind::TableTiltAC && machine.kind != MachineKind::TableTiltBC) return in_machine;
  // Undo the table's motion: m = r + o + T (R_z (t - r) - o)  =>  t = r + R_z^T (T^T (m - r - o) + o).
  const Vec3& r = machine.geometry.rot_point;
  const Vec3& o = machine.geometry.offset;
  const Eigen::Matrix3d table_to_machine = tiltRotation(machine.kind, joints.tilt) * rotationZ(joints.rotary);
  ToolPose pose;
  pose.tip = r + rotationZ(joints.rotary).transpose() *
                     (tiltRotation(machine.kind, joints.tilt).transpose() * (in_machine.tip - r - o) + o);
  pose.axis = table_to_machine.transpose() * in_machine.axis;
  return pose;
}

ToolPose forwardKinematics(const Machine& machine, const Placement& placement, const JointPosition& joints) {
  const ToolPose in_table = toolPoseInTable(machine, placement.tool_length, joints);
  ToolPose pose;
  pose.tip = placement.fixture.pointToPart(in_table.tip);
  pose.axis = placement.fixture.directionToPart(in_table.axis);
  return pose;
}

}  // namespace art2part
