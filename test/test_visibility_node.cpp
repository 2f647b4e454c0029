// visibility_node over ROS: the action returns a bit matrix that says what a machinist expects, bad goals abort with
// a reason, and the node keeps serving.
#include <actionlib/client/simple_action_client.h>
#include <gtest/gtest.h>
#include <ros/ros.h>

#include <art2part/AnalyseVisibilityAction.h>
#include <art2part/LoadPart.h>
#include <art2part/ShowCone.h>

#include <atomic>

using namespace art2part;
using Client = actionlib::SimpleActionClient<AnalyseVisibilityAction>;

namespace {

const std::string kExample = std::string(ART2PART_SOURCE_DIR) + "/examples/nist_ctc_01_asme1_rd.stp";

AnalyseVisibilityResultConstPtr run(Client& client, const AnalyseVisibilityGoal& goal, int* feedbacks = nullptr) {
  client.sendGoal(goal, Client::SimpleDoneCallback(), Client::SimpleActiveCallback(),
                  [feedbacks](const AnalyseVisibilityFeedbackConstPtr&) {
                    if (feedbacks) ++*feedbacks;
                  });
  EXPECT_TRUE(client.waitForResult(ros::Duration(180)));
  return client.getResult();
}

}  // namespace

TEST(VisibilityNode, AnalysesALoadedPartAndSurvivesBadGoals) {
  ASSERT_TRUE(ros::service::waitForService("load_part", ros::Duration(60)));
  Client client("analyse_visibility", true);
  ASSERT_TRUE(client.waitForServer(ros::Duration(60)));

  // No part yet: aborted with a reason.
  AnalyseVisibilityGoal goal;
  goal.part_id = "ctc1";
  goal.level = 2;
  auto r = run(client, goal);
  ASSERT_TRUE(r);
  EXPECT_FALSE(r->success);
  EXPECT_NE(r->message.find("ctc1"), std::string::npos) << r->message;

  LoadPart load;
  load.request.path = kExample;
  load.request.part_id = "ctc1";
  ASSERT_TRUE(ros::service::call("load_part", load));
  ASSERT_TRUE(load.response.success) << load.response.message;

  goal.backend = "warp-drive";
  r = run(client, goal);
  EXPECT_FALSE(r->success);
  EXPECT_NE(r->message.find("warp-drive"), std::string::npos);

  goal.backend = "";
  int feedbacks = 0;
  r = run(client, goal, &feedbacks);
  ASSERT_TRUE(r->success) << r->message;
  EXPECT_GT(feedbacks, 0);
  const int D = static_cast<int>(r->directions.size());
  const int T = static_cast<int>(r->triangle_count);
  EXPECT_GE(D, 64);  // 4 * 4^2 cells, special directions replace centroids or add to them
  ASSERT_EQ(r->bits.size(), static_cast<std::size_t>(T) * ((D + 7) / 8));
  ASSERT_EQ(r->cone_solid_angle.size(), static_cast<std::size_t>(T));

  // The top of the plate (z = 50 mm, the highest plane) is seen along +z, a special direction of the part.
  int up = -1;
  for (int d = 0; d < D; ++d)
    if (r->directions[d].z > 1 - 1e-12) up = d;
  ASSERT_GE(up, 0) << "the +z plane normal must be among the directions";
  EXPECT_TRUE(r->special[up]);
  const int bytes = (D + 7) / 8;
  int seen_up = 0;
  for (int t = 0; t < T; ++t) seen_up += (r->bits[t * bytes + up / 8] >> (up % 8)) & 1;
  EXPECT_GT(seen_up, 0);
  EXPECT_LT(seen_up, T);

  ShowCone cone;
  cone.request.triangle = T + 5;
  cone.request.face = -1;
  ASSERT_TRUE(ros::service::waitForService("show_cone", ros::Duration(30)));
  ASSERT_TRUE(ros::service::call("show_cone", cone));
  EXPECT_FALSE(cone.response.success);
  cone.request.triangle = 0;
  ASSERT_TRUE(ros::service::call("show_cone", cone));
  EXPECT_TRUE(cone.response.success) << cone.response.message;
  EXPECT_NEAR(cone.response.solid_angle, r->cone_solid_angle[0], 1e-12);
}

// A goal that comes while one runs waits for it: both end SUCCEEDED, in order (a stage node never lets one client's
// goal preempt another's: the cell supervisor's goal would fail).
TEST(VisibilityNode, ASecondGoalWaitsForTheRunningOne) {
  Client first("analyse_visibility", true), second("analyse_visibility", true);
  ASSERT_TRUE(first.waitForServer(ros::Duration(60)));
  ASSERT_TRUE(second.waitForServer(ros::Duration(60)));
  LoadPart load;
  load.request.path = kExample;
  load.request.part_id = "ctc1";
  ASSERT_TRUE(ros::service::call("load_part", load));
  AnalyseVisibilityGoal big, small;
  big.part_id = small.part_id = "ctc1";
  big.level = 4;
  small.level = 1;
  std::atomic<bool> running{false};
  first.sendGoal(big, Client::SimpleDoneCallback(), Client::SimpleActiveCallback(),
                 [&running](const AnalyseVisibilityFeedbackConstPtr& f) {
                   if (f->stage == "visibility") running = true;
                 });
  for (int i = 0; i < 600 && !running; ++i) ros::Duration(0.05).sleep();
  ASSERT_TRUE(running) << "the first goal never reported its analysis";
  second.sendGoal(small);
  ASSERT_TRUE(first.waitForResult(ros::Duration(300)));
  EXPECT_EQ(first.getState(), actionlib::SimpleClientGoalState::SUCCEEDED) << first.getState().toString();
  ASSERT_TRUE(first.getResult());
  EXPECT_TRUE(first.getResult()->success) << first.getResult()->message;
  EXPECT_GE(first.getResult()->directions.size(), 1024u) << "the first goal's own level";
  ASSERT_TRUE(second.waitForResult(ros::Duration(300)));
  EXPECT_EQ(second.getState(), actionlib::SimpleClientGoalState::SUCCEEDED) << second.getState().toString();
  ASSERT_TRUE(second.getResult());
  EXPECT_LT(second.getResult()->directions.size(), 1024u) << "the second goal's own level";
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_visibility_node");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
