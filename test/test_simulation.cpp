// Verification (issue 5): hand-made toolpaths on hand-made parts, whose answers are known in closed form.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <utility>
#include <sys/wait.h>

#include "art2part/geometry/mesh_io.h"
#include "art2part/geometry/part.h"
#include "art2part/simulation/mesh_dexels.h"
#include "art2part/simulation/stock_mesh.h"
#include "art2part/simulation/verify.h"
#include "test_meshes.h"

using namespace art2part;

namespace {

constexpr double kPi = 3.14159265358979323846;

Tool endMill(const std::string& id, ToolType type, double diameter, double flutes, double stickout,
             double holder_diameter = 30, double holder_length = 40) {
  Tool t;
  t.id = id;
  t.type = type;
  t.diameter = diameter;
  t.corner_radius = type == ToolType::Ball ? diameter / 2 : (type == ToolType::Bull ? diameter / 6 : 0);
  t.flute_length = flutes;
  t.shank_diameter = diameter;
  t.stickout = stickout;
  t.holder = {{holder_diameter, holder_length}};
  return t;
}

const Tool kFlat = endMill("flat6", ToolType::Flat, 6, 25, 40);
const Tool kBall = endMill("ball6", ToolType::Ball, 6, 25, 40);

CutterLocation at(const std::string& tool, MoveKind move, double x, double y, double z, Vec3 axis = Vec3::UnitZ()) {
  CutterLocation c;
  c.tool = tool;
  c.move = move;
  c.tip = Vec3(x, y, z);
  c.axis = axis.normalized();
  return c;
}

// Down from a safe height at `from`, along to `to`, back up: the usual single pass.
Toolpath pass(const std::string& tool, const Vec3& from, const Vec3& to, double safe_z = 40) {
  return {at(tool, MoveKind::Rapid, from.x(), from.y(), safe_z), at(tool, MoveKind::Feed, from.x(), from.y(), from.z()),
          at(tool, MoveKind::Feed, to.x(), to.y(), to.z()), at(tool, MoveKind::Feed, to.x(), to.y(), safe_z)};
}

// The part of most tests: a 40 x 20 x 10 block at the origin.
const Mesh kBlock = test::box(Vec3(0, 0, 0), Vec3(40, 20, 10));

VerifyOptions options(double resolution, double margin) {
  VerifyOptions o;
  o.resolution = resolution;
  o.stock_margin = margin;
  return o;
}

VerificationReport verify(const Toolpath& path, const Tool& tool, const VerifyOptions& o) {
  return verifyToolpath(kBlock, {}, path, {tool}, o);
}

}  // namespace

TEST(MeshDexels, BoxVolumeIsExactEvenWithRaysThroughEdgesAndVertices) {
  // Rays at 0.25 + 0.5 k pass exactly through the diagonals of the box's faces.
  const Mesh cube = test::box(Vec3(0, 0, 0), Vec3(10, 10, 10));
  Box box;
  box.extend(Vec3(-2, -2, -2));
  box.extend(Vec3(12, 12, 12));
  const MeshDexels dexels(cube, DexelLattice::over(box, 0.5));
  EXPECT_NEAR(dexels.volume(), 1000.0, 1e-9);
  // Rays through the corner (0, 0) of a face: still one span, not two or none.
  EXPECT_TRUE(dexels.containsNear(Vec3(0.25, 0.25, 5)));
  EXPECT_FALSE(dexels.containsNear(Vec3(-0.25, 0.25, 5)));
  Mesh inside_out = cube;
  test::flipAll(inside_out);
  EXPECT_NEAR(MeshDexels(inside_out, dexels.lattice()).volume(), 1000.0, 1e-9);
}

// Rays whose coordinate equals a vertex's: featuretype at 0.1 mm puts x-rays exactly through the seam edges of its
// holes (y = -25.4); rounding in the index range left them out of both wall triangles, and the rays ran solid through
// the holes (4,853 phantom gouges in a plan). Every x-ray's solid length must be that of a neighbour's, give or take
// what the holes' curvature changes over one cell.
TEST(MeshDexels, RaysThroughHoleSeamsCrossBothWalls) {
  const Part part = loadPart(std::string(ART2PART_SHARED_PARTS) + "/featuretype.STEP");
  Box box = boundingBox(part.mesh);
  box.min -= Vec3::Constant(2);
  box.max += Vec3::Constant(2);
  const DexelLattice lattice = DexelLattice::over(box, 0.1);
  const MeshDexels dexels(part.mesh, lattice);
  auto length = [&](int iu, int iv) {
    double l = 0;
    const int ray = lattice.rayIndex(0, iu, iv);
    for (const SolidSpan* s = dexels.begin(0, ray); s != dexels.end(0, ray); ++s) l += s->hi - s->lo;
    return l;
  };
  int phantom = 0;
  for (int iv = 0; iv < lattice.cells[2]; ++iv)
    for (int iu = 1; iu + 1 < lattice.cells[1]; ++iu)
      if (length(iu, iv) > std::max(length(iu - 1, iv), length(iu + 1, iv)) + 1.0) ++phantom;
  EXPECT_EQ(phantom, 0);
}

