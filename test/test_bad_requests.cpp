// Every bad request of issue 18's list against the running cell (bad_requests.test): paths outside the configured
// folders (`..`, /etc/shadow, links, output_dir elsewhere), refused with the same message whether the file exists or
// not and before anything is opened or made; NaN, infinity, negatives and metre unit slips in every numeric field;
// each refused with a reason. Then every node serves a good request, and every node's /diagnostics counts what it
// refused.
#include <actionlib/client/simple_action_client.h>
#include <diagnostic_msgs/DiagnosticArray.h>
#include <gtest/gtest.h>
#include <ros/ros.h>

#include <art2part/AnalyseVisibilityAction.h>
#include <art2part/FollowJointTrajectoryAction.h>
#include <art2part/LoadPart.h>
#include <art2part/PlanFinishingAction.h>
#include <art2part/PlanRoughingAction.h>
#include <art2part/PlanSetups.h>
#include <art2part/RunToolpaths.h>
#include <art2part/VerifyToolpaths.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <memory>
#include <mutex>

#include "art2part/geometry/mesh_io.h"
#include "art2part/tooling/tool.h"
#include "art2part/tooling/toolpath.h"
#include "test_meshes.h"

using namespace art2part;
namespace fs = std::filesystem;

namespace {

// bad_requests.test configures /art2part/part_folders = [examples, kRoot/parts] and /art2part/output_root =
// kRoot/plans; kRoot/outside is neither.
const fs::path kRoot = "/tmp/art2part_bad_requests";
const fs::path kParts = kRoot / "parts";
const fs::path kPlans = kRoot / "plans";
const fs::path kOutside = kRoot / "outside";
const std::string kPid = std::to_string(::getpid());
const double kNan = std::nan("");
const double kInf = std::numeric_limits<double>::infinity();
const std::string kOutsideParts = "path is outside the configured part folders";
const std::string kOutsidePlans = "path is outside the configured output folder";

template <class Action>
using Client = actionlib::SimpleActionClient<Action>;

std::unique_ptr<Client<AnalyseVisibilityAction>> visibility;
std::unique_ptr<Client<PlanRoughingAction>> roughing;
std::unique_ptr<Client<PlanFinishingAction>> finishing;
std::unique_ptr<Client<FollowJointTrajectoryAction>> controller;

// The message with `path` cut out: what must be the same for a file that exists and one that does not.
std::string without(const std::string& message, const std::string& path) {
  std::string out = message;
  for (std::size_t at; (at = out.find(path)) != std::string::npos;) out.erase(at, path.size());
  return out;
}

template <class Service>
typename Service::Response call(const std::string& name, const typename Service::Request& request) {
  Service srv;
  srv.request = request;
  EXPECT_TRUE(ros::service::call(name, srv)) << name << ": the service itself failed (the node died?)";
  return srv.response;
}

LoadPart::Response load(const std::string& path, double chordal_tolerance = 0, const std::string& id = "") {
  LoadPart::Request req;
  req.path = path;
  req.chordal_tolerance = chordal_tolerance;
  req.part_id = id;
  return call<LoadPart>("load_part", req);
}

template <class Action, class Goal>
auto run(Client<Action>& client, const Goal& goal, double timeout = 60) {
  client.sendGoal(goal);
  EXPECT_TRUE(client.waitForResult(ros::Duration(timeout))) << "no result: the node hangs or died";
  return client.getResult();
}

// A refused answer: success false and a message naming `named`.
#define EXPECT_REFUSED(response, named)                                                                  \
  do {                                                                                                   \
    const auto& r_ = (response);                                                                         \
    EXPECT_FALSE(r_.success) << "accepted: " << r_.message;                                             \
    EXPECT_NE(r_.message.find(named), std::string::npos) << "'" << r_.message << "' should name " << named; \
  } while (0)

Tool flatMill() {
  Tool t = test::flat6();
  t.feed_mm_min = 600;
  t.plunge_mm_min = 200;
  return t;
}

// A plan folder under the output root: one pass over a 40 x 20 x 10 block, its tool, the block as mesh.stl.
fs::path planFolder(const std::string& name) {
  const fs::path dir = kPlans / name;
  fs::create_directories(dir);
  Toolpath path;
  for (const Vec3& tip : {Vec3(5, 10, 40), Vec3(5, 10, 12), Vec3(35, 10, 12), Vec3(35, 10, 40)}) {
    CutterLocation c;
    c.tool = "flat6";
    c.move = tip.z() > 20 && path.empty() ? MoveKind::Rapid : MoveKind::Feed;
    c.tip = tip;
    c.axis = Vec3::UnitZ();
    path.push_back(c);
  }
  writeToolpathsCsv(path, (dir / "toolpaths.csv").string());
  writeToolsJson({flatMill()}, (dir / "tools.json").string());
  writeBinaryStl(test::box(Vec3(0, 0, 0), Vec3(40, 20, 10)), (dir / "mesh.stl").string());
  return dir;
}

class BadRequests : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    fs::create_directories(kParts);
    fs::create_directories(kOutside);
    writeBinaryStl(test::box(Vec3(0, 0, 0), Vec3(40, 20, 10)), (kParts / ("block_" + kPid + ".stl")).string());
    writeBinaryStl(test::box(Vec3(0, 0, 0), Vec3(40, 20, 10)), (kOutside / "secret.stl").string());
    fs::remove(kParts / ("link_out_" + kPid));
    fs::create_symlink(kOutside / "secret.stl", kParts / ("link_out_" + kPid));
    for (const char* service : {"load_part", "plan_setups", "verify_toolpaths", "run_program"})
      ASSERT_TRUE(ros::service::waitForService(service, ros::Duration(60))) << service;
    ASSERT_TRUE(visibility->waitForServer(ros::Duration(60)));
    ASSERT_TRUE(roughing->waitForServer(ros::Duration(60)));
    ASSERT_TRUE(finishing->waitForServer(ros::Duration(60)));
    ASSERT_TRUE(controller->waitForServer(ros::Duration(60)));
    const LoadPart::Response block = load((kParts / ("block_" + kPid + ".stl")).string(), 0, "block");
    ASSERT_TRUE(block.success) << block.message;
  }

  // What this run wrote: every entry whose name ends in its pid.
  static void TearDownTestSuite() {
    for (const fs::path& dir : {kParts, kPlans})
      for (const fs::directory_entry& entry : fs::directory_iterator(dir)) {
        const std::string stem = entry.path().stem().string();
        const std::string suffix = "_" + kPid;
        if (stem.size() > suffix.size() && stem.compare(stem.size() - suffix.size(), suffix.size(), suffix) == 0)
          fs::remove_all(entry.path());
      }
  }

  const std::string block_file = (kParts / ("block_" + kPid + ".stl")).string();
};

}  // namespace

