// controller_bridge: toolpaths -> the machine's joint trajectory (the post stage) -> a controller.
//   params:   ~machine (a config/machines/*.yaml path, required), ~rate (trajectory points per second, default 50),
//             ~blend_tolerance (mm, default the post's 0.005), ~chordal_tolerance (mm, default the post's 0.005),
//             ~controller_wait (s to wait for follow_joint_trajectory's server, default 2), ~joint_state_wait (s to
//             wait for a joint_states sent after the request that shows the joints still, default 1)
//   service:  run_program (RunToolpaths): reads FOLDER/toolpaths.csv and FOLDER/tools.json (a plan folder), places
//             each setup's part on the machine (placeSetups: the fixtures FOLDER/plan.json records for this machine,
//             else the search from its setup frames; no plan.json: the machine file's fixtures), checks the travel
//             of every setup before anything runs (success=false naming each setup the machine cannot reach, and
//             why), builds the machine program (buildMachineProgram, mode 3+2 | 5axis | auto), its waypoints and
//             their time parameterization, samples it at the rate; publishes it and sends it to the controller. The
//             trajectory starts where the controller's joint_states put the joints (the first after the request that
//             shows them still; up to the safe height first, then to the program's start), else at the program's
//             start. Bad input or joints still moving: success=false with the reason. One program at a time: a
//             request while the last one is being built or is still running on the controller is refused with a
//             reason (cancel it first: the follow_joint_trajectory action's cancel).
//             With wait, a program cancelled or preempted on the controller answers success=false, error_code
//             PREEMPTED (-6) and the controller's reason. FOLDER must lie under /art2part/output_root (cell_folders.h;
//             relative: under it), rate 0 or 1..1000.
//   action client: follow_joint_trajectory (FollowJointTrajectory), when a server is there
//   topics:   joint_trajectory (trajectory_msgs/JointTrajectory, latched), the last trajectory built;
//             subscribes joint_states (sensor_msgs/JointState); /diagnostics (node_diagnostics.h)
#include <actionlib/client/simple_action_client.h>
#include <ros/ros.h>
#include <sensor_msgs/JointState.h>
#include <trajectory_msgs/JointTrajectory.h>

#include <art2part/FollowJointTrajectoryAction.h>
#include <art2part/RunToolpaths.h>

#include <chrono>
#include <condition_variable>
#include <filesystem>
#include <mutex>
#include <optional>

#include "art2part/common/request_limits.h"
#include "art2part/post/fixture_placement.h"
#include "art2part/post/joint_trajectory.h"
#include "art2part/post/machine_program.h"
#include "art2part/tooling/tool.h"
#include "art2part/tooling/toolpath.h"
#include "cell_folders.h"
#include "machine_conversions.h"
#include "node_diagnostics.h"

namespace art2part {

using TrajectoryClient = actionlib::SimpleActionClient<FollowJointTrajectoryAction>;

class ControllerBridge {
 public:
  ControllerBridge(ros::NodeHandle& nh, ros::NodeHandle& pnh, Machine machine)
      : machine_(std::move(machine)), client_(nh, "follow_joint_trajectory", true) {
    pnh.param("rate", rate_, 50.0);
    pnh.param("blend_tolerance", trajectory_options_.blend_tolerance, trajectory_options_.blend_tolerance);
    pnh.param("chordal_tolerance", post_options_.chordal_tolerance, post_options_.chordal_tolerance);
    pnh.param("controller_wait", controller_wait_, 2.0);
    pnh.param("joint_state_wait", joint_state_wait_, 1.0);
    if (!(joint_state_wait_ >= 0)) throw InputError("~joint_state_wait must be 0 or more");
    if (!(rate_ > 0) || !(trajectory_options_.blend_tolerance > 0) || !(post_options_.chordal_tolerance > 0))
      throw InputError("~rate, ~blend_tolerance and ~chordal_tolerance must be positive");
    trajectory_pub_ = nh.advertise<trajectory_msgs::JointTrajectory>("joint_trajectory", 1, true);
    state_sub_ = nh.subscribe("joint_states", 10, &ControllerBridge::onJointState, this);
    service_ = nh.advertiseService("run_program", &ControllerBridge::runProgram, this);
    ROS_INFO("controller_bridge: machine %s (%s)", machine_.name.c_str(), kinematicsModuleName(machine_.kind).c_str());
    diagnostics_.setConfiguration("machine", machine_.name);
    diagnostics_.setConfiguration("output root", folderList(folders_.plans));
    for (const std::string& problem : folders_.problems) diagnostics_.addProblem(problem);
  }