TEST(ToolSolid, OutlineMatchesToolRadiusAt) {
  for (Tool tool : {kFlat, kBall, endMill("bull6", ToolType::Bull, 6, 25, 40)}) {
    tool.shank_diameter = 5;
    tool.holder = {{30, 20}, {40, 20}};
    const ToolSolid solid = toolSolid(tool);
    for (double h = 0.0; h < 85.0; h += 0.37) {
      EXPECT_NEAR(solid.radiusAt(h), toolRadiusAt(tool, h), 0.002) << tool.id << " at h = " << h;
      for (const ToolPiece& p : solid.pieces)
        if (h > p.h0 + 1e-6 && h < p.h1 - 1e-6) {
          EXPECT_EQ(p.zone, toolZoneAt(tool, h)) << tool.id << " h " << h;
        }
    }
  }
}

TEST(Simulation, FlatSlotRemovesTheAnalyticVolume) {
  // A 6 mm slot 3 mm deep and 30 mm long (plus the plunge) in the 5 mm of stock above the block.
  const auto r = verify(pass("flat6", Vec3(5, 10, 12), Vec3(35, 10, 12)), kFlat, options(0.2, 5));
  const double expected = 30 * 6 * 3 + kPi * 9 * 3;
  EXPECT_NEAR(r.removed_volume_mm3, expected, 0.01 * expected);
  EXPECT_EQ(r.gouges, 0);
  EXPECT_EQ(r.collisions, 0);
}

// The sweep passes over rays where a piece lies in air between two spans of material (the widest gap of each ray):
// a pass down a slot already cut removes nothing, one 1 mm aside removes just the strip it widens by, on the rays
// across the slot (two walls each) as on the others.
TEST(Simulation, PassesInsideACutSlotRemoveOnlyWhatTheyWiden) {
  Toolpath path;
  const Vec3 offsets[] = {Vec3(0, 0, 0), Vec3(0, 0, 0), Vec3(0, 1, 0)};
  for (int op = 0; op < 3; ++op)
    for (CutterLocation c : pass("flat6", Vec3(5, 10, 12) + offsets[op], Vec3(35, 10, 12) + offsets[op])) {
      c.op = op;
      path.push_back(c);
    }
  const auto r = verify(path, kFlat, options(0.2, 5));
  const double slot = 30 * 6 * 3 + kPi * 9 * 3;
  const double strip = 1.0 * (30 + 6) * 3;  // the slot's outline (36 mm across x) moved 1 mm along y, 3 mm deep
  EXPECT_NEAR(r.by_op.at(0).swept.removed_mm3, slot, 0.01 * slot);
  EXPECT_LT(r.by_op.at(1).swept.removed_mm3, 0.5);
  EXPECT_NEAR(r.by_op.at(2).swept.removed_mm3, strip, 0.03 * strip);
  EXPECT_EQ(r.gouges, 0);
  EXPECT_EQ(r.collisions, 0);
}

TEST(Simulation, BallSlotRemovesTheAnalyticVolume) {
  // Ball centre on the stock's top face: the lower half of a capsule, half a cylinder and half a sphere.
  const auto r = verify(pass("ball6", Vec3(5, 10, 12), Vec3(35, 10, 12)), kBall, options(0.2, 5));
  const double expected = 0.5 * kPi * 9 * 30 + 2.0 / 3.0 * kPi * 27;
  EXPECT_NEAR(r.removed_volume_mm3, expected, 0.01 * expected);
  EXPECT_EQ(r.gouges, 0);
}

TEST(Simulation, BullSlotAndDrillPlungeRemoveTheAnalyticVolume) {
  // Bull (corner radius 1): the slot's section is the 6 x 3 rectangle less two corners of (1 - pi/4); the plunge adds
  // the tool's own volume below the top, a cylinder less the corner ring (Pappus: its centroid sits rc / (6 (1 - pi/4))
  // in from the corner's outer edge).
  const Tool bull = endMill("bull6", ToolType::Bull, 6, 25, 40);
  const double corner_area = 1 - kPi / 4, ring = 2 * kPi * (2 + 1.0 / (6 * corner_area)) * corner_area;
  const double bull_expected = 30 * (18 - 2 * corner_area) + (kPi * 9 * 3 - ring);
  const auto b = verify(pass("bull6", Vec3(5, 10, 12), Vec3(35, 10, 12)), bull, options(0.2, 5));
  EXPECT_NEAR(b.removed_volume_mm3, bull_expected, 0.01 * bull_expected);
  // A 118-degree drill 5 mm deep: a cylinder and the cone of its point.
  Tool drill = endMill("drill6", ToolType::Drill, 6, 25, 40);
  drill.point_angle_deg = 118;
  const double cone = 3 / std::tan(59 * kPi / 180), drill_expected = kPi * 9 * (5 - cone) + kPi * 9 * cone / 3;
  const auto d = verify(pass("drill6", Vec3(20, 10, 10), Vec3(20, 10, 10)), drill, options(0.2, 5));
  EXPECT_NEAR(d.removed_volume_mm3, drill_expected, 0.01 * drill_expected);
  EXPECT_EQ(d.gouges + d.collisions + b.gouges + b.collisions, 0);
}

