#include "rotary_axes.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace art2part::kinematics_detail {

Eigen::Matrix3d rotationX(double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  Eigen::Matrix3d r;
  r << 1, 0, 0,
       0, c, -s,
       0, s, c;
  return r;
}

Eigen::Matrix3d rotationY(double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  Eigen::Matrix3d r;
  r << c, 0, s,
       0, 1, 0,
       -s, 0, c;
  return r;
}

Eigen::Matrix3d rotationZ(double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  Eigen::Matrix3d r;
  r << c, -s, 0,
       s, c, 0,
       0, 0, 1;
  return r;
}

Eigen::Matrix3d tiltRotation(MachineKind kind, double tilt) {
  return kind == MachineKind::TableTiltAC ? rotationX(tilt) : rotationY(tilt);
}

Vec3 toolAxisOf(MachineKind kind, double tilt, double rotary) {
  const double st = std::sin(tilt), ct = std::cos(tilt);
  const double sc = std::sin(rotary), cc = std::cos(rotary);
  switch (kind) {
    case MachineKind::TableTiltAC: return Vec3(sc * st, cc * st, ct);   // R_z(C)^T R_x(A)^T z
    case MachineKind::TableTiltBC: return Vec3(-cc * st, sc * st, ct);  // R_z(C)^T R_y(B)^T z
    case MachineKind::HeadBC: return Vec3(-cc * st, -sc * st, ct);      // R_z(C) R_y(-B) z
    case MachineKind::Mill3Axis: break;
  }
  return Vec3::UnitZ();
}

void rotaryAnglesOf(MachineKind kind, const Vec3& axis, double& tilt, double& rotary) {
  tilt = std::atan2(std::hypot(axis.x(), axis.y()), axis.z());
  switch (kind) {
    case MachineKind::TableTiltAC: rotary = std::atan2(axis.x(), axis.y()); break;
    case MachineKind::TableTiltBC: rotary = std::atan2(axis.y(), -axis.x()); break;
    case MachineKind::HeadBC: rotary = std::atan2(-axis.y(), -axis.x()); break;
    case MachineKind::Mill3Axis: tilt = rotary = 0; break;
  }
}

double tiltWithRotaryHeld(MachineKind kind, const Vec3& axis, double rotary) {
  // At a fixed C the tilt sweeps the axis through the plane spanned by z and the horizontal direction it leans to.
  const Vec3 lean = toolAxisOf(kind, kPi / 2, rotary);
  return std::atan2(lean.dot(axis), axis.z());
}

std::optional<double> nearestTurn(double angle, double reference, double min, double max) {
  const double turn = 2 * kPi;
  const double inf = std::numeric_limits<double>::infinity();
  const double k_min = std::isfinite(min) ? std::ceil((min - angle) / turn) : -inf;
  const double k_max = std::isfinite(max) ? std::floor((max - angle) / turn) : inf;
  if (k_min > k_max) return std::nullopt;
  const double k = std::clamp(std::round((reference - angle) / turn), k_min, k_max);
  return angle + k * turn;
}

double nearestTurn(double angle, double reference) {
  const double turn = 2 * kPi;
  return angle + std::round((reference - angle) / turn) * turn;
}

Vec3 linearJointsFor(const Machine& machine, double tool_length, const Vec3& tip_table, double tilt, double rotary) {
  const Vec3 z = Vec3::UnitZ();
  switch (machine.kind) {
    case MachineKind::Mill3Axis: return tip_table + tool_length * z;
    case MachineKind::TableTiltAC:
    case MachineKind::TableTiltBC: {
      const Vec3& r = machine.geometry.rot_point;
      const Vec3& o = machine.geometry.offset;
      const Vec3 tip_machine = r + o + tiltRotation(machine.kind, tilt) * (rotationZ(rotary) * (tip_table - r) - o);
      return tip_machine + tool_length * z;
    }
    case MachineKind::HeadBC: {
      const double pivot = machine.geometry.pivot_length;
      return tip_table + (pivot + tool_length) * toolAxisOf(machine.kind, tilt, rotary) - pivot * z;
    }
  }
  return tip_table;
}

}  // namespace art2part::kinematics_detail