TEST_F(BadRequests, PartPathsOutsideThePartFolders) {
  // /etc/shadow (exists) and a missing file beside it: refused alike, neither opened ("not a mesh") nor looked up.
  const LoadPart::Response shadow = load("/etc/shadow");
  const LoadPart::Response missing = load("/etc/no-such-part-" + kPid + ".stl");
  EXPECT_REFUSED(shadow, kOutsideParts);
  EXPECT_REFUSED(missing, kOutsideParts);
  EXPECT_EQ(without(shadow.message, "/etc/shadow"), without(missing.message, "/etc/no-such-part-" + kPid + ".stl"));
  for (const char* leak : {"mesh", "exist", "No such", "cannot", "permission", "read"})
    EXPECT_EQ(shadow.message.find(leak), std::string::npos) << shadow.message;

  // `..` out of a part folder, absolute and relative; a file beside the folders; a link from inside to outside.
  const std::string secret = (kOutside / "secret.stl").string();
  for (const std::string& path :
       {(kParts / ".." / "outside" / "secret.stl").string(), std::string("../../../../../etc/passwd"),
        (kParts / "no_such_dir" / ".." / ".." / "outside" / "secret.stl").string(), secret,
        (kParts / ("link_out_" + kPid)).string(), std::string("/etc/passwd"), std::string("/")})
    EXPECT_REFUSED(load(path), kOutsideParts);
  const LoadPart::Response secret_missing = load((kOutside / "nothing.stl").string());
  EXPECT_EQ(without(load(secret).message, secret),
            without(secret_missing.message, (kOutside / "nothing.stl").string()));
  EXPECT_REFUSED(load(""), "no path");

  // Inside the folders, through `..` that stays inside: loads.
  const LoadPart::Response inside = load((kParts / "no_such_dir" / ".." / ("block_" + kPid + ".stl")).string());
  EXPECT_TRUE(inside.success) << inside.message;
}

