// cell_supervisor over ROS, chaining the stage nodes: one plan_part goal makes the same plan as `art2part plan`
// (operations, faces, the simulation's figures, a program), with feedback at least once a second; a stage node killed
// during a goal fails it naming the stage, and its respawn serves the next; a cancel ends a running goal PREEMPTED within
// a second; goals beyond the queue are rejected with the reason; bad goals (paths outside the part folders, whether
// the file exists or not, unit slips, unknown modes and machines) are refused and the node serves the next goal;
// list_plans and get_plan serve the plan folders and nothing outside them.
#include <actionlib/client/simple_action_client.h>
#include <gtest/gtest.h>
#include <ros/ros.h>

#include <art2part/GetPlan.h>
#include <art2part/ListPlans.h>
#include <art2part/PlanPartAction.h>

#include <chrono>
#include <csignal>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <sys/types.h>
#include <signal.h>

#include <nlohmann/json.hpp>

#include "test_meshes.h"  // test::tempDir

using namespace art2part;
using Client = actionlib::SimpleActionClient<PlanPartAction>;
using State = actionlib::SimpleClientGoalState;
namespace fs = std::filesystem;

namespace {

const std::string kFeaturetype = std::string(ART2PART_SHARED_PARTS) + "/featuretype.STEP";
constexpr double kPlanTimeout = 300;  // s for one featuretype plan (about 10 s on 2 idle cores)

// One goal's run: its end state and result, and when each feedback came.
struct GoalRun {
  State state{State::LOST};
  PlanPartResult result;
  std::vector<PlanPartFeedback> feedback;
  std::vector<double> times;  // s since the goal was sent
  double seconds = 0;
};

class Tracker {
 public:
  explicit Tracker(Client& client) : client_(client), shared_(std::make_shared<Shared>()) {}

  // The feedback callback holds the shared state, not the tracker: a late feedback message of a goal that has
  // ended (the client keeps the callback until its next goal) never reaches a tracker that is gone.
  void send(const PlanPartGoal& goal) {
    start_ = std::chrono::steady_clock::now();
    shared_->start = start_;
    auto shared = shared_;
    client_.sendGoal(goal, Client::SimpleDoneCallback(), Client::SimpleActiveCallback(),
                     [shared](const PlanPartFeedbackConstPtr& f) {
                       std::lock_guard<std::mutex> lock(shared->mutex);
                       shared->run.feedback.push_back(*f);
                       shared->run.times.push_back(
                           std::chrono::duration<double>(std::chrono::steady_clock::now() - shared->start).count());
                     });
  }

  bool waitForStage(const std::string& stage, double timeout) {
    for (double t = 0; t < timeout; t += 0.02) {
      {
        std::lock_guard<std::mutex> lock(shared_->mutex);
        for (const PlanPartFeedback& f : shared_->run.feedback)
          if (f.stage == stage) return true;
      }
      ros::Duration(0.02).sleep();
    }
    return false;
  }

  // The client's state and result are read before our lock is taken: actionlib holds its own lock while it calls the
  // feedback callback (which takes ours), so taking them in the other order deadlocks when a goal's feedback and
  // result come together (a refused goal: "queued", then its result).
  GoalRun finish(double timeout) {
    client_.waitForResult(ros::Duration(timeout));
    const State state = client_.getState();
    const auto result = client_.getResult();
    std::lock_guard<std::mutex> lock(shared_->mutex);
    GoalRun run = shared_->run;
    run.state = state;
    if (result) run.result = *result;
    run.seconds = elapsed();
    return run;
  }

  double elapsed() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }

 private:
  struct Shared {
    std::mutex mutex;
    GoalRun run;
    std::chrono::steady_clock::time_point start;
  };
  Client& client_;
  std::shared_ptr<Shared> shared_;
  std::chrono::steady_clock::time_point start_;
};

Client& client(int k = 0) {
  static std::vector<std::unique_ptr<Client>> clients;
  while (static_cast<int>(clients.size()) <= k) {
    clients.push_back(std::make_unique<Client>("plan_part", true));
    EXPECT_TRUE(clients.back()->waitForServer(ros::Duration(60))) << "no plan_part action server";
  }
  return *clients[k];
}

GoalRun plan(const PlanPartGoal& goal, double timeout = kPlanTimeout) {
  Tracker t(client());
  t.send(goal);
  return t.finish(timeout);
}

PlanPartGoal featuretypeGoal() {
  PlanPartGoal goal;
  goal.part_file = kFeaturetype;
  return goal;
}

nlohmann::json readJson(const std::string& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

}  // namespace

