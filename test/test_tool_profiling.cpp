// Profiling (thesis 4.1.3.2): the tool, shank and holder against the part with FCL, tilting away from collisions,
// then a smaller tool. Blocks built here; overlaps checked against exact geometry.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "art2part/roughing/tool_profiling.h"
#include "test_meshes.h"

using namespace art2part;

namespace {

constexpr double kPi = 3.14159265358979323846;

Tool mill(const std::string& id, ToolType type, double diameter, double flutes, double stickout,
          double holder_diameter = 32) {
  Tool t;
  t.id = id;
  t.type = type;
  t.diameter = diameter;
  t.corner_radius = type == ToolType::Ball ? diameter / 2 : 0;
  t.flute_length = flutes;
  t.shank_diameter = diameter;
  t.stickout = stickout;
  t.holder = {{holder_diameter, 40}};
  return t;
}

const Tool kFlat10 = mill("flat10", ToolType::Flat, 10, 22, 40);
const Tool kFlat20 = mill("flat20", ToolType::Flat, 20, 38, 60, 50);
const Tool kBall10 = mill("ball10", ToolType::Ball, 10, 20, 40);

double degrees(const Vec3& a, const Vec3& b) { return std::acos(std::clamp(a.dot(b), -1.0, 1.0)) * 180 / kPi; }

}  // namespace

TEST(PartCollider, FlutesAgainstAFloorAndAnEdge) {
  const PartCollider block(test::box(Vec3(0, 0, 0), Vec3(100, 100, 20)));
  // Above the top face, over its middle, margins 0: clear at 0.05 mm, not at 0.05 mm into it.
  EXPECT_TRUE(block.toolClear(kFlat10, {Vec3(50, 50, 20.05), Vec3::UnitZ()}, 0, 0));
  EXPECT_FALSE(block.toolClear(kFlat10, {Vec3(50, 50, 19.95), Vec3::UnitZ()}, 0, 0));
  // Beside the wall x = 100 with its tip below the top: clear when the flutes stay 0.05 mm off it.
  EXPECT_TRUE(block.toolClear(kFlat10, {Vec3(105.05, 50, 10), Vec3::UnitZ()}, 0, 0));
  EXPECT_FALSE(block.toolClear(kFlat10, {Vec3(104.95, 50, 10), Vec3::UnitZ()}, 0, 0));
  // The allowance is a margin: 0.2 mm off the wall is too close for 0.3 of allowance.
  EXPECT_FALSE(block.toolClear(kFlat10, {Vec3(105.2, 50, 10), Vec3::UnitZ()}, 0.3, 0));
  // A ball over the top edge (x = 100, z = 20) along the diagonal: its sphere clears the edge by +-0.05 mm.
  const Vec3 diagonal = Vec3(1, 0, 1).normalized();
  for (const double gap : {0.05, -0.05}) {
    const Vec3 centre = Vec3(100, 50, 20) + (5 + gap) * diagonal;
    EXPECT_EQ(block.toolClear(kBall10, {centre - 5 * Vec3::UnitZ(), Vec3::UnitZ()}, 0, 0), gap > 0) << gap;
  }
}

TEST(PartCollider, HolderUnderAnOverhangIsReportedAsHolder) {
  // A floor at z = 0..10 and, 30 mm above it, a roof over x < 60 (from a wall at x = 0..10).
  Mesh part = test::box(Vec3(0, 0, 0), Vec3(100, 100, 10));
  test::append(part, test::box(Vec3(0, 0, 10), Vec3(10, 100, 60)));
  test::append(part, test::box(Vec3(10, 0, 50), Vec3(60, 100, 60)));
  const PartCollider collider(part);
  // The flutes of the 10 mm tool at x = 70 clear everything; the holder (r = 16) at z = 10 + 40 reaches x = 54:
  // under the roof.
  std::vector<ProfileContact> contacts;
  EXPECT_FALSE(collider.toolClear(kFlat10, {Vec3(70, 50, 10.5), Vec3::UnitZ()}, 0.3, 0.5, &contacts));
  ASSERT_FALSE(contacts.empty());
  for (const ProfileContact& c : contacts) EXPECT_EQ(c.zone, ToolZone::Holder);
  EXPECT_TRUE(collider.toolClear(kFlat10, {Vec3(80, 50, 10.5), Vec3::UnitZ()}, 0.3, 0.5));
}

