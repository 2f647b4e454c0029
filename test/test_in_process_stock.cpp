// The stock between setups (in_process_stock.h): what a cut leaves, seen from a setup, is never less than what is there.
#include <gtest/gtest.h>

#include <cmath>

#include "art2part/geometry/part.h"
#include "art2part/roughing/in_process_stock.h"
#include "test_meshes.h"

using namespace art2part;

namespace {

Tool flat10() {
  Tool t;
  t.id = "flat10";
  t.type = ToolType::Flat;
  t.diameter = 10;
  t.flute_length = 22;
  t.shank_diameter = 10;
  t.stickout = 38;
  t.holder = {{32, 20}, {40, 44}};
  return t;
}

// A zig-zag of a 10 mm flat mill with its tip at height z over [x0, x1] x [y0, y1], passes 4 mm apart.
Toolpath raster(double x0, double x1, double y0, double y1, double z) {
  Toolpath path;
  bool forth = true;
  for (double y = y0; y <= y1 + 1e-9; y += 4, forth = !forth)
    for (double x : {forth ? x0 : x1, forth ? x1 : x0}) {
      CutterLocation c;
      c.tool = "flat10";
      c.tip = Vec3(x, y, z);
      path.push_back(c);
    }
  return path;
}

bool inside(const Region& r, double x, double y) { return regionContains(r, Point2(x, y)); }

}  // namespace

TEST(InProcessStock, WhatACutTookIsGoneAndWhatItLeftStays) {
  // A 20 x 20 x 10 part in a 40 x 40 x 20 block; a 10 mm mill clears everything above z = 10.
  const Part part = partFromMesh(test::box(Vec3(10, 10, 0), Vec3(30, 30, 10)), "block");
  const Mesh stock = test::box(Vec3(0, 0, 0), Vec3(40, 40, 20));
  InProcessStock in_process(part, stock, 400, 2.0);  // 2 mm cells
  EXPECT_NEAR(in_process.cell(), 2.0, 1e-9);
  EXPECT_NEAR(in_process.volume(), 40 * 40 * 20, 1e-6);
  in_process.remove(raster(-6, 46, -6, 46, 10), {flat10()});
  // The model keeps what the tool eroded by half a cell's diagonal (1.41 mm) leaves: a film that thick over the cut
  // floor, never less than what the tool left. The volume averages the three ray families, and the x- and y-rays
  // 1 mm over the floor stand for their whole 2 mm cells: at most a film and a cell over it.
  const double film = std::sqrt(2.0);
  EXPECT_GE(in_process.volume(), 40 * 40 * 10 - 1.0);
  EXPECT_LE(in_process.volume(), 40 * 40 * (10 + 2) + 1.0);

  SetupFrame top;  // from +z, origin at 0
  // Above the film and half a cell (a ray stands for its cell): nothing.
  const std::vector<Region> from_top = in_process.slabs(top, {{10 + film + 1.0, 20}, {0, 9}});
  EXPECT_TRUE(regionEmpty(from_top[0])) << regionArea(from_top[0]);
  for (double x : {0.5, 20.0, 39.5})
    for (double y : {0.5, 20.0, 39.5}) EXPECT_TRUE(inside(from_top[1], x, y)) << x << " " << y;
  // Grown by a cell: never far beyond the block.
  EXPECT_FALSE(inside(from_top[1], -5, 20));

  // From +x (frame y along part z): the slab x in [0, 9] holds material only below z = 10 (and not above 10 plus
  // the growth).
  SetupFrame side;
  side.x = Vec3::UnitY();
  side.y = Vec3::UnitZ();
  side.z = Vec3::UnitX();
  const std::vector<Region> from_side = in_process.slabs(side, {{0, 9}});
  EXPECT_TRUE(inside(from_side[0], 20, 5));
  EXPECT_TRUE(inside(from_side[0], 0.5, 0.5));
  EXPECT_FALSE(inside(from_side[0], 20, 19.5));
}

