// Holes (issue 17, item 4): recognition on parts built with OpenCASCADE (the truth is how they were built) and on the
// shared parts, the method each gets from the shop's library, the plugs, and drilling and helical paths swept by the
// tri-dexel simulation (the judge: no gouge, no collision, the hole's volume gone).
#include <gtest/gtest.h>
#include <unistd.h>

#include <BRepAlgoAPI_Cut.hxx>
#include <BRepAlgoAPI_Fuse.hxx>
#include <BRepBuilderAPI_Transform.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCone.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <STEPControl_Writer.hxx>
#include <TopoDS_Shape.hxx>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>

#include "art2part/finishing/holes.h"
#include "art2part/geometry/adjacency.h"
#include "art2part/geometry/part.h"
#include "art2part/geometry/repair.h"
#include "art2part/simulation/verify.h"
#include "art2part/tooling/tool.h"

namespace art2part {
namespace {

constexpr double kPi = 3.14159265358979323846;
const std::string kParts = ART2PART_SHARED_PARTS;
const std::string kLibrary = std::string(ART2PART_SOURCE_DIR) + "/config/tools.yaml";

const ToolLibrary& library() {
  static const ToolLibrary tools = loadToolLibrary(kLibrary);
  return tools;
}

// ---- parts built with OpenCASCADE -----------------------------------------------------------------------------------

// One stretch of a hole from the mouth down: a cylinder (r_top == r_bottom) or a cone (r_bottom 0: an apex).
struct Stretch {
  double r_top, r_bottom, length;
};

double pointLengthOf(double radius, double angle_deg) { return radius / std::tan(0.5 * angle_deg * kPi / 180); }

// The solid a hole removes: its stretches from `mouth` down `down`, the first one grown 1 mm above the mouth.
TopoDS_Shape holeSolid(const gp_Pnt& mouth, const gp_Dir& down, const std::vector<Stretch>& stretches) {
  TopoDS_Shape solid;
  double at = -1;
  for (size_t i = 0; i < stretches.size(); ++i) {
    Stretch s = stretches[i];
    const double length = s.length + (i == 0 ? 1 : 0);
    if (i == 0) s.r_top += (s.r_top - s.r_bottom) / s.length;  // a cone grown upwards keeps its angle
    const gp_Pnt base = mouth.Translated(gp_Vec(down) * at);
    const gp_Ax2 frame(base, down);
    const TopoDS_Shape piece = s.r_top == s.r_bottom ? BRepPrimAPI_MakeCylinder(frame, s.r_top, length).Shape()
                                                     : BRepPrimAPI_MakeCone(frame, s.r_top, s.r_bottom, length).Shape();
    solid = i == 0 ? piece : BRepAlgoAPI_Fuse(solid, piece).Shape();
    at += length;
  }
  return solid;
}

TopoDS_Shape block(double x, double y, double z) { return BRepPrimAPI_MakeBox(gp_Pnt(0, 0, 0), x, y, z).Shape(); }

TopoDS_Shape cut(TopoDS_Shape shape, const TopoDS_Shape& tool) { return BRepAlgoAPI_Cut(shape, tool).Shape(); }

// Writes the shape as STEP to a temporary file and loads it as the pipeline does.
Part partOf(const TopoDS_Shape& shape, const std::string& name) {
  const std::string path = (std::filesystem::temp_directory_path() /
                            ("art2part_holes_" + std::to_string(getpid()) + "_" + name + ".step")).string();
  STEPControl_Writer writer;
  writer.Transfer(shape, STEPControl_AsIs);
  EXPECT_EQ(writer.Write(path.c_str()), IFSelect_RetDone);
  Part part = loadPart(path);
  std::filesystem::remove(path);
  return part;
}

const gp_Dir kDown(0, 0, -1);

// The hole of `holes` whose mouth is nearest `mouth`.
const Hole* holeAt(const std::vector<Hole>& holes, const Vec3& mouth) {
  const Hole* best = nullptr;
  for (const Hole& hole : holes)
    if (!best || (hole.mouth - mouth).norm() < (best->mouth - mouth).norm()) best = &hole;
  return best && (best->mouth - mouth).norm() < 1e-3 ? best : nullptr;
}

std::string describe(const Hole& hole) {
  char text[400];
  std::snprintf(text, sizeof text, "mouth [%.3f %.3f %.3f] axis [%.3f %.3f %.3f] %s", hole.mouth.x(), hole.mouth.y(),
                hole.mouth.z(), hole.axis.x(), hole.axis.y(), hole.axis.z(), hole.signature.c_str());
  return text;
}

// ---- recognition and methods on built parts -------------------------------------------------------------------------

TEST(FindHoles, BlindHoleWithA118DegreeConeBottomIsDrilledWithTheHssDrill) {
  const double r = 4.2, cone = pointLengthOf(r, 118);
  const Part part = partOf(cut(block(60, 40, 30), holeSolid(gp_Pnt(20, 20, 30), kDown, {{r, r, 20}, {r, 0, cone}})),
                           "cone118");
  const std::vector<Hole> holes = findHoles(part);
  ASSERT_EQ(holes.size(), 1u);
  const Hole& hole = holes[0];
  SCOPED_TRACE(describe(hole));
  EXPECT_NEAR((hole.axis - Vec3::UnitZ()).norm(), 0, 1e-9);
  EXPECT_NEAR((hole.mouth - Vec3(20, 20, 30)).norm(), 0, 1e-6);
  EXPECT_NEAR(hole.diameter, 8.4, 1e-9);
  EXPECT_NEAR(hole.depth, 20, 1e-6);
  EXPECT_NEAR(hole.total_depth, 20 + cone, 1e-6);
  EXPECT_EQ(hole.bottom, HoleBottom::Cone);
  EXPECT_NEAR(hole.point_angle_deg, 118, 1e-6);
  EXPECT_EQ(hole.counterbore_diameter, 0);
  EXPECT_EQ(hole.countersink_diameter, 0);
  EXPECT_EQ(hole.bore_start, 0);
  EXPECT_GE(hole.arc_deg, 359);
  ASSERT_EQ(hole.segments.size(), 2u);
  EXPECT_EQ(hole.segments[0].kind, HoleSegmentKind::Cylinder);
  EXPECT_EQ(hole.segments[1].kind, HoleSegmentKind::Cone);
  EXPECT_NEAR(hole.segments[1].diameter_from, 8.4, 1e-6);
  EXPECT_NEAR(hole.segments[1].diameter_to, 0, 1e-6);
  EXPECT_EQ(hole.bore_faces, hole.faces);
  EXPECT_EQ(hole.signature, "d8.400 z22.524 cone118 cb0 cs0");
  // Above the mouth: nothing but air (the block's top face is the mouth's plane).
  for (double free : hole.free_radius) EXPECT_TRUE(std::isinf(free));

  const HoleMachining m = chooseHoleMethod(hole, library());
  EXPECT_EQ(m.method, HoleMethod::Drill) << m.reason;
  EXPECT_EQ(m.drill, "hss8.4");  // the 118 deg jobber; the 140 deg carbide drills do not make this cone
  EXPECT_EQ(m.spot, "spot6");
  EXPECT_NEAR(m.tip_depth, 20 + cone, 1e-6);
  EXPECT_NEAR(m.spot_depth, 3, 1e-9);  // a 6 mm chamfer: spot6's whole diameter, 3 mm deep at 90 deg
  EXPECT_FALSE(m.peck);                // 24.5 mm of feed from the R plane, under 3 x 8.4
  EXPECT_EQ(m.reason, "");
}

TEST(FindHoles, WhatNoDrillMakesIsReportedWithDiameterAndDepth) {
  const auto method = [](double r, double depth, double angle, const std::string& name) {
    const Part part = partOf(cut(block(40, 40, 120), holeSolid(gp_Pnt(20, 20, 120), kDown,
                                                               {{r, r, depth}, {r, 0, pointLengthOf(r, angle)}})),
                             name);
    const std::vector<Hole> holes = findHoles(part);
    EXPECT_EQ(holes.size(), 1u);
    return holes.empty() ? HoleMachining{} : chooseHoleMethod(holes[0], library());
  };
  // 8.25 mm: 0.05 mm from 8.2 and 8.3, 0.046 from letter P (8.204 mm).
  HoleMachining m = method(4.125, 20, 118, "d825");
  EXPECT_EQ(m.method, HoleMethod::None);
  EXPECT_NE(m.reason.find("no drill within 0.02 mm of 8.25 mm"), std::string::npos) << m.reason;
  EXPECT_NE(m.reason.find("cone bottom needs a flat floor"), std::string::npos) << m.reason;
  m = method(4.2, 20, 120, "cone120");
  EXPECT_EQ(m.method, HoleMethod::None);
  EXPECT_NE(m.reason.find("cone bottom 120.0 deg: no 8.40 mm drill point matches (118, 140 deg)"), std::string::npos)
      << m.reason;
  m = method(4.2, 100, 118, "deep");
  EXPECT_EQ(m.method, HoleMethod::None);
  EXPECT_NE(m.reason.find("102.52 mm deep: longest 8.40 mm drill (hss8.4) reaches 75.00 mm"), std::string::npos)
      << m.reason;
  m = method(4.2, 40, 118, "peck");  // 44.5 mm of feed: pecked
  EXPECT_EQ(m.method, HoleMethod::Drill) << m.reason;
  EXPECT_TRUE(m.peck);
}

TEST(FindHoles, FlatBottomIsHelixMilledOrDrilledToTheFloorWhenTooDeep) {
  const Part part = partOf(cut(cut(block(80, 40, 50), holeSolid(gp_Pnt(20, 20, 50), kDown, {{5, 5, 12}})),
                               holeSolid(gp_Pnt(55, 20, 50), kDown, {{5, 5, 40}})),
                           "flat");
  const std::vector<Hole> holes = findHoles(part);
  ASSERT_EQ(holes.size(), 2u);
  const Hole* shallow = holeAt(holes, Vec3(20, 20, 50));
  const Hole* deep = holeAt(holes, Vec3(55, 20, 50));
  ASSERT_TRUE(shallow && deep);
  EXPECT_EQ(shallow->bottom, HoleBottom::Flat);
  EXPECT_NEAR(shallow->depth, 12, 1e-6);
  EXPECT_NEAR(shallow->total_depth, 12, 1e-6);
  ASSERT_EQ(shallow->segments.size(), 2u);
  EXPECT_EQ(shallow->segments[1].kind, HoleSegmentKind::Flat);
  EXPECT_NEAR(shallow->segments[1].diameter_from, 10, 1e-6);
  EXPECT_EQ(shallow->segments[1].diameter_to, 0);
  HoleMachining m = chooseHoleMethod(*shallow, library());
  EXPECT_EQ(m.method, HoleMethod::Helix) << m.reason;
  EXPECT_EQ(m.drill, "flat8");  // the largest of 5 .. 8 mm
  EXPECT_NEAR(m.tip_depth, 12, 1e-6);
  // 40 mm: beyond flat8's 20 mm and flat6's 16 mm of flutes; the 10 mm carbide stub drills to the floor.
  m = chooseHoleMethod(*deep, library());
  EXPECT_EQ(m.method, HoleMethod::Drill) << m.reason;
  EXPECT_EQ(m.drill, "drill10");
  EXPECT_NEAR(m.tip_depth, 40, 1e-6);
  EXPECT_NE(m.reason.find("flat bottom drilled to the floor"), std::string::npos) << m.reason;
}

TEST(FindHoles, ThroughCounterboredAndCountersunkHoles) {
  TopoDS_Shape shape = block(90, 40, 30);
  shape = cut(shape, holeSolid(gp_Pnt(15, 20, 30), kDown, {{3.3, 3.3, 31}}));                 // M6 clearance, through
  shape = cut(shape, holeSolid(gp_Pnt(45, 20, 30), kDown, {{5.5, 5.5, 6.5}, {3.3, 3.3, 25}}));  // counterbored
  shape = cut(shape, holeSolid(gp_Pnt(75, 20, 30), kDown, {{6, 3.3, 2.7}, {3.3, 3.3, 29}}));   // 90 deg countersink
  const Part part = partOf(shape, "through");
  const std::vector<Hole> holes = findHoles(part);
  ASSERT_EQ(holes.size(), 3u);
  const Hole* plain = holeAt(holes, Vec3(15, 20, 30));
  const Hole* counterbored = holeAt(holes, Vec3(45, 20, 30));
  const Hole* countersunk = holeAt(holes, Vec3(75, 20, 30));
  ASSERT_TRUE(plain && counterbored && countersunk);
  for (const Hole* hole : {plain, counterbored, countersunk}) {
    SCOPED_TRACE(describe(*hole));
    EXPECT_EQ(hole->bottom, HoleBottom::Through);
    EXPECT_NEAR(hole->diameter, 6.6, 1e-9);
    EXPECT_NEAR(hole->total_depth, 30, 1e-6);
    EXPECT_NEAR(hole->depth, 30, 1e-6);
    EXPECT_NEAR((hole->axis - Vec3::UnitZ()).norm(), 0, 1e-9) << "the counterbore's end is the mouth";
    EXPECT_TRUE(std::isinf(hole->free_beyond));
    const HoleMachining m = chooseHoleMethod(*hole, library());
    EXPECT_EQ(m.method, HoleMethod::Drill) << m.reason;
    EXPECT_EQ(m.drill, "carb6.6");  // through: any point; the shortest flutes that reach
    EXPECT_NEAR(m.tip_depth, 30 + pointLengthOf(3.3, 140) + 1, 1e-6);  // the full diameter 1 mm past the far end
    EXPECT_EQ(m.spot, "spot6");
  }
  EXPECT_NEAR(counterbored->counterbore_diameter, 11, 1e-9);
  EXPECT_NEAR(counterbored->counterbore_depth, 6.5, 1e-6);
  EXPECT_NEAR(counterbored->bore_start, 6.5, 1e-6);
  ASSERT_EQ(counterbored->segments.size(), 3u);
  EXPECT_EQ(counterbored->segments[1].kind, HoleSegmentKind::Flat);
  EXPECT_NEAR(counterbored->segments[1].diameter_from, 11, 1e-6);
  EXPECT_NEAR(counterbored->segments[1].diameter_to, 6.6, 1e-6);
  EXPECT_EQ(counterbored->signature, "d6.600 z30.000 through cb11.000x6.500 cs0");
  EXPECT_LT(counterbored->bore_faces.size(), counterbored->faces.size());
  EXPECT_NEAR(countersunk->countersink_angle_deg, 90, 1e-6);
  EXPECT_NEAR(countersunk->countersink_diameter, 12, 1e-6);
  EXPECT_NEAR(countersunk->bore_start, 2.7, 1e-6);
  EXPECT_EQ(plain->counterbore_diameter, 0);
  EXPECT_EQ(plain->countersink_diameter, 0);
  // The spot drill starts at the bore: in the counterbore, 6.5 + 3 mm down.
  EXPECT_NEAR(chooseHoleMethod(*counterbored, library()).spot_depth, 9.5, 1e-9);
  // From below: the plain hole is the same hole upside down; the counterbored one has a narrower stretch first.
  const Hole below = reversedHole(part, *plain);
  EXPECT_NEAR((below.axis + Vec3::UnitZ()).norm(), 0, 1e-9);
  EXPECT_NEAR((below.mouth - Vec3(15, 20, 0)).norm(), 0, 1e-6);
  EXPECT_NEAR(below.diameter, 6.6, 1e-9);
  EXPECT_EQ(chooseHoleMethod(below, library()).drill, "carb6.6");
  const Hole back = reversedHole(part, *counterbored);
  EXPECT_NEAR(back.diameter, 11, 1e-9);
  const HoleMachining blocked = chooseHoleMethod(back, library());
  EXPECT_EQ(blocked.method, HoleMethod::None);
  EXPECT_NE(blocked.reason.find("a narrower stretch (6.60 mm)"), std::string::npos) << blocked.reason;
  EXPECT_THROW(reversedHole(part, Hole{}), InputError);
}

TEST(FindHoles, TiltedHoleKeepsItsMeasures) {
  const double r = 4.2, cone = pointLengthOf(r, 118);
  const TopoDS_Shape upright =
      cut(block(60, 40, 30), holeSolid(gp_Pnt(20, 20, 30), kDown, {{r, r, 20}, {r, 0, cone}}));
  gp_Trsf tilt, turn;
  tilt.SetRotation(gp_Ax1(gp_Pnt(0, 0, 0), gp_Dir(1, 0, 0)), 30 * kPi / 180);
  turn.SetRotation(gp_Ax1(gp_Pnt(0, 0, 0), gp_Dir(0, 0, 1)), 20 * kPi / 180);
  const gp_Trsf both = turn * tilt;
  const Part part = partOf(BRepBuilderAPI_Transform(upright, both).Shape(), "tilted");
  const std::vector<Hole> holes = findHoles(part);
  ASSERT_EQ(holes.size(), 1u);
  const gp_Pnt mouth = gp_Pnt(20, 20, 30).Transformed(both);
  const gp_Dir axis = gp_Dir(0, 0, 1).Transformed(both);
  SCOPED_TRACE(describe(holes[0]));
  EXPECT_NEAR((holes[0].mouth - Vec3(mouth.X(), mouth.Y(), mouth.Z())).norm(), 0, 1e-6);
  EXPECT_NEAR((holes[0].axis - Vec3(axis.X(), axis.Y(), axis.Z())).norm(), 0, 1e-9);
  EXPECT_NEAR(holes[0].diameter, 8.4, 1e-9);
  EXPECT_NEAR(holes[0].depth, 20, 1e-6);
  EXPECT_NEAR(holes[0].total_depth, 20 + cone, 1e-6);
  EXPECT_EQ(holes[0].bottom, HoleBottom::Cone);
  EXPECT_EQ(chooseHoleMethod(holes[0], library()).drill, "hss8.4");
}

TEST(FindHoles, BossesGroovesAndPartialCylindersAreNotHoles) {
  TopoDS_Shape shape = block(100, 60, 30);
  // A boss on top, a half-cylinder groove across the top, a bore breaking out of the side wall (270 deg of arc).
  shape = BRepAlgoAPI_Fuse(shape, BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(20, 30, 30), gp_Dir(0, 0, 1)), 6, 10).Shape())
              .Shape();
  shape = cut(shape, BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(-1, 50, 30), gp_Dir(1, 0, 0)), 5, 102).Shape());
  shape = cut(shape, holeSolid(gp_Pnt(100 - 0.7 * 5, 10, 30), kDown, {{5, 5, 10}}));
  // Arc on the threshold's other side: 324 deg (the axis 0.95 r in from the side) is a hole.
  shape = cut(shape, holeSolid(gp_Pnt(100 - 0.95 * 5, 30, 30), kDown, {{5, 5, 10}}));
  const Part part = partOf(shape, "boss");
  const std::vector<Hole> holes = findHoles(part);
  ASSERT_EQ(holes.size(), 1u);
  SCOPED_TRACE(describe(holes[0]));
  EXPECT_NEAR(holes[0].mouth.y(), 30, 1e-6);
  EXPECT_NEAR(holes[0].arc_deg, 360 - 2 * std::acos(0.95) * 180 / kPi, 2);
}