TEST(Profiling, TiltsAwayFromTheWallItLeansInto) {
  // A wall x <= 0 from z = 0 to 80 standing on a floor; the point 6 mm off its foot; the proposed axis leans 20
  // degrees into the wall: the holder hits it.
  Mesh part = test::box(Vec3(-50, -50, -10), Vec3(100, 50, 0));
  test::append(part, test::box(Vec3(-50, -50, 0), Vec3(0, 50, 80)));
  const PartCollider collider(part);
  const double a = 20 * kPi / 180;
  const ToolPose proposed{Vec3(5.5, 0, 0.3), Vec3(-std::sin(a), 0, std::cos(a))};
  EXPECT_FALSE(collider.toolClear(kFlat10, proposed, 0.3, 0.5));
  const Posture p = profileTool(collider, {&kFlat10}, proposed, Vec3::UnitZ());
  ASSERT_TRUE(p.live);
  EXPECT_GT(p.pose.axis.x(), -std::sin(a)) << "tilted back, away from the wall";
  EXPECT_TRUE(collider.toolClear(kFlat10, p.pose, 0.3, 0.5));
  // The tool is pushed along its axis so that its lowest point (grown by the 0.3 mm allowance) stays at the machining
  // point's height.
  const Vec3 push = p.pose.tip - proposed.tip;
  EXPECT_LT(push.cross(p.pose.axis).norm(), 1e-9);
  const double tilt = std::acos(p.pose.axis.z());
  EXPECT_NEAR(p.pose.tip.z() - 5.3 * std::sin(tilt), proposed.tip.z(), 1e-9);
  EXPECT_GT(tilt, 1e-3);
}

TEST(Profiling, ANarrowSlotTakesTheSmallerToolOrNone) {
  // A slot 12 mm wide and 30 deep in a block; the point at its bottom in the middle.
  auto slotted = [](double width) {
    Mesh part = test::box(Vec3(-50, -50, -40), Vec3(50, 50, -30));
    test::append(part, test::box(Vec3(-50, -50, -30), Vec3(-width / 2, 50, 0)));
    test::append(part, test::box(Vec3(width / 2, -50, -30), Vec3(50, 50, 0)));
    return part;
  };
  const PartCollider wide(slotted(12));
  const Posture p = profileTool(wide, {&kFlat20, &kFlat10}, {Vec3(0, 0, -29.7), Vec3::UnitZ()}, Vec3::UnitZ());
  ASSERT_TRUE(p.live);
  EXPECT_EQ(p.tool, 1) << "the 20 mm tool meets both walls: no tilt frees it";
  EXPECT_LT(degrees(p.pose.axis, Vec3::UnitZ()), 1e-9);
  const PartCollider narrow(slotted(6));
  EXPECT_FALSE(profileTool(narrow, {&kFlat20, &kFlat10}, {Vec3(0, 0, -29.7), Vec3::UnitZ()}, Vec3::UnitZ()).live);
}

TEST(PartCollider, AgreesWithAnExactCylinderBoxTest) {
  // A flat tool (cylinder of radius 5 from the tip up, shank the same, no holder reach) near a box, random upright
  // poses: FCL's verdict against the exact one (distance from the cylinder's axis segment to the box in plan and in
  // height), except within 0.01 mm of touching.
  const Box box{Vec3(0, 0, 0), Vec3(40, 30, 20)};
  const PartCollider collider(test::box(box.min, box.max));
  Tool t = mill("flat10", ToolType::Flat, 10, 22, 40);
  t.holder.clear();
  std::mt19937 random(3);
  std::uniform_real_distribution<double> x(-15, 55), y(-15, 45), z(-45, 30);
  int checked = 0;
  for (int i = 0; i < 400; ++i) {
    const Vec3 tip(x(random), y(random), z(random));
    // Plan distance from the axis to the box's rectangle; the cylinder spans z in [tip.z, tip.z + 40].
    const double dx = std::max({box.min.x() - tip.x(), 0.0, tip.x() - box.max.x()});
    const double dy = std::max({box.min.y() - tip.y(), 0.0, tip.y() - box.max.y()});
    const double plan = std::hypot(dx, dy) - 5;
    const double below = tip.z() - box.max.z(), above = box.min.z() - (tip.z() + 40);
    const double gap = std::max({plan, below, above});
    if (std::abs(gap) < 0.01) continue;
    EXPECT_EQ(collider.toolClear(t, {tip, Vec3::UnitZ()}, 0, 0), gap > 0) << tip.transpose() << " gap " << gap;
    ++checked;
  }
  EXPECT_GT(checked, 350);
}