 private:
  void onJointState(const sensor_msgs::JointState::ConstPtr& msg) {
    if (msg->name.size() != msg->position.size()) return;
    JointReading reading;
    reading.joints.assign(machine_.jointCount(), 0.0);
    std::vector<bool> seen(machine_.jointCount(), false);
    for (std::size_t i = 0; i < msg->name.size(); ++i) {
      const int j = machineJointIndex(machine_, msg->name[i]);
      if (j < 0) continue;
      reading.joints[j] = fromRos(machine_.joints[j], msg->position[i]);
      seen[j] = true;
      if (i < msg->velocity.size() && std::abs(msg->velocity[i]) > 1e-9) reading.still = false;
    }
    if (std::find(seen.begin(), seen.end(), false) != seen.end()) return;  // not all of this machine's joints
    reading.received = ros::Time::now();
    {
      std::lock_guard<std::mutex> lock(state_mutex_);
      current_ = std::move(reading);
    }
    state_changed_.notify_all();
  }

  // Where the joints are for a program asked for at `asked`: the first joint_states received after it that shows
  // them still (a state sent before a cancelled goal stopped is stale by up to one period), waiting up to
  // ~joint_state_wait. Nothing when no joint_states ever came (the trajectory then starts at the program's start);
  // the last known state when none came since (a controller that stopped publishing). Throws InputError when the
  // joints are still moving after the wait.
  std::optional<std::vector<double>> jointsAfter(const ros::Time& asked) {
    std::unique_lock<std::mutex> lock(state_mutex_);
    if (!current_) return std::nullopt;
    const auto fresh_and_still = [&] { return current_->received > asked && current_->still; };
    state_changed_.wait_for(lock, std::chrono::duration<double>(joint_state_wait_), fresh_and_still);
    if (current_->received > asked && !current_->still)
      throw InputError("the joints are still moving " + std::to_string(joint_state_wait_) +
                       " s after the request; wait until the controller has stopped them");
    return current_->joints;
  }

  // The machine's waypoints: from where the joints are (if known and elsewhere) up to the safe height, to the
  // program's start, then the program.
  std::vector<JointWaypoint> waypointsFrom(const MachineProgram& program,
                                           const std::optional<std::vector<double>>& current) {
    std::vector<JointWaypoint> waypoints = programWaypoints(program);
    if (!current || waypoints.empty()) return waypoints;
    const std::vector<double> start = jointVector(machine_, waypoints.front().joints);
    double gap = 0;
    for (int j = 0; j < machine_.jointCount(); ++j) gap = std::max(gap, std::abs((*current)[j] - start[j]));
    if (gap < 1e-9) return waypoints;
    JointWaypoint here;
    here.joints = jointPositionFromVector(machine_, *current);
    here.move = MoveKind::Rapid;
    here.stop = true;
    JointWaypoint up = here;
    up.joints.linear.z() = std::max(here.joints.linear.z(), program.retract_z);
    std::vector<JointWaypoint> lead_in{here};
    if (up.joints.linear.z() > here.joints.linear.z()) lead_in.push_back(up);
    waypoints.front().move = MoveKind::Rapid;
    waypoints.insert(waypoints.begin(), lead_in.begin(), lead_in.end());
    return waypoints;
  }

