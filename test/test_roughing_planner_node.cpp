// roughing_planner over ROS: plan_roughing refuses bad goals with a reason and keeps serving; it roughs CTC 1 setup by
// setup with feedback, with flat and bull mills of the tool library only, writes the file contracts when asked, and
// publishes the toolpath and levels for rviz. One CTC 1 plan is made (the tests share it).
#include <actionlib/client/simple_action_client.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <ros/topic.h>
#include <visualization_msgs/MarkerArray.h>

#include <art2part/LoadPart.h>
#include <art2part/PlanRoughingAction.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <vector>

#include "art2part/tooling/tool.h"
#include "art2part/tooling/toolpath.h"

using namespace art2part;
using Client = actionlib::SimpleActionClient<PlanRoughingAction>;
namespace fs = std::filesystem;

namespace {

const std::string kExample = std::string(ART2PART_SOURCE_DIR) + "/examples/nist_ctc_01_asme1_rd.stp";
const std::string kTools = std::string(ART2PART_SOURCE_DIR) + "/config/tools.yaml";
const std::string kPart = "ctc1";
constexpr int kLevel = 2;
constexpr double kGoalTimeout = 200;  // seconds for one plan (the one below: about 50 s on 2 busy cores)

void loadPart() {
  static bool loaded = false;
  if (loaded) return;
  ASSERT_TRUE(ros::service::waitForService("load_part", ros::Duration(60)));
  LoadPart load;
  load.request.path = kExample;
  load.request.part_id = kPart;
  ASSERT_TRUE(ros::service::call("load_part", load));
  ASSERT_TRUE(load.response.success) << load.response.message;
  loaded = true;
}

std::unique_ptr<Client> the_client;  // made in main after ros::init, gone before it returns

Client& client() { return *the_client; }

struct Outcome {
  bool finished = false;
  actionlib::SimpleClientGoalState state{actionlib::SimpleClientGoalState::LOST};
  PlanRoughingResult result;
  std::vector<PlanRoughingFeedback> feedback;
};

Outcome run(const PlanRoughingGoal& goal) {
  Outcome out;
  EXPECT_TRUE(client().waitForServer(ros::Duration(60))) << "no plan_roughing action server";
  struct Log {
    std::mutex mutex;
    std::vector<PlanRoughingFeedback> feedback;
  };
  auto log = std::make_shared<Log>();  // outlives the call, should feedback come late
  client().sendGoal(goal, Client::SimpleDoneCallback(), Client::SimpleActiveCallback(),
                    [log](const PlanRoughingFeedbackConstPtr& f) {
                      std::lock_guard<std::mutex> lock(log->mutex);
                      log->feedback.push_back(*f);
                    });
  out.finished = client().waitForResult(ros::Duration(kGoalTimeout));
  EXPECT_TRUE(out.finished) << "no result within " << kGoalTimeout << " s (goal part '" << goal.part_id << "')";
  if (!out.finished) {
    client().cancelGoal();
    return out;
  }
  out.state = client().getState();
  if (auto result = client().getResult()) out.result = *result;
  std::lock_guard<std::mutex> lock(log->mutex);
  out.feedback = log->feedback;
  return out;
}

PlanRoughingGoal goal(const std::string& part_id) {
  PlanRoughingGoal g;
  g.part_id = part_id;
  g.mode = "3axis";
  g.level = kLevel;
  return g;
}

const ToolLibrary& library() {
  static const ToolLibrary tools = loadToolLibrary(kTools);
  return tools;
}

std::string outputDir() {
  static const std::string dir =
      (fs::temp_directory_path() / ("art2part_roughing_node_" + std::to_string(::getpid()))).string();
  return dir;
}

// The plan the tests look at, made once, with its files. The 20 mm flat mill (what the planner chooses for CTC 1's
// first setup anyway), no rest pass: on CTC 1 (800 x 450 x 150 mm) choosing among the 16 flat and bull mills and the
// rest pass with a 10 mm mill each take minutes a setup today; the 20 mm mill's operations take about 50 s in all.
const Outcome& fullPlan() {
  static Outcome outcome;
  static bool made = false;
  if (!made) {
    made = true;
    PlanRoughingGoal g = goal(kPart);
    g.tool = "flat20";
    g.rest_pass = false;
    g.output_dir = outputDir();
    outcome = run(g);
  }
  return outcome;
}

double norm(const geometry_msgs::Vector3& v) { return std::sqrt(v.x * v.x + v.y * v.y + v.z * v.z); }

// What every successful roughing plan of CTC 1 must satisfy.
void expectSoundPlan(const Outcome& o) {
  ASSERT_TRUE(o.finished);
  ASSERT_EQ(o.state, actionlib::SimpleClientGoalState::SUCCEEDED) << o.state.toString() << ": " << o.result.message;
  const PlanRoughingResult& r = o.result;
  ASSERT_TRUE(r.success) << r.message;
  ROS_INFO("plan_roughing: %s (%.1f s)", r.message.c_str(), r.seconds);
  EXPECT_NE(r.message.find(kPart), std::string::npos) << r.message;
  EXPECT_EQ(r.mode, "3axis");
  ASSERT_GE(r.setup_count, 1u);
  ASSERT_GE(r.operations.size(), 1u) << r.message;
  ASSERT_EQ(r.moves.size(), r.tips.size());
  uint32_t next = 0;
  for (std::size_t i = 0; i < r.operations.size(); ++i) {
    const MachiningOperation& op = r.operations[i];
    EXPECT_EQ(op.id, i);
    EXPECT_GE(op.setup, 0) << "operation " << i;
    EXPECT_LT(op.setup, static_cast<int>(r.setup_count)) << "operation " << i;
    EXPECT_TRUE(op.kind == "roughing" || op.kind == "rest roughing") << "operation " << i << ": " << op.kind;
    const Tool* tool = library().find(op.tool);
    ASSERT_NE(tool, nullptr) << "operation " << i << " uses tool '" << op.tool << "', not in " << kTools;
    EXPECT_TRUE(tool->type == ToolType::Flat || tool->type == ToolType::Bull)
        << "operation " << i << " roughs with " << op.tool << ", a " << toolTypeName(tool->type);
    EXPECT_EQ(op.first_point, next) << "operations' points follow one another";
    ASSERT_GE(op.points, 2u) << "operation " << i;
    next += op.points;
    ASSERT_LE(next, r.tips.size());
    EXPECT_NEAR(norm(op.axis), 1.0, 1e-6) << "operation " << i;
    EXPECT_GT(op.cutting_length_m, 0) << "operation " << i;
    EXPECT_GT(op.estimated_time_s, 0) << "operation " << i;
    EXPECT_GE(op.levels, 1u) << "operation " << i;
    int feeds = 0;
    for (uint32_t j = op.first_point; j < op.first_point + op.points; ++j) {
      ASSERT_TRUE(r.moves[j] == PlanRoughingResult::RAPID || r.moves[j] == PlanRoughingResult::FEED) << int(r.moves[j]);
      feeds += r.moves[j] == PlanRoughingResult::FEED;
      ASSERT_TRUE(std::isfinite(r.tips[j].x) && std::isfinite(r.tips[j].y) && std::isfinite(r.tips[j].z));
      ASSERT_LT(std::abs(r.tips[j].x) + std::abs(r.tips[j].y) + std::abs(r.tips[j].z), 10.0) << "metres, not mm";
    }
    EXPECT_GT(feeds, 0) << "operation " << i << " cuts nothing";
  }
  EXPECT_EQ(next, r.tips.size()) << "every point belongs to an operation";
  ASSERT_FALSE(o.feedback.empty()) << "no feedback";
}

}  // namespace

