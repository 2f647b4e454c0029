// controller_bridge + simulated_controller over ROS (test/controller_bridge.test, trunnion_ac, time scale 10):
// a hand-made 5-axis toolpath becomes a joint trajectory that the simulated controller runs to its last point; the
// URDF (robot_state_publisher) puts the spindle where the core's forward kinematics does; bad goals and bad folders
// are refused with a reason and both nodes keep serving; a second program while one runs is refused, and a cancelled
// one answers success false with error_code PREEMPTED.
#include <actionlib/client/simple_action_client.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <ros/topic.h>
#include <sensor_msgs/JointState.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>
#include <trajectory_msgs/JointTrajectory.h>

#include <art2part/FollowJointTrajectoryAction.h>
#include <art2part/RunToolpaths.h>

#include <cmath>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <thread>

#include "art2part/kinematics/inverse_kinematics.h"
#include "art2part/tooling/tool.h"
#include "art2part/tooling/toolpath.h"

using namespace art2part;
using Client = actionlib::SimpleActionClient<FollowJointTrajectoryAction>;
namespace fs = std::filesystem;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180;
const std::string kMachine = std::string(ART2PART_SOURCE_DIR) + "/config/machines/trunnion_ac.yaml";

Tool ballTool() {
  Tool tool;
  tool.id = "ball6";
  tool.type = ToolType::Ball;
  tool.diameter = 6;
  tool.corner_radius = 3;
  tool.flute_length = 15;
  tool.shank_diameter = 6;
  tool.stickout = 30;
  tool.holder = {{20, 30}};
  tool.feed_mm_min = 600;
  tool.plunge_mm_min = 200;
  return tool;
}

// A quarter circle of radius 15 mm at z = 10 with the tool leaning 20 deg outwards (A and C both move), entered and
// left from 10 mm up the axis.
fs::path writeFiveAxisFolder() {
  Toolpath path;
  for (int k = 0; k <= 9; ++k) {
    const double theta = k * 10 * kDeg;
    CutterLocation p;
    p.tool = "ball6";
    p.axis = Vec3(std::sin(20 * kDeg) * std::cos(theta), std::sin(20 * kDeg) * std::sin(theta), std::cos(20 * kDeg));
    p.tip = Vec3(15 * std::cos(theta), 15 * std::sin(theta), 10);
    if (k == 0) {
      CutterLocation above = p;
      above.move = MoveKind::Rapid;
      above.tip += 10 * p.axis;
      path.push_back(above);
    }
    p.move = MoveKind::Feed;
    path.push_back(p);
  }
  CutterLocation away = path.back();
  away.move = MoveKind::Rapid;
  away.tip += 10 * away.axis;
  path.push_back(away);

  const fs::path dir = fs::temp_directory_path() / ("art2part_bridge_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  writeToolpathsCsv(path, (dir / "toolpaths.csv").string());
  writeToolsJson({ballTool()}, (dir / "tools.json").string());
  return dir;
}

// The next joint_states published after `after`, by name.
std::map<std::string, double> jointStatesAfter(ros::NodeHandle& nh, const ros::Time& after) {
  for (int attempt = 0; attempt < 100; ++attempt) {
    auto msg = ros::topic::waitForMessage<sensor_msgs::JointState>("joint_states", nh, ros::Duration(5));
    if (!msg) break;
    if (msg->header.stamp <= after) continue;
    std::map<std::string, double> joints;
    for (std::size_t i = 0; i < msg->name.size() && i < msg->position.size(); ++i) joints[msg->name[i]] = msg->position[i];
    return joints;
  }
  ADD_FAILURE() << "no joint_states after " << after;
  return {};
}

FollowJointTrajectoryResultConstPtr runGoal(Client& client, const FollowJointTrajectoryGoal& goal,
                                            actionlib::SimpleClientGoalState* state = nullptr) {
  client.sendGoal(goal);
  EXPECT_TRUE(client.waitForResult(ros::Duration(30)));
  if (state) *state = client.getState();
  return client.getResult();
}

trajectory_msgs::JointTrajectoryPoint pointAt(double seconds, const std::vector<double>& positions) {
  trajectory_msgs::JointTrajectoryPoint point;
  point.time_from_start = ros::Duration(seconds);
  point.positions = positions;
  return point;
}

}  // namespace