// The holder is kept clear of the part by measurement, and the simulation agrees: a 6 mm hole at the floor of a
// 20 mm wide pocket 30 mm deep is drilled; 60 mm deep, the ER16 nut (32 mm) would enter the pocket: no drill reaches.
TEST(FindHoles, HolderClearanceIsMeasuredOnThePartAndTheSimulationAgrees) {
  const double r = 3, cone = pointLengthOf(r, 118);
  for (const double pocket : {30.0, 60.0}) {
    SCOPED_TRACE(pocket);
    TopoDS_Shape shape = cut(block(60, 60, 80), BRepPrimAPI_MakeBox(gp_Pnt(20, 20, 80 - pocket), 20, 20, pocket + 1).Shape());
    shape = cut(shape, holeSolid(gp_Pnt(30, 30, 80 - pocket), kDown, {{r, r, 10}, {r, 0, cone}}));
    const Part part = partOf(shape, "pocket" + std::to_string(static_cast<int>(pocket)));
    const std::vector<Hole> holes = findHoles(part);
    ASSERT_EQ(holes.size(), 1u);
    const Hole& hole = holes[0];
    // The pocket's walls 10 mm from the axis up to its top; nothing above.
    const int wall_bands = static_cast<int>(pocket / hole.clearance_step);
    EXPECT_NEAR(hole.free_radius[0], 10, 1e-9);
    EXPECT_NEAR(hole.free_radius[wall_bands - 1], 10, 1e-9);
    EXPECT_TRUE(std::isinf(hole.free_radius[wall_bands + 1]));
    const HoleMachining m = chooseHoleMethod(hole, library());
    Tool drill = *library().find("hss6");
    if (pocket < 50) {
      EXPECT_EQ(m.method, HoleMethod::Drill) << m.reason;
      EXPECT_EQ(m.drill, "hss6");
    } else {
      EXPECT_EQ(m.method, HoleMethod::None);
      EXPECT_NE(m.reason.find("holder"), std::string::npos) << m.reason;
      EXPECT_NE(m.reason.find("10.00 mm from the axis"), std::string::npos) << m.reason;
      std::printf("60 mm deep pocket: %s\n", m.reason.c_str());
    }
    // The judge: the same drill's path swept through the part (stock: the plug).
    HoleMachining forced;
    forced.method = HoleMethod::Drill;
    const Mesh plug = holePlugs(holes, {forced});
    VerifyOptions options;
    options.resolution = 0.25;
    options.stock_mesh = &plug;
    const VerificationReport report =
        verifyToolpath(part.mesh, part.triangle_face, drillingPath(holes, drill, false, 0, 5), {drill}, options);
    EXPECT_EQ(report.collisions > 0, pocket > 50) << report.collisions << " collisions, deepest "
                                                  << report.worst_collision_mm;
  }
}