TEST_F(BadRequests, LoadPartNumbers) {
  EXPECT_REFUSED(load(block_file, kNan), "chordal_tolerance");
  EXPECT_REFUSED(load(block_file, -0.001), "chordal_tolerance");
  EXPECT_REFUSED(load(block_file, 0.1), "chordal_tolerance");  // 0.1 mm typed as metres
  EXPECT_REFUSED(load(block_file, kInf), "chordal_tolerance");
}

TEST_F(BadRequests, VisibilityNumbers) {
  auto refused = [](int level, int resolution, const std::string& named) {
    AnalyseVisibilityGoal g;
    g.part_id = "block";
    g.level = level;
    g.resolution = resolution;
    const auto r = run(*visibility, g);
    ASSERT_TRUE(r);
    EXPECT_REFUSED(*r, named);
  };
  refused(9, 0, "level");
  refused(-1, 0, "level");
  refused(1, -5, "resolution");
  refused(1, 1000000, "resolution");
}

TEST_F(BadRequests, SetupNumbers) {
  auto request = [] {
    PlanSetups::Request req;
    req.part_id = "block";
    req.level = 1;
    return req;
  };
  PlanSetups::Request req = request();
  req.max_tilt_deg = kNan;
  EXPECT_REFUSED(call<PlanSetups>("plan_setups", req), "max_tilt_deg");
  req.max_tilt_deg = 1.92;  // 110 deg in radians
  EXPECT_REFUSED(call<PlanSetups>("plan_setups", req), "max_tilt_deg");
  req = request();
  req.time_limit = -1;
  EXPECT_REFUSED(call<PlanSetups>("plan_setups", req), "time_limit");
  req.time_limit = kInf;
  EXPECT_REFUSED(call<PlanSetups>("plan_setups", req), "time_limit");
  req = request();
  req.level = 9;
  EXPECT_REFUSED(call<PlanSetups>("plan_setups", req), "level");
}

TEST_F(BadRequests, RoughingNumbersAndOutputDir) {
  auto goal = [] {
    PlanRoughingGoal g;
    g.part_id = "block";
    g.level = 1;
    return g;
  };
  auto refused = [](const PlanRoughingGoal& g, const std::string& named) {
    const auto r = run(*roughing, g);
    ASSERT_TRUE(r);
    EXPECT_REFUSED(*r, named);
  };
  PlanRoughingGoal g = goal();
  g.stepdown_m = 5;  // 5 m
  refused(g, "stepdown_m");
  g.stepdown_m = kNan;
  refused(g, "stepdown_m");
  g = goal();
  g.allowance_m = 0.3;  // 0.3 mm typed as metres
  refused(g, "allowance_m");
  g.allowance_m = -0.0003;
  refused(g, "allowance_m");
  g.allowance_m = kInf;
  refused(g, "allowance_m");
  g = goal();
  g.level = -2;
  refused(g, "level");

  // output_dir outside the output root: refused before the plan, and nothing made there.
  g = goal();
  for (const fs::path& dir : {kOutside / ("made_" + kPid), kPlans / ".." / "outside" / ("made_" + kPid),
                              fs::path("../outside/made_" + kPid), fs::path("/etc/art2part_" + kPid)}) {
    g.output_dir = dir.string();
    refused(g, kOutsidePlans);
    EXPECT_FALSE(fs::exists(kOutside / ("made_" + kPid))) << dir;
  }
}

TEST_F(BadRequests, FinishingNumbersAndOutputDir) {
  auto goal = [] {
    PlanFinishingGoal g;
    g.part_id = "block";
    g.level = 1;
    return g;
  };
  auto refused = [](const PlanFinishingGoal& g, const std::string& named) {
    const auto r = run(*finishing, g);
    ASSERT_TRUE(r);
    EXPECT_REFUSED(*r, named);
  };
  PlanFinishingGoal g = goal();
  g.allowance_m = 0.3;
  refused(g, "allowance_m");
  g = goal();
  g.scallop_m = kNan;
  refused(g, "scallop_m");
  g.scallop_m = -1e-5;
  refused(g, "scallop_m");
  g.scallop_m = 0.01;  // 10 mm
  refused(g, "scallop_m");
  g = goal();
  g.output_dir = (kOutside / ("made_" + kPid)).string();
  refused(g, kOutsidePlans);
  EXPECT_FALSE(fs::exists(kOutside / ("made_" + kPid)));
}

