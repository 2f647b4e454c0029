// Surface finishing's order and links (surface_linking.cpp): links stay down where the clearance maps prove them
// clear, waterline contours go down one feature before crossing to the next, and an open contour is cut from its
// nearer end; every path judged by the simulation.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include <BRepAlgoAPI_Fuse.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCone.hxx>
#include <BRepPrimAPI_MakeSphere.hxx>
#include <gp_Ax2.hxx>
#include <gp_Pnt.hxx>

#include "art2part/finishing/surface_finishing.h"
#include "art2part/setup/setup_plan.h"
#include "art2part/simulation/verify.h"
#include "test_solids.h"
#include "test_tools.h"

using namespace art2part;
using test::ball6;
using test::facesOfType;

namespace {

Part stepPart(const TopoDS_Shape& shape, const std::string& name) {
  LoadOptions options;
  options.chordal_tolerance = 0.01;
  return test::stepPart(shape, name, options);
}

// Two domes of radius 8 on one 140 x 40 x 10 block, 100 mm apart, grown by `grow`.
TopoDS_Shape twoDomes(double grow) {
  TopoDS_Shape shape =
      BRepPrimAPI_MakeBox(gp_Pnt(-20 - grow, -20 - grow, -grow), gp_Pnt(120 + grow, 20 + grow, 10 + grow)).Shape();
  for (double x : {0.0, 100.0})
    shape = BRepAlgoAPI_Fuse(shape, BRepPrimAPI_MakeSphere(gp_Pnt(x, 0, 10), 8 + grow, 0, M_PI / 2).Shape()).Shape();
  return shape;
}

}  // namespace

TEST(SurfaceFinishing, LinksStayDownWhereTheMapsProveThemClearHoweverLong) {
  // From one dome to the other is 84 mm of flat block (14 diameters): the link passes over it at the height the
  // clearance maps prove clear, not over the clearance plane, and the simulation finds it clear.
  const Part part = stepPart(twoDomes(0), "two_domes");
  const Part stock = stepPart(twoDomes(0.3), "two_domes_stock");
  const std::vector<int> spheres = facesOfType(part, SurfaceType::Sphere);
  ASSERT_EQ(spheres.size(), 2u);
  const Tool tool = ball6();
  const SetupFrame frame = setupFrame(part, Vec3::UnitZ());
  const SurfaceFinishingResult r = finishSurfaces3Axis(part, spheres, frame, tool, 0, SurfaceFinishingOptions{});
  ASSERT_GT(r.path.size(), 100u);
  EXPECT_EQ(r.retracts, 0);
  double longest = 0;  // the longest rapid across, and how high it went
  double its_height = 0;
  for (std::size_t i = 1; i < r.path.size(); ++i) {
    const Vec3 d = r.path[i].tip - r.path[i - 1].tip;
    if (r.path[i].move == MoveKind::Rapid && std::hypot(d.x(), d.y()) > longest)
      longest = std::hypot(d.x(), d.y()), its_height = r.path[i].tip.z();
  }
  EXPECT_GT(longest, 60.0) << "the link from dome to dome";
  EXPECT_LT(its_height, 18 + SurfaceFinishingOptions{}.clearance - 1) << "under the clearance plane";
  VerifyOptions vo;
  vo.stock_mesh = &stock.mesh;
  vo.resolution = 0.3;
  const VerificationReport report = verifyToolpath(part.mesh, part.triangle_face, r.path, {tool}, vo);
  EXPECT_EQ(report.gouges, 0);
  EXPECT_EQ(report.collisions, 0);
}

TEST(SurfaceFinishing, WaterlineGoesDownOneFeatureBeforeCrossingToTheNext) {
  // The two domes' walls take waterline contours at the same levels: level by level the tool crossed the 84 mm
  // between them at every level; nearest contour next, it finishes one dome's wall before the other's.
  const Part part = stepPart(twoDomes(0), "two_domes");
  const std::vector<int> spheres = facesOfType(part, SurfaceType::Sphere);
  const SurfaceFinishingResult r =
      finishSurfaces3Axis(part, spheres, setupFrame(part, Vec3::UnitZ()), ball6(), 0, SurfaceFinishingOptions{});
  ASSERT_GT(r.waterline_levels, 5);
  int crossings = 0;
  for (std::size_t i = 1; i < r.path.size(); ++i)
    crossings += (r.path[i].tip.x() > 50) != (r.path[i - 1].tip.x() > 50);
  std::printf("%d waterline levels, %d contours; %d crossings from dome to dome\n", r.waterline_levels,
              r.waterline_contours, crossings);
  EXPECT_LE(crossings, 3) << "one for the waterline, one or two for the raster rows";
}

