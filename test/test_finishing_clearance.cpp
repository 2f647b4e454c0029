// Finishing keeps clear of what stands: the stock roughing left along a direction that is no setup's own
// (stock_after_roughing.h), the part between the holes of one helical milling run (helixPaths), and what stands
// between the holes of a drilling run crossed low (hole_links.h). The first two were found on ANC101 in 5-axis mode
// (1 gouge and 4,819 collisions, all in finishing).
#include "art2part/finishing/stock_after_roughing.h"

#include "art2part/finishing/hole_links.h"

#include <gtest/gtest.h>

#include <cmath>

#include "art2part/simulation/verify.h"

#include "test_meshes.h"
#include "test_solids.h"

using namespace art2part;
using namespace art2part::test;

namespace {

// A 60 x 40 x 30 block with a hole opening on its +x face at (60, 20, 15), in a stock that runs 20 mm past that face.
struct SideHole {
  Part part = stepPart(solidBox({0, 0, 0}, {60, 40, 30}), "side_hole_block");
  Mesh stock = box({-2, -2, -2}, {80, 42, 32});
  Hole hole;
  ToolLibrary library;
  SideHole() {
    hole.axis = Vec3::UnitX();
    hole.mouth = Vec3(60, 20, 15);
    hole.diameter = 8;
    hole.depth = hole.total_depth = 10;
    library.tools.push_back(flat6());
  }
};

// Setup 0's roughing along +x, flat6's tip at x = 60.3 over the whole face (roughing's 0.3 mm allowance): its 25 mm
// of flutes take all the stock beyond (the model takes away what the flutes cut).
RoughingPlan roughedPastTheFace() {
  RoughingPlan plan;
  RoughingOperation op;
  op.setup = 0;
  op.tool = "flat6";
  for (int k = 0; k <= 20; ++k) {
    const double z = -5 + 2.0 * k;
    const double y0 = k % 2 ? 45 : -5, y1 = k % 2 ? -5 : 45;
    op.path.push_back(cutterLocation(0, "flat6", MoveKind::Feed, Vec3(60.3, y0, z), Vec3::UnitX()));
    op.path.push_back(cutterLocation(0, "flat6", MoveKind::Feed, Vec3(60.3, y1, z), Vec3::UnitX()));
  }
  plan.operations.push_back(op);
  return plan;
}

// mm^2 of the slabs lying wholly beyond `height` along the frame, per slab on average.
double meanAreaBeyond(const std::vector<SlabState>& slabs, double height) {
  double area = 0;
  int n = 0;
  for (const SlabState& s : slabs)
    if (s.z >= height) area += regionArea(s.remaining), ++n;
  return n ? area / n : 0;
}

}  // namespace

// With nothing roughed the 20 mm of stock past the face stands over the hole's mouth: no tool may make it along +x,
// and every slab past the face holds the stock's whole section. Roughed down to the allowance over the face, what is
// left is within the model's film: the hole is clear, the slabs past the allowance and the film empty.
TEST(StockAfterRoughing, StockOverAHoleAlongATiltedAxisBlocksItUntilRoughingTakesIt) {
  const SideHole s;
  const Tool& tool = s.library.tools.front();
  const SetupFrame frame = setupFrame(s.part, Vec3::UnitX());
  const double face = (Vec3(60, 0, 0) - frame.origin).dot(frame.z);

  const RoughingPlan none;
  StockAfterRoughing raw(s.part, s.stock, none, s.library);
  EXPECT_FALSE(raw.clearOverHole(0, s.hole, tool, 0.5));
  const std::vector<SlabState> raw_slabs = raw.slabs(0, frame);
  ASSERT_FALSE(raw_slabs.empty());
  EXPECT_GT(raw.film(), 0);
  EXPECT_GT(meanAreaBeyond(raw_slabs, face + 2), 0.95 * 44 * 34);  // the stock's section, 44 x 34 mm

  const RoughingPlan roughed = roughedPastTheFace();
  StockAfterRoughing after(s.part, s.stock, roughed, s.library);
  EXPECT_TRUE(after.clearOverHole(0, s.hole, tool, 0.5));
  EXPECT_EQ(meanAreaBeyond(after.slabs(0, frame), face + 0.3 + after.film()), 0);
  // The roughing belongs to setup 0: what setup 1 sees includes it, and a setup before any roughing sees the raw block
  // (setup -1 has none).
  EXPECT_TRUE(after.clearOverHole(1, s.hole, tool, 0.5));
  EXPECT_FALSE(after.clearOverHole(-1, s.hole, tool, 0.5));
}

