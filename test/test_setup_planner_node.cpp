// setup_planner over ROS: plan_setups shares out the triangles of CTC 1 among setups, publishes their frames on tf2
// and markers for rviz, plans the same on an analyse_visibility result as in-process, refuses bad requests with a
// reason and keeps serving.
#include <actionlib/client/simple_action_client.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <ros/topic.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>
#include <visualization_msgs/MarkerArray.h>

#include <art2part/AnalyseVisibilityAction.h>
#include <art2part/LoadPart.h>
#include <art2part/PlanSetups.h>

#include <algorithm>
#include <cmath>

using namespace art2part;
using Client = actionlib::SimpleActionClient<AnalyseVisibilityAction>;

namespace {

const std::string kExample = std::string(ART2PART_SOURCE_DIR) + "/examples/nist_ctc_01_asme1_rd.stp";
const std::string kPart = "ctc1";
constexpr int kLevel = 2;
constexpr double kTimeLimit = 20;  // generous, so that both plans of a comparison prove their minimum

int triangle_count = 0;

void loadPart() {
  if (triangle_count > 0) return;
  ASSERT_TRUE(ros::service::waitForService("load_part", ros::Duration(60)));
  ASSERT_TRUE(ros::service::waitForService("plan_setups", ros::Duration(60)));
  LoadPart load;
  load.request.path = kExample;
  load.request.part_id = kPart;
  ASSERT_TRUE(ros::service::call("load_part", load));
  ASSERT_TRUE(load.response.success) << load.response.message;
  triangle_count = static_cast<int>(load.response.summary.triangles);
  ASSERT_GT(triangle_count, 0);
}

PlanSetups::Request request(const std::string& mode) {
  PlanSetups::Request req;
  req.part_id = kPart;
  req.mode = mode;
  req.level = kLevel;
  req.time_limit = kTimeLimit;
  return req;
}

PlanSetups::Response plan(const PlanSetups::Request& req) {
  PlanSetups srv;
  srv.request = req;
  EXPECT_TRUE(ros::service::call("plan_setups", srv)) << "the node must answer, not die";
  return srv.response;
}

// The 3-axis plan at kLevel, made once.
const PlanSetups::Response& threeAxis() {
  static PlanSetups::Response response;
  static bool made = false;
  if (!made) {
    response = plan(request("3axis"));
    made = true;
  }
  return response;
}

double norm(const geometry_msgs::Vector3& v) { return std::sqrt(v.x * v.x + v.y * v.y + v.z * v.z); }

// The z axis of a pose's rotation.
geometry_msgs::Vector3 zAxis(const geometry_msgs::Quaternion& q) {
  geometry_msgs::Vector3 z;
  z.x = 2 * (q.x * q.z + q.w * q.y);
  z.y = 2 * (q.y * q.z - q.w * q.x);
  z.z = 1 - 2 * (q.x * q.x + q.y * q.y);
  return z;
}

// What every successful plan of CTC 1 must satisfy.
void expectSoundPlan(const PlanSetups::Response& r) {
  ASSERT_TRUE(r.success) << r.message;
  ROS_INFO("plan_setups: %s", r.message.c_str());
  ASSERT_GE(r.setups.size(), 1u) << r.message;
  std::vector<int> owner(triangle_count, -1);
  for (std::size_t k = 0; k < r.setups.size(); ++k) {
    const MachiningSetup& s = r.setups[k];
    EXPECT_EQ(s.id, static_cast<int>(k));
    EXPECT_FALSE(s.triangles.empty()) << "setup " << k << " machines nothing";
    EXPECT_NEAR(norm(s.direction), 1.0, 1e-9) << "setup " << k;
    const geometry_msgs::Vector3 z = zAxis(s.frame.orientation);
    EXPECT_NEAR(z.x, s.direction.x, 1e-6) << "the frame's z is the setup direction (setup " << k << ")";
    EXPECT_NEAR(z.y, s.direction.y, 1e-6);
    EXPECT_NEAR(z.z, s.direction.z, 1e-6);
    for (int t : s.triangles) {
      ASSERT_GE(t, 0);
      ASSERT_LT(t, triangle_count);
      EXPECT_EQ(owner[t], -1) << "triangle " << t << " in setups " << owner[t] << " and " << k;
      owner[t] = static_cast<int>(k);
    }
  }
  for (uint32_t t : r.unmachinable_triangles) {
    ASSERT_LT(t, static_cast<uint32_t>(triangle_count));
    EXPECT_EQ(owner[t], -1) << "unmachinable triangle " << t << " assigned to setup " << owner[t];
    owner[t] = -2;
  }
  EXPECT_EQ(std::count(owner.begin(), owner.end(), -1), 0) << "every triangle: one setup, or unmachinable";
}

std::vector<int> directionIndices(const PlanSetups::Response& r) {
  std::vector<int> out;
  for (const MachiningSetup& s : r.setups) out.push_back(s.direction_index);
  return out;
}

std::vector<bool> specialFlags(const PlanSetups::Response& r) {
  std::vector<bool> out;
  for (const MachiningSetup& s : r.setups) out.push_back(s.special);
  return out;
}

}  // namespace