  // One program at a time: claims the bridge for this request, or says what it is busy with.
  class Claim {
   public:
    explicit Claim(ControllerBridge& bridge) : bridge_(bridge) {
      std::lock_guard<std::mutex> lock(bridge_.run_mutex_);
      if (bridge_.goal_sent_ && !bridge_.client_.getState().isDone()) {
        busy_ = "busy: '" + bridge_.running_name_ + "' is still running on the controller (" +
                bridge_.client_.getState().toString() + "); cancel it first (follow_joint_trajectory/cancel) or wait";
      } else if (bridge_.building_) {
        busy_ = "busy: another run_program is building its program";
      } else {
        bridge_.building_ = true;
      }
    }
    ~Claim() {
      if (!busy_.empty()) return;
      std::lock_guard<std::mutex> lock(bridge_.run_mutex_);
      bridge_.building_ = false;
    }
    const std::string& busy() const { return busy_; }

   private:
    ControllerBridge& bridge_;
    std::string busy_;
  };

  // run_program as /diagnostics counts it: refused when the request or its files were bad (or the bridge busy),
  // cancelled when the controller's goal was cancelled or preempted, failed when it did not run to the end.
  bool runProgram(RunToolpaths::Request& req, RunToolpaths::Response& res) {
    NodeDiagnostics::Request request = diagnostics_.request("run_program");
    runProgramUnrecorded(req, res);
    request.finish(res.success                                                 ? RequestOutcome::Served
                   : res.error_code == FollowJointTrajectoryResult::PREEMPTED ? RequestOutcome::Cancelled
                   : res.sent                                                 ? RequestOutcome::Failed
                                                                              : RequestOutcome::Refused,
                   res.message);
    return true;
  }