TEST(ControllerBridge, RunsAFiveAxisProgramToItsLastPoint) {
  ros::NodeHandle nh;
  ASSERT_TRUE(ros::service::waitForService("run_program", ros::Duration(30)));
  Client client("follow_joint_trajectory", true);
  ASSERT_TRUE(client.waitForServer(ros::Duration(30)));
  tf2_ros::Buffer tf_buffer;
  tf2_ros::TransformListener tf_listener(tf_buffer);

  const fs::path dir = writeFiveAxisFolder();
  RunToolpaths run;
  run.request.folder = dir.string();
  run.request.mode = "5axis";
  run.request.wait = true;
  const ros::WallTime started = ros::WallTime::now();
  ASSERT_TRUE(ros::service::call("run_program", run));
  ASSERT_TRUE(run.response.success) << run.response.message;
  EXPECT_TRUE(run.response.sent);
  EXPECT_EQ(run.response.error_code, FollowJointTrajectoryResult::SUCCESSFUL) << run.response.error_string;
  EXPECT_EQ(run.response.mode, "5axis");
  EXPECT_GT(run.response.points, 10u);
  EXPECT_LT((ros::WallTime::now() - started).toSec(), 0.5 * run.response.duration + 10)
      << "~time_scale 10 runs it faster than real time";
  const ros::Time finished = ros::Time::now();

  auto trajectory = ros::topic::waitForMessage<trajectory_msgs::JointTrajectory>("joint_trajectory", nh,
                                                                                 ros::Duration(5));
  ASSERT_TRUE(trajectory) << "joint_trajectory is latched";
  ASSERT_EQ(trajectory->points.size(), run.response.points);
  const std::vector<std::string> names{"X", "Y", "Z", "A", "C"};
  ASSERT_EQ(trajectory->joint_names, names);
  EXPECT_NEAR(trajectory->points.back().time_from_start.toSec(), run.response.duration, 1e-6);
  for (std::size_t p = 1; p < trajectory->points.size(); ++p)
    ASSERT_GT(trajectory->points[p].time_from_start, trajectory->points[p - 1].time_from_start) << p;

  // The joints end at the trajectory's last point.
  const std::map<std::string, double> state = jointStatesAfter(nh, finished);
  for (std::size_t i = 0; i < names.size(); ++i) {
    ASSERT_TRUE(state.count(names[i])) << names[i];
    EXPECT_NEAR(state.at(names[i]), trajectory->points.back().positions[i], 1e-6) << names[i];
  }
  // The quarter circle turns C from -+90 deg (axis leaning towards +x) to 0 (towards +y), A tilts 20 deg.
  double c_min = 1e9, c_max = -1e9, a_max = 0;
  for (const auto& point : trajectory->points) {
    c_min = std::min(c_min, point.positions[4]);
    c_max = std::max(c_max, point.positions[4]);
    a_max = std::max(a_max, std::abs(point.positions[3]));
  }
  EXPECT_NEAR(c_max - c_min, 90 * kDeg, 1e-6);
  EXPECT_NEAR(a_max, 20 * kDeg, 1e-6);

  // The URDF (robot_state_publisher) puts the spindle's gauge point where the core's forward kinematics does, in the
  // part frame.
  const Machine machine = loadMachine(kMachine);
  std::vector<double> joints;
  for (std::size_t i = 0; i < names.size(); ++i) joints.push_back(i < 3 ? state.at(names[i]) * 1e3 : state.at(names[i]));
  const ToolPose expected =
      forwardKinematics(machine, placementFor(machine, 0, 0.0), jointPositionFromVector(machine, joints));
  ros::Duration(0.5).sleep();
  geometry_msgs::TransformStamped gauge;
  try {
    gauge = tf_buffer.lookupTransform("part", "z_slide", ros::Time(0), ros::Duration(10));
  } catch (const tf2::TransformException& e) {
    FAIL() << "robot_state_publisher with the generated URDF: " << e.what();
  }
  EXPECT_NEAR(gauge.transform.translation.x * 1e3, expected.tip.x(), 1e-6);
  EXPECT_NEAR(gauge.transform.translation.y * 1e3, expected.tip.y(), 1e-6);
  EXPECT_NEAR(gauge.transform.translation.z * 1e3, expected.tip.z(), 1e-6);
  const auto& r = gauge.transform.rotation;  // the spindle's z axis in the part frame = the tool axis
  const Vec3 axis(2 * (r.x * r.z + r.w * r.y), 2 * (r.y * r.z - r.w * r.x), 1 - 2 * (r.x * r.x + r.y * r.y));
  EXPECT_LT((axis - expected.axis).norm(), 1e-6) << axis.transpose() << " vs " << expected.axis.transpose();
  fs::remove_all(dir);
}