TEST(SetupPlannerNode, PlansCtc1In3AxisWithFramesAndMarkers) {
  ASSERT_NO_FATAL_FAILURE(loadPart());
  const PlanSetups::Response r = plan(request("3axis"));
  ASSERT_NO_FATAL_FAILURE(expectSoundPlan(r));
  EXPECT_EQ(r.mode, "3axis");
  EXPECT_GE(r.greedy_setups, r.setups.size()) << "the minimum cover is never worse than greedy";
  EXPECT_NE(r.message.find(kPart), std::string::npos) << r.message;

  // setup_0 on tf2 under part, where the response says. The listener starts after the plan, so the latched
  // /tf_static it gets on connecting already holds this plan (polled all the same).
  tf2_ros::Buffer buffer;
  tf2_ros::TransformListener listener(buffer);
  const geometry_msgs::Pose& pose = r.setups[0].frame;
  geometry_msgs::TransformStamped tf;
  bool same = false;
  for (ros::WallTime end = ros::WallTime::now() + ros::WallDuration(15); !same && ros::WallTime::now() < end;) {
    try {
      tf = buffer.lookupTransform("part", "setup_0", ros::Time(0), ros::Duration(1));
      const auto& q = tf.transform.rotation;
      const double dot = q.x * pose.orientation.x + q.y * pose.orientation.y + q.z * pose.orientation.z +
                         q.w * pose.orientation.w;
      same = std::abs(tf.transform.translation.x - pose.position.x) < 1e-6 &&
             std::abs(tf.transform.translation.y - pose.position.y) < 1e-6 &&
             std::abs(tf.transform.translation.z - pose.position.z) < 1e-6 && std::abs(std::abs(dot) - 1) < 1e-6;
    } catch (const tf2::TransformException& e) {
      ROS_INFO("waiting for setup_0: %s", e.what());
    }
    if (!same) ros::WallDuration(0.2).sleep();
  }
  EXPECT_TRUE(same) << "setup_0 on tf2 (" << tf.transform.translation.x << ", " << tf.transform.translation.y << ", "
                    << tf.transform.translation.z << ") differs from the response's pose (" << pose.position.x
                    << ", " << pose.position.y << ", " << pose.position.z << ") or is missing; frames:\n"
                    << buffer.allFramesAsString();

  // Markers: the old ones deleted first, an arrow and a label per setup, the part coloured per triangle.
  const auto markers = ros::topic::waitForMessage<visualization_msgs::MarkerArray>("setup_markers", ros::Duration(15));
  ASSERT_TRUE(markers) << "nothing on setup_markers";
  ASSERT_FALSE(markers->markers.empty());
  EXPECT_EQ(markers->markers.front().action, visualization_msgs::Marker::DELETEALL);
  int arrows = 0, labels = 0, surfaces = 0;
  for (const auto& m : markers->markers) {
    if (m.action != visualization_msgs::Marker::ADD) continue;
    if (m.type == visualization_msgs::Marker::ARROW) ++arrows;
    if (m.type == visualization_msgs::Marker::TEXT_VIEW_FACING && m.text.rfind("setup_", 0) == 0) ++labels;
    if (m.type == visualization_msgs::Marker::TRIANGLE_LIST) {
      ++surfaces;
      EXPECT_EQ(m.points.size(), 3u * triangle_count);
      EXPECT_EQ(m.colors.size(), m.points.size());
    }
  }
  EXPECT_GE(arrows, 1);
  EXPECT_EQ(arrows, static_cast<int>(r.setups.size()));
  EXPECT_EQ(labels, arrows);
  EXPECT_EQ(surfaces, 1);
}