// The axial depth of cut (issue 19 item 4's measure): a level feed 3 mm under the stock's top cuts 3 mm deep (the z
// rays meet the top exactly); tilted 30 deg about x across a level feed along x, the flutes reach (3 + 3 sin 30) /
// cos 30 = 5.196 mm up the axis (the rim on the low side meets the top); a ramp to the same depth is no level feed.
TEST(Simulation, LevelFeedsMeasureTheirAxialDepthOfCut) {
  const auto level = verify(pass("flat6", Vec3(5, 10, 12), Vec3(35, 10, 12)), kFlat, options(0.2, 5));
  ASSERT_EQ(level.by_op.count(0), 1u);
  const OperationSweep& slot = level.by_op.at(0).swept;
  EXPECT_NEAR(slot.deepest_level_cut_mm, 3.0, 1e-6);
  EXPECT_NEAR(slot.removed_mm3, level.removed_volume_mm3, 1e-6 * level.removed_volume_mm3);
  // By height: the slot beyond the plunge's hole (30 x 6 x 3, the hole's half-disc ends cancel), evenly over 3 mm.
  const double slot_mm3 = levelCutAbove(slot, 0);
  EXPECT_NEAR(slot_mm3, 30 * 6 * 3, 0.01 * 30 * 6 * 3);
  EXPECT_NEAR(levelCutAbove(slot, 2.0), slot_mm3 / 3, 0.02 * slot_mm3);
  EXPECT_EQ(levelCutAbove(slot, 3.25), 0.0);
  EXPECT_NEAR(levelCutDepth(slot, kAxialDepthShare), 3.0, kLevelCutBinMm + 1e-9);

  const Vec3 axis(0, -std::sin(kPi / 6), std::cos(kPi / 6));
  Toolpath tilted = {at("flat6", MoveKind::Rapid, 5, 10, 40, axis), at("flat6", MoveKind::Feed, 5, 10, 12, axis),
                     at("flat6", MoveKind::Feed, 35, 10, 12, axis), at("flat6", MoveKind::Feed, 35, 10, 40, axis)};
  const auto t = verify(tilted, kFlat, options(0.1, 5));
  EXPECT_NEAR(t.by_op.at(0).swept.deepest_level_cut_mm, (3 + 3 * std::sin(kPi / 6)) / std::cos(kPi / 6), 0.06);

  const Toolpath ramp = {at("flat6", MoveKind::Rapid, 5, 10, 40), at("flat6", MoveKind::Feed, 5, 10, 15),
                         at("flat6", MoveKind::Feed, 35, 10, 12), at("flat6", MoveKind::Feed, 35, 10, 40)};
  const auto r = verify(ramp, kFlat, options(0.2, 5));
  EXPECT_GT(r.by_op.at(0).swept.removed_mm3, 0);
  EXPECT_EQ(r.by_op.at(0).swept.deepest_level_cut_mm, 0.0);
  EXPECT_TRUE(r.by_op.at(0).swept.level_cut_by_height_mm3.empty());
}

TEST(Simulation, DipIntoThePartIsAGougeOfItsDepth) {
  for (const Tool& tool : {kFlat, kBall}) {
    const auto r = verify(pass(tool.id, Vec3(10, 10, 9.95), Vec3(30, 10, 9.95)), tool, options(0.2, 2));
    EXPECT_GT(r.gouges, 0) << tool.id;
    EXPECT_NEAR(r.worst_gouge_mm, 0.05, 0.01) << tool.id;
    ASSERT_FALSE(r.gouge_list.empty());
    EXPECT_NEAR(r.gouge_list[0].position.z(), 9.95, 0.011);
    EXPECT_EQ(r.collisions, 0) << tool.id;
    const auto shallow = verify(pass(tool.id, Vec3(10, 10, 9.995), Vec3(30, 10, 9.995)), tool, options(0.2, 2));
    EXPECT_EQ(shallow.gouges, 0) << tool.id << " worst " << shallow.worst_gouge_mm;
  }
}