// The refusals name what is wrong; a path outside the part folders gets the same words whether the file exists or not,
// so a caller learns nothing about the file system.
TEST(CellSupervisor, BadGoalsAreRefusedWithAReasonAndTheNodeServesOn) {
  auto refused = [](const PlanPartGoal& goal) {
    const GoalRun r = plan(goal, 30);
    EXPECT_EQ(r.state, State::ABORTED) << r.result.reason;
    EXPECT_FALSE(r.result.success);
    EXPECT_FALSE(r.result.reason.empty());
    return r.result.reason;
  };
  PlanPartGoal goal;
  goal.part_file = "/etc/shadow";
  const std::string exists = refused(goal);
  goal.part_file = "/etc/no_such_file_here";
  const std::string missing = refused(goal);
  auto without = [](std::string text, const std::string& path) { return text.replace(text.find(path), path.size(), "P"); };
  EXPECT_EQ(without(exists, "/etc/shadow"), without(missing, "/etc/no_such_file_here"));
  EXPECT_NE(exists.find("outside"), std::string::npos) << exists;
  goal.part_file = "../../../../../../etc/passwd";
  EXPECT_NE(refused(goal).find("outside"), std::string::npos);

  goal = featuretypeGoal();
  goal.mode = "4axis";
  EXPECT_NE(refused(goal).find("mode"), std::string::npos);
  goal = featuretypeGoal();
  goal.scallop_m = 0.01;  // 10 mm: millimetres typed as metres
  EXPECT_NE(refused(goal).find("scallop"), std::string::npos);
  goal.scallop_m = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(refused(goal).find("scallop"), std::string::npos);
  goal = featuretypeGoal();
  goal.machine = "../machines/vmc_3axis";
  EXPECT_NE(refused(goal).find("not a path"), std::string::npos);
  goal.machine = "no_such_machine";
  EXPECT_NE(refused(goal).find("vmc_3axis"), std::string::npos) << "the refusal lists the cell's machines";
  goal = PlanPartGoal();
  goal.part_id = "never_loaded";
  refused(goal);
}

// The single call: the plan folder of a goal holds what `art2part plan` writes for the same part, the same
// operations (kind, tool, setup, points), the same faces' verdicts and a program; feedback never pauses a second.
TEST(CellSupervisor, OneGoalMakesTheSamePlanAsTheCommandLine) {
  const GoalRun r = plan(featuretypeGoal());
  ASSERT_EQ(r.state, State::SUCCEEDED) << r.result.reason;
  ASSERT_TRUE(r.result.success);
  const fs::path dir = r.result.output_dir;
  for (const char* file : {"plan.json", "toolpaths.csv", "tools.json", "mesh.stl", "program.ngc", "setups.png",
                           "remaining.png"})
    EXPECT_TRUE(fs::exists(dir / file)) << file;
  ASSERT_GE(r.times.size(), 2u);
  double gap = r.times.front();
  for (std::size_t i = 1; i < r.times.size(); ++i) gap = std::max(gap, r.times[i] - r.times[i - 1]);
  gap = std::max(gap, r.seconds - r.times.back());
  EXPECT_LE(gap, 1.0) << "feedback paused " << gap << " s";

  const std::string cli_dir = test::tempDir() + "/cli";
  const std::string command = std::string(ART2PART_CLI) + " plan " + kFeaturetype + " --out " + cli_dir + " > " +
                              cli_dir + ".log 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0) << command;
  const nlohmann::json ours = readJson((dir / "plan.json").string()), cli = readJson(cli_dir + "/plan.json");
  ASSERT_EQ(ours["operations"].size(), cli["operations"].size());
  for (std::size_t i = 0; i < cli["operations"].size(); ++i) {
    SCOPED_TRACE("operation " + std::to_string(i));
    for (const char* key : {"kind", "tool", "setup", "points"}) EXPECT_EQ(ours["operations"][i][key], cli["operations"][i][key]) << key;
  }
  EXPECT_EQ(ours["finishing"]["faces_by_status"], cli["finishing"]["faces_by_status"]);
  EXPECT_EQ(ours["verification"]["gouges"], cli["verification"]["gouges"]);
  EXPECT_EQ(ours["verification"]["collisions"], cli["verification"]["collisions"]);
  EXPECT_EQ(ours["verification"]["gouges"], 0);
  EXPECT_EQ(ours["verification"]["collisions"], 0);
  EXPECT_EQ(ours["program"]["written"], true) << ours["program"].dump();

  const nlohmann::json summary = nlohmann::json::parse(r.result.summary_json);
  EXPECT_EQ(summary["operations"], ours["operations"].size());
  EXPECT_EQ(summary["verification"]["gouges"], 0);

  // list_plans names the folder; get_plan serves it and nothing outside the output root.
  ListPlans list;
  ASSERT_TRUE(ros::service::call("list_plans", list));
  const std::string name = dir.filename().string();
  EXPECT_NE(std::find(list.response.names.begin(), list.response.names.end(), name), list.response.names.end());
  GetPlan get;
  get.request.name = name;
  ASSERT_TRUE(ros::service::call("get_plan", get));
  EXPECT_TRUE(get.response.success) << get.response.message;
  EXPECT_EQ(nlohmann::json::parse(get.response.plan_json)["operations"].size(), ours["operations"].size());
  for (const char* bad : {"..", "../..", "/etc", "x/../..", "no_such_plan"}) {
    get.request.name = bad;
    ASSERT_TRUE(ros::service::call("get_plan", get));
    EXPECT_FALSE(get.response.success) << bad;
    EXPECT_TRUE(get.response.plan_json.empty()) << bad;
  }
}