// Two flat-bottomed holes helix-milled in one run, one opening 30 mm higher than the other, a rib between them
// standing 20 mm over both: every rapid between the holes runs level at the run's clearance height over the rib, and
// the simulation finds no gouge. (Each hole at its own height over its own mouth, the rapid from the high hole's
// height down to the low one's went through the rib.)
TEST(HelixPaths, ARunOfHolesAtDifferentHeightsTraversesLevelOverAllOfThem) {
  // The left block's top at 40, the rib's at 60, the right floor at 10; the holes 10 mm wide, each 75 mm from the rib
  // (beyond HoleOptions::clearance_radius: their own clearance heights do not see it).
  TopoDS_Shape shape = solidBox({0, 0, 0}, {200, 40, 60});
  shape = cut(shape, solidBox({-1, -1, 40}, {95, 41, 61}));
  shape = cut(shape, solidBox({105, -1, 10}, {201, 41, 61}));
  shape = cut(shape, solidCylinder({20.0123, 20.0377, 32}, Vec3::UnitZ(), 5, 9));
  shape = cut(shape, solidCylinder({180.0123, 20.0377, 4}, Vec3::UnitZ(), 5, 7));
  const Part part = stepPart(shape, "helix_run_block");
  const std::vector<Hole> holes = findHoles(part);
  ASSERT_EQ(holes.size(), 2u);
  const ToolLibrary library = loadToolLibrary(std::string(ART2PART_SOURCE_DIR) + "/config/tools.yaml");
  const Tool* tool = library.find("flat6");
  ASSERT_NE(tool, nullptr);
  const double rib_top = 60, clearance = 5;
  const double highest = std::max(holes[0].mouth.z(), holes[1].mouth.z());
  Toolpath run = helixPaths(holes, *tool, 0, rib_top + clearance - highest);
  ASSERT_FALSE(run.empty());
  for (CutterLocation& point : run) point.op = 0;
  // The sideways rapids: all at one height, over the rib.
  int sideways = 0;
  for (std::size_t i = 1; i < run.size(); ++i) {
    const Vec3 d = run[i].tip - run[i - 1].tip;
    if (run[i].move != MoveKind::Rapid || std::hypot(d.x(), d.y()) < 1e-6) continue;
    ++sideways;
    EXPECT_NEAR(run[i].tip.z(), run[i - 1].tip.z(), 1e-9) << "a slanted rapid at point " << i;
    EXPECT_GE(run[i].tip.z(), rib_top + clearance - 1e-9) << "a rapid under the clearance height at point " << i;
  }
  EXPECT_EQ(sideways, 1);  // from the first hole to the second
  const Mesh plugs = holePlugs(holes, {chooseHoleMethod(holes[0], library), chooseHoleMethod(holes[1], library)});
  VerifyOptions options;
  options.resolution = 0.25;
  options.stock_mesh = &plugs;
  const VerificationReport report = verifyToolpath(part.mesh, part.triangle_face, run, {*tool}, options);
  EXPECT_EQ(report.gouges, 0) << report.worst_gouge_mm;
  EXPECT_EQ(report.collisions, 0);
}


namespace {

// The simulation of a drilling run that cuts the holes' plugs: no gouge, no collision of drill, shank or holder.
void expectDrilledClean(const Part& part, const std::vector<Hole>& holes, Toolpath run, const Tool& drill) {
  std::vector<HoleMachining> methods(holes.size());
  for (HoleMachining& m : methods) m.method = HoleMethod::Drill;
  const Mesh plugs = holePlugs(holes, methods);
  VerifyOptions options;
  options.resolution = 0.25;
  options.stock_mesh = &plugs;
  for (CutterLocation& point : run) point.op = 0;
  const VerificationReport report = verifyToolpath(part.mesh, part.triangle_face, run, {drill}, options);
  EXPECT_EQ(report.gouges, 0) << report.worst_gouge_mm;
  EXPECT_EQ(report.collisions, 0);
}

}  // namespace

