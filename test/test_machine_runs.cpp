// The bundled machines run the package's own plans (test/machine_runs.test): `art2part plan` makes plan folders of
// the shared featuretype part (a multi-setup 3-axis plan, roughing only to keep the test short, and the whole 5-axis
// plan, whose finishing links tool axes across the setup);
// the controller bridge places each setup on its machine from plan.json, and the simulated controller runs the whole
// trajectory to its last point: on the 3-axis VMC and on the default 5-axis trunnion. LinuxCNC's sim trunnion is too
// short in Z: its bridge refuses before running anything, naming every setup and the joint.
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <ros/topic.h>
#include <sensor_msgs/JointState.h>
#include <trajectory_msgs/JointTrajectory.h>

#include <art2part/FollowJointTrajectoryAction.h>
#include <art2part/RunToolpaths.h>

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include <nlohmann/json.hpp>

using namespace art2part;
namespace fs = std::filesystem;

namespace {

const std::string kPart = std::string(ART2PART_SHARED_PARTS) + "/featuretype.STEP";

std::string readFile(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// `art2part plan featuretype.STEP ARGS` into a fresh folder; the folder, or "" with a test failure.
fs::path planFolder(const std::string& name, const std::string& arguments) {
  const fs::path dir = fs::temp_directory_path() / ("art2part_runs_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string command = std::string(ART2PART_CLI) + " plan " + kPart + " --out " + dir.string() +
                              " " + arguments + " > " + (dir / "log").string() + " 2>&1";
  if (std::system(command.c_str()) != 0) {
    ADD_FAILURE() << command << "\n" << readFile(dir / "log");
    return "";
  }
  return dir;
}

nlohmann::json planJson(const fs::path& dir) { return nlohmann::json::parse(readFile(dir / "plan.json")); }

// run_program in namespace `ns` on `dir`, waiting for the controller.
RunToolpaths::Response runProgram(const std::string& ns, const fs::path& dir) {
  EXPECT_TRUE(ros::service::waitForService(ns + "/run_program", ros::Duration(30)));
  RunToolpaths run;
  run.request.folder = dir.string();
  run.request.rate = 10;
  run.request.wait = true;
  EXPECT_TRUE(ros::service::call(ns + "/run_program", run));
  return run.response;
}

// The machine's joints after the run end where the published trajectory ends.
void expectJointsAtTheEnd(const std::string& ns) {
  ros::NodeHandle nh;
  auto trajectory =
      ros::topic::waitForMessage<trajectory_msgs::JointTrajectory>(ns + "/joint_trajectory", nh, ros::Duration(5));
  ASSERT_TRUE(trajectory) << ns << "/joint_trajectory is latched";
  const ros::Time after = ros::Time::now();
  for (int attempt = 0; attempt < 100; ++attempt) {
    auto state = ros::topic::waitForMessage<sensor_msgs::JointState>(ns + "/joint_states", nh, ros::Duration(5));
    ASSERT_TRUE(state);
    if (state->header.stamp <= after) continue;
    ASSERT_EQ(state->name, trajectory->joint_names);
    for (std::size_t i = 0; i < state->name.size(); ++i)
      EXPECT_NEAR(state->position[i], trajectory->points.back().positions[i], 1e-6) << ns << " " << state->name[i];
    return;
  }
  FAIL() << "no joint_states from " << ns;
}

}  // namespace

TEST(MachineRuns, AMultiSetupThreeAxisPlanRunsToTheEndOnTheVmc) {
  const fs::path dir = planFolder("3axis", "--no-finish");
  ASSERT_FALSE(dir.empty());
  const nlohmann::json plan = planJson(dir);
  const std::size_t setups = plan["setups"].size();
  ASSERT_GE(setups, 2u) << "a multi-setup plan";
  ASSERT_TRUE(plan["program"]["written"].get<bool>()) << plan["program"]["error"];
  for (const nlohmann::json& setup : plan["setups"]) {
    EXPECT_EQ(setup["fixture"]["machine"], "vmc_3axis");
    EXPECT_TRUE(setup["fixture"]["reachable"].get<bool>()) << setup["fixture"]["reason"];
  }

  const RunToolpaths::Response run = runProgram("/vmc", dir);
  ASSERT_TRUE(run.success) << run.message;
  EXPECT_TRUE(run.sent);
  EXPECT_EQ(run.error_code, FollowJointTrajectoryResult::SUCCESSFUL) << run.error_string;
  EXPECT_NE(run.message.find(std::to_string(setups) + " setup(s)"), std::string::npos) << run.message;
  expectJointsAtTheEnd("/vmc");

  // The same plan on the default trunnion: placed afresh there (plan.json's fixtures are the VMC's), and run.
  const RunToolpaths::Response on_trunnion = runProgram("/trunnion", dir);
  ASSERT_TRUE(on_trunnion.success) << on_trunnion.message;
  EXPECT_EQ(on_trunnion.error_code, FollowJointTrajectoryResult::SUCCESSFUL) << on_trunnion.error_string;
  expectJointsAtTheEnd("/trunnion");

  // LinuxCNC's sim trunnion: refused before anything runs, every setup named with the joint that leaves its travel.
  const RunToolpaths::Response toy = runProgram("/toy", dir);
  EXPECT_FALSE(toy.success);
  EXPECT_FALSE(toy.sent);
  EXPECT_NE(toy.message.find("machine trunnion_ac cannot reach setups 0, 1"), std::string::npos) << toy.message;
  EXPECT_NE(toy.message.find("above its maximum 120 mm"), std::string::npos) << toy.message;
  fs::remove_all(dir);
}

TEST(MachineRuns, AFiveAxisPlanRunsToTheEndOnTheDefaultTrunnion) {
  const fs::path dir = planFolder("5axis", "--mode 5axis");
  ASSERT_FALSE(dir.empty());
  const nlohmann::json plan = planJson(dir);
  EXPECT_EQ(plan["program"]["machine"], "trunnion_5axis") << "the default machine of --mode 5axis";
  ASSERT_TRUE(plan["program"]["written"].get<bool>()) << plan["program"]["error"];
  EXPECT_TRUE(fs::exists(dir / "program.ngc"));
  for (const nlohmann::json& setup : plan["setups"])
    EXPECT_TRUE(setup["fixture"]["reachable"].get<bool>()) << setup["fixture"]["reason"];

  const RunToolpaths::Response run = runProgram("/trunnion", dir);
  ASSERT_TRUE(run.success) << run.message;
  EXPECT_EQ(run.error_code, FollowJointTrajectoryResult::SUCCESSFUL) << run.error_string;
  expectJointsAtTheEnd("/trunnion");
  fs::remove_all(dir);
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_machine_runs");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