TEST(Simulation, EachFaceReportsItsOwnGougeAndWhatIsLeftOnIt) {
  // The block's six faces (test::box: two triangles per face, in the order -z, +z, -y, +y, -x, +x). A flat pass 0.1 mm
  // into the middle of the top (+z, face 1) and, after it, a pass down the +x side (face 5) 0.08 mm into it: each
  // face reports its own gouge, no other face any. The rest of the stock stays: 2 mm on the faces it covers.
  std::vector<int> faces;
  for (int t = 0; t < kBlock.triangleCount(); ++t) faces.push_back(t / 2);
  Toolpath path = pass("flat6", Vec3(8, 10, 9.9), Vec3(32, 10, 9.9));
  const Toolpath side = pass("flat6", Vec3(42.92, 5, 3), Vec3(42.92, 15, 3));
  path.insert(path.end(), side.begin(), side.end());
  VerifyOptions o = options(0.2, 2);
  const VerificationReport r = verifyToolpath(kBlock, faces, path, {kFlat}, o);
  ASSERT_EQ(r.face_checks.size(), 6u);
  for (const FaceVerification& f : r.face_checks) {
    EXPECT_GT(f.samples, 0) << "face " << f.face;
    if (f.face == 1 || f.face == 5) {
      EXPECT_GT(f.gouges, 0) << "face " << f.face;
      EXPECT_NEAR(f.deepest_gouge_mm, f.face == 1 ? 0.1 : 0.08, 0.01) << "face " << f.face;
    } else {
      EXPECT_EQ(f.gouges, 0) << "face " << f.face;
      EXPECT_EQ(f.deepest_gouge_mm, 0.0) << "face " << f.face;
    }
    if (f.face == 0) {
      EXPECT_NEAR(f.left_max_mm, 2.0, 0.25) << "the bottom keeps its margin";
    }
  }
  EXPECT_NEAR(r.face_checks[1].deepest_gouge_point.z(), 9.9, 0.02);
  EXPECT_NEAR(r.face_checks[5].deepest_gouge_point.x(), 39.92, 0.02);
  int listed = 0;
  for (const FaceVerification& f : r.face_checks) listed += f.gouges;
  EXPECT_EQ(listed, r.gouges) << "every gouge lies under one face";
  // The JSON lists every face.
  const nlohmann::json j = nlohmann::json::parse(reportJson(r));
  ASSERT_EQ(j["face_checks"].size(), 6u);
  EXPECT_EQ(j["face_checks"][5]["face"], 5);
  EXPECT_NEAR(j["face_checks"][5]["deepest_gouge_mm"].get<double>(), 0.08, 0.01);
  // Without faces, no list.
  EXPECT_TRUE(verifyToolpath(kBlock, {}, path, {kFlat}, o).face_checks.empty());
}

TEST(Simulation, GougesGoToTheMovesThatMadeThemAlongAStraightRun) {
  // Points every 0.5 mm on one line 0.03 mm into the top (swept as one segment). A move gouges when it removes part
  // material: from when the front of the flat bottom passes 0.01 mm over the edge (the move to x = -2.5) until the
  // crescent it adds leaves the top (the move to about x = 40, the last slivers as thin as the rays allow).
  Toolpath path = {at("flat6", MoveKind::Rapid, -10, 10, 40)};
  for (double x = -10; x <= 50; x += 0.5) path.push_back(at("flat6", MoveKind::Feed, x, 10, 9.97));
  VerifyOptions o = options(0.2, 2);
  o.max_listed = 1000;
  const auto r = verify(path, kFlat, o);
  EXPECT_NEAR(r.worst_gouge_mm, 0.03, 0.005);
  int first = 1 << 30, last = 0;
  for (const GougeRecord& g : r.gouge_list) {
    first = std::min(first, g.point);
    last = std::max(last, g.point);
    EXPECT_NEAR(g.tip.x(), path[g.point].tip.x(), 0.5);
  }
  EXPECT_EQ(r.gouges, last - first + 1);  // every move between
  EXPECT_DOUBLE_EQ(path[first].tip.x(), -2.5);
  EXPECT_GE(path[last].tip.x(), 39.0);
  EXPECT_LE(path[last].tip.x(), 40.5);
}

TEST(Simulation, TiltedDipIsMeasuredAlongTheNormal) {
  // The block, the path and the tool axis turned together, so no family of rays runs along the face's normal.
  const Eigen::Matrix3d turn =
      (Eigen::AngleAxisd(0.5, Vec3::UnitX()) * Eigen::AngleAxisd(0.3, Vec3::UnitY())).toRotationMatrix();
  Mesh block = kBlock;
  for (Vec3& v : block.vertices) v = turn * v;
  for (const Tool& tool : {kFlat, kBall}) {
    Toolpath path = pass(tool.id, Vec3(10, 10, 9.95), Vec3(30, 10, 9.95));
    for (CutterLocation& c : path) {
      c.tip = turn * c.tip;
      c.axis = turn * c.axis;
    }
    const auto r = verifyToolpath(block, {}, path, {tool}, options(0.25, 2));
    EXPECT_NEAR(r.worst_gouge_mm, 0.05, 0.01) << tool.id;
    EXPECT_EQ(r.collisions, 0) << tool.id;
  }
}

