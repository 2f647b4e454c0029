// Forward and inverse kinematics of the machines in machine.h: joints <-> (tool tip, tool axis) in the part frame.
//
// Geometry (LinuxCNC's trtfuncs.c and 5axiskins.c; R_x, R_y, R_z rotate right-handedly by the angle; z = (0,0,1)):
//   table-table  a table point t goes to m = r + o + T(tilt) (R_z(C) (t - r) - o) in the machine frame, where
//                r = rot_point, o = offset, T = R_x (A, xyzac) or R_y (B, xyzbc); tip m = gauge - tool_length z;
//                tool axis in the table frame = R_z(C)^T T(tilt)^T z
//                  xyzac: (sin C sin A,  cos C sin A, cos A)     xyzbc: (-cos C sin B, sin C sin B, cos B)
//   head-head    tool axis = R_z(C) R_y(-B) z = (-cos C sin B, -sin C sin B, cos B) (5axiskins: +B swings the tip
//                towards +X at C = 0);
//                tip = gauge + pivot_length z - (pivot_length + tool_length) axis
//   3-axis       tool axis = z; tip = gauge - tool_length z
// Each 5-axis pose away from the singularity has two solution branches, (tilt, C) and (-tilt, C + 180 deg), and every
// rotary angle repeats each 360 deg; the inverse picks among them the one nearest the previous joints (shortest
// rotary move) that stays inside the limits. The singularity is the tool axis along the C axis (tilt 0): C is then
// free; inverseKinematics holds it at its previous value, inverseKinematicsPath takes it from the next regular pose.
#pragma once

#include <string>
#include <vector>

#include "art2part/kinematics/machine.h"
#include "art2part/tooling/tool.h"

namespace art2part {

// What the kinematics needs besides the machine: where the part sits and how long the tool is.
struct Placement {
  FixturePose fixture;       // the part frame in the table frame
  double tool_length = 0;    // from the spindle gauge line to the tool tip, mm (LinuxCNC's tool length offset)
};

// The fixture of `setup` on `machine` (its override, else the machine's default) with a tool of tool_length.
Placement placementFor(const Machine& machine, int setup, double tool_length);

// ---- forward: joints -> tool pose ----
ToolPose forwardKinematics(const Machine& machine, const Placement& placement, const JointPosition& joints);
// In the table frame: the X Y Z (and tool axis) of G-code under LinuxCNC's TCP kinematics (M428 in the trt sim).
ToolPose toolPoseInTable(const Machine& machine, double tool_length, const JointPosition& joints);
// In the machine frame: G-code X Y Z under identity kinematics with G43 (tool length compensation) active.
ToolPose toolPoseInMachine(const Machine& machine, double tool_length, const JointPosition& joints);

// ---- inverse: tool pose -> joints ----
struct IkOptions {
  // rad. Within this angle of the C axis the pose is singular and C is held; the axis then comes out at most this far
  // from the one asked for (axis_error). A 3-axis machine accepts axes within this angle of its spindle.
  double axis_tolerance = 1e-6;
  double limit_tolerance = 1e-9;  // mm or rad a joint may overrun its travel (rounding)
};

enum class IkStatus {
  Ok,
  OutsideLimits,    // every branch leaves some joint's travel (reason names which)
  AxisUnreachable,  // the machine cannot point the tool that way at all (a tilted axis on a 3-axis machine)
  InvalidPose,      // NaN, or an axis of zero length
};

struct IkSolution {
  IkStatus status = IkStatus::Ok;
  // The joints chosen. When not Ok: the candidate nearest the previous joints, for diagnosis (not to be run).
  JointPosition joints;
  std::string reason;         // empty when Ok; otherwise one line saying why
  bool rotary_held = false;   // singular pose: C was held at its previous value
  double axis_error = 0;      // rad between the requested axis and the one the joints give (held, or 3-axis)
  bool ok() const { return status == IkStatus::Ok; }
};

// The joints that put the tool at `pose` (part frame), nearest `previous` (continuity; use the machine's current
// position, or JointPosition{} from home). Branch choice: of the candidates inside the limits, the one with the
// shortest rotary move time max(|d tilt| / v_tilt, |d C| / v_C); C (and the tilt if its travel exceeds a turn) is taken
// as the turn (angle + 360 k) nearest the previous value that lies in its travel. Never throws.
IkSolution inverseKinematics(const Machine& machine, const Placement& placement, const ToolPose& pose,
                             const JointPosition& previous, const IkOptions& options = {});

// Every exact solution branch (none on a 3-axis machine when the axis is tilted; one when singular), each rotary
// angle taken at the turn nearest `previous` regardless of limits. For tests and for planners that weigh branches.
std::vector<JointPosition> inverseKinematicsBranches(const Machine& machine, const Placement& placement,
                                                     const ToolPose& pose, const JointPosition& previous,
                                                     const IkOptions& options = {});

// Whether the pose is singular on this machine: a 5-axis machine with the tool axis within options.axis_tolerance of
// the C axis (C is then free). False on a 3-axis machine and for an invalid pose.
bool singularPose(const Machine& machine, const Placement& placement, const ToolPose& pose, const IkOptions& options = {});

// A whole sequence of poses, each solved from the solution before (the first from `start`), so that rotary motion is
// continuous: C never jumps by more than the move between two poses needs. A singular pose does not hold C blindly:
// it takes the C of the next regular (non-singular) pose of the sequence, that pose's branch nearest the joints before
// the singularity (issue 17: a finishing pass over a dome's apex tilts -x, is vertical, tilts +x: C stays; a pass that
// starts vertical takes the C it tilts at; a run of singular poses shares one C). Singular poses at the end of the
// sequence hold C. When the branch before the singularity and the one after differ in C (the axis leaves the
// singularity in another plane than it came), C turns at the singular pose: the post turns it there in place
// (five_axis_motion.cpp). A pose that fails leaves the chain at the last good solution. One solution per pose.
std::vector<IkSolution> inverseKinematicsPath(const Machine& machine, const Placement& placement,
                                              const std::vector<ToolPose>& poses, const JointPosition& start,
                                              const IkOptions& options = {});

// Angle between two directions (rad), accurate for tiny angles.
double angleBetween(const Vec3& a, const Vec3& b);

}  // namespace art2part
