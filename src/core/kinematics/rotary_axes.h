// Internal: the rotary-axis formulas each machine kind is made of, shared by forward and inverse kinematics.
#pragma once

#include <optional>

#include "art2part/common/angles.h"
#include "art2part/kinematics/machine.h"

namespace art2part::kinematics_detail {

Eigen::Matrix3d rotationX(double angle);
Eigen::Matrix3d rotationY(double angle);
Eigen::Matrix3d rotationZ(double angle);

// Table-table: the rotation of the tilt axis (R_x for A, R_y for B).
Eigen::Matrix3d tiltRotation(MachineKind kind, double tilt);

// The tool axis the rotaries give, in the table frame (machine frame for head-head): see inverse_kinematics.h.
Vec3 toolAxisOf(MachineKind kind, double tilt, double rotary);

// The rotaries (tilt >= 0, C in (-pi, pi]) of the positive branch that give `axis` (unit, table frame). Undefined C
// when the axis lies along the C axis (singular).
void rotaryAnglesOf(MachineKind kind, const Vec3& axis, double& tilt, double& rotary);

// The signed tilt that brings the tool nearest `axis` with C held at `rotary` (exact when the axis lies in the plane
// the tilt sweeps at that C).
double tiltWithRotaryHeld(MachineKind kind, const Vec3& axis, double rotary);

// angle + 2 pi k nearest `reference` among those inside [min, max]; none when no turn lies inside.
std::optional<double> nearestTurn(double angle, double reference, double min, double max);
// angle + 2 pi k nearest `reference`, regardless of limits.
double nearestTurn(double angle, double reference);

// Linear joints (gauge point) that put the tip at `tip_table` with the rotaries at `tilt`, `rotary`.
Vec3 linearJointsFor(const Machine& machine, double tool_length, const Vec3& tip_table, double tilt, double rotary);

}  // namespace art2part::kinematics_detail
