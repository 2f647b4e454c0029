// verification_node over ROS (issue 5): verify_toolpaths passes a clean plan folder, catches a 0.05 mm dip as a gouge
// of its depth (success, not passed), refuses bad folders with a reason and keeps serving, and shows the remaining
// stock on verification_markers.
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <ros/topic.h>
#include <visualization_msgs/MarkerArray.h>

#include <art2part/VerifyToolpaths.h>

#include <nlohmann/json.hpp>

#include "art2part/geometry/mesh_io.h"
#include "art2part/tooling/tool.h"
#include "art2part/tooling/toolpath.h"
#include "test_meshes.h"

using namespace art2part;

namespace {

constexpr double kResolution = 0.25;  // mm: a few tens of thousands of rays on the block's stock
constexpr double kDip = 0.05;         // mm into the block's top

// The part: a 40 x 20 x 10 block at the origin (mm), as in test_simulation.cpp.
const Mesh kBlock = test::box(Vec3(0, 0, 0), Vec3(40, 20, 10));


CutterLocation at(MoveKind move, const Vec3& tip, const std::string& tool = "flat6") {
  CutterLocation c;
  c.tool = tool;
  c.move = move;
  c.tip = tip;
  c.axis = Vec3::UnitZ();
  return c;
}

// Down from a safe height at `from`, along to `to`, back up.
Toolpath pass(const Vec3& from, const Vec3& to, const std::string& tool = "flat6") {
  const double safe_z = 40;
  return {at(MoveKind::Rapid, Vec3(from.x(), from.y(), safe_z), tool), at(MoveKind::Feed, from, tool),
          at(MoveKind::Feed, to, tool), at(MoveKind::Feed, Vec3(to.x(), to.y(), safe_z), tool)};
}

// A plan folder: toolpaths.csv, tools.json and the part as binary STL (`part_name` in the folder).
std::string planFolder(const Toolpath& path, const std::string& part_name = "mesh.stl") {
  const std::string dir = test::tempDir();
  writeToolpathsCsv(path, dir + "/toolpaths.csv");
  writeToolsJson({test::flat6()}, dir + "/tools.json");
  writeBinaryStl(kBlock, dir + "/" + part_name);
  return dir;
}

// A pass over the top at the stock's top face (2 mm margin): cuts nothing of the part.
const std::string& cleanFolder() {
  static const std::string dir = planFolder(pass(Vec3(5, 10, 12), Vec3(35, 10, 12)));
  return dir;
}

// A pass kDip into the block's top.
const std::string& gougingFolder() {
  static const std::string dir = planFolder(pass(Vec3(10, 10, 10 - kDip), Vec3(30, 10, 10 - kDip)));
  return dir;
}

VerifyToolpaths::Request request(const std::string& folder) {
  VerifyToolpaths::Request req;
  req.folder = folder;
  req.resolution = kResolution;
  return req;
}

VerifyToolpaths::Response verify(const VerifyToolpaths::Request& req) {
  EXPECT_TRUE(ros::service::waitForService("verify_toolpaths", ros::Duration(60)));
  VerifyToolpaths srv;
  srv.request = req;
  EXPECT_TRUE(ros::service::call("verify_toolpaths", srv)) << "the node must answer, not die";
  return srv.response;
}

void expectClean(const VerifyToolpaths::Response& r) {
  ASSERT_TRUE(r.success) << r.message;
  EXPECT_TRUE(r.passed) << r.message;
  EXPECT_EQ(r.gouges, 0) << r.message;
  EXPECT_EQ(r.collisions, 0) << r.message;
  EXPECT_EQ(r.moves, 4);  // toolpath points (verify.cpp counts each)
  EXPECT_GT(r.leftover_volume_mm3, 0) << "the margin around the block is left";
  EXPECT_GT(r.seconds, 0);
}

}  // namespace

TEST(VerificationNode, CleanFolderPasses) {
  const VerifyToolpaths::Response r = verify(request(cleanFolder()));
  ASSERT_NO_FATAL_FAILURE(expectClean(r));
  ROS_INFO("verify_toolpaths: %s (%.2f s)", r.message.c_str(), r.seconds);
  // The whole report rides along, and agrees with the fields.
  const auto j = nlohmann::json::parse(r.report_json);
  for (const char* field : {"gouges", "worst_gouge_mm", "collisions", "leftover_volume_mm3", "leftover_max_mm"})
    EXPECT_TRUE(j.contains(field)) << field;
  EXPECT_EQ(j["gouges"].get<int>(), r.gouges);
  EXPECT_NEAR(j["leftover_max_mm"].get<double>(), r.leftover_max_mm, 0.01);
}

TEST(VerificationNode, PartFileNamedInTheRequest) {
  const std::string dir = planFolder(pass(Vec3(5, 10, 12), Vec3(35, 10, 12)), "block.stl");
  VerifyToolpaths::Request req = request(dir);
  const VerifyToolpaths::Response missing = verify(req);  // no mesh.stl in this folder
  EXPECT_FALSE(missing.success) << missing.message;
  EXPECT_NE(missing.message.find("mesh.stl"), std::string::npos) << missing.message;
  req.part_file = dir + "/block.stl";
  ASSERT_NO_FATAL_FAILURE(expectClean(verify(req)));
}

