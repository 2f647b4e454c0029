// Machine models for the kinematics stage: which joints a machine has, how far and how fast they move, where its
// rotary axes sit, and where the part sits on its table. Read from config/machines/*.yaml by loadMachine().
//
// The four kinds are the geometry of LinuxCNC 2.9 kinematics modules, with their parameters named as LinuxCNC names
// its HAL pins, so that a joint position here is the joint position there:
//   trivkins        3-axis mill                  X Y Z
//   xyzac-trt-kins  table-table trunnion         X Y Z, A tilts the table about X, C turns the platter on it
//   xyzbc-trt-kins  table-table                  X Y Z, B tilts the table about Y, C turns the platter on it
//   5axiskins       head-head (bridge mill)      X Y Z, C turns the head about Z, B tilts the spindle about Y
//
// Frames (all right-handed, millimetres):
//   machine frame  fixed to the machine base: x y z along the X Y Z slides, origin at machine zero (G53). On
//                  table-table and 3-axis machines the spindle points along +z (tool axis from tip towards spindle).
//   table frame    fixed to what the part is clamped on (the C platter of a trunnion); equal to the machine frame
//                  when every rotary joint is at 0. It is the Cartesian ("world") frame of LinuxCNC's trt kinematics
//                  with zero work offsets. Head-head and 3-axis machines: the table frame is the machine frame.
//   part frame     the frame of toolpaths.csv, placed in the table frame by the fixture pose of the setup.
//
// Joint values in the core: linear joints in mm, rotary joints in RADIANS (the YAML and G-code use degrees).
// Linear joints X Y Z are the spindle's gauge point (the controlled point with no tool loaded) in machine
// coordinates, as LinuxCNC's joint positions with its tool length offset fed to the kinematics:
//   table-table, 3-axis   tool tip = gauge point - tool_length * z (the spindle does not tilt)
//   head-head             the head's pivot (B and C axes meet) is pivot-length above the gauge point at B = 0;
//                         tool tip = pivot - (pivot-length + tool_length) * tool axis
// Under identity kinematics with G43 active, G-code X Y Z = the joints' X Y Z minus tool_length in Z (table-table).
#pragma once

#include <map>
#include <string>
#include <vector>

#include "art2part/geometry/mesh.h"

namespace art2part {

enum class MachineKind {
  Mill3Axis,    // trivkins
  TableTiltAC,  // xyzac-trt-kins
  TableTiltBC,  // xyzbc-trt-kins
  HeadBC,       // 5axiskins
};

// "trivkins", "xyzac-trt-kins", "xyzbc-trt-kins", "5axiskins": the LinuxCNC module and the YAML `kinematics` value.
std::string kinematicsModuleName(MachineKind kind);

// One joint (a slide or a rotary axis) and what it may do.
struct Joint {
  std::string name;         // the G-code letter, as on the machine's DRO: X Y Z A B C
  std::string description;  // as a machinist says it: "table X", "saddle Y", "trunnion tilt A", "rotary table C"
  bool rotary = false;
  double min = 0, max = 0;          // travel: mm, or rad for a rotary joint
  double max_velocity = 0;          // mm/s or rad/s
  double max_acceleration = 0;      // mm/s^2 or rad/s^2
  double rapid_velocity = 0;        // G0 rate: mm/s or rad/s (LinuxCNC rapids each joint at its max velocity)

  bool within(double value, double tolerance = 1e-9) const {
    return value >= min - tolerance && value <= max + tolerance;
  }
};

// Where the rotary axes sit, in LinuxCNC's terms (the HAL pins of xyzac/xyzbc-trt-kins and 5axiskins).
struct RotaryGeometry {
  // Table-table: a point of the C axis in machine coordinates with the rotaries at 0 (x/y/z-rot-point), and the
  // centre of the tilt axis relative to that point (x/y/z-offset: y and z for the A axis along x, x and z for the
  // B axis along y). The tilt axis passes through rot_point + offset.
  Vec3 rot_point = Vec3::Zero();
  Vec3 offset = Vec3::Zero();
  // Head-head: from the gauge point (at B = 0) up to the pivot where the B and C axes meet (pivot-length, without the
  // tool: LinuxCNC's 5axiskins.pivot-length pin is this plus the tool length).
  double pivot_length = 0;
};

// The part frame placed in the table frame: p_table = rotation * p_part + origin.
struct FixturePose {
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Vec3 origin = Vec3::Zero();  // the part frame's origin in the table frame, mm