TEST(Simulation, HolderTouchingTheStockIsACollision) {
  // 10 mm deep in the 10 mm margin beside the block, clear of it; the holder's face sits 8 mm above the tip.
  const Tool short_tool = endMill("short", ToolType::Flat, 6, 8, 8);
  const auto r = verify(pass("short", Vec3(5, -5, 10), Vec3(35, -5, 10)), short_tool, options(0.25, 10));
  EXPECT_EQ(r.gouges, 0);
  ASSERT_GT(r.collisions, 0);
  EXPECT_EQ(r.collision_list[0].kind, CollisionKind::Holder);
  EXPECT_NEAR(r.worst_collision_mm, 2.0, 0.05);
  EXPECT_EQ(r.by_op.at(0).collisions, r.collisions);  // the op's own figures: its moves, not rapids, the worst
  EXPECT_EQ(r.by_op.at(0).rapid_collisions, 0);
  EXPECT_EQ(r.by_op.at(0).worst_collision_mm, r.worst_collision_mm);
  // Flutes 8 mm long on a long shank: the shank rubs instead.
  const Tool shank_tool = endMill("shank", ToolType::Flat, 6, 8, 30);
  const auto s = verify(pass("shank", Vec3(5, -5, 10), Vec3(35, -5, 10)), shank_tool, options(0.25, 10));
  ASSERT_GT(s.collisions, 0);
  EXPECT_EQ(s.collision_list[0].kind, CollisionKind::Shank);
}

TEST(Simulation, RapidThroughTheStockIsACollision) {
  Toolpath path = {at("flat6", MoveKind::Rapid, -20, -5, 40), at("flat6", MoveKind::Rapid, -20, -5, 5),
                   at("flat6", MoveKind::Rapid, 60, -5, 5)};
  const auto r = verify(path, kFlat, options(0.25, 10));
  ASSERT_GT(r.collisions, 0);
  EXPECT_EQ(r.collision_list[0].kind, CollisionKind::Rapid);
  EXPECT_EQ(r.collision_list[0].point, 2);
  EXPECT_EQ(r.by_op.at(0).rapid_collisions, r.collisions);
}

TEST(Simulation, CleanPathAroundAndAboveThePartPasses) {
  // A contour touching the block's walls exactly, then a facing pass 0.2 mm above its top.
  const double R = 3;
  Toolpath path = {at("flat6", MoveKind::Rapid, -R, -R, 40)};
  for (const Vec3& p : {Vec3(-R, -R, 0.5), Vec3(40 + R, -R, 0.5), Vec3(40 + R, 20 + R, 0.5), Vec3(-R, 20 + R, 0.5),
                        Vec3(-R, -R, 0.5), Vec3(-R, -R, 40)})
    path.push_back(at("flat6", MoveKind::Feed, p.x(), p.y(), p.z()));
  path.push_back(at("flat6", MoveKind::Rapid, -R, -1, 40));
  for (double y = -1; y <= 21; y += 4) {
    path.push_back(at("flat6", MoveKind::Feed, -R, y, 10.2));
    path.push_back(at("flat6", MoveKind::Feed, 40 + R, y, 10.2));
  }
  const auto r = verify(path, kFlat, options(0.2, 2));
  EXPECT_EQ(r.gouges, 0) << r.worst_gouge_mm;
  EXPECT_EQ(r.collisions, 0) << r.worst_collision_mm;
  EXPECT_TRUE(r.passed());
  // What is left: the 0.2 mm skin on top and the 2.5 mm of margin under the contour, thickest at the bottom corners
  // (2 mm out in x, y and z: 2 sqrt(3), less half a cell).
  EXPECT_GT(r.leftover_volume_mm3, 0.2 * 40 * 20 + 2 * 40 * 20);
  EXPECT_NEAR(r.leftover_max_mm, 2 * std::sqrt(3.0), 0.25);
  ASSERT_FALSE(r.regions.empty());
  EXPECT_NEAR(r.regions[0].box.min.z(), -2, 1e-9);
}

TEST(Simulation, DiagonalMovePastACornerAtACoarseLatticeIsMeasuredOnItsLine) {
  // A flat 6 mm tool moves diagonally past the block's corner (40, 20) at mid height, `clearance` from the corner's
  // edge, at a 1.6 mm lattice. A sweep pose holding the move's sideways part at its end while it slides along the rays
  // stood 0.56 mm off the line, towards the corner: 0.05 mm of clearance read as a 0.5 mm gouge. Moving 0.5 mm into
  // the corner is a gouge all the same.
  const Vec3 outward = Vec3(1, 1, 0).normalized(), along = Vec3(1, -1, 0).normalized();
  for (const double clearance : {0.05, -0.5}) {
    const Vec3 centre = Vec3(40, 20, 5) + (3 + clearance) * outward;
    const auto r = verify(pass("flat6", centre - 20 * along, centre + 20 * along), kFlat, options(1.6, 2));
    if (clearance > 0) {
      EXPECT_EQ(r.gouges, 0) << r.worst_gouge_mm;
      EXPECT_EQ(r.collisions, 0) << r.worst_collision_mm;
    } else {
      EXPECT_GT(r.gouges, 0);
      EXPECT_LE(r.worst_gouge_mm, 0.5 + 0.01);
    }
  }
}

