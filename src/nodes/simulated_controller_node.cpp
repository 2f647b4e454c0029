// simulated_controller: a machine's joints, driven by trajectories as a real controller would (in place of
// ros_control's joint_trajectory_controller, which Debian does not have).
//   params:   ~machine (a config/machines/*.yaml path, required), ~rate (joint_states per second, default 50),
//             ~time_scale (trajectory seconds per second of ROS time, default 1: 10 runs ten times faster),
//             ~initial_positions (m and rad, machine joint order; default: each joint at 0 clamped into its travel,
//             the post's start), ~start_tolerance (m or rad, default 1e-4: how far a first point at time 0 may be
//             from where the joints are)
//   action:   follow_joint_trajectory (FollowJointTrajectory). Rejected (aborted at once) with INVALID_JOINTS for a
//             joint the machine does not have or one named twice, INVALID_GOAL for no points, times not strictly
//             increasing, a position outside the travel, a velocity above the limit (given, or the mean velocity
//             between two consecutive points or from the joints to the first point), a first point at time 0 away
//             from the joints; the reason in error_string.
//             A new goal preempts the running one; cancel stops the joints where they are (no deceleration: a
//             simulation); either way the stopped goal ends PREEMPTED with error_code PREEMPTED and says which.
//   topics:   joint_states (sensor_msgs/JointState) at ~rate, always (still joints too); /diagnostics
//             (node_diagnostics.h: a rejected goal counts as refused, a tolerance violated as failed)
// The simulation tracks the trajectory exactly: actual = desired (cubic Hermite between points with velocities,
// linear otherwise), the last point's positions exactly at the end; so path and goal tolerances hold by construction
// (they are still checked, against the same numbers).
#include <actionlib/server/simple_action_server.h>
#include <ros/ros.h>
#include <sensor_msgs/JointState.h>

#include <art2part/FollowJointTrajectoryAction.h>

#include <algorithm>
#include <cmath>
#include <mutex>

#include "machine_conversions.h"
#include "node_diagnostics.h"

namespace art2part {

class SimulatedController {
 public:
  SimulatedController(ros::NodeHandle& nh, ros::NodeHandle& pnh, Machine machine)
      : machine_(std::move(machine)),
        server_(nh, "follow_joint_trajectory",
                [this](const FollowJointTrajectoryGoalConstPtr& goal) { execute(goal); }, false) {
    pnh.param("rate", rate_, 50.0);
    pnh.param("time_scale", time_scale_, 1.0);
    pnh.param("start_tolerance", start_tolerance_, 1e-4);
    if (!(rate_ > 0)) throw InputError("~rate must be positive");
    if (!(time_scale_ > 0)) throw InputError("~time_scale must be positive");
    for (const Joint& joint : machine_.joints) positions_.push_back(toRos(joint, std::clamp(0.0, joint.min, joint.max)));
    std::vector<double> initial;
    if (pnh.getParam("initial_positions", initial)) {
      if (initial.size() != positions_.size())
        throw InputError("~initial_positions needs " + std::to_string(positions_.size()) + " values (m, rad)");
      for (int j = 0; j < machine_.jointCount(); ++j)
        if (!machine_.joints[j].within(fromRos(machine_.joints[j], initial[j])))
          throw InputError("~initial_positions: joint " + machine_.joints[j].name + " outside its travel");
      positions_ = initial;
    }
    velocities_.assign(positions_.size(), 0.0);
    state_pub_ = nh.advertise<sensor_msgs::JointState>("joint_states", 10);
    timer_ = nh.createTimer(ros::Duration(1.0 / rate_), [this](const ros::TimerEvent&) { publishState(); });
    server_.start();
    ROS_INFO("simulated_controller: machine %s (%s), %d joints, joint_states at %g Hz, time scale %g",
             machine_.name.c_str(), kinematicsModuleName(machine_.kind).c_str(), machine_.jointCount(), rate_,
             time_scale_);
  }