  Vec3 pointToTable(const Vec3& p) const { return rotation * p + origin; }
  Vec3 directionToTable(const Vec3& d) const { return rotation * d; }
  Vec3 pointToPart(const Vec3& p) const { return rotation.transpose() * (p - origin); }
  Vec3 directionToPart(const Vec3& d) const { return rotation.transpose() * d; }
};

// Roll, pitch, yaw (rad) about the fixed x, y, z axes, applied in that order: R = Rz(yaw) Ry(pitch) Rx(roll), as URDF.
Eigen::Matrix3d rotationFromRpy(const Vec3& rpy);
Vec3 rpyFromRotation(const Eigen::Matrix3d& rotation);

// The fixture that clamps the part with a setup frame (x, y, z orthonormal, z = the setup direction, in the part
// frame) along the table's x, y, z, with the part frame's point `anchor` at `table_point`: how a 3-axis setup puts the
// part on the table.
FixturePose fixtureFacingUp(const Vec3& x, const Vec3& y, const Vec3& z, const Vec3& anchor, const Vec3& table_point);

// What a machine file that says nothing about its changes stands for (plan.json's cycle time, post/cycle_time.h).
constexpr double kDefaultToolChangeSeconds = 10;    // chip to chip: from the last cut of one tool to the next's first
constexpr double kDefaultSetupChangeSeconds = 600;  // unclamp, turn and clamp the part, touch off the new setup

struct Machine {
  std::string name;
  std::string description;
  std::string source;  // the file it came from (for messages)
  MachineKind kind = MachineKind::Mill3Axis;
  std::vector<Joint> joints;  // X Y Z, then the tilt (A or B) and C on a 5-axis machine: LinuxCNC joints 0..4
  RotaryGeometry geometry;
  FixturePose default_fixture;                  // where the part sits unless its setup says otherwise
  std::map<int, FixturePose> setup_fixtures;    // by setup index (toolpaths.csv `setup`)
  double tool_change_s = kDefaultToolChangeSeconds;    // YAML `tool_change_s`: seconds per tool change
  double setup_change_s = kDefaultSetupChangeSeconds;  // YAML `setup_change_s`: seconds per change of clamping

  bool fiveAxis() const { return kind != MachineKind::Mill3Axis; }
  int jointCount() const { return static_cast<int>(joints.size()); }
  const Joint& tiltJoint() const { return joints.at(3); }    // A or B (5-axis only)
  const Joint& rotaryJoint() const { return joints.at(4); }  // C (5-axis only)
};

const FixturePose& fixtureForSetup(const Machine& machine, int setup);

// One position of the joints. 3-axis machines leave tilt and rotary at 0.
struct JointPosition {
  Vec3 linear = Vec3::Zero();  // X Y Z: the gauge point in machine coordinates, mm
  double tilt = 0;             // A (xyzac-trt) or B (xyzbc-trt, head-head), rad
  double rotary = 0;           // C, rad
};

// The joints as a vector in machine.joints order (mm, rad), and back; e.g. for sensor_msgs/JointState (convert mm to
// m there).
std::vector<double> jointVector(const Machine& machine, const JointPosition& joints);
JointPosition jointPositionFromVector(const Machine& machine, const std::vector<double>& values);

// Empty when every joint is inside its travel (give or take tolerance, mm or rad); otherwise what leaves it, in the
// YAML's units, e.g. "A = -104.2 deg below its minimum -100 deg".
std::string limitViolation(const Machine& machine, const JointPosition& joints, double tolerance = 1e-9);

// Reads a machine file (YAML: see config/machines/). Throws InputError naming the file and the key for anything
// missing, of the wrong type or inconsistent (min > max, a joint letter the kinematics does not have, ...).
Machine loadMachine(const std::string& yaml_path);
// The same from YAML text; `source` names it in messages.
Machine parseMachine(const std::string& yaml_text, const std::string& source);

}  // namespace art2part