TEST(Simulation, RapidDownAPassJustCutIsNoCollisionAtACoarseLattice) {
  // A pass in the stock beside the block, then a rapid straight down into the groove it cut, on the same line: the
  // tool comes down inside what it swept. At a 3 mm lattice, poses half a spacing apart leave cusps of 0.09 mm on
  // the groove's sides (step^2 / 8r) that the rapid read as a collision; the cusp bound holds the step to 0.35 mm.
  Toolpath path = {at("flat6", MoveKind::Rapid, -10, -6, 40), at("flat6", MoveKind::Feed, -10, -6, 2),
                   at("flat6", MoveKind::Feed, 50, -6, 2), at("flat6", MoveKind::Feed, 50, -6, 40)};
  for (double x = 3.3; x < 40; x += 4.1) {
    path.push_back(at("flat6", MoveKind::Rapid, x, -6, 40));
    path.push_back(at("flat6", MoveKind::Rapid, x, -6, 2.5));
    path.push_back(at("flat6", MoveKind::Rapid, x, -6, 40));
  }
  VerifyOptions o = options(3.0, 10);
  const auto r = verify(path, kFlat, o);
  EXPECT_EQ(r.collisions, 0) << r.worst_collision_mm;
  EXPECT_EQ(r.gouges, 0);
  o.cusp_step = false;
  const auto cusped = verify(path, kFlat, o);
  EXPECT_GT(cusped.collisions, 0) << "without the bound the cusps are there to be found";
}

TEST(Simulation, TiltingMoveSweepsWithoutGaps) {
  // 20 mm along x while the axis tilts 40 degrees: the holder-length lever makes the fine sub-steps matter.
  const double a = 40 * kPi / 180;
  Toolpath path = {at("flat6", MoveKind::Rapid, 5, -5, 40), at("flat6", MoveKind::Feed, 5, -5, 5),
                   at("flat6", MoveKind::Feed, 25, -5, 5, Vec3(std::sin(a), 0, std::cos(a)))};
  VerifyOptions o = options(0.25, 10);
  const auto normal = verify(path, kFlat, o);
  o.step_fraction = 0.05;
  const auto fine = verify(path, kFlat, o);
  o.step_fraction = 4;  // eight times the bound (and no cusp bound, which would hold the step down): ridges
  o.cusp_step = false;
  const auto coarse = verify(path, kFlat, o);
  EXPECT_GT(fine.poses, 5 * normal.poses);
  EXPECT_NEAR(normal.removed_volume_mm3, fine.removed_volume_mm3, 0.0005 * fine.removed_volume_mm3);
  EXPECT_GT(std::abs(coarse.removed_volume_mm3 - fine.removed_volume_mm3), 0.001 * fine.removed_volume_mm3);
  EXPECT_EQ(normal.gouges, 0);
}

TEST(Simulation, ThreadCountDoesNotChangeTheResult) {
  const Toolpath path = pass("ball6", Vec3(10, 10, 9.9), Vec3(30, 12, 9.9));
  VerifyOptions o = options(0.3, 2);
  o.threads = 1;
  const auto one = verify(path, kBall, o);
  o.threads = 3;
  const auto three = verify(path, kBall, o);
  EXPECT_DOUBLE_EQ(one.removed_volume_mm3, three.removed_volume_mm3);
  EXPECT_DOUBLE_EQ(one.worst_gouge_mm, three.worst_gouge_mm);
  EXPECT_EQ(one.gouges, three.gouges);
}

// ---- checkpoints: a verification resumed where an earlier one's path was the same -----------------------------------

// Three setups over the block: a dip into the part (a gouge to carry over), a facing pass over its top, and two
// passes; `last` moves the last setup's second pass, `first_dip` the first setup's dip.
Toolpath threeSetups(double last, double first_dip = 9.95) {
  Toolpath path;
  auto add = [&](Toolpath piece, int setup, int op) {
    for (CutterLocation& c : piece) c.setup = setup, c.op = op, path.push_back(c);
  };
  add(pass("flat6", Vec3(10, 10, first_dip), Vec3(30, 10, first_dip)), 0, 0);
  add(pass("flat6", Vec3(-3, 5, 11), Vec3(43, 5, 11)), 1, 1);
  add(pass("flat6", Vec3(-3, 15, 11), Vec3(43, 15, 11)), 2, 2);
  add(pass("flat6", Vec3(-3, last, 10.5), Vec3(43, last, 10.5)), 2, 3);
  return path;
}

// The report without the clock and without where its sweep began.
std::string unclocked(VerificationReport r) {
  r.seconds_sweep = r.seconds_total = r.moves_per_second = 0;
  r.resumed_at_row = 0;
  return reportJson(r);
}