// A cancel in any stage ends the goal PREEMPTED within a second, and the next goal runs.
TEST(CellSupervisor, CancelEndsAGoalWithinASecond) {
  for (const char* stage : {"visibility", "roughing", "finishing", "verification"}) {
    SCOPED_TRACE(stage);
    Tracker t(client());
    t.send(featuretypeGoal());
    ASSERT_TRUE(t.waitForStage(stage, kPlanTimeout)) << "never reached " << stage;
    const double asked = t.elapsed();
    client().cancelGoal();
    const GoalRun r = t.finish(30);
    EXPECT_EQ(r.state, State::PREEMPTED) << r.result.reason;
    EXPECT_LE(r.seconds - asked, 1.0) << "the cancel took " << r.seconds - asked << " s";
  }
}

// The pid of a running node, from `rosnode info` (-1 when it is not running).
int nodePid(const std::string& node) {
  const std::string command = "rosnode info " + node + " 2>/dev/null";
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return -1;
  char line[512];
  int pid = -1;
  while (std::fgets(line, sizeof line, pipe))
    if (std::strncmp(line, "Pid: ", 5) == 0) pid = std::atoi(line + 5);
  pclose(pipe);
  return pid;
}

// A stage node killed during a goal fails the goal naming the stage, within seconds (not its timeout of an hour); the
// node launch respawns serves the next goal.
TEST(CellSupervisor, AStageNodeKilledFailsTheGoalNamingTheStageAndItsRespawnServesTheNext) {
  Tracker t(client());
  t.send(featuretypeGoal());
  ASSERT_TRUE(t.waitForStage("roughing", kPlanTimeout)) << "never reached roughing";
  const int pid = nodePid("/roughing_planner");
  ASSERT_GT(pid, 0) << "no roughing_planner pid";
  ASSERT_EQ(::kill(pid, SIGKILL), 0);
  const double killed = t.elapsed();
  const GoalRun r = t.finish(60);
  EXPECT_EQ(r.state, State::ABORTED) << r.result.reason;
  EXPECT_NE(r.result.reason.find("stage 'roughing'"), std::string::npos) << r.result.reason;
  EXPECT_LE(r.seconds - killed, 10.0) << "the goal failed " << r.seconds - killed << " s after the kill";

  const GoalRun next = plan(featuretypeGoal());
  EXPECT_EQ(next.state, State::SUCCEEDED) << next.result.reason;
  EXPECT_NE(nodePid("/roughing_planner"), pid) << "served by a new roughing_planner";
}

// With a goal running and max_queue (1, in the test's launch file) goals waiting, the next goal is rejected with the
// reason; a queued goal can be cancelled; the queue runs in order.
TEST(CellSupervisor, GoalsQueueAndTheQueueHasALength) {
  Tracker first(client(0)), second(client(1)), third(client(2));
  first.send(featuretypeGoal());
  ASSERT_TRUE(first.waitForStage("visibility", 60));
  second.send(featuretypeGoal());
  ASSERT_TRUE(second.waitForStage("queued", 10));
  third.send(featuretypeGoal());
  const GoalRun rejected = third.finish(10);
  EXPECT_EQ(rejected.state, State::REJECTED);
  EXPECT_NE(rejected.result.reason.find("busy"), std::string::npos) << rejected.result.reason;
  client(1).cancelGoal();
  const GoalRun cancelled = second.finish(10);
  EXPECT_EQ(cancelled.state, State::PREEMPTED) << cancelled.result.reason;
  client(0).cancelGoal();
  EXPECT_EQ(first.finish(10).state, State::PREEMPTED);
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_cell_supervisor_node");
  ros::NodeHandle nh;
  ros::AsyncSpinner spinner(2);
  spinner.start();
  const int status = RUN_ALL_TESTS();
  ros::shutdown();
  return status;
}