TEST(RoughingPlannerNode, RefusesBadGoalsAndKeepsServing) {
  ASSERT_NO_FATAL_FAILURE(loadPart());
  auto refused = [](const PlanRoughingGoal& g, const std::string& named) {
    const Outcome o = run(g);
    ASSERT_TRUE(o.finished);
    EXPECT_EQ(o.state, actionlib::SimpleClientGoalState::ABORTED) << o.state.toString();
    EXPECT_FALSE(o.result.success) << "accepted: " << o.result.message;
    EXPECT_FALSE(o.result.message.empty());
    EXPECT_EQ(o.result.message.find('\n'), std::string::npos) << "one line: " << o.result.message;
    EXPECT_NE(o.result.message.find(named), std::string::npos) << "'" << o.result.message << "' should name " << named;
    EXPECT_TRUE(o.result.operations.empty());
    EXPECT_TRUE(o.result.tips.empty());
  };

  refused(goal("nope"), "nope");

  PlanRoughingGoal g = goal(kPart);
  g.tool = "ball6";
  refused(g, "ball6");
  g.tool = "no_such_tool";
  refused(g, "no_such_tool");

  g = goal(kPart);
  g.mode = "4axis";
  refused(g, "4axis");
  g = goal(kPart);
  g.level = 9;
  refused(g, "level");
  g = goal(kPart);
  g.allowance_m = -0.001;
  refused(g, "allowance_m");

  // Still serving: the plan the other tests look at comes after the refusals (made once: a CTC 1 plan takes a while).
  ASSERT_NO_FATAL_FAILURE(expectSoundPlan(fullPlan()));
}