// A through hole that breaks into a slot 1.5 mm high: the drill's point (2.5 mm) would reach the slot's floor, so no
// drill; a flat end mill goes 1 mm past the far end instead.
TEST(FindHoles, BreakthroughStopsShortOfMaterialBeyond) {
  TopoDS_Shape shape = cut(block(60, 40, 30), BRepPrimAPI_MakeBox(gp_Pnt(-1, 10, 15), 62, 20, 1.5).Shape());
  shape = cut(shape, holeSolid(gp_Pnt(30, 20, 30), kDown, {{4.2, 4.2, 13.5}}));
  const Part part = partOf(shape, "slot");
  const std::vector<Hole> holes = findHoles(part);
  ASSERT_EQ(holes.size(), 1u);
  const Hole& hole = holes[0];
  SCOPED_TRACE(describe(hole));
  EXPECT_EQ(hole.bottom, HoleBottom::Through);
  EXPECT_NEAR(hole.total_depth, 13.5, 1e-6);
  EXPECT_LE(hole.free_beyond, 1.5);  // never overstated
  EXPECT_GE(hole.free_beyond, 1.45);  // to its bands' 0.05 mm
  const HoleMachining m = chooseHoleMethod(hole, library());
  EXPECT_EQ(m.method, HoleMethod::Helix) << m.reason;
  EXPECT_EQ(m.drill, "flat6");
  EXPECT_NEAR(m.tip_depth, 13.5 + 1, 1e-9);
  HoleOptions tight;
  tight.breakthrough = 2;  // 2 mm past the far end: only what the slot leaves, less the margin
  EXPECT_NEAR(helixDepth(hole, tight), 13.5 + hole.free_beyond - tight.holder_margin, 1e-9);
}