TEST(VerificationNode, DipIsAGougeOfItsDepth) {
  const VerifyToolpaths::Response r = verify(request(gougingFolder()));
  ASSERT_TRUE(r.success) << "a gouge is a finding, not an error: " << r.message;
  EXPECT_FALSE(r.passed) << r.message;
  EXPECT_GT(r.gouges, 0) << r.message;
  EXPECT_NEAR(r.worst_gouge_mm, kDip, 0.01) << r.message;
  EXPECT_EQ(r.collisions, 0) << r.message;
  const auto j = nlohmann::json::parse(r.report_json);
  EXPECT_FALSE(j["passed"].get<bool>());
  EXPECT_NEAR(j["worst_gouge_mm"].get<double>(), r.worst_gouge_mm, 1e-3);

  // A looser tolerance lets the same dip through.
  VerifyToolpaths::Request loose = request(gougingFolder());
  loose.tolerance = 0.1;
  const VerifyToolpaths::Response l = verify(loose);
  ASSERT_TRUE(l.success) << l.message;
  EXPECT_EQ(l.gouges, 0) << l.message;
}

TEST(VerificationNode, RefusesBadInputAndKeepsServing) {
  auto refused = [](const VerifyToolpaths::Request& req, const std::string& named) {
    const VerifyToolpaths::Response r = verify(req);
    EXPECT_FALSE(r.success) << "accepted: " << r.message;
    EXPECT_FALSE(r.passed);
    EXPECT_NE(r.message.find(named), std::string::npos) << "'" << r.message << "' should name " << named;
    EXPECT_TRUE(r.report_json.empty());
  };

  refused(request("/nonexistent-art2part-folder"), "/nonexistent-art2part-folder");
  refused(request(""), "folder");

  // Malformed toolpaths.csv.
  const std::string malformed = planFolder(pass(Vec3(5, 10, 12), Vec3(35, 10, 12)));
  test::writeText(malformed + "/toolpaths.csv", "op,setup,tool,move,x,y,z,i,j,k\n0,0,flat6,feed,1,2\n");
  refused(request(malformed), "toolpaths.csv");

  // A tool the path uses but tools.json lacks.
  refused(request(planFolder(pass(Vec3(5, 10, 12), Vec3(35, 10, 12), "ball6"))), "ball6");

  // Missing tools.json.
  const std::string no_tools = planFolder(pass(Vec3(5, 10, 12), Vec3(35, 10, 12)));
  std::remove((no_tools + "/tools.json").c_str());
  refused(request(no_tools), "tools.json");

  VerifyToolpaths::Request negative = request(cleanFolder());
  negative.resolution = -1;
  refused(negative, "resolution");

  // Still serving.
  ASSERT_NO_FATAL_FAILURE(expectClean(verify(request(cleanFolder()))));
}

TEST(VerificationNode, MarkersShowTheRemainingStockAndTheGouges) {
  const VerifyToolpaths::Response r = verify(request(gougingFolder()));
  ASSERT_TRUE(r.success) << r.message;
  // Latched: the last verification's markers, published before the service answered.
  const auto markers =
      ros::topic::waitForMessage<visualization_msgs::MarkerArray>("verification_markers", ros::Duration(15));
  ASSERT_TRUE(markers) << "nothing on verification_markers";
  ASSERT_FALSE(markers->markers.empty());
  EXPECT_EQ(markers->markers.front().action, visualization_msgs::Marker::DELETEALL);
  int surfaces = 0, gouge_lists = 0;
  // Namespaced by the plan folder's name (the part is the folder's mesh.stl), so two plans never mix in rviz.
  const std::string folder = gougingFolder(), prefix = folder.substr(folder.find_last_of('/') + 1) + "/";
  for (const auto& m : markers->markers) {
    if (m.action != visualization_msgs::Marker::ADD) continue;
    EXPECT_EQ(m.header.frame_id, "part");
    ASSERT_EQ(m.ns.rfind(prefix, 0), 0u) << m.ns << " is not in the namespace of " << prefix;
    if (m.type == visualization_msgs::Marker::TRIANGLE_LIST) {
      ++surfaces;
      ASSERT_GT(m.points.size(), 100u);
      EXPECT_EQ(m.points.size() % 3, 0u);
      EXPECT_EQ(m.colors.size(), m.points.size());
      // Metres: the stock is the block with 2 mm margins, (-2, -2, -2) .. (42, 22, 12) mm.
      for (const auto& p : m.points) {
        ASSERT_GE(p.x, -0.0021);
        ASSERT_LE(p.x, 0.0421);
        ASSERT_GE(p.y, -0.0021);
        ASSERT_LE(p.y, 0.0221);
        ASSERT_GE(p.z, -0.0021);
        ASSERT_LE(p.z, 0.0121);
      }
    }
    if (m.type == visualization_msgs::Marker::SPHERE_LIST && m.ns == prefix + "gouges") {
      ++gouge_lists;
      ASSERT_FALSE(m.points.empty());
      EXPECT_NEAR(m.points[0].z, (10 - kDip) * 1e-3, 2e-5) << "the deepest gouge, in metres";
      EXPECT_GT(m.scale.x, 0);
      EXPECT_LT(m.scale.x, 0.01) << "a sphere of a few mm, in metres";
    }
  }
  EXPECT_EQ(surfaces, 1);
  EXPECT_EQ(gouge_lists, 1);
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_verification_node");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