TEST(RoughingPlannerNode, RoughsCtc1SetupBySetupWithFeedbackAndFiles) {
  ASSERT_NO_FATAL_FAILURE(loadPart());
  const Outcome& o = fullPlan();
  ASSERT_NO_FATAL_FAILURE(expectSoundPlan(o));
  const PlanRoughingResult& r = o.result;

  // Feedback of the roughing stage: setup k of n, operations and levels counted up.
  bool roughing = false;
  uint32_t operations = 0, levels = 0;
  for (const PlanRoughingFeedback& f : o.feedback) {
    if (f.stage != "roughing" && f.stage != "done") continue;
    roughing = true;
    EXPECT_EQ(f.setups, r.setup_count);
    EXPECT_LE(f.setup, f.setups);
    EXPECT_GE(f.operations, operations);
    EXPECT_GE(f.levels_done, levels);
    operations = f.operations;
    levels = f.levels_done;
  }
  EXPECT_TRUE(roughing) << o.feedback.size() << " feedback messages, none of the roughing stage";
  EXPECT_LE(operations, r.operations.size());  // the last feedback may come after the result (another topic)

  // The file contracts: the same points in mm, the tools used.
  const Toolpath csv = readToolpathsCsv(outputDir() + "/toolpaths.csv");
  ASSERT_EQ(csv.size(), r.tips.size());
  for (std::size_t j = 0; j < csv.size(); j += std::max<std::size_t>(1, csv.size() / 200)) {
    EXPECT_NEAR(csv[j].tip.x(), 1e3 * r.tips[j].x, 1e-5) << "point " << j;
    EXPECT_NEAR(csv[j].tip.y(), 1e3 * r.tips[j].y, 1e-5) << "point " << j;
    EXPECT_NEAR(csv[j].tip.z(), 1e3 * r.tips[j].z, 1e-5) << "point " << j;
    EXPECT_EQ(csv[j].move == MoveKind::Feed, r.moves[j] == PlanRoughingResult::FEED) << "point " << j;
  }
  for (const MachiningOperation& op : r.operations) {
    const CutterLocation& first = csv[op.first_point];
    EXPECT_EQ(first.op, static_cast<int>(op.id));
    EXPECT_EQ(first.setup, op.setup);
    EXPECT_EQ(first.tool, op.tool);
  }
  std::set<std::string> used, listed;
  for (const MachiningOperation& op : r.operations) used.insert(op.tool);
  for (const Tool& t : readToolsJson(outputDir() + "/tools.json")) listed.insert(t.id);
  EXPECT_EQ(listed, used);

  // The goal's tool, no rest pass: one operation per setup at most.
  std::set<int> roughed;
  for (const MachiningOperation& op : r.operations) {
    EXPECT_EQ(op.tool, "flat20") << "operation " << op.id;
    EXPECT_EQ(op.kind, "roughing") << "operation " << op.id;
    EXPECT_TRUE(roughed.insert(op.setup).second) << "two operations in setup " << op.setup;
  }
  std::error_code ignored;
  fs::remove_all(outputDir(), ignored);
}

TEST(RoughingPlannerNode, PublishesToolpathAndLevelMarkers) {
  ASSERT_NO_FATAL_FAILURE(loadPart());
  const Outcome& o = fullPlan();
  ASSERT_NO_FATAL_FAILURE(expectSoundPlan(o));
  const auto markers =
      ros::topic::waitForMessage<visualization_msgs::MarkerArray>("roughing_planner/markers", ros::Duration(15));
  ASSERT_TRUE(markers) << "nothing on roughing_planner/markers";
  ASSERT_FALSE(markers->markers.empty());
  EXPECT_EQ(markers->markers.front().action, visualization_msgs::Marker::DELETEALL);
  std::set<std::string> feed, rapid;
  int slabs = 0;
  for (const auto& m : markers->markers) {
    if (m.action != visualization_msgs::Marker::ADD) continue;
    EXPECT_EQ(m.header.frame_id, "part") << m.ns;
    EXPECT_FALSE(m.points.empty()) << m.ns;
    // Every namespace under the part id, so two parts never mix in rviz.
    ASSERT_EQ(m.ns.rfind(kPart + "/", 0), 0u) << m.ns << " is not in part " << kPart << "'s namespace";
    const std::string ns = m.ns.substr(kPart.size() + 1);
    if (ns.rfind("feed_", 0) == 0 || ns.rfind("rapid_", 0) == 0) {
      EXPECT_EQ(m.type, visualization_msgs::Marker::LINE_LIST) << m.ns;
      EXPECT_EQ(m.points.size() % 2, 0u) << m.ns;
      (ns[0] == 'f' ? feed : rapid).insert(ns);
    } else if (ns.rfind("slabs_", 0) == 0) {
      EXPECT_EQ(m.type, visualization_msgs::Marker::LINE_STRIP) << m.ns;
      EXPECT_EQ(m.points.size(), 5u) << m.ns;
      ++slabs;
    }
  }
  EXPECT_EQ(feed.size(), o.result.operations.size()) << "a feed_<i> marker per operation";
  EXPECT_EQ(feed.count("feed_0"), 1u);
  EXPECT_GE(rapid.size(), 1u) << "no rapid_<i> marker";
  EXPECT_GE(slabs, 1) << "no slabs_<k> marker";
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_roughing_planner_node");
  ros::NodeHandle nh;
  the_client = std::make_unique<Client>("plan_roughing", true);  // its own spin thread: feedback while we wait
  const int failed = RUN_ALL_TESTS();
  the_client.reset();
  return failed;
}