// ---- plugs and paths, judged by the simulation ----------------------------------------------------------------------

TEST(HolePlugs, AreClosedOutwardAndFillTheBore) {
  const double r = 4.2, cone = pointLengthOf(r, 118);
  const Part part = partOf(cut(cut(block(60, 40, 30), holeSolid(gp_Pnt(15, 20, 30), kDown, {{r, r, 20}, {r, 0, cone}})),
                               holeSolid(gp_Pnt(40, 20, 30), kDown, {{5.5, 5.5, 6.5}, {3.3, 3.3, 25}})),
                           "plugs");
  const std::vector<Hole> holes = findHoles(part);
  ASSERT_EQ(holes.size(), 2u);
  std::vector<HoleMachining> methods;
  for (const Hole& hole : holes) methods.push_back(chooseHoleMethod(hole, library()));
  const Mesh plugs = holePlugs(holes, methods);
  const MeshCheck check = checkMesh(plugs);
  EXPECT_TRUE(check.closed);
  EXPECT_EQ(buildAdjacency(plugs).nonmanifold_edges, 0);
  // Inscribed polygons: within 0.01 mm of the true volume (the chords' slivers) and never above it.
  const double blind = kPi * r * r * (20 + cone / 3), through = kPi * 3.3 * 3.3 * (30 - 6.5);
  EXPECT_LE(signedVolume(plugs), blind + through);
  EXPECT_NEAR(signedVolume(plugs), blind + through, 0.01 * 2 * kPi * (r * 20 + 3.3 * 23.5));
  EXPECT_THROW(holePlugs(holes, {}), InputError);
}

