// part_server_node over ROS: loads, serves, rejects bad requests with a reason, and stays up.
#include <gtest/gtest.h>

#include <cmath>
#include <ros/ros.h>
#include <ros/topic.h>

#include <art2part/GetPart.h>
#include <art2part/ListParts.h>
#include <art2part/LoadPart.h>
#include <art2part/LoadedPart.h>

#include "../src/nodes/part_conversions.h"
#include "art2part/geometry/mesh_io.h"
#include "test_meshes.h"

using namespace art2part;

namespace {

const std::string kExample = std::string(ART2PART_SOURCE_DIR) + "/examples/nist_ctc_01_asme1_rd.stp";

LoadPart::Response load(const std::string& path, const std::string& id = "", const std::string& units = "") {
  LoadPart srv;
  srv.request.path = path;
  srv.request.part_id = id;
  srv.request.units = units;
  EXPECT_TRUE(ros::service::call("load_part", srv)) << "the service itself failed: the node died?";
  return srv.response;
}

}  // namespace

TEST(PartServer, LoadsServesAndSurvivesBadRequests) {
  ASSERT_TRUE(ros::service::waitForService("load_part", ros::Duration(60)));

  const LoadPart::Response ok = load(kExample, "ctc1");
  ASSERT_TRUE(ok.success) << ok.message;
  EXPECT_EQ(ok.part_id, "ctc1");
  EXPECT_EQ(ok.summary.planes + ok.summary.cylinders + ok.summary.cones, 139u);
  EXPECT_TRUE(ok.summary.closed);
  EXPECT_NEAR(ok.summary.box_max.x - ok.summary.box_min.x, 0.8, 1e-3);  // metres on the wire

  // Bad requests: a reason, and the node answers the next one.
  for (const std::string& bad : {std::string("/nonexistent/part.stl"), std::string(ART2PART_SOURCE_DIR) + "/package.xml",
                                 std::string(ART2PART_SOURCE_DIR)}) {
    const LoadPart::Response r = load(bad);
    EXPECT_FALSE(r.success) << bad;
    EXPECT_FALSE(r.message.empty());
  }
  EXPECT_FALSE(load(kExample, "x", "furlongs").success);

  // Meshes that are files of the right kind but not parts: NaN, a size that says metres, zero size.
  const std::string dir = test::tempDir();
  Mesh nan = test::box(Vec3(0, 0, 0), Vec3(10, 10, 10));
  nan.vertices[2].x() = std::nan("");
  writeBinaryStl(nan, dir + "/nan.stl");
  writeBinaryStl(test::box(Vec3(0, 0, 0), Vec3(0.1, 0.05, 0.02)), dir + "/metres.stl");
  writeBinaryStl(test::box(Vec3(3, 3, 3), Vec3(3, 3, 3)), dir + "/point.stl");
  for (const auto& [file, reason] : {std::pair<std::string, std::string>{"nan.stl", "not a finite number"},
                                     {"metres.stl", "metres"},
                                     {"point.stl", "zero size"}}) {
    const LoadPart::Response r = load(dir + "/" + file);
    EXPECT_FALSE(r.success) << file;
    EXPECT_NE(r.message.find(reason), std::string::npos) << r.message;
  }
  LoadPart::Response metres = load(dir + "/metres.stl", "in-metres", "m");  // told the unit, it loads
  EXPECT_TRUE(metres.success) << metres.message;
  EXPECT_NEAR(metres.summary.box_max.x - metres.summary.box_min.x, 0.1, 1e-6);  // float32 in the STL

  GetPart get;
  get.request.part_id = "ctc1";
  ASSERT_TRUE(ros::service::call("get_part", get));
  ASSERT_TRUE(get.response.success) << get.response.message;
  const LoadedPart& msg = get.response.part;
  EXPECT_EQ(msg.triangle_face.size(), msg.mesh.triangles.size());
  EXPECT_EQ(msg.faces.size(), 139u);
  // The round trip back into the core gives the same closed part.
  const Part part = fromMsg(msg);
  EXPECT_TRUE(part.check.closed);
  EXPECT_NEAR(part.check.volume * 1e-9, ok.summary.volume, 1e-9);

  get.request.part_id = "no-such-part";
  ASSERT_TRUE(ros::service::call("get_part", get));
  EXPECT_FALSE(get.response.success);
  EXPECT_NE(get.response.message.find("no-such-part"), std::string::npos);

  // The latched topic carries the last good part.
  auto latched = ros::topic::waitForMessage<LoadedPart>("part", ros::Duration(10));
  ASSERT_TRUE(latched);
  EXPECT_EQ(latched->id, "in-metres");

  ListParts list;
  ASSERT_TRUE(ros::service::call("list_parts", list));
  EXPECT_EQ(list.response.part_ids, (std::vector<std::string>{"ctc1", "in-metres"}));
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_part_server");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