namespace {

// A 60 x 40 x 20 block with half a cone frustum standing on its +y side, as tall as the block, its wall sloping at 70
// degrees (radius 15 at the foot, 7.7 at the top), grown by `grow`: the wall takes waterline contours that end where
// it meets the block's side (open ones).
TopoDS_Shape halfCone(double grow) {
  const TopoDS_Shape block =
      BRepPrimAPI_MakeBox(gp_Pnt(-30 - grow, -20 - grow, -grow), gp_Pnt(30 + grow, 20 + grow, 20 + grow)).Shape();
  const double foot = 15, top = foot - 20 / std::tan(70 * M_PI / 180);
  const TopoDS_Shape boss = BRepPrimAPI_MakeCone(gp_Ax2(gp_Pnt(0, 20, -grow), gp_Dir(0, 0, 1), gp_Dir(1, 0, 0)),
                                                 foot + grow, top + grow, 20 + 2 * grow, M_PI)
                                .Shape();
  return BRepAlgoAPI_Fuse(block, boss).Shape();
}

struct WallFigures {
  double rapid_mm = 0;
  double climb_mm = 0, conventional_mm = 0;  // feed along the wall with the boss on the right of the motion, or left
};

// The cone's axis stands at (0, 20): a feed at one height along the wall has it on its right when the turn from the
// motion to the axis is clockwise.
WallFigures wallFigures(const Toolpath& path) {
  WallFigures f;
  for (std::size_t i = 1; i < path.size(); ++i) {
    const Vec3 a = path[i - 1].tip, b = path[i].tip, d = b - a;
    if (path[i].move == MoveKind::Rapid) {
      f.rapid_mm += d.norm();
      continue;
    }
    if (std::abs(d.z()) > 1e-6 || a.y() < 20.5 || std::hypot(d.x(), d.y()) < 1e-6) continue;  // along the wall only
    const Vec3 to_axis = Vec3(0, 20, a.z()) - a;
    (d.x() * to_axis.y() - d.y() * to_axis.x() < 0 ? f.climb_mm : f.conventional_mm) += std::hypot(d.x(), d.y());
  }
  return f;
}

}  // namespace

TEST(SurfaceFinishing, AnOpenWaterlineContourIsCutFromItsNearerEnd) {
  // The cone's wall, 20 mm tall, takes a contour every half millimetre or so, each a half circle of 24 to 47 mm
  // ending on the block's side. Climb only, each one starts at the same end: the tool moves back 15 to 30 mm at every
  // level. Either way, the next level starts where the last one ended, a feed down the wall away.
  const Part part = stepPart(halfCone(0), "half_cone");
  const Part stock = stepPart(halfCone(0.3), "half_cone_stock");
  const std::vector<int> walls = facesOfType(part, SurfaceType::Cone);
  ASSERT_EQ(walls.size(), 1u);
  const Tool tool = ball6();
  const SetupFrame frame = setupFrame(part, Vec3::UnitZ());
  SurfaceFinishingOptions climb_only;
  climb_only.waterline_both_ways = false;
  const SurfaceFinishingResult either = finishSurfaces3Axis(part, walls, frame, tool, 0, SurfaceFinishingOptions{});
  const SurfaceFinishingResult climb = finishSurfaces3Axis(part, walls, frame, tool, 0, climb_only);
  const WallFigures e = wallFigures(either.path), c = wallFigures(climb.path);
  std::printf("%d levels, %d contours; climb only: %.0f mm rapid, %.0f mm climb, %.0f conventional; either way: %.0f "
              "mm rapid, %.0f climb, %.0f conventional\n",
              either.waterline_levels, either.waterline_contours, c.rapid_mm, c.climb_mm, c.conventional_mm,
              e.rapid_mm, e.climb_mm, e.conventional_mm);
  ASSERT_GT(either.waterline_levels, 20);
  EXPECT_LT(c.conventional_mm, 0.01 * c.climb_mm);  // climb only (but where a contour runs onto the block's side)
  EXPECT_GT(c.rapid_mm, 20.0 * either.waterline_levels);
  EXPECT_LT(e.rapid_mm, 0.2 * c.rapid_mm);
  EXPECT_GT(e.conventional_mm, 0.3 * (e.climb_mm + e.conventional_mm));  // every other level
  EXPECT_GT(e.climb_mm, 0.3 * (e.climb_mm + e.conventional_mm));
  EXPECT_NEAR(e.climb_mm + e.conventional_mm, c.climb_mm, 0.02 * c.climb_mm);  // the same wall cut
  VerifyOptions vo;
  vo.stock_mesh = &stock.mesh;
  vo.resolution = 0.3;
  for (const SurfaceFinishingResult* r : {&either, &climb}) {
    const VerificationReport report = verifyToolpath(part.mesh, part.triangle_face, r->path, {tool}, vo);
    EXPECT_EQ(report.gouges, 0);
    EXPECT_EQ(report.collisions, 0);
  }
}