// A spot drill, the matching drills and a helix on a part with a cone-bottomed, a through and a flat-bottomed hole,
// swept through stock that is the holes' plugs: no gouge, no collision, and the plugs gone to the lattice's error.
TEST(HolePaths, DrillingAndHelixPathsCutThePlugsWithoutGouges) {
  const double r = 4.2, cone = pointLengthOf(r, 118);
  // Axes off the lattice's rays: a ray through a cylinder's seam edge exactly is miscounted by the part's
  // dexelization (featuretype at 0.1 mm: 5.2 mm phantom "gouges" on rays at its holes' seam planes; bench_holes).
  const double y = 20.0377;
  TopoDS_Shape shape = block(80, 40, 40);
  shape = cut(shape, holeSolid(gp_Pnt(15.0123, y, 40), kDown, {{r, r, 20}, {r, 0, cone}}));
  shape = cut(shape, holeSolid(gp_Pnt(40.0123, y, 40), kDown, {{3.3, 3.3, 41}}));
  shape = cut(shape, holeSolid(gp_Pnt(65.0123, y, 40), kDown, {{5, 5, 12}}));
  // The bores' chords lie inside their circles by r (1 - cos(a / 2)) for an angular deflection a: 0.02 mm at the
  // default 0.2 rad, more than the gouge tolerance a drill of the exact size cuts them by. A finer tessellation here.
  const std::string path = (std::filesystem::temp_directory_path() /
                            ("art2part_holes_" + std::to_string(getpid()) + "_paths.step")).string();
  STEPControl_Writer writer;
  writer.Transfer(shape, STEPControl_AsIs);
  ASSERT_EQ(writer.Write(path.c_str()), IFSelect_RetDone);
  LoadOptions fine;
  fine.angular_tolerance = 0.04;
  const Part part = loadPart(path, fine);
  std::filesystem::remove(path);

  const std::vector<Hole> holes = findHoles(part);
  ASSERT_EQ(holes.size(), 3u);
  std::vector<HoleMachining> methods;
  Toolpath toolpath;
  std::vector<Tool> tools;
  const auto add = [&](Toolpath run, const std::string& tool) {
    for (CutterLocation& point : run) point.op = static_cast<int>(toolpath.empty() ? 0 : toolpath.back().op + 1);
    toolpath.insert(toolpath.end(), run.begin(), run.end());
    if (std::none_of(tools.begin(), tools.end(), [&](const Tool& t) { return t.id == tool; }))
      tools.push_back(*library().find(tool));
  };
  for (const Hole& hole : holes) {
    methods.push_back(chooseHoleMethod(hole, library()));
    const HoleMachining& m = methods.back();
    SCOPED_TRACE(describe(hole));
    ASSERT_NE(m.method, HoleMethod::None) << m.reason;
    if (m.method == HoleMethod::Drill) {
      add(drillingPath({hole}, *library().find(m.spot), true, 0, 5), m.spot);
      add(drillingPath({hole}, *library().find(m.drill), false, 0, 5), m.drill);
      const Toolpath run = drillingPath({hole}, *library().find(m.drill), false, 0, 5);
      double deepest = 1e9;
      for (const CutterLocation& point : run) deepest = std::min(deepest, point.tip.z());
      EXPECT_NEAR(40 - deepest, m.tip_depth, 1e-9);
    } else {
      add(helixPath(hole, *library().find(m.drill), 0, 5), m.drill);
    }
  }
  EXPECT_EQ(std::count_if(methods.begin(), methods.end(), [](const HoleMachining& m) { return m.method == HoleMethod::Helix; }), 1);
  const Mesh plugs = holePlugs(holes, methods);
  VerifyOptions options;
  options.resolution = 0.1;
  options.stock_mesh = &plugs;
  const auto start = std::chrono::steady_clock::now();
  const VerificationReport report = verifyToolpath(part.mesh, part.triangle_face, toolpath, tools, options);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("holes swept: %zu points, %lld poses, %.2f s; plugs %.1f mm^3, removed %.1f, left %.3f mm^3 "
              "(thickest %.3f mm), worst gouge %.4f mm\n",
              toolpath.size(), static_cast<long long>(report.poses), seconds, signedVolume(plugs),
              report.removed_volume_mm3, report.leftover_volume_mm3, report.leftover_max_mm, report.worst_gouge_mm);
  EXPECT_EQ(report.gouges, 0) << report.worst_gouge_mm;
  EXPECT_EQ(report.collisions, 0);
  // The plugs are gone: what is left is the lattice's rounding along the bores' walls (a tenth of a cell's share).
  EXPECT_LT(report.leftover_volume_mm3, 0.01 * signedVolume(plugs));
  EXPECT_NEAR(report.removed_volume_mm3, signedVolume(plugs), 0.01 * signedVolume(plugs));
}