  bool runProgramUnrecorded(RunToolpaths::Request& req, RunToolpaths::Response& res) {
    const ros::Time asked = ros::Time::now();
    const Claim claim(*this);  // one program at a time
    try {
      if (!claim.busy().empty()) throw InputError(claim.busy());
      // The request's checks: the folder under the output root (the rest of the callback reads the resolved one),
      // the rate in range.
      req.folder = confinedField(folders_.plans, "folder", req.folder);
      checkedRequestValue(req.rate, request_limits::kTrajectoryRate);
      namespace fs = std::filesystem;
      if (!fs::is_directory(req.folder)) throw InputError(req.folder + " is not a folder");
      for (const char* file : {"toolpaths.csv", "tools.json"})
        if (!fs::is_regular_file(fs::path(req.folder) / file))
          throw InputError(req.folder + " has no " + file);
      const double rate = req.rate > 0 ? req.rate : rate_;
      PostOptions options = post_options_;
      options.mode = parsePostMode(req.mode.empty() ? "auto" : req.mode);
      const Toolpath path = readToolpathsCsv((fs::path(req.folder) / "toolpaths.csv").string());
      const std::vector<Tool> tools = readToolsJson((fs::path(req.folder) / "tools.json").string());
      // Every setup's part where this machine reaches it, checked before anything runs.
      const FixturePlan placement =
          placeSetups(machine_, path, tools, clampingsFromPlanFolder(req.folder, machine_), options);
      for (const SetupPlacement& p : placement.setups) ROS_INFO("run_program: %s", placementText(machine_, p).c_str());
      if (!placement.allReachable()) throw InputError(placement.unreachableText());
      options.fixtures = placement.fixtures();
      std::string name = fs::path(req.folder).lexically_normal().filename().string();
      if (name.empty()) name = fs::path(req.folder).lexically_normal().parent_path().filename().string();
      const MachineProgram program = buildMachineProgram(machine_, path, tools, name.empty() ? "part" : name, options);
      const JointTrajectory trajectory =
          parameterizeTrajectory(machine_, waypointsFrom(program, jointsAfter(asked)), trajectory_options_);
      trajectory_msgs::JointTrajectory msg = jointTrajectoryMessage(machine_, trajectory, rate);
      msg.header.stamp = ros::Time(0);  // start when the controller gets it
      trajectory_pub_.publish(msg);
      res.mode = postModeName(program.mode);
      res.duration = trajectory.duration();
      res.points = static_cast<uint32_t>(msg.points.size());
      res.success = true;
      res.message = "'" + name + "' on " + machine_.name + ": " + std::to_string(program.setups.size()) +
                    " setup(s), mode " + res.mode + ", " + std::to_string(program.stepCount()) + " steps, " +
                    std::to_string(trajectory.duration()) + " s, " + std::to_string(msg.points.size()) + " points";

      if (!client_.waitForServer(ros::Duration(controller_wait_))) {
        res.message += "; no controller on follow_joint_trajectory: published only";
        ROS_INFO("run_program: %s", res.message.c_str());
        return true;
      }
      FollowJointTrajectoryGoal goal;
      goal.trajectory = msg;
      {
        std::lock_guard<std::mutex> lock(run_mutex_);
        client_.sendGoal(goal);
        goal_sent_ = true;
        running_name_ = name;
      }
      res.sent = true;
      if (!req.wait) {
        res.message += "; sent to the controller";
        ROS_INFO("run_program: %s", res.message.c_str());
        return true;
      }
      // Wait for the controller's result: as long as the trajectory takes at the controller's time scale, so no
      // time limit here, only ROS shutting down.
      while (ros::ok() && !client_.waitForResult(ros::Duration(0.5))) {
      }
      const actionlib::SimpleClientGoalState state = client_.getState();
      const auto result = client_.getResult();
      res.error_code = result ? result->error_code : FollowJointTrajectoryResult::INVALID_GOAL;
      res.error_string = result ? result->error_string : "no result";
      if (state == actionlib::SimpleClientGoalState::PREEMPTED &&
          res.error_code == FollowJointTrajectoryResult::SUCCESSFUL)  // a controller that reports no code for it
        res.error_code = FollowJointTrajectoryResult::PREEMPTED;
      res.success = state == actionlib::SimpleClientGoalState::SUCCEEDED &&
                    res.error_code == FollowJointTrajectoryResult::SUCCESSFUL;
      res.message += "; controller: " + state.toString() + (res.error_string.empty() ? "" : ": " + res.error_string);
      ROS_INFO("run_program: %s", res.message.c_str());
    } catch (const std::exception& e) {  // InputError (bad input) and anything else: an answer, not a crash
      res = RunToolpaths::Response();
      res.success = false;
      res.message = e.what();
      ROS_WARN("run_program: %s", e.what());
    }
    return true;
  }

  const CellFolders folders_ = readCellFolders(false);
  NodeDiagnostics diagnostics_;
  Machine machine_;
  double rate_ = 50, controller_wait_ = 2, joint_state_wait_ = 1;
  PostOptions post_options_;
  TrajectoryOptions trajectory_options_;
  TrajectoryClient client_;
  ros::Publisher trajectory_pub_;
  ros::Subscriber state_sub_;
  ros::ServiceServer service_;
  // The last joint_states of all this machine's joints: where they were (core units, machine joint order), whether
  // every velocity given was zero, and when it arrived.
  struct JointReading {
    std::vector<double> joints;
    bool still = true;
    ros::Time received;
  };
  std::mutex state_mutex_;
  std::condition_variable state_changed_;  // a new current_
  std::mutex run_mutex_;      // guards building_, goal_sent_, running_name_ and the client's goal
  bool building_ = false;     // a run_program is between its claim and its answer
  bool goal_sent_ = false;    // the client has had a goal (its state is defined)
  std::string running_name_;  // the program of the last goal sent
  std::optional<JointReading> current_;
};

}  // namespace art2part

int main(int argc, char** argv) {
  // 3 threads: joint_states and the action client's callbacks while run_program waits.
  return art2part::runMachineNode<art2part::ControllerBridge>(argc, argv, "controller_bridge", 3);
}