TEST(Simulation, AVerificationResumedFromACheckpointReportsWhatTheWholeSweepDoes) {
  VerifyOptions keep = options(0.25, 2);
  keep.checkpoints = 4;
  VerificationState first;
  const auto original = verifyToolpath(kBlock, {}, threeSetups(10), {kFlat}, keep, &first);
  EXPECT_GT(original.gouges, 0);
  ASSERT_EQ(first.checkpoints.size(), 2u) << "at the two setup changes";
  EXPECT_EQ(first.checkpoints[0].row, 4);
  EXPECT_EQ(first.checkpoints[1].row, 8);

  const VerifyOptions o = options(0.25, 2);
  // The last setup changed: resumed at its start, with the first setup's gouge and the second's volume carried.
  const Toolpath changed = threeSetups(12);
  VerificationState whole_state, resumed_state;
  const auto whole = verifyToolpath(kBlock, {}, changed, {kFlat}, o, &whole_state);
  const auto resumed = verifyToolpath(kBlock, {}, changed, {kFlat}, o, &resumed_state, {}, first.checkpoints);
  EXPECT_EQ(resumed.resumed_at_row, 8);
  EXPECT_EQ(whole.resumed_at_row, 0);
  EXPECT_GT(resumed.gouges, 0);
  EXPECT_EQ(unclocked(resumed), unclocked(whole));
  EXPECT_DOUBLE_EQ(resumed_state.stock.volume(), whole_state.stock.volume());
  EXPECT_NE(unclocked(resumed), unclocked(original)) << "the change is seen";
  // A tool the earlier path had and this one does not use (left out with its operation) changes nothing.
  EXPECT_EQ(verifyToolpath(kBlock, {}, changed, {kBall, kFlat}, o, nullptr, {}, first.checkpoints).resumed_at_row, 8);

  // A change in the first setup: nothing to resume from.
  const Toolpath early = threeSetups(10, 9.9);
  const auto early_resumed = verifyToolpath(kBlock, {}, early, {kFlat}, o, nullptr, {}, first.checkpoints);
  EXPECT_EQ(early_resumed.resumed_at_row, 0);
  EXPECT_EQ(unclocked(early_resumed), unclocked(verifyToolpath(kBlock, {}, early, {kFlat}, o)));
  // Nor with another tolerance, another lattice or another tool of the same name.
  VerifyOptions tighter = o;
  tighter.tolerance = 0.005;
  EXPECT_EQ(verifyToolpath(kBlock, {}, changed, {kFlat}, tighter, nullptr, {}, first.checkpoints).resumed_at_row, 0);
  EXPECT_EQ(verifyToolpath(kBlock, {}, changed, {kFlat}, options(0.3, 2), nullptr, {}, first.checkpoints)
                .resumed_at_row,
            0);
  Tool longer = kFlat;
  longer.stickout += 5;
  EXPECT_EQ(verifyToolpath(kBlock, {}, changed, {longer}, o, nullptr, {}, first.checkpoints).resumed_at_row, 0);
}

// keep_sweeping is asked at each checkpoint with the findings so far, counted as the whole report counts them; a
// false stops the sweep there, with the checkpoints so far kept for a later verification to resume from.
TEST(Simulation, ASweepStoppedAtACheckpointReportsTheRowsBeforeItAndResumesFromThere) {
  const Toolpath path = threeSetups(10);
  const VerifyOptions o = options(0.25, 2);
  const auto whole = verifyToolpath(kBlock, {}, path, {kFlat}, o);
  ASSERT_GT(whole.gouges, 0) << "the first setup's dip";
  VerifyOptions gated = o;
  gated.checkpoints = 4;
  std::vector<int> asked;
  gated.keep_sweeping = [&](int row, const VerificationReport& so_far) {
    asked.push_back(row);
    EXPECT_EQ(so_far.gouges, whole.gouges) << "every gouge lies in the first setup, rows before " << row;
    EXPECT_EQ(so_far.by_op.at(0).gouges, whole.by_op.at(0).gouges);
    return row < 8;
  };
  VerificationState state;
  const auto stopped = verifyToolpath(kBlock, {}, path, {kFlat}, gated, &state);
  EXPECT_EQ(asked, (std::vector<int>{4, 8}));
  EXPECT_EQ(stopped.stopped_at_row, 8);
  EXPECT_FALSE(stopped.passed());
  EXPECT_EQ(stopped.gouges, whole.gouges);
  EXPECT_EQ(stopped.leftover_volume_mm3, 0) << "nothing measured";
  ASSERT_EQ(state.checkpoints.size(), 2u);
  EXPECT_EQ(state.checkpoints.back().row, 8);
  const auto resumed = verifyToolpath(kBlock, {}, path, {kFlat}, o, nullptr, {}, state.checkpoints);
  EXPECT_EQ(resumed.resumed_at_row, 8);
  EXPECT_EQ(unclocked(resumed), unclocked(whole));

  // A sweep the gate lets go on is the whole sweep.
  gated.keep_sweeping = [](int, const VerificationReport&) { return true; };
  const auto let_go = verifyToolpath(kBlock, {}, path, {kFlat}, gated);
  EXPECT_EQ(let_go.stopped_at_row, 0);
  EXPECT_EQ(unclocked(let_go), unclocked(whole));
}