TEST(ControllerBridge, RefusesBadGoalsAndBadFoldersAndKeepsServing) {
  ros::NodeHandle nh;
  ASSERT_TRUE(ros::service::waitForService("run_program", ros::Duration(30)));
  Client client("follow_joint_trajectory", true);
  ASSERT_TRUE(client.waitForServer(ros::Duration(30)));
  const ros::Time now = ros::Time::now();
  const std::map<std::string, double> at = jointStatesAfter(nh, now);
  ASSERT_EQ(at.size(), 5u);

  FollowJointTrajectoryGoal goal;
  goal.trajectory.joint_names = {"X", "W"};
  goal.trajectory.points = {pointAt(1, {0, 0})};
  actionlib::SimpleClientGoalState state(actionlib::SimpleClientGoalState::LOST);
  auto result = runGoal(client, goal, &state);
  ASSERT_TRUE(result);
  EXPECT_EQ(state, actionlib::SimpleClientGoalState::ABORTED);
  EXPECT_EQ(result->error_code, FollowJointTrajectoryResult::INVALID_JOINTS);
  EXPECT_NE(result->error_string.find("unknown joint 'W'"), std::string::npos) << result->error_string;

  goal.trajectory.joint_names = {"X", "A"};
  goal.trajectory.points = {pointAt(1, {at.at("X"), -120 * kDeg})};  // A travels -100 .. 50 deg
  result = runGoal(client, goal, &state);
  ASSERT_TRUE(result);
  EXPECT_EQ(result->error_code, FollowJointTrajectoryResult::INVALID_GOAL);
  EXPECT_NE(result->error_string.find("A = -120 deg outside its travel"), std::string::npos) << result->error_string;

  goal.trajectory.points = {pointAt(1, {at.at("X"), at.at("A")}), pointAt(1, {at.at("X"), at.at("A")})};
  result = runGoal(client, goal, &state);
  EXPECT_EQ(result->error_code, FollowJointTrajectoryResult::INVALID_GOAL);
  EXPECT_NE(result->error_string.find("times must increase"), std::string::npos) << result->error_string;

  goal.trajectory.points = {pointAt(0.1, {at.at("X") + 0.05, at.at("A")})};  // 50 mm in 0.1 s: X runs 20 mm/s
  result = runGoal(client, goal, &state);
  EXPECT_EQ(result->error_code, FollowJointTrajectoryResult::INVALID_GOAL);
  EXPECT_NE(result->error_string.find("above its maximum"), std::string::npos) << result->error_string;

  // Still serving: a good goal (X 5 mm in 1 s of trajectory time, a subset of the joints) runs to its end.
  const double x_goal = at.at("X") + 0.005;
  goal.trajectory.points = {pointAt(1, {x_goal, at.at("A")})};
  result = runGoal(client, goal, &state);
  ASSERT_TRUE(result);
  EXPECT_EQ(state, actionlib::SimpleClientGoalState::SUCCEEDED) << result->error_string;
  EXPECT_EQ(result->error_code, FollowJointTrajectoryResult::SUCCESSFUL);
  const std::map<std::string, double> moved = jointStatesAfter(nh, ros::Time::now());
  EXPECT_NEAR(moved.at("X"), x_goal, 1e-9);
  EXPECT_NEAR(moved.at("Y"), at.at("Y"), 1e-12) << "joints the goal leaves out hold";

  // Cancel: a long move stops part way.
  goal.trajectory.points = {pointAt(100, {x_goal + 0.1, at.at("A")})};
  client.sendGoal(goal);
  ros::Duration(0.5).sleep();
  client.cancelGoal();
  EXPECT_TRUE(client.waitForResult(ros::Duration(10)));
  EXPECT_EQ(client.getState(), actionlib::SimpleClientGoalState::PREEMPTED);
  ASSERT_TRUE(client.getResult());
  EXPECT_EQ(client.getResult()->error_code, FollowJointTrajectoryResult::PREEMPTED) << "a cancelled goal did not succeed";
  EXPECT_NE(client.getResult()->error_string.find("cancelled"), std::string::npos) << client.getResult()->error_string;
  const std::map<std::string, double> stopped = jointStatesAfter(nh, ros::Time::now());
  EXPECT_GT(stopped.at("X"), x_goal);
  EXPECT_LT(stopped.at("X"), x_goal + 0.1);

  // run_program on bad folders and modes: success=false with the reason.
  RunToolpaths run;
  run.request.folder = "/nonexistent/plan";
  ASSERT_TRUE(ros::service::call("run_program", run));
  EXPECT_FALSE(run.response.success);
  EXPECT_NE(run.response.message.find("/nonexistent/plan"), std::string::npos) << run.response.message;

  const fs::path dir = writeFiveAxisFolder();
  run.request.folder = dir.string();
  run.request.mode = "7axis";
  ASSERT_TRUE(ros::service::call("run_program", run));
  EXPECT_FALSE(run.response.success);
  EXPECT_NE(run.response.message.find("7axis"), std::string::npos) << run.response.message;

  fs::remove(dir / "tools.json");
  run.request.mode = "5axis";
  ASSERT_TRUE(ros::service::call("run_program", run));
  EXPECT_FALSE(run.response.success);
  EXPECT_NE(run.response.message.find("tools.json"), std::string::npos) << run.response.message;

  { std::ofstream(dir / "tools.json") << "[{\"id\": \"ball6\", \"diameter\": -3}]"; }
  ASSERT_TRUE(ros::service::call("run_program", run));
  EXPECT_FALSE(run.response.success);
  EXPECT_FALSE(run.response.message.empty());
  fs::remove_all(dir);

  // And both nodes still answer.
  ASSERT_TRUE(ros::service::waitForService("run_program", ros::Duration(5)));
  EXPECT_TRUE(client.waitForServer(ros::Duration(5)));
}