TEST(InProcessStock, AWallThinnerThanACellIsSeen) {
  // A plate 0.6 mm thick standing between two of the z-rays: the x-rays cross it, so every slab from +z holds it.
  const Part part = partFromMesh(test::box(Vec3(100, 100, 0), Vec3(101, 101, 1)), "far away");
  const Mesh plate = test::box(Vec3(10.7, 0, 0), Vec3(11.3, 40, 20));
  InProcessStock in_process(part, plate, 400, 2.0);  // cells wider than the plate
  SetupFrame top;
  const std::vector<Region> slabs = in_process.slabs(top, {{15, 16}, {5, 6}});
  for (const Region& r : slabs) {
    EXPECT_TRUE(inside(r, 11, 20));
    EXPECT_TRUE(inside(r, 11, 1));
  }
}

TEST(InProcessStock, TheFilmOnACutFaceIsNotProvenStock) {
  // The cut of the first test: everything above z = 10 is gone but the film the model keeps on the floor.
  const Part part = partFromMesh(test::box(Vec3(10, 10, 0), Vec3(30, 30, 10)), "block");
  const Mesh stock = test::box(Vec3(0, 0, 0), Vec3(40, 40, 20));
  InProcessStock in_process(part, stock, 400, 2.0);  // 2 mm cells
  in_process.remove(raster(-6, 46, -6, 46, 10), {flat10()});
  SetupFrame top;
  const std::vector<std::pair<double, double>> slabs = {{10, 13}, {0, 9}};
  const std::vector<Region> may = in_process.slabs(top, slabs), proven = in_process.provenSlabs(top, slabs);
  // The film over the floor: in what may be there, not in what is.
  EXPECT_TRUE(inside(may[0], 20, 20));
  EXPECT_TRUE(regionEmpty(proven[0])) << regionArea(proven[0]);
  // Below the floor the stock round the part is there, out to the block's sides (grown back over the proof's cell);
  // the part is no stock.
  for (double x : {0.5, 5.0, 35.0, 39.5}) EXPECT_TRUE(inside(proven[1], x, 20)) << x;
  EXPECT_FALSE(inside(proven[1], 20, 20));
  EXPECT_TRUE(inside(may[1], 20, 20));
}

TEST(InProcessStock, TheAllowanceOverAFinishedPartIsNoStock) {
  // Earlier setups took everything to 0.3 mm of the part: the model holds the part, the allowance and its film, which
  // a later setup would trace round the part at every level as stock. Thicker stock on one side stays proven.
  const Part part = partFromMesh(test::box(Vec3(10, 10, 0), Vec3(30, 30, 10)), "block");
  for (const double side : {0.3, 10.0}) {
    const Mesh stock = test::box(Vec3(9.7, 9.7, 0), Vec3(30 + side, 30.3, 10.3));
    InProcessStock in_process(part, stock, 400, 1.5);
    SetupFrame top;
    const std::vector<Region> may = in_process.slabs(top, {{2, 8}}), proven = in_process.provenSlabs(top, {{2, 8}});
    EXPECT_GE(regionArea(may[0]), 20.6 * 20.6) << side;
    EXPECT_FALSE(inside(proven[0], 20, 20)) << side;     // the part
    EXPECT_FALSE(inside(proven[0], 9.85, 20)) << side;   // the allowance beside it
    if (side < 1) {
      EXPECT_TRUE(regionEmpty(proven[0])) << regionArea(proven[0]);
    } else {
      EXPECT_TRUE(inside(proven[0], 35, 20));            // 5 mm clear of the part, 5 mm from the stock's side
      EXPECT_TRUE(inside(proven[0], 30.5, 20));          // grown back to the allowance
      EXPECT_FALSE(inside(proven[0], 35, 5));            // never far beyond the stock
    }
  }
}

TEST(InProcessStock, StockTwoCellsThickIsProvenAndThinnerIsNot) {
  const Part part = partFromMesh(test::box(Vec3(100, 100, 0), Vec3(101, 101, 1)), "far away");
  SetupFrame top;
  for (const double thickness : {5.0, 3.0}) {  // cells of 2 mm
    const Mesh plate = test::box(Vec3(10, 0, 0), Vec3(10 + thickness, 40, 20));
    InProcessStock in_process(part, plate, 400, 2.0);
    const std::vector<Region> may = in_process.slabs(top, {{5, 15}}), proven = in_process.provenSlabs(top, {{5, 15}});
    EXPECT_TRUE(inside(may[0], 10 + thickness / 2, 20)) << thickness;
    EXPECT_EQ(inside(proven[0], 10 + thickness / 2, 20), thickness > 4) << thickness;
  }
}