// ---- the shared parts -----------------------------------------------------------------------------------------------

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Whether some drill of the library matches the hole's bore and bottom (the oracle: sizes and points only).
bool aDrillMatches(const Hole& hole, const HoleOptions& options = {}) {
  if (hole.bottom == HoleBottom::Other) return false;
  for (const Tool& tool : library().tools) {
    if (tool.type != ToolType::Drill || std::abs(tool.point_angle_deg - 90) < 1) continue;
    if (std::abs(tool.diameter - hole.diameter) > options.diameter_tolerance + 2 * options.measurement_credit) continue;
    if (hole.bottom != HoleBottom::Cone || std::abs(tool.point_angle_deg - hole.point_angle_deg) <= 0.5) return true;
  }
  return false;
}

// CTC-02: 84 cylinder faces of 8.38 mm and 60 of 10.1 mm, each half of a hole, and 148 cones of 59 deg (halves too):
// 74 holes with 118 deg cone bottoms (42 + 30 + 2 of 12 mm), every one drilled with the 118 deg jobber of its size.
void expectCtc02Holes(const Part& part, const std::vector<Hole>& holes, bool exact_faces) {
  std::map<std::string, int> drilled;
  std::map<int, int> hole_of_face;
  for (size_t h = 0; h < holes.size(); ++h) {
    const Hole& hole = holes[h];
    for (int f : hole.bore_faces) hole_of_face[f] += 1;
    if (hole.bottom != HoleBottom::Cone) continue;
    SCOPED_TRACE(describe(hole));
    EXPECT_NEAR(hole.point_angle_deg, 118, 0.1);
    EXPECT_NEAR(hole.total_depth - hole.depth, pointLengthOf(0.5 * hole.diameter, 118), 0.01);
    const HoleMachining m = chooseHoleMethod(hole, library());
    EXPECT_EQ(m.method, HoleMethod::Drill) << m.reason;
    EXPECT_EQ(m.spot, "spot6");
    ++drilled[m.drill];
  }
  EXPECT_EQ(drilled["hss8.4"], 42);
  EXPECT_EQ(drilled["hss10.1"], 30);
  EXPECT_EQ(drilled["hss12"], 2);
  if (!exact_faces) return;
  // The faces, independently: every 8.38 and 10.1 mm hole face and every 59 deg cone is in exactly one hole's bore.
  int bore_faces = 0, cones = 0;
  for (int f = 0; f < static_cast<int>(part.faces.size()); ++f) {
    const Face& face = part.faces[f];
    const bool bore = face.type == SurfaceType::Cylinder && face.concave &&
                      (std::abs(face.radius - 4.19) < 1e-6 || std::abs(face.radius - 5.05) < 1e-6);
    const bool cone = face.type == SurfaceType::Cone && face.concave && std::abs(face.half_angle - 59 * kPi / 180) < 1e-6;
    if (!bore && !cone) continue;
    (bore ? bore_faces : cones) += 1;
    EXPECT_EQ(hole_of_face[f], 1) << "face " << f;
  }
  EXPECT_EQ(bore_faces, 84 + 60);
  EXPECT_EQ(cones, 148);
}

