#include "machine_conversions.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>

#include "art2part/common/angles.h"
#include "art2part/common/number_text.h"
#include "art2part/common/request_limits.h"

namespace art2part {

namespace {

constexpr double kMetre = 1e-3;  // per mm

std::string fmt(double value) { return numberText(value, 10); }

// A core value in the YAML's units with the unit: "12.5 mm", "-104.2 deg".
std::string yamlValue(const Joint& joint, double core_value, const char* per = "") {
  return fmt(joint.rotary ? core_value * 180 / kPi : core_value) + (joint.rotary ? " deg" : " mm") + per;
}

bool finite(const std::vector<double>& values) {
  return std::all_of(values.begin(), values.end(), [](double v) { return std::isfinite(v); });
}

ros::Duration durationFromSeconds(double seconds) {
  ros::Duration d;
  d.fromNSec(static_cast<int64_t>(std::llround(seconds * 1e9)));
  return d;
}

}  // namespace

double toRos(const Joint& joint, double value) { return joint.rotary ? value : value * kMetre; }
double fromRos(const Joint& joint, double value) { return joint.rotary ? value : value / kMetre; }

std::vector<std::string> rosJointNames(const Machine& machine) {
  std::vector<std::string> names;
  for (const Joint& joint : machine.joints) names.push_back(rosJointName(joint));
  return names;
}

int machineJointIndex(const Machine& machine, const std::string& name) {
  for (int j = 0; j < machine.jointCount(); ++j)
    if (rosJointName(machine.joints[j]) == name) return j;
  return -1;
}

sensor_msgs::JointState jointStateMessage(const Machine& machine, const std::vector<double>& positions,
                                          const std::vector<double>& velocities) {
  sensor_msgs::JointState msg;
  msg.name = rosJointNames(machine);
  for (int j = 0; j < machine.jointCount(); ++j) {
    msg.position.push_back(toRos(machine.joints[j], positions.at(j)));
    if (!velocities.empty()) msg.velocity.push_back(toRos(machine.joints[j], velocities.at(j)));
  }
  return msg;
}

trajectory_msgs::JointTrajectory jointTrajectoryMessage(const Machine& machine, const JointTrajectory& trajectory,
                                                        double rate_hz) {
  trajectory_msgs::JointTrajectory msg;
  msg.joint_names = rosJointNames(machine);
  for (const TrajectorySample& sample : sampleTrajectory(trajectory, rate_hz)) {
    trajectory_msgs::JointTrajectoryPoint point;
    const std::vector<double> v = trajectory.velocityAt(sample.time);
    const std::vector<double> a = trajectory.accelerationAt(sample.time);
    for (int j = 0; j < machine.jointCount(); ++j) {
      point.positions.push_back(toRos(machine.joints[j], sample.joints.at(j)));
      point.velocities.push_back(toRos(machine.joints[j], v.at(j)));
      point.accelerations.push_back(toRos(machine.joints[j], a.at(j)));
    }
    point.time_from_start = durationFromSeconds(sample.time);
    if (!msg.points.empty() && point.time_from_start <= msg.points.back().time_from_start)
      msg.points.back() = point;  // the end, within a nanosecond of the last regular sample
    else
      msg.points.push_back(point);
  }
  return msg;
}

TrajectoryCheck checkTrajectoryGoal(const Machine& machine, const trajectory_msgs::JointTrajectory& msg,
                                    const std::vector<double>& path_tolerance,
                                    const std::vector<double>& goal_tolerance, double limit_tolerance,
                                    double velocity_tolerance) {
  TrajectoryCheck check;
  auto fail = [&check](TrajectoryCheck::Status status, const std::string& reason) {
    check.status = status;
    check.reason = reason;
    return check;
  };
  if (msg.joint_names.empty()) return fail(TrajectoryCheck::InvalidJoints, "the trajectory names no joints");
  for (std::size_t i = 0; i < msg.joint_names.size(); ++i) {
    const int j = machineJointIndex(machine, msg.joint_names[i]);
    if (j < 0) {
      std::string known;
      for (const std::string& name : rosJointNames(machine)) known += (known.empty() ? "" : " ") + name;
      return fail(TrajectoryCheck::InvalidJoints, "unknown joint '" + msg.joint_names[i] + "': machine " +
                                                      machine.name + " has " + known);
    }
    if (std::find(check.joint_index.begin(), check.joint_index.end(), j) != check.joint_index.end())
      return fail(TrajectoryCheck::InvalidJoints, "joint '" + msg.joint_names[i] + "' is named twice");
    check.joint_index.push_back(j);
  }
  const std::size_t n = msg.joint_names.size();
  if (!path_tolerance.empty() && path_tolerance.size() != n)
    return fail(TrajectoryCheck::InvalidGoal, "path_tolerance has " + std::to_string(path_tolerance.size()) +
                                                  " values for " + std::to_string(n) + " joints");
  if (!goal_tolerance.empty() && goal_tolerance.size() != n)
    return fail(TrajectoryCheck::InvalidGoal, "goal_tolerance has " + std::to_string(goal_tolerance.size()) +
                                                  " values for " + std::to_string(n) + " joints");
  for (const auto& [values, range] : {std::pair(&path_tolerance, request_limits::kPathTolerance),
                                      std::pair(&goal_tolerance, request_limits::kGoalTolerance)})
    for (std::size_t i = 0; i < values->size(); ++i)
      if (const std::string reason = rangeViolation((*values)[i], range); !reason.empty())
        return fail(TrajectoryCheck::InvalidGoal, "joint " + msg.joint_names[i] + ": " + reason);
  if (msg.points.empty()) return fail(TrajectoryCheck::InvalidGoal, "the trajectory has no points");

  for (std::size_t p = 0; p < msg.points.size(); ++p) {
    const trajectory_msgs::JointTrajectoryPoint& point = msg.points[p];
    const std::string where = "point " + std::to_string(p) + " (t = " + fmt(point.time_from_start.toSec()) + " s)";
    if (point.positions.size() != n)
      return fail(TrajectoryCheck::InvalidGoal, where + " has " + std::to_string(point.positions.size()) +
                                                    " positions for " + std::to_string(n) + " joints");
    if (!point.velocities.empty() && point.velocities.size() != n)
      return fail(TrajectoryCheck::InvalidGoal, where + " has " + std::to_string(point.velocities.size()) +
                                                    " velocities for " + std::to_string(n) + " joints");
    if (!point.accelerations.empty() && point.accelerations.size() != n)
      return fail(TrajectoryCheck::InvalidGoal, where + " has " + std::to_string(point.accelerations.size()) +
                                                    " accelerations for " + std::to_string(n) + " joints");
    if (!finite(point.positions) || !finite(point.velocities) || !finite(point.accelerations))
      return fail(TrajectoryCheck::InvalidGoal, where + " is not a finite number");
    if (point.time_from_start < ros::Duration(0))
      return fail(TrajectoryCheck::InvalidGoal, where + ": negative time");
    if (p > 0 && point.time_from_start <= msg.points[p - 1].time_from_start)
      return fail(TrajectoryCheck::InvalidGoal, where + ": times must increase (point " + std::to_string(p - 1) +
                                                    " is at " + fmt(msg.points[p - 1].time_from_start.toSec()) + " s)");
    for (std::size_t i = 0; i < n; ++i) {
      const Joint& joint = machine.joints[check.joint_index[i]];
      const double q = fromRos(joint, point.positions[i]);
      if (!joint.within(q, limit_tolerance))
        return fail(TrajectoryCheck::InvalidGoal,
                    where + ": " + joint.name + " = " + yamlValue(joint, q) + " outside its travel " +
                        yamlValue(joint, joint.min) + " .. " + yamlValue(joint, joint.max));
      const double v_max = joint.max_velocity * (1 + velocity_tolerance) + 1e-12;
      if (!point.velocities.empty() && std::abs(fromRos(joint, point.velocities[i])) > v_max)
        return fail(TrajectoryCheck::InvalidGoal,
                    where + ": " + joint.name + " velocity " + yamlValue(joint, fromRos(joint, point.velocities[i]), "/s") +
                        " above its maximum " + yamlValue(joint, joint.max_velocity, "/s"));
      if (p > 0) {
        const double dt = (point.time_from_start - msg.points[p - 1].time_from_start).toSec();
        const double mean = std::abs(q - fromRos(joint, msg.points[p - 1].positions[i])) / dt;
        if (mean > v_max)
          return fail(TrajectoryCheck::InvalidGoal,
                      where + ": " + joint.name + " moves at " + yamlValue(joint, mean, "/s") + " on average from point " +
                          std::to_string(p - 1) + ", above its maximum " + yamlValue(joint, joint.max_velocity, "/s"));
      }
    }
  }
  return check;
}

std::vector<TrajectorySample> trajectorySamples(const Machine& machine, const trajectory_msgs::JointTrajectory& msg,
                                                const std::vector<double>& fallback) {
  const TrajectoryCheck check = checkTrajectoryGoal(machine, msg);
  if (!check.ok()) throw InputError("joint trajectory: " + check.reason);
  std::vector<TrajectorySample> samples;
  for (const trajectory_msgs::JointTrajectoryPoint& point : msg.points) {
    TrajectorySample sample;
    sample.time = point.time_from_start.toSec();
    sample.joints = fallback.empty() ? std::vector<double>(machine.jointCount(), 0.0) : fallback;
    for (std::size_t i = 0; i < check.joint_index.size(); ++i) {
      const int j = check.joint_index[i];
      sample.joints.at(j) = fromRos(machine.joints[j], point.positions[i]);
    }
    samples.push_back(sample);
  }
  return samples;
}

void interpolateTrajectory(const trajectory_msgs::JointTrajectory& msg, const std::vector<double>& start, double t,
                           std::vector<double>* positions, std::vector<double>* velocities) {
  const std::size_t n = msg.joint_names.size();
  std::vector<double> q(n, 0.0), v(n, 0.0);
  const auto& points = msg.points;
  if (points.empty()) {
    q = start;
  } else if (t >= points.back().time_from_start.toSec()) {
    q = points.back().positions;
    if (!points.back().velocities.empty()) v = points.back().velocities;
  } else {
    // The interval [t0, t1] holding t: before the first point, from `start` at rest at time 0.
    std::size_t k = 0;
    while (k < points.size() && points[k].time_from_start.toSec() <= t) ++k;  // points[k] is the first after t
    const bool from_start = k == 0;
    const double t0 = from_start ? 0.0 : points[k - 1].time_from_start.toSec();
    const double t1 = points[k].time_from_start.toSec();
    const std::vector<double>& q0 = from_start ? start : points[k - 1].positions;
    const std::vector<double> zero(n, 0.0);
    const std::vector<double>& v0 = from_start ? zero : points[k - 1].velocities;
    const std::vector<double>& q1 = points[k].positions;
    const std::vector<double>& v1 = from_start && points[k].velocities.empty() ? zero : points[k].velocities;
    const double h = t1 - t0;
    const double s = h > 0 ? std::clamp((t - t0) / h, 0.0, 1.0) : 1.0;
    const bool hermite = v0.size() == n && v1.size() == n && h > 0;
    for (std::size_t i = 0; i < n; ++i) {
      if (hermite) {
        const double s2 = s * s, s3 = s2 * s;
        q[i] = (2 * s3 - 3 * s2 + 1) * q0[i] + (s3 - 2 * s2 + s) * h * v0[i] + (-2 * s3 + 3 * s2) * q1[i] +
               (s3 - s2) * h * v1[i];
        v[i] = ((6 * s2 - 6 * s) * q0[i] + (-6 * s2 + 6 * s) * q1[i]) / h + (3 * s2 - 4 * s + 1) * v0[i] +
               (3 * s2 - 2 * s) * v1[i];
      } else {
        q[i] = q0[i] + s * (q1[i] - q0[i]);
        v[i] = h > 0 ? (q1[i] - q0[i]) / h : 0.0;
      }
    }
  }
  if (positions) *positions = q;
  if (velocities) *velocities = v;
}

Machine machineParameter(const ros::NodeHandle& pnh) {
  std::string machine_file;
  if (!pnh.getParam("machine", machine_file))
    throw InputError("set ~machine to a machine file (config/machines/*.yaml)");
  return loadMachine(machine_file);
}

}  // namespace art2part
