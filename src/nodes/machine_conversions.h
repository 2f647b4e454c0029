// Thin conversions between the core's machine joints and ROS messages, and the checks a controller makes on a
// trajectory goal.
//
// Units: the core uses mm and rad (mm/s, rad/s, ...); ROS messages use m and rad (REP 103). Joint names are the
// machine's joint letters (rosJointName, as the URDF of machine_urdf.h).
#pragma once

#include "node_main.h"
#include <ros/ros.h>
#include <sensor_msgs/JointState.h>
#include <trajectory_msgs/JointTrajectory.h>

#include <string>
#include <vector>

#include "art2part/kinematics/machine.h"
#include "art2part/kinematics/machine_urdf.h"
#include "art2part/post/joint_trajectory.h"

namespace art2part {

// Core unit -> ROS unit for a joint: mm -> m for a slide; rad stays rad. And back.
double toRos(const Joint& joint, double value);
double fromRos(const Joint& joint, double value);

std::vector<std::string> rosJointNames(const Machine& machine);
// The index in machine.joints of a ROS joint name; -1 when the machine has no such joint.
int machineJointIndex(const Machine& machine, const std::string& name);

// JointState of every machine joint (positions in machine.joints order, core units); velocities optional (core units,
// empty = none).
sensor_msgs::JointState jointStateMessage(const Machine& machine, const std::vector<double>& positions,
                                          const std::vector<double>& velocities = {});

// The trajectory sampled at rate_hz (sampleTrajectory: t = 0, 1/rate, ..., and the end), with positions, velocities
// and accelerations at each sample, in ROS units. Times are rounded to ros::Duration's nanoseconds; a sample that
// would land within a nanosecond of the one before replaces it (so times strictly increase).
trajectory_msgs::JointTrajectory jointTrajectoryMessage(const Machine& machine, const JointTrajectory& trajectory,
                                                        double rate_hz);

// The inverse, for tests and tools: each point's time (s) and positions (core units, machine.joints order). Joints the
// message leaves out take `fallback` (core units, machine.joints order; empty = 0). Throws InputError like
// checkTrajectoryGoal.
std::vector<TrajectorySample> trajectorySamples(const Machine& machine, const trajectory_msgs::JointTrajectory& msg,
                                                const std::vector<double>& fallback = {});

// What a controller of `machine` checks before it runs a trajectory goal.
struct TrajectoryCheck {
  enum Status { Ok, InvalidJoints, InvalidGoal } status = Ok;
  std::string reason;          // empty when Ok; one line otherwise, in the YAML's units (mm, deg)
  std::vector<int> joint_index;  // per msg joint: its index in machine.joints
  bool ok() const { return status == Ok; }
};
// InvalidJoints: an empty joint list, a name the machine does not have, a name given twice.
// InvalidGoal: no points; a point whose positions / velocities / accelerations have the wrong length; NaN or infinity;
// a negative time or times not strictly increasing; a position outside the travel (give or take
// limit_tolerance, core units); a velocity above max_velocity, given or implied by consecutive positions (the mean
// velocity between two points), allowing velocity_tolerance (relative) for rounding; path / goal tolerance arrays
// whose length is neither 0 nor the joint count, or a tolerance outside its range (request_limits.h: NaN, negative,
// mm or deg for m or rad).
TrajectoryCheck checkTrajectoryGoal(const Machine& machine, const trajectory_msgs::JointTrajectory& msg,
                                    const std::vector<double>& path_tolerance = {},
                                    const std::vector<double>& goal_tolerance = {}, double limit_tolerance = 1e-9,
                                    double velocity_tolerance = 1e-6);

// Where a trajectory wants the joints at time t (s from its start), in ROS units for its own joints, interpolating
// between its points: cubic Hermite when both points have velocities, else linear; before the first point's time,
// from `start` (ROS units, msg joint order) at rest; after the last, the last point. Velocities likewise.
void interpolateTrajectory(const trajectory_msgs::JointTrajectory& msg, const std::vector<double>& start, double t,
                           std::vector<double>* positions, std::vector<double>* velocities);

// The machine file in a node's ~machine parameter, loaded. Throws InputError when it is not set or not a machine.
Machine machineParameter(const ros::NodeHandle& pnh);

// A node that drives one machine: runNode (node_main.h) of a Node(nh, pnh, machine) with the machine from its
// ~machine parameter; a missing parameter or a bad machine file is one ROS_FATAL line and exit code 1.
template <class Node>
struct MachineNode {
  MachineNode(ros::NodeHandle& nh, ros::NodeHandle& pnh) : node(nh, pnh, machineParameter(pnh)) {}
  Node node;
};
template <class Node>
int runMachineNode(int argc, char** argv, const char* name, int threads) {
  return runNode<MachineNode<Node>>(argc, argv, name, threads);
}

}  // namespace art2part