 private:
  void publishState() {
    sensor_msgs::JointState msg;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      msg.name = rosJointNames(machine_);
      msg.position = positions_;
      msg.velocity = velocities_;
    }
    msg.header.stamp = ros::Time::now();
    state_pub_.publish(msg);
  }

  void finish(int code, const std::string& reason, bool preempted = false) {
    const bool rejected =
        code == FollowJointTrajectoryResult::INVALID_GOAL || code == FollowJointTrajectoryResult::INVALID_JOINTS;
    outcome_ = preempted                                       ? RequestOutcome::Cancelled
               : code == FollowJointTrajectoryResult::SUCCESSFUL ? RequestOutcome::Served
               : rejected                                      ? RequestOutcome::Refused
                                                               : RequestOutcome::Failed;
    outcome_message_ = reason;
    FollowJointTrajectoryResult result;
    result.error_code = code;
    result.error_string = reason;
    if (preempted) {
      ROS_INFO("follow_joint_trajectory: %s", reason.c_str());
      server_.setPreempted(result, reason);
    } else if (code == FollowJointTrajectoryResult::SUCCESSFUL) {
      server_.setSucceeded(result);
    } else {
      ROS_WARN("follow_joint_trajectory: %s", reason.c_str());
      server_.setAborted(result, reason);
    }
  }

  void execute(const FollowJointTrajectoryGoalConstPtr& goal) {
    NodeDiagnostics::Request request = diagnostics_.request("follow_joint_trajectory");
    outcome_ = RequestOutcome::Failed;
    outcome_message_ = "ended without a result";
    follow(goal);
    request.finish(outcome_, outcome_message_);
  }

