// Markers carry their part's id and clear the topic first, so two parts never mix in rviz (issue 18).
#include <gtest/gtest.h>

#include "../src/nodes/marker_helpers.h"

namespace art2part {
namespace {

visualization_msgs::MarkerArray twoPaths() {
  visualization_msgs::MarkerArray a;
  a.markers.push_back(deleteAllMarker("part"));
  a.markers.push_back(lineMarker("part", "feed_0", 0, visualization_msgs::Marker::LINE_LIST, 1.0));
  a.markers.push_back(lineMarker("part", "rapid_0", 0, visualization_msgs::Marker::LINE_LIST, 0.5));
  return a;
}

TEST(MarkerHelpers, ForPartClearsFirstAndNamespacesEveryMarker) {
  const visualization_msgs::MarkerArray a = forPart("ctc1", twoPaths());
  ASSERT_EQ(a.markers.size(), 3u);
  EXPECT_EQ(a.markers[0].action, visualization_msgs::Marker::DELETEALL);
  EXPECT_EQ(a.markers[0].header.frame_id, "part");
  EXPECT_EQ(a.markers[1].ns, "ctc1/feed_0");
  EXPECT_EQ(a.markers[2].ns, "ctc1/rapid_0");
  EXPECT_EQ(a.markers[1].action, visualization_msgs::Marker::ADD);
}

TEST(MarkerHelpers, ForPartKeepsOneDeleteAllWhereverTheOthersWere) {
  visualization_msgs::MarkerArray in = twoPaths();
  in.markers.push_back(deleteAllMarker("part"));  // a clear after the paths would wipe them in rviz
  const visualization_msgs::MarkerArray a = forPart("p", in);
  int clears = 0;
  for (const auto& m : a.markers) clears += m.action == visualization_msgs::Marker::DELETEALL;
  EXPECT_EQ(clears, 1);
  EXPECT_EQ(a.markers.front().action, visualization_msgs::Marker::DELETEALL);
  EXPECT_EQ(a.markers.back().ns, "p/rapid_0");
}

TEST(MarkerHelpers, ForPartOfNothingStillClears) {
  const visualization_msgs::MarkerArray a = forPart("p", {});
  ASSERT_EQ(a.markers.size(), 1u);
  EXPECT_EQ(a.markers[0].action, visualization_msgs::Marker::DELETEALL);
}

TEST(MarkerHelpers, PartIdsOfFilesAndFolders) {
  EXPECT_EQ(partIdOfFile("/parts/nist_ctc_01_asme1_rd.stp"), "nist_ctc_01_asme1_rd");
  EXPECT_EQ(partIdOfFile("/out/ctc1_plan/"), "ctc1_plan");
  EXPECT_EQ(partIdOfFile("block.stl"), "block");
  EXPECT_EQ(partNamespace("", "feed_0"), "feed_0");
  EXPECT_EQ(partNamespace("a", "feed_0"), "a/feed_0");
}

}  // namespace
}  // namespace art2part