// Three holes drilled in one run: two in one face, the third beyond a rib standing 20 mm over it. Over the stock
// (here the part alone: nothing left to rough), the drill crosses between the first two at their R planes and lifts
// over the rib only for the third (linkOverStock); at the clearance level every crossing went up 23 mm and down again.
// The simulation finds no gouge and no collision of drill, shank or holder.
TEST(HoleLinks, ARunCrossesLowOverOpenGroundAndLiftsOverWhatStands) {
  TopoDS_Shape shape = solidBox({0, 0, 0}, {200, 40, 60});
  shape = cut(shape, solidBox({-1, -1, 40}, {95, 41, 61}));
  shape = cut(shape, solidBox({105, -1, 40}, {201, 41, 61}));
  for (const double x : {20.0123, 60.0123, 160.0123})
    shape = cut(shape, solidCylinder({x, 20.0377, 30}, Vec3::UnitZ(), 3, 11));
  const Part part = stepPart(shape, "drilled_rib_block");
  std::vector<Hole> holes = findHoles(part);
  ASSERT_EQ(holes.size(), 3u);
  std::sort(holes.begin(), holes.end(), [](const Hole& a, const Hole& b) { return a.mouth.x() < b.mouth.x(); });
  const ToolLibrary library = loadToolLibrary(std::string(ART2PART_SOURCE_DIR) + "/config/tools.yaml");
  const Tool* drill = library.find("drill6");
  ASSERT_NE(drill, nullptr);
  const double rib_top = 60, clearance = 5, margin = 0.5;
  const double clearance_above = rib_top + clearance - 40;

  StockAfterRoughing stock(part, part.mesh, RoughingPlan{}, library);
  const SetupFrame frame = setupFrame(part, Vec3::UnitZ());
  const HoleLink link = linkOverStock(stock.slabs(0, frame), frame, *drill, margin);
  const Toolpath low = drillingPath(holes, *drill, false, 0, clearance_above, {}, link);
  const Toolpath high = drillingPath(holes, *drill, false, 0, clearance_above);

  // The sideways rapids: one between each pair of holes, level; the first low, the second over the rib.
  std::vector<double> crossings;
  for (std::size_t i = 1; i < low.size(); ++i) {
    const Vec3 d = low[i].tip - low[i - 1].tip;
    if (low[i].move != MoveKind::Rapid || std::hypot(d.x(), d.y()) < 1e-6) continue;
    EXPECT_NEAR(d.z(), 0, 1e-9) << "a slanted rapid at point " << i;
    crossings.push_back(low[i].tip.z());
  }
  ASSERT_EQ(crossings.size(), 2u);
  const double r_plane = 40 + HoleOptions{}.retract_height;
  EXPECT_LT(crossings[0], r_plane + 2) << "over the open face between the first two holes";
  EXPECT_GE(crossings[1], rib_top + margin) << "over the rib to the third";
  EXPECT_LT(crossings[1], rib_top + clearance);
  const auto rapidLength = [](const Toolpath& path) {
    double length = 0;
    for (std::size_t i = 1; i < path.size(); ++i)
      if (path[i].move == MoveKind::Rapid) length += (path[i].tip - path[i - 1].tip).norm();
    return length;
  };
  EXPECT_LT(rapidLength(low), rapidLength(high) - 40);

  expectDrilledClean(part, holes, low, *drill);
}

// Two counterbored holes (14 mm x 8 deep over a 6 mm through bore). Where the stock roughing left proves the
// counterbores cut (here the part itself), the drill's R plane lies 2 mm over the counterbore's floor, not 2 mm over
// the mouth: it fed 8 mm of air in every hole before. Where the stock still fills them (the uncut block, which the
// drill could reach 0.5 mm over), the R plane stays 2 mm over the mouth. The simulation finds no gouge and no collision of drill, shank or holder either way.
TEST(HoleLinks, ACounterboreCutBeforeTheDrillHoldsItsRPlane) {
  TopoDS_Shape shape = solidBox({0, 0, 0}, {100, 40, 20});
  const Part block = stepPart(shape, "uncut_block");
  for (const double x : {30.0123, 70.0123}) {
    shape = cut(shape, solidCylinder({x, 20.0377, -1}, Vec3::UnitZ(), 3, 22));
    shape = cut(shape, solidCylinder({x, 20.0377, 12}, Vec3::UnitZ(), 7, 9));
  }
  const Part part = stepPart(shape, "counterbored_block");
  std::vector<Hole> holes = findHoles(part);
  ASSERT_EQ(holes.size(), 2u);
  for (const Hole& hole : holes) ASSERT_NEAR(hole.bore_start, 8, 1e-6);
  const ToolLibrary library = loadToolLibrary(std::string(ART2PART_SOURCE_DIR) + "/config/tools.yaml");
  const Tool* drill = library.find("drill6");
  ASSERT_NE(drill, nullptr);
  const SetupFrame frame = setupFrame(part, Vec3::UnitZ());
  const double retract = HoleOptions{}.retract_height, margin = 0.5;
  // The height of the rapid each feed starts from: the R planes.
  const auto rPlanes = [](const Toolpath& path) {
    std::vector<double> heights;
    for (std::size_t i = 1; i < path.size(); ++i)
      if (path[i].move == MoveKind::Feed && path[i - 1].move == MoveKind::Rapid) heights.push_back(path[i - 1].tip.z());
    return heights;
  };
  StockAfterRoughing cut_stock(part, part.mesh, RoughingPlan{}, library);
  const Toolpath low =
      drillingPath(holes, *drill, false, 0, 5, {}, linkOverStock(cut_stock.slabs(0, frame), frame, *drill, margin));
  StockAfterRoughing full_stock(part, block.mesh, RoughingPlan{}, library);
  const Toolpath high =
      drillingPath(holes, *drill, false, 0, 5, {}, linkOverStock(full_stock.slabs(0, frame), frame, *drill, margin));
  const std::vector<double> low_r = rPlanes(low), high_r = rPlanes(high);
  ASSERT_EQ(low_r.size(), 2u);
  ASSERT_EQ(high_r.size(), 2u);
  for (int h = 0; h < 2; ++h) {
    EXPECT_NEAR(low_r[h], 12 + retract, 1e-6) << "hole " << h;
    EXPECT_NEAR(high_r[h], 20 + retract, 1e-6) << "hole " << h;
  }

  expectDrilledClean(part, holes, low, *drill);
}