TEST(InProcessStock, CutSlabsHoldTheFacesACutLeftNotTheRawOnes) {
  // The first test's block and part, the top cleared only over x <= 23 (a 10 mm mill's centres to x = 18).
  const Part part = partFromMesh(test::box(Vec3(10, 10, 0), Vec3(30, 30, 10)), "block");
  const Mesh stock = test::box(Vec3(0, 0, 0), Vec3(40, 40, 20));
  InProcessStock in_process(part, stock, 400, 2.0);  // 2 mm cells: doubt 1.73 + 4 mm
  SetupFrame top;
  const std::vector<std::pair<double, double>> slabs = {{9, 12}, {0, 3}};
  for (const Region& r : in_process.cutSlabs(top, slabs)) EXPECT_TRUE(regionEmpty(r)) << "nothing cut yet";
  in_process.remove(raster(-6, 18, -6, 46, 10), {flat10()});
  const std::vector<Region> cuts = in_process.cutSlabs(top, slabs);
  // The cut floor (z = 10 and its film) and the cut wall at x = 23 are in the slab round them, grown by the doubt.
  for (double x : {1.0, 12.0, 22.0, 26.0}) EXPECT_TRUE(inside(cuts[0], x, 20)) << x;
  // The block's raw faces are no cut: its top beyond the wall, its side at x = 40, its bottom.
  EXPECT_FALSE(inside(cuts[0], 36, 20));
  EXPECT_TRUE(regionEmpty(cuts[1])) << regionArea(cuts[1]);  // the floor's film is 7 mm above
}

TEST(InProcessStock, AProofAskedBeforeACutIsAskedAgainAfterIt) {
  // The proof's tests across each ray and the projections asked are kept until the model changes: a model asked
  // before a cut answers after it as one that never was. A pocket down the block's middle and a step along one side change
  // which cells the x- and y-rays prove while the z-rays beside them keep their material.
  const Part part = partFromMesh(test::box(Vec3(10, 10, 0), Vec3(30, 30, 4)), "slab");
  const Mesh stock = test::box(Vec3(0, 0, 0), Vec3(40, 40, 20));
  SetupFrame top, side;
  side.x = Vec3::UnitY();
  side.y = Vec3::UnitZ();
  side.z = Vec3::UnitX();
  const std::vector<std::pair<double, double>> slabs = {{14, 19}, {9, 14}, {4, 9}};
  Toolpath cut = raster(14, 26, 14, 26, 8);
  const Toolpath step = raster(-6, 46, -6, 2, 12);
  cut.insert(cut.end(), step.begin(), step.end());
  InProcessStock asked(part, stock, 400, 2.0), fresh(part, stock, 400, 2.0);
  const std::vector<Region> before = asked.provenSlabs(top, slabs);
  for (const SetupFrame& frame : {top, side}) {
    asked.provenSlabs(frame, slabs);
    asked.slabs(frame, slabs);
    asked.cutSlabs(frame, slabs);
  }
  asked.remove(cut, {flat10()});
  fresh.remove(cut, {flat10()});
  for (const SetupFrame& frame : {top, side}) {
    const std::vector<Region> again = asked.provenSlabs(frame, slabs), once = fresh.provenSlabs(frame, slabs);
    const std::vector<Region> may = asked.slabs(frame, slabs), may_once = fresh.slabs(frame, slabs);
    const std::vector<Region> cuts = asked.cutSlabs(frame, slabs), cuts_once = fresh.cutSlabs(frame, slabs);
    for (std::size_t s = 0; s < slabs.size(); ++s) {
      EXPECT_NEAR(regionArea(again[s]), regionArea(once[s]), 1e-6) << s;
      EXPECT_NEAR(regionArea(may[s]), regionArea(may_once[s]), 1e-6) << s;
      EXPECT_NEAR(regionArea(cuts[s]), regionArea(cuts_once[s]), 1e-6) << s;
    }
  }
  // The pocket is gone from the proof from the top.
  EXPECT_TRUE(inside(before[1], 20, 20));
  EXPECT_FALSE(inside(asked.provenSlabs(top, slabs)[1], 20, 20));
}