TEST(SharedParts, Ctc02EveryConeBottomedHoleIsFoundAndDrilled) {
  const Part part = loadPart(kParts + "/nist_ctc_02_asme1_rc.stp");
  const auto start = std::chrono::steady_clock::now();
  const std::vector<Hole> holes = findHoles(part);
  std::printf("CTC-02 (STEP): %zu holes in %.3f s over %d triangles\n", holes.size(), secondsSince(start),
              part.mesh.triangleCount());
  expectCtc02Holes(part, holes, true);
}

// The same part as a mesh (122k triangles, faces by segmentation, float vertices): the same holes, the same drills.
TEST(SharedParts, Ctc02FineMeshGivesTheSameHoles) {
  const Part part = loadPart(kParts + "/nist_ctc_02_asme1_rc_fine_tess.stl");
  const auto start = std::chrono::steady_clock::now();
  const std::vector<Hole> holes = findHoles(part);
  std::printf("CTC-02 (mesh): %zu holes in %.3f s over %d triangles\n", holes.size(), secondsSince(start),
              part.mesh.triangleCount());
  expectCtc02Holes(part, holes, false);
}

// CTC-01, ANC101, featuretype (inch): every hole a library drill matches (the oracle above) is drilled, unless its
// reason names what stops the drill (reach, holder, breakthrough); the count printed.
TEST(SharedParts, HolesALibraryDrillMatchesAreDrilled) {
  for (const auto& [name, expected] : std::map<std::string, int>{
           {"nist_ctc_01_asme1_rd.stp", 2}, {"ANC101.stp", 0}, {"featuretype.STEP", 9}}) {
    SCOPED_TRACE(name);
    const Part part = loadPart(kParts + "/" + name);
    const std::vector<Hole> holes = findHoles(part);
    int matched = 0, drilled = 0;
    for (const Hole& hole : holes) {
      const HoleMachining m = chooseHoleMethod(hole, library());
      if (!aDrillMatches(hole)) {
        EXPECT_NE(m.method, HoleMethod::Drill) << describe(hole);
        continue;
      }
      ++matched;
      if (m.method == HoleMethod::Drill) {
        ++drilled;
        std::printf("%s: %s drilled with %s (tip %.3f mm)\n", name.c_str(), describe(hole).c_str(), m.drill.c_str(),
                    m.tip_depth);
      } else {
        EXPECT_TRUE(m.reason.find("deep") != std::string::npos || m.reason.find("meets") != std::string::npos ||
                    m.reason.find("fit") != std::string::npos || m.reason.find("beyond") != std::string::npos)
            << describe(hole) << ": " << m.reason;
      }
    }
    std::printf("%s: %zu holes, %d a library drill matches, %d drilled\n", name.c_str(), holes.size(), matched, drilled);
    EXPECT_EQ(drilled, expected);
  }
}

