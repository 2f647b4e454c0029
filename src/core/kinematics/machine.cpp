// Machine models: plain helpers over the data (fixtures, joint vectors, limits). Loading is in machine_yaml.cpp.
#include "art2part/kinematics/machine.h"

#include <cmath>
#include <cstdio>

namespace art2part {

namespace {
constexpr double kDegree = 3.14159265358979323846 / 180;
}

std::string kinematicsModuleName(MachineKind kind) {
  switch (kind) {
    case MachineKind::Mill3Axis: return "trivkins";
    case MachineKind::TableTiltAC: return "xyzac-trt-kins";
    case MachineKind::TableTiltBC: return "xyzbc-trt-kins";
    case MachineKind::HeadBC: return "5axiskins";
  }
  return "";
}

Eigen::Matrix3d rotationFromRpy(const Vec3& rpy) {
  return (Eigen::AngleAxisd(rpy.z(), Vec3::UnitZ()) * Eigen::AngleAxisd(rpy.y(), Vec3::UnitY()) *
          Eigen::AngleAxisd(rpy.x(), Vec3::UnitX()))
      .toRotationMatrix();
}

Vec3 rpyFromRotation(const Eigen::Matrix3d& r) {
  const double pitch = std::atan2(-r(2, 0), std::hypot(r(0, 0), r(1, 0)));
  if (std::hypot(r(0, 0), r(1, 0)) < 1e-12) {  // pitch +-90 deg: roll and yaw share one angle; put it in roll
    return Vec3(std::atan2(-r(1, 2), r(1, 1)), pitch, 0);
  }
  return Vec3(std::atan2(r(2, 1), r(2, 2)), pitch, std::atan2(r(1, 0), r(0, 0)));
}

FixturePose fixtureFacingUp(const Vec3& x, const Vec3& y, const Vec3& z, const Vec3& anchor, const Vec3& table_point) {
  FixturePose fixture;
  fixture.rotation.row(0) = x.transpose();
  fixture.rotation.row(1) = y.transpose();
  fixture.rotation.row(2) = z.transpose();
  fixture.origin = table_point - fixture.rotation * anchor;
  return fixture;
}

const FixturePose& fixtureForSetup(const Machine& machine, int setup) {
  const auto found = machine.setup_fixtures.find(setup);
  return found == machine.setup_fixtures.end() ? machine.default_fixture : found->second;
}

std::vector<double> jointVector(const Machine& machine, const JointPosition& joints) {
  std::vector<double> values{joints.linear.x(), joints.linear.y(), joints.linear.z()};
  if (machine.fiveAxis()) {
    values.push_back(joints.tilt);
    values.push_back(joints.rotary);
  }
  return values;
}

JointPosition jointPositionFromVector(const Machine& machine, const std::vector<double>& values) {
  if (static_cast<int>(values.size()) != machine.jointCount()) {
    throw InputError("machine " + machine.name + " has " + std::to_string(machine.jointCount()) + " joints, got " +
                     std::to_string(values.size()) + " values");
  }
  JointPosition joints;
  joints.linear = Vec3(values[0], values[1], values[2]);
  if (machine.fiveAxis()) {
    joints.tilt = values[3];
    joints.rotary = values[4];
  }
  return joints;
}

std::string limitViolation(const Machine& machine, const JointPosition& joints, double tolerance) {
  const std::vector<double> values = jointVector(machine, joints);
  std::string violations;
  for (int j = 0; j < machine.jointCount(); ++j) {
    const Joint& joint = machine.joints[j];
    if (joint.within(values[j], tolerance)) continue;
    const double scale = joint.rotary ? 1 / kDegree : 1;
    const char* unit = joint.rotary ? "deg" : "mm";
    const bool below = !(values[j] >= joint.min - tolerance);  // NaN counts as below
    char text[160];
    std::snprintf(text, sizeof text, "%s = %.4f %s %s its %s %.4g %s", joint.name.c_str(), values[j] * scale, unit,
                  below ? "below" : "above", below ? "minimum" : "maximum", (below ? joint.min : joint.max) * scale,
                  unit);
    if (!violations.empty()) violations += ", ";
    violations += text;
  }
  return violations;
}

}  // namespace art2part