TEST(SetupPlannerNode, FiveAxisNeedsNoMoreSetupsAndLeftoverFramesLeaveThePart) {
  ASSERT_NO_FATAL_FAILURE(loadPart());
  const PlanSetups::Response& three = threeAxis();
  ASSERT_NO_FATAL_FAILURE(expectSoundPlan(three));
  const PlanSetups::Response five = plan(request("5axis"));
  ASSERT_NO_FATAL_FAILURE(expectSoundPlan(five));
  EXPECT_EQ(five.mode, "5axis");
  EXPECT_LE(five.setups.size(), three.setups.size()) << five.message << " / " << three.message;
  EXPECT_LE(five.unmachinable_triangles.size(), three.unmachinable_triangles.size()) << "tilting reaches more";

  // A frame of the bigger 3-axis plan that the 5-axis plan does not have no longer hangs under part.
  if (five.setups.size() < three.setups.size()) {
    tf2_ros::Buffer buffer;
    tf2_ros::TransformListener listener(buffer);
    const std::string leftover = "setup_" + std::to_string(five.setups.size());
    bool gone = false;
    for (ros::WallTime end = ros::WallTime::now() + ros::WallDuration(15); !gone && ros::WallTime::now() < end;) {
      // Known to the buffer (the listener got /tf_static) but not connected to part.
      gone = buffer._frameExists(leftover) && !buffer.canTransform("part", leftover, ros::Time(0));
      if (!gone) ros::WallDuration(0.2).sleep();
    }
    EXPECT_TRUE(gone) << leftover << " unknown or still reachable from part after a plan with " << five.setups.size()
                      << " setups; frames:\n" << buffer.allFramesAsString();
  }
}

TEST(SetupPlannerNode, PlansTheSameOnAnAnalyseVisibilityResult) {
  ASSERT_NO_FATAL_FAILURE(loadPart());
  Client client("analyse_visibility", true);
  ASSERT_TRUE(client.waitForServer(ros::Duration(60)));
  AnalyseVisibilityGoal goal;  // the options plan_setups uses in-process: same level, special directions, ray, sides
  goal.part_id = kPart;
  goal.level = kLevel;
  client.sendGoal(goal);
  ASSERT_TRUE(client.waitForResult(ros::Duration(180)));
  const auto visibility = client.getResult();
  ASSERT_TRUE(visibility);
  ASSERT_TRUE(visibility->success) << visibility->message;
  ASSERT_EQ(static_cast<int>(visibility->triangle_count), triangle_count);

  PlanSetups::Request req = request("3axis");
  req.level = 0;  // ignored with directions
  req.directions = visibility->directions;
  req.bits = visibility->bits;
  req.special = visibility->special;
  const PlanSetups::Response given = plan(req);
  ASSERT_NO_FATAL_FAILURE(expectSoundPlan(given));
  const PlanSetups::Response& here = threeAxis();
  ASSERT_NO_FATAL_FAILURE(expectSoundPlan(here));
  EXPECT_EQ(given.setups.size(), here.setups.size())
      << "from the action: " << given.message << "; in-process: " << here.message;
  EXPECT_EQ(given.unmachinable_triangles.size(), here.unmachinable_triangles.size());
  EXPECT_NE(given.message.find("from the request"), std::string::npos) << given.message;

  // Without the special flags the node finds them on the part: the same plan.
  req.special.clear();
  const PlanSetups::Response unflagged = plan(req);
  ASSERT_NO_FATAL_FAILURE(expectSoundPlan(unflagged));
  EXPECT_EQ(directionIndices(unflagged), directionIndices(given));
  EXPECT_EQ(specialFlags(unflagged), specialFlags(given));
}

TEST(SetupPlannerNode, RefusesBadRequestsAndKeepsServing) {
  ASSERT_NO_FATAL_FAILURE(loadPart());
  auto refused = [](const PlanSetups::Request& req, const std::string& named) {
    const PlanSetups::Response r = plan(req);
    EXPECT_FALSE(r.success) << "accepted: " << r.message;
    EXPECT_NE(r.message.find(named), std::string::npos) << "'" << r.message << "' should name " << named;
    EXPECT_TRUE(r.setups.empty());
  };

  PlanSetups::Request req = request("3axis");
  req.part_id = "no_such_part";
  refused(req, "no_such_part");

  refused(request("4axis"), "4axis");

  req = request("5axis");
  req.max_tilt_deg = 200;
  refused(req, "max_tilt_deg");

  req = request("3axis");
  req.level = 9;
  refused(req, "level");

  req = request("3axis");
  geometry_msgs::Vector3 up;
  up.z = 1;
  req.directions = {up};
  req.bits.assign(static_cast<std::size_t>(triangle_count) + 1, 0xff);  // one byte a triangle, plus one
  refused(req, "bits");
  req.bits.clear();
  refused(req, "bits");

  req.bits.assign(static_cast<std::size_t>(triangle_count), 0x01);
  up.z = 2;  // not a unit vector
  req.directions = {up};
  refused(req, "direction");

  // Still serving.
  const PlanSetups::Response good = plan(request("3axis"));
  ASSERT_NO_FATAL_FAILURE(expectSoundPlan(good));
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_setup_planner_node");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