TEST(Simulation, APathSweptInPiecesBetweenPlacementsIsSweptAsAWhole) {
  const Toolpath path = threeSetups(10);
  const DexelLattice lattice = DexelLattice::over(stockBox(boundingBox(kBlock), 2), 0.25);
  const MeshDexels part(kBlock, lattice);
  const PartDistance distance(kBlock);
  const std::map<std::string, ToolSolid> tools{{"flat6", toolSolid(kFlat, 0.001)}};
  Stock whole = boxStock(lattice), pieces = boxStock(lattice);
  addSolid(whole, part);
  addSolid(pieces, part);
  const SweepResult all = sweepToolpath(whole, part, distance, path, tools);
  SweepOptions o;
  std::map<int, MoveFinding> findings;
  double removed = 0;
  for (const auto& [first, end] : std::vector<std::pair<int, int>>{{0, 4}, {4, 8}, {8, -1}}) {
    o.first_row = first;
    o.end_row = end;
    const SweepResult piece = sweepToolpath(pieces, part, distance, path, tools, o);
    for (const auto& [row, f] : piece.findings) findings[row] = f;
    for (const auto& [op, swept] : piece.by_op) removed += swept.removed_mm3;
  }
  EXPECT_EQ(findings.size(), all.findings.size());
  EXPECT_DOUBLE_EQ(pieces.volume(), whole.volume());
  double all_removed = 0;
  for (const auto& [op, swept] : all.by_op) all_removed += swept.removed_mm3;
  EXPECT_NEAR(removed, all_removed, 1e-9 * all_removed);
  o.first_row = 5;  // in the middle of the second setup's pass
  o.end_row = -1;
  EXPECT_THROW(sweepToolpath(pieces, part, distance, path, tools, o), InputError);
}

TEST(Simulation, RemainingStockMeshIsClosedAndMeasuresTheStock) {
  VerificationState state;
  const auto r = verifyToolpath(kBlock, {}, pass("flat6", Vec3(5, 10, 12), Vec3(35, 10, 12)), {kFlat},
                                options(0.25, 5), &state);
  const PartDistance distance(kBlock);
  const StockMesh m = remainingStockMesh(state.stock, state.part, distance, 400);
  EXPECT_NEAR(signedVolume(m.mesh), r.remaining_volume_mm3, 0.01 * r.remaining_volume_mm3);
  ASSERT_EQ(m.deviation.size(), m.mesh.triangles.size());
  EXPECT_NEAR(*std::max_element(m.deviation.begin(), m.deviation.end()), 5 * std::sqrt(3.0), 0.3);
}

namespace {

struct CliRun {
  int status = -1;
  std::string out, err;
};

CliRun runCli(const std::string& arguments) {
  const std::string dir = test::tempDir();
  const std::string command = std::string(ART2PART_CLI) + " " + arguments + " > " + dir + "/out 2> " + dir + "/err";
  CliRun r;
  const int raw = std::system(command.c_str());
  r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  auto slurp = [](const std::string& path) {
    std::ifstream in(path);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  r.out = slurp(dir + "/out");
  r.err = slurp(dir + "/err");
  return r;
}

std::string planDir(const Toolpath& path, const Tool& tool) {
  const std::string dir = test::tempDir();
  writeToolpathsCsv(path, dir + "/toolpaths.csv");
  writeToolsJson({tool}, dir + "/tools.json");
  writeBinaryStl(kBlock, dir + "/mesh.stl");
  return dir;
}

}  // namespace

TEST(VerifyCli, CleanDirPassesAndGougingDirFails) {
  const std::string clean = planDir(pass("flat6", Vec3(5, 10, 12), Vec3(35, 10, 12)), kFlat);
  const CliRun ok = runCli("verify " + clean + " --resolution 0.25 --picture " + clean + "/stock.png --stock-out " +
                           clean + "/stock.stl");
  ASSERT_EQ(ok.status, 0) << ok.err;
  const auto j = nlohmann::json::parse(ok.out);
  for (const char* field : {"gouges", "worst_gouge_mm", "collisions", "leftover_volume_mm3", "leftover_max_mm"})
    EXPECT_TRUE(j.contains(field)) << field;
  EXPECT_EQ(j["gouges"], 0);
  EXPECT_TRUE(std::ifstream(clean + "/stock.png").good());
  EXPECT_GT(readMeshFile(clean + "/stock.stl").triangleCount(), 100);

  const std::string gouging = planDir(pass("flat6", Vec3(10, 10, 9.9), Vec3(30, 10, 9.9)), kFlat);
  const CliRun bad = runCli("verify " + gouging + " --resolution 0.25");
  EXPECT_EQ(bad.status, 1) << bad.err;
  const auto b = nlohmann::json::parse(bad.out);
  EXPECT_GT(b["gouges"].get<int>(), 0);
  EXPECT_NEAR(b["worst_gouge_mm"].get<double>(), 0.1, 0.01);

  const CliRun missing = runCli("verify /nonexistent-dir");
  EXPECT_EQ(missing.status, 1);
  EXPECT_EQ(std::count(missing.err.begin(), missing.err.end(), '\n'), 1) << missing.err;
  EXPECT_EQ(runCli("verify").status, 2);
}