TEST_F(BadRequests, VerificationPathsAndNumbers) {
  const fs::path good = planFolder("verify_" + kPid);
  auto request = [&good](const std::string& folder) {
    VerifyToolpaths::Request req;
    req.folder = folder.empty() ? good.string() : folder;
    req.resolution = 0.5;
    return req;
  };
  // Folders outside the output root: existing and missing read alike.
  const VerifyToolpaths::Response etc = call<VerifyToolpaths>("verify_toolpaths", request("/etc"));
  const VerifyToolpaths::Response none = call<VerifyToolpaths>("verify_toolpaths", request("/no-such-folder-" + kPid));
  EXPECT_REFUSED(etc, kOutsidePlans);
  EXPECT_REFUSED(none, kOutsidePlans);
  EXPECT_EQ(without(etc.message, "/etc"), without(none.message, "/no-such-folder-" + kPid));
  EXPECT_REFUSED(call<VerifyToolpaths>("verify_toolpaths", request((kPlans / ".." / "outside").string())),
                 kOutsidePlans);
  EXPECT_REFUSED(call<VerifyToolpaths>("verify_toolpaths", request("../../../etc")), kOutsidePlans);

  // A part file outside: /etc/shadow and a missing one alike.
  VerifyToolpaths::Request req = request("");
  req.part_file = "/etc/shadow";
  const VerifyToolpaths::Response shadow = call<VerifyToolpaths>("verify_toolpaths", req);
  req.part_file = "/etc/no-such-part-" + kPid;
  const VerifyToolpaths::Response missing = call<VerifyToolpaths>("verify_toolpaths", req);
  EXPECT_REFUSED(shadow, "outside the configured part and output folders");
  EXPECT_REFUSED(missing, "outside the configured part and output folders");
  EXPECT_EQ(without(shadow.message, "/etc/shadow"), without(missing.message, "/etc/no-such-part-" + kPid));

  // Numbers in mm: NaN, negative, metres typed for mm, half a metre of margin.
  req = request("");
  req.resolution = kNan;
  EXPECT_REFUSED(call<VerifyToolpaths>("verify_toolpaths", req), "resolution");
  req.resolution = 0.0002;  // 0.2 mm typed as metres
  EXPECT_REFUSED(call<VerifyToolpaths>("verify_toolpaths", req), "resolution");
  req = request("");
  req.tolerance = -1;
  EXPECT_REFUSED(call<VerifyToolpaths>("verify_toolpaths", req), "tolerance");
  req = request("");
  req.stock_margin = 500;
  EXPECT_REFUSED(call<VerifyToolpaths>("verify_toolpaths", req), "stock_margin");
}

TEST_F(BadRequests, RunProgramPathsAndNumbers) {
  const fs::path good = planFolder("run_" + kPid);
  RunToolpaths::Request req;
  req.folder = "/etc";
  const RunToolpaths::Response etc = call<RunToolpaths>("run_program", req);
  req.folder = "/no-such-plan-" + kPid;
  const RunToolpaths::Response none = call<RunToolpaths>("run_program", req);
  EXPECT_REFUSED(etc, kOutsidePlans);
  EXPECT_REFUSED(none, kOutsidePlans);
  EXPECT_EQ(without(etc.message, "/etc"), without(none.message, "/no-such-plan-" + kPid));
  req.folder = (kPlans / ".." / "outside").string();
  EXPECT_REFUSED(call<RunToolpaths>("run_program", req), kOutsidePlans);

  req.folder = good.string();
  for (double rate : {kNan, -5.0, kInf, 1e7}) {
    req.rate = rate;
    const RunToolpaths::Response r = call<RunToolpaths>("run_program", req);
    EXPECT_REFUSED(r, "rate");
    EXPECT_FALSE(r.sent) << "a refused program must not reach the controller";
  }
}

// The controller's goal: tolerances NaN, negative, or in mm where metres are meant; rejected before a joint moves.
TEST_F(BadRequests, ControllerTolerances) {
  FollowJointTrajectoryGoal goal;
  goal.trajectory.joint_names = {"X"};
  goal.trajectory.points.resize(1);
  goal.trajectory.points[0].positions = {0.0};
  goal.trajectory.points[0].time_from_start = ros::Duration(1.0);
  for (const auto& [path, end] : {std::pair(kNan, 0.0), std::pair(-0.001, 0.0), std::pair(0.0, 5.0)}) {
    goal.path_tolerance = {path};
    goal.goal_tolerance = {end};
    const auto r = run(*controller, goal);
    ASSERT_TRUE(r);
    EXPECT_EQ(r->error_code, FollowJointTrajectoryResult::INVALID_GOAL) << r->error_string;
    EXPECT_NE(r->error_string.find("tolerance"), std::string::npos) << r->error_string;
  }
}