// Whether p lies inside the closed mesh: the parity of a ray's crossings, along a direction of its own.
bool insideMesh(const Mesh& mesh, const Vec3& p) {
  const Vec3 d = Vec3(-0.3111, 0.8427, 0.4393).normalized();
  int crossings = 0;
  for (int t = 0; t < mesh.triangleCount(); ++t) {
    const Vec3 &a = mesh.corner(t, 0), &b = mesh.corner(t, 1), &c = mesh.corner(t, 2);
    const Vec3 n = (b - a).cross(c - a);
    const double along = n.dot(d);
    if (std::abs(along) < 1e-14) continue;
    const double s = n.dot(a - p) / along;  // the ray meets the plane at p + s d
    if (s <= 0) continue;
    const Vec3 x = p + s * d;
    if ((b - a).cross(x - a).dot(n) < 0 || (c - b).cross(x - b).dot(n) < 0 || (a - c).cross(x - c).dot(n) < 0) continue;
    ++crossings;
  }
  return crossings % 2 == 1;
}

// A hole called through is open past its far end: the drill's breakthrough meets no material there. ktoolcav (a mesh,
// faces by segmentation) has shallow recesses whose floors belong to larger faces: taken for through holes, they were
// drilled 3 mm into the part.
TEST(SharedParts, ThroughHolesAreOpenPastTheirFarEnd) {
  LoadOptions inches;
  inches.unit = LengthUnit::Inch;
  for (const auto& [name, options] : std::vector<std::pair<std::string, LoadOptions>>{
           {"ktoolcav.stl", inches}, {"featuretype.STEP", {}}, {"nist_ctc_01_asme1_rd.stp", {}}}) {
    SCOPED_TRACE(name);
    const Part part = loadPart(kParts + "/" + name, options);
    int through = 0;
    for (const Hole& hole : findHoles(part)) {
      if (hole.bottom != HoleBottom::Through) continue;
      ++through;
      const Vec3 past = hole.mouth - (hole.total_depth + 0.05) * hole.axis;
      EXPECT_FALSE(insideMesh(part.mesh, past)) << describe(hole);
    }
    EXPECT_GT(through, 0);
  }
}

}  // namespace
}  // namespace art2part
