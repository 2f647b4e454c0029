// finishing_planner over ROS: plan_finishing refuses bad goals with a reason and keeps serving; it finishes the
// featuretype part (faces accounted for, face milling and drilling among the operations, the toolpath and its axes),
// writes the file contracts when asked, publishes paths by operation kind and the faces' directions, and a cancel ends
// a goal preempted. One featuretype plan is made (the tests share it).
#include <actionlib/client/simple_action_client.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <ros/topic.h>
#include <visualization_msgs/MarkerArray.h>

#include <art2part/LoadPart.h>
#include <art2part/PlanFinishingAction.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <vector>

#include "art2part/geometry/part.h"
#include "art2part/tooling/tool.h"
#include "art2part/tooling/toolpath.h"

using namespace art2part;
using Client = actionlib::SimpleActionClient<PlanFinishingAction>;
namespace fs = std::filesystem;

namespace {

const std::string kPartFile = std::string(ART2PART_SHARED_PARTS) + "/featuretype.STEP";
const std::string kPart = "featuretype";
constexpr double kGoalTimeout = 300;  // seconds for one plan (about 15 s on 2 idle cores)

void loadPart() {
  static bool loaded = false;
  if (loaded) return;
  ASSERT_TRUE(ros::service::waitForService("load_part", ros::Duration(60)));
  LoadPart load;
  load.request.path = kPartFile;
  load.request.part_id = kPart;
  ASSERT_TRUE(ros::service::call("load_part", load));
  ASSERT_TRUE(load.response.success) << load.response.message;
  loaded = true;
}

std::unique_ptr<Client> the_client;
Client& client() { return *the_client; }

struct Outcome {
  bool finished = false;
  actionlib::SimpleClientGoalState state{actionlib::SimpleClientGoalState::LOST};
  PlanFinishingResult result;
  std::vector<PlanFinishingFeedback> feedback;
};

Outcome run(const PlanFinishingGoal& goal, bool cancel_on_feedback = false) {
  Outcome out;
  EXPECT_TRUE(client().waitForServer(ros::Duration(60))) << "no plan_finishing action server";
  struct Log {
    std::mutex mutex;
    std::vector<PlanFinishingFeedback> feedback;
  };
  auto log = std::make_shared<Log>();
  client().sendGoal(goal, Client::SimpleDoneCallback(), Client::SimpleActiveCallback(),
                    [log](const PlanFinishingFeedbackConstPtr& f) {
                      std::lock_guard<std::mutex> lock(log->mutex);
                      log->feedback.push_back(*f);
                    });
  if (cancel_on_feedback) {
    for (int i = 0; i < 600; ++i) {
      {
        std::lock_guard<std::mutex> lock(log->mutex);
        if (!log->feedback.empty() && log->feedback.back().stage == "visibility") break;
      }
      ros::Duration(0.05).sleep();
    }
    client().cancelGoal();
  }
  out.finished = client().waitForResult(ros::Duration(kGoalTimeout));
  EXPECT_TRUE(out.finished) << "no result within " << kGoalTimeout << " s";
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

PlanFinishingGoal goal(const std::string& part_id) {
  PlanFinishingGoal g;
  g.part_id = part_id;
  g.mode = "3axis";
  g.level = 4;
  return g;
}

std::string outputDir() {
  static const std::string dir =
      (fs::temp_directory_path() / ("art2part_finishing_node_" + std::to_string(::getpid()))).string();
  return dir;
}

const Outcome& fullPlan() {
  static Outcome outcome;
  static bool made = false;
  if (!made) {
    made = true;
    PlanFinishingGoal g = goal(kPart);
    g.output_dir = outputDir();
    outcome = run(g);
  }
  return outcome;
}

}  // namespace

TEST(FinishingPlannerNode, RefusesBadGoalsAndKeepsServing) {
  ASSERT_NO_FATAL_FAILURE(loadPart());
  auto refused = [](const PlanFinishingGoal& g, const std::string& named) {
    const Outcome o = run(g);
    ASSERT_TRUE(o.finished);
    EXPECT_EQ(o.state, actionlib::SimpleClientGoalState::ABORTED) << o.state.toString();
    EXPECT_FALSE(o.result.success) << "accepted: " << o.result.message;
    EXPECT_EQ(o.result.message.find('\n'), std::string::npos) << "one line: " << o.result.message;
    EXPECT_NE(o.result.message.find(named), std::string::npos) << "'" << o.result.message << "' should name " << named;
    EXPECT_TRUE(o.result.operations.empty());
  };
  refused(goal("nope"), "nope");
  PlanFinishingGoal g = goal(kPart);
  g.mode = "4axis";
  refused(g, "4axis");
  g = goal(kPart);
  g.level = 9;
  refused(g, "level");
  g = goal(kPart);
  g.allowance_m = 0.3;  // mm typed as metres
  refused(g, "allowance_m");
  g = goal(kPart);
  g.scallop_m = std::nan("");
  refused(g, "scallop_m");
  g = goal(kPart);
  g.scallop_m = -1e-5;
  refused(g, "scallop_m");
  // Still serving.
  const Outcome& o = fullPlan();
  ASSERT_TRUE(o.finished);
  EXPECT_TRUE(o.result.success) << o.result.message;
}

TEST(FinishingPlannerNode, FinishesEveryFaceOrSaysWhy) {
  ASSERT_NO_FATAL_FAILURE(loadPart());
  const Outcome& o = fullPlan();
  ASSERT_TRUE(o.finished);
  ASSERT_EQ(o.state, actionlib::SimpleClientGoalState::SUCCEEDED) << o.result.message;
  const PlanFinishingResult& r = o.result;
  ROS_INFO("plan_finishing: %s (%.1f s)", r.message.c_str(), r.seconds);
  const Part part = art2part::loadPart(kPartFile);
  ASSERT_EQ(r.faces.size(), part.faces.size());
  int finished = 0;
  for (std::size_t i = 0; i < r.faces.size(); ++i) {
    const FaceFinishing& f = r.faces[i];
    EXPECT_EQ(f.face, static_cast<int>(i));
    EXPECT_TRUE(f.status == "finished" || f.status == "partial" || f.status == "unmachinable") << f.status;
    if (f.status != "finished") {
      EXPECT_FALSE(f.reason.empty()) << "face " << i << " " << f.status << " without a reason";
    }
    if (f.status == "finished") {
      ++finished;
      EXPECT_FALSE(f.operations.empty()) << "face " << i;
      EXPECT_FALSE(f.tools.empty()) << "face " << i;
      for (int op : f.operations) EXPECT_LT(op, static_cast<int>(r.operations.size())) << "face " << i;
    }
  }
  EXPECT_GT(finished, static_cast<int>(r.faces.size()) / 2);
  std::set<std::string> kinds;
  uint32_t next = 0;
  for (const MachiningOperation& op : r.operations) {
    kinds.insert(op.kind);
    EXPECT_EQ(op.first_point, next);
    next += op.points;
  }
  EXPECT_EQ(next, r.tips.size());
  ASSERT_EQ(r.axes.size(), r.tips.size());
  ASSERT_EQ(r.moves.size(), r.tips.size());
  for (const auto& a : r.axes) EXPECT_NEAR(std::sqrt(a.x * a.x + a.y * a.y + a.z * a.z), 1.0, 1e-6);
  EXPECT_TRUE(kinds.count("face_mill")) << "no face milling";
  EXPECT_TRUE(kinds.count("drill")) << "featuretype's letter-H holes are drilled";
  EXPECT_GT(r.holes_drilled, 0u);
  // Feedback of the finishing stage, with a message.
  bool finishing = false;
  for (const PlanFinishingFeedback& f : o.feedback) finishing = finishing || (f.stage == "finishing" && !f.message.empty());
  EXPECT_TRUE(finishing);
  // The file contracts: the same points in mm.
  const Toolpath csv = readToolpathsCsv(outputDir() + "/toolpaths.csv");
  ASSERT_EQ(csv.size(), r.tips.size());
  for (std::size_t j = 0; j < csv.size(); j += std::max<std::size_t>(1, csv.size() / 100))
    EXPECT_NEAR(csv[j].tip.z(), 1e3 * r.tips[j].z, 1e-5) << "point " << j;
  std::set<std::string> used, listed;
  for (const MachiningOperation& op : r.operations) used.insert(op.tool);
  for (const Tool& t : readToolsJson(outputDir() + "/tools.json")) listed.insert(t.id);
  EXPECT_EQ(listed, used);
  std::error_code ignored;
  fs::remove_all(outputDir(), ignored);
}

TEST(FinishingPlannerNode, PublishesPathsByKindAndFaceDirections) {
  ASSERT_NO_FATAL_FAILURE(loadPart());
  ASSERT_TRUE(fullPlan().result.success);
  const auto markers =
      ros::topic::waitForMessage<visualization_msgs::MarkerArray>("finishing_planner/markers", ros::Duration(15));
  ASSERT_TRUE(markers);
  ASSERT_FALSE(markers->markers.empty());
  EXPECT_EQ(markers->markers.front().action, visualization_msgs::Marker::DELETEALL);
  std::set<std::string> ns;
  int arrows = 0;
  for (const auto& m : markers->markers) {
    if (m.action != visualization_msgs::Marker::ADD) continue;
    // Every namespace under the part id, so two parts never mix in rviz.
    ASSERT_EQ(m.ns.rfind(kPart + "/", 0), 0u) << m.ns << " is not in part " << kPart << "'s namespace";
    ns.insert(m.ns.substr(kPart.size() + 1));
    if (m.ns == kPart + "/face_directions") {
      EXPECT_EQ(m.type, visualization_msgs::Marker::ARROW);
      EXPECT_EQ(m.points.size(), 2u);
      ++arrows;
    } else {
      EXPECT_EQ(m.type, visualization_msgs::Marker::LINE_LIST) << m.ns;
      EXPECT_EQ(m.points.size() % 2, 0u) << m.ns;
    }
  }
  EXPECT_TRUE(ns.count("finishing_face_mill"));
  EXPECT_TRUE(ns.count("finishing_drill"));
  EXPECT_GT(arrows, 0);
}

TEST(FinishingPlannerNode, CancelEndsTheGoalPreempted) {
  ASSERT_NO_FATAL_FAILURE(loadPart());
  const Outcome o = run(goal(kPart), true);
  ASSERT_TRUE(o.finished);
  EXPECT_EQ(o.state, actionlib::SimpleClientGoalState::PREEMPTED) << o.state.toString() << ": " << o.result.message;
  EXPECT_FALSE(o.result.success);
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_finishing_planner_node");
  ros::NodeHandle nh;
  the_client = std::make_unique<Client>("plan_finishing", true);
  const int failed = RUN_ALL_TESTS();
  the_client.reset();
  return failed;
}