// After all of the above: every node serves a good request, and /diagnostics shows each node with what it refused.
TEST_F(BadRequests, ZEveryNodeStillServes) {
  std::mutex mutex;
  std::map<std::string, diagnostic_msgs::DiagnosticStatus> statuses;
  ros::NodeHandle nh;
  ros::Subscriber sub = nh.subscribe<diagnostic_msgs::DiagnosticArray>(
      "/diagnostics", 100, [&](const diagnostic_msgs::DiagnosticArray::ConstPtr& msg) {
        std::lock_guard<std::mutex> lock(mutex);
        for (const auto& s : msg->status) statuses[s.name] = s;
      });

  const LoadPart::Response loaded = load(block_file, 0, "block");
  EXPECT_TRUE(loaded.success) << loaded.message;

  AnalyseVisibilityGoal v;
  v.part_id = "block";
  v.level = 1;
  const auto seen = run(*visibility, v);
  ASSERT_TRUE(seen);
  EXPECT_TRUE(seen->success) << seen->message;

  PlanSetups::Request s;
  s.part_id = "block";
  s.level = 1;
  const PlanSetups::Response setups = call<PlanSetups>("plan_setups", s);
  EXPECT_TRUE(setups.success) << setups.message;

  PlanRoughingGoal r;
  r.part_id = "block";
  r.level = 1;
  r.output_dir = "rough_" + kPid;  // relative: under the output root
  const auto rough = run(*roughing, r);
  ASSERT_TRUE(rough);
  EXPECT_TRUE(rough->success) << rough->message;
  EXPECT_TRUE(fs::exists(kPlans / ("rough_" + kPid) / "toolpaths.csv"));

  PlanFinishingGoal f;
  f.part_id = "block";
  f.level = 1;
  f.output_dir = (kPlans / ("finish_" + kPid)).string();
  const auto finish = run(*finishing, f, 120);
  ASSERT_TRUE(finish);
  EXPECT_TRUE(finish->success) << finish->message;
  EXPECT_TRUE(fs::exists(kPlans / ("finish_" + kPid) / "tools.json"));

  VerifyToolpaths::Request check;
  check.folder = planFolder("verify_good_" + kPid).string();
  check.resolution = 0.5;
  const VerifyToolpaths::Response verified = call<VerifyToolpaths>("verify_toolpaths", check);
  EXPECT_TRUE(verified.success) << verified.message;

  RunToolpaths::Request program;
  program.folder = "run_good_" + kPid;  // relative: under the output root
  planFolder(program.folder);
  program.wait = true;
  const RunToolpaths::Response ran = call<RunToolpaths>("run_program", program);
  EXPECT_TRUE(ran.success) << ran.message;

  // /diagnostics: one status per node, with its counts; part_server refused many load_part requests before.
  const ros::WallTime until = ros::WallTime::now() + ros::WallDuration(3);
  while (ros::WallTime::now() < until) ros::WallDuration(0.1).sleep();
  std::lock_guard<std::mutex> lock(mutex);
  for (const std::string node : {"part_server", "visibility", "setup_planner", "roughing_planner", "finishing_planner",
                                 "verification", "controller_bridge", "simulated_controller"}) {
    const auto it = statuses.find(node + ": requests");
    ASSERT_NE(it, statuses.end()) << "no /diagnostics status from " << node << " (" << statuses.size() << " statuses)";
    std::map<std::string, std::string> values;
    for (const auto& kv : it->second.values) values[kv.key] = kv.value;
    EXPECT_GT(std::stol(values["served"]), 0) << node;
    EXPECT_GT(std::stol(values["refused"]), 0) << node << ": " << it->second.message;
    EXPECT_EQ(values["state"], "idle") << node;
    EXPECT_EQ(it->second.level, diagnostic_msgs::DiagnosticStatus::OK) << node << ": " << it->second.message;
  }
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_bad_requests");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  visibility = std::make_unique<Client<AnalyseVisibilityAction>>("analyse_visibility", true);
  roughing = std::make_unique<Client<PlanRoughingAction>>("plan_roughing", true);
  finishing = std::make_unique<Client<PlanFinishingAction>>("plan_finishing", true);
  controller = std::make_unique<Client<FollowJointTrajectoryAction>>("follow_joint_trajectory", true);
  const int result = RUN_ALL_TESTS();
  visibility.reset();
  roughing.reset();
  finishing.reset();
  controller.reset();
  ros::shutdown();
  return result;
}