  void follow(const FollowJointTrajectoryGoalConstPtr& goal) {
    const trajectory_msgs::JointTrajectory& trajectory = goal->trajectory;
    const TrajectoryCheck check =
        checkTrajectoryGoal(machine_, trajectory, goal->path_tolerance, goal->goal_tolerance);
    if (!check.ok()) {
      finish(check.status == TrajectoryCheck::InvalidJoints ? FollowJointTrajectoryResult::INVALID_JOINTS
                                                            : FollowJointTrajectoryResult::INVALID_GOAL,
             check.reason);
      return;
    }
    const std::size_t n = check.joint_index.size();
    std::vector<double> start(n);
    {
      std::lock_guard<std::mutex> lock(mutex_);
      for (std::size_t i = 0; i < n; ++i) start[i] = positions_[check.joint_index[i]];
    }
    // The way from where the joints are to the first point: at most the maximum velocity on average.
    const double first_time = trajectory.points.front().time_from_start.toSec();
    for (std::size_t i = 0; first_time > 0 && i < n; ++i) {
      const Joint& joint = machine_.joints[check.joint_index[i]];
      const double mean = std::abs(fromRos(joint, trajectory.points.front().positions[i] - start[i])) / first_time;
      if (mean > joint.max_velocity * (1 + 1e-6) + 1e-12) {
        const double unit = joint.rotary ? 180 / 3.14159265358979323846 : 1.0;  // deg/s or mm/s, as the YAML
        const std::string per = joint.rotary ? " deg/s" : " mm/s";
        finish(FollowJointTrajectoryResult::INVALID_GOAL,
               "point 0: " + joint.name + " would move at " + std::to_string(mean * unit) + per +
                   " on average from where it is, above its maximum " + std::to_string(joint.max_velocity * unit) + per);
        return;
      }
    }
    if (trajectory.points.front().time_from_start.isZero()) {
      for (std::size_t i = 0; i < n; ++i) {
        const double gap = std::abs(trajectory.points.front().positions[i] - start[i]);
        if (gap > start_tolerance_) {
          finish(FollowJointTrajectoryResult::INVALID_GOAL,
                 "the trajectory starts at time 0 with " + trajectory.joint_names[i] + " " +
                     std::to_string(gap) + (machine_.joints[check.joint_index[i]].rotary ? " rad" : " m") +
                     " away from where it is (start it later, or where the joints are)");
          return;
        }
      }
    }
    // Start at the header's stamp when it is in the future, else now.
    ros::Time begin = ros::Time::now();
    if (!trajectory.header.stamp.isZero() && trajectory.header.stamp > begin) begin = trajectory.header.stamp;
    const double end = trajectory.points.back().time_from_start.toSec();

    FollowJointTrajectoryFeedback feedback;
    feedback.joint_names = trajectory.joint_names;
    ros::Rate loop(std::max(rate_, 100.0));
    std::vector<double> q, v;
    while (true) {
      if (server_.isPreemptRequested() || !ros::ok()) {
        {
          std::lock_guard<std::mutex> lock(mutex_);
          for (int j : check.joint_index) velocities_[j] = 0;  // stopped where they are
        }
        finish(FollowJointTrajectoryResult::PREEMPTED,
               std::string(!ros::ok()                     ? "shutting down"
                           : server_.isNewGoalAvailable() ? "preempted by a newer goal"
                                                          : "cancelled") +
                   ": the joints stopped where they were",
               true);
        return;
      }
      const ros::Time now = ros::Time::now();
      const double t = now < begin ? -1.0 : (now - begin).toSec() * time_scale_;
      if (t < 0) {
        loop.sleep();
        continue;
      }
      const bool done = t >= end;
      interpolateTrajectory(trajectory, start, done ? end : t, &q, &v);
      if (done) std::fill(v.begin(), v.end(), 0.0);
      {
        std::lock_guard<std::mutex> lock(mutex_);
        for (std::size_t i = 0; i < n; ++i) {
          positions_[check.joint_index[i]] = q[i];
          velocities_[check.joint_index[i]] = v[i];
        }
      }
      // Actual = desired in this simulation; the tolerances are checked all the same.
      feedback.header.stamp = now;
      feedback.desired.positions = q;
      feedback.desired.velocities = v;
      feedback.desired.time_from_start = ros::Duration(std::min(t, end));
      feedback.actual = feedback.desired;
      feedback.error.positions.assign(n, 0.0);
      feedback.error.velocities.assign(n, 0.0);
      feedback.error.time_from_start = feedback.desired.time_from_start;
      server_.publishFeedback(feedback);
      for (std::size_t i = 0; i < n && i < goal->path_tolerance.size(); ++i)
        if (goal->path_tolerance[i] > 0 && std::abs(feedback.error.positions[i]) > goal->path_tolerance[i]) {
          finish(FollowJointTrajectoryResult::PATH_TOLERANCE_VIOLATED,
                 "joint " + trajectory.joint_names[i] + " left its path tolerance");
          return;
        }
      if (done) break;
      loop.sleep();
    }
    for (std::size_t i = 0; i < n && i < goal->goal_tolerance.size(); ++i) {
      const double error = std::abs(q[i] - trajectory.points.back().positions[i]);
      if (goal->goal_tolerance[i] > 0 && error > goal->goal_tolerance[i]) {
        finish(FollowJointTrajectoryResult::GOAL_TOLERANCE_VIOLATED,
               "joint " + trajectory.joint_names[i] + " ended " + std::to_string(error) + " from its goal");
        return;
      }
    }
    finish(FollowJointTrajectoryResult::SUCCESSFUL, "");
  }

  NodeDiagnostics diagnostics_;
  RequestOutcome outcome_ = RequestOutcome::Served;  // of the goal running (set by finish)
  std::string outcome_message_;
  Machine machine_;
  actionlib::SimpleActionServer<FollowJointTrajectoryAction> server_;
  double rate_ = 50, time_scale_ = 1, start_tolerance_ = 1e-4;
  std::mutex mutex_;
  std::vector<double> positions_, velocities_;  // ROS units, machine joint order
  ros::Publisher state_pub_;
  ros::Timer timer_;
};

}  // namespace art2part

int main(int argc, char** argv) {
  // 2 threads: joint_states keep coming while a goal runs.
  return art2part::runMachineNode<art2part::SimulatedController>(argc, argv, "simulated_controller", 2);
}