TEST(ControllerBridge, ASecondProgramWhileOneRunsIsRefusedAndACancelledOneFails) {
  ros::NodeHandle nh;
  ASSERT_TRUE(ros::service::waitForService("run_program", ros::Duration(30)));
  Client client("follow_joint_trajectory", true);  // any client of the controller may cancel
  ASSERT_TRUE(client.waitForServer(ros::Duration(30)));
  const fs::path dir = writeFiveAxisFolder();

  RunToolpaths first;
  first.request.folder = dir.string();
  first.request.mode = "5axis";
  first.request.wait = true;
  bool called = false;
  std::thread runner([&] { called = ros::service::call("run_program", first); });
  auto feedback = ros::topic::waitForMessage<FollowJointTrajectoryActionFeedback>("follow_joint_trajectory/feedback",
                                                                                  nh, ros::Duration(30));
  ASSERT_TRUE(feedback) << "the first program runs on the controller";

  RunToolpaths second;
  second.request.folder = dir.string();
  second.request.mode = "5axis";
  ASSERT_TRUE(ros::service::call("run_program", second));
  EXPECT_FALSE(second.response.success);
  EXPECT_FALSE(second.response.sent);
  EXPECT_NE(second.response.message.find("still running on the controller"), std::string::npos)
      << second.response.message;

  client.cancelAllGoals();
  runner.join();
  ASSERT_TRUE(called);
  EXPECT_FALSE(first.response.success) << first.response.message;
  EXPECT_TRUE(first.response.sent);
  EXPECT_EQ(first.response.error_code, FollowJointTrajectoryResult::PREEMPTED) << first.response.message;
  EXPECT_NE(first.response.message.find("PREEMPTED: cancelled"), std::string::npos) << first.response.message;

  // The bridge is free again: the next program runs to its end.
  ASSERT_TRUE(ros::service::call("run_program", first));
  EXPECT_TRUE(first.response.success) << first.response.message;
  EXPECT_EQ(first.response.error_code, FollowJointTrajectoryResult::SUCCESSFUL);
  fs::remove_all(dir);
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_controller_bridge_node");
  ros::NodeHandle nh;
  ros::AsyncSpinner spinner(1);  // the tf listener
  spinner.start();
  return RUN_ALL_TESTS();
}
