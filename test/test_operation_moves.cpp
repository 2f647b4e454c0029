// An operation's moves across its levels: the heights LinkClearance proves links clear at, and the order
// PieceSchedule hands the levels' pieces out in.
#include "art2part/roughing/link_clearance.h"
#include "art2part/roughing/operation_moves.h"

#include <gtest/gtest.h>

#include <optional>
#include <random>

#include "region_shapes.h"

using namespace art2part;
using namespace art2part::test;

namespace {

Region region(const std::vector<Ring>& rings) { return regionFromPolygons(rings); }

}  // namespace

namespace {

// Brute force: the tool at `height` over points of a-b every 0.05 mm, its radius every 0.5 mm of height (and at the
// ends) up to its holder's top (the spindle side above it as wide as the holder), against each slab's stock standing
// `margin` higher and grown by that radius and the margin (in Beside::BodyOnly none for a radius no wider than the
// cutter's: LinkClearance's rule) and `slack`.
bool clearByProbing(const Tool& tool, const std::vector<SlabState>& slabs, const Point2& a, const Point2& b,
                    double height, double margin, LinkClearance::Beside beside, double slack) {
  const int samples = 1 + static_cast<int>((b - a).norm() / 0.05);
  for (const SlabState& slab : slabs) {
    const double from = std::max(0.0, slab.z - height), to = slab.top + margin - height;
    for (double h = from; h <= to + 0.5; h += 0.5) {
      const double at = std::min(h, to);
      if (at < from) break;
      const double radius = at > toolLength(tool) ? holderTopRadius(tool) : toolRadiusAt(tool, at);
      if (radius <= 0) continue;
      const bool keeps = radius > tool.diameter / 2 || beside == LinkClearance::Beside::WholeTool;
      const Region grown = offsetRegion(slab.remaining, radius + (keeps ? margin : 0) + slack);
      for (int i = 0; i <= samples; ++i)
        if (regionContains(grown, a + (b - a) * (static_cast<double>(i) / samples))) return false;
    }
  }
  return true;
}

}  // namespace

// LinkClearance against probing: the height it gives is clear by probing (with 0.05 mm less margin, for the probe's
// spacing) and 0.2 mm lower is not (with 0.05 mm more, under the ceiling); where probing finds the lowest height clear
// with 0.3 mm more margin, it gives that height. Both rules beside the stock: roughing's (the flutes keep none) and
// finishing's (the whole tool keeps the margin).
class LinkClearanceBeside : public testing::TestWithParam<LinkClearance::Beside> {
 protected:
  // A 10 mm end mill in a holder of one step: bodyZones merges none, so probing sees the same body.
  static Tool flat10() {
    Tool tool;
    tool.id = "flat10";
    tool.diameter = 10;
    tool.flute_length = 22;
    tool.shank_diameter = 10;
    tool.stickout = 38;
    tool.holder = {{40, 64}};
    return tool;
  }
};

TEST_P(LinkClearanceBeside, HeightsAreClearByProbingAndNotNeedlesslyHigh) {
  const LinkClearance::Beside beside = GetParam();
  const Tool tool = flat10();
  const double margin = 0.5, ceiling = 60;
  std::mt19937 random(5);
  std::uniform_real_distribution<double> unit(0, 1);
  int raised = 0, lowest_kept = 0, lowest_proven = 0;
  for (int trial = 0; trial < 30; ++trial) {
    SCOPED_TRACE(trial);
    // Slabs 4 mm thick from z = 0 up to 20: a few blocks of stock each, fewer higher up.
    std::vector<SlabState> slabs;
    LinkClearance clearance(tool, margin, beside);
    for (double top = 20; top > 0; top -= 4) {
      std::vector<Ring> blocks;
      for (int i = 0; i < 1 + static_cast<int>(4 * unit(random) * (20 - top) / 20); ++i) {
        const Point2 c(200 * unit(random), 200 * unit(random));
        blocks.push_back(rectangle(c.x(), c.y(), c.x() + 5 + 20 * unit(random), c.y() + 5 + 20 * unit(random)));
      }
      slabs.push_back({top - 4, top, region(blocks)});
      clearance.addSlab(slabs.back(), {});
    }
    const Point2 a(200 * unit(random), 200 * unit(random)), b(200 * unit(random), 200 * unit(random));
    const double lowest = 1;  // under every slab's top: only a way round the stock's sides is clear there
    const double height = clearance.lowestClear(a, b, lowest, ceiling);
    if (height < ceiling) {
      EXPECT_TRUE(clearByProbing(tool, slabs, a, b, height, margin, beside, -0.05)) << "height " << height;
    }
    if (height > lowest + 0.2 && height < ceiling) {  // and no lower: 0.2 mm under it probing finds stock within a zone's reach
      EXPECT_FALSE(clearByProbing(tool, slabs, a, b, height - 0.2, margin, beside, 0.05)) << "height " << height;
      ++lowest_proven;
    }
    if (clearByProbing(tool, slabs, a, b, lowest, margin, beside, 0.3)) {
      EXPECT_EQ(height, lowest);
      ++lowest_kept;
    }
    if (height > lowest && height < ceiling) ++raised;
  }
  EXPECT_GE(raised, 3);       // the random cases include hops over stock
  EXPECT_GE(lowest_kept, 3);  // and ways clear at the lowest height
  EXPECT_GE(lowest_proven, 3);
}

// A link passing a block of stock half the margin farther than the cutter's radius, below its top: roughing's rule
// (the slab lost what the cutter swept) lets the flutes pass there; finishing's (the slab leaves out the skin the
// margin covers) lifts the tool over the block.
TEST_P(LinkClearanceBeside, TheFlutesKeepTheMarginBesideTheStockOnlyWhereTheRuleSaysSo) {
  const LinkClearance::Beside beside = GetParam();
  const Tool tool = flat10();
  const double margin = 1.5, lowest = 2, ceiling = 60;
  LinkClearance clearance(tool, margin, beside);
  clearance.addSlab({0, 10, region({rectangle(0, 0, 20, 20)})}, {});
  const Point2 a(-40, 20 + 5 + margin / 2), b(60, 20 + 5 + margin / 2);  // 5.75 mm from the block's side
  const double height = clearance.lowestClear(a, b, lowest, ceiling);
  if (beside == LinkClearance::Beside::BodyOnly)
    EXPECT_EQ(height, lowest);
  else
    EXPECT_NEAR(height, 10 + margin, 1e-3);  // the flutes' margin over the block's top
}

INSTANTIATE_TEST_SUITE_P(Rules, LinkClearanceBeside,
                         testing::Values(LinkClearance::Beside::BodyOnly, LinkClearance::Beside::WholeTool));

namespace {

// The pieces in the order PieceSchedule hands them out, the tool ending each piece at the first vertex of its outer
// ring.
std::vector<LevelPiece> scheduledOrder(PieceSchedule schedule) {
  std::vector<LevelPiece> order;
  std::optional<Point2> at;
  for (std::size_t k = schedule.next(at); k < schedule.pieces().size(); k = schedule.next(at)) {
    order.push_back(schedule.pieces()[k]);
    at = regionRings(order.back().rings).front().front();
  }
  return order;
}
std::vector<LevelPiece> scheduledOrder(const std::vector<ClearingLevel>& levels, double reach) {
  return scheduledOrder(PieceSchedule(levels, reach));
}

}  // namespace

// Operations cut piece after piece (operation_moves.h): that order is sound only if every piece comes after each
// piece above it within the reach. Checked on random levels of boxes against Clipper: every piece of every level is
// cut once, and a piece whose region grown by the reach meets a piece below it comes first. One reach for every pair
// of levels, or (as roughing's body, wider up the tool) a reach growing with the levels between.
class PieceOrderReach : public testing::TestWithParam<bool> {};  // true: a reach per pair of levels

TEST_P(PieceOrderReach, APieceComesAfterEveryPieceAboveItWithinTheReach) {
  const bool per_pair = GetParam();
  const LevelReach by_levels = [](std::size_t shallower, std::size_t deeper) {
    return 8.0 + 6.0 * static_cast<double>(deeper - shallower);
  };
  std::mt19937 random(3);
  std::uniform_real_distribution<double> unit(0, 1);
  int near_pairs = 0;
  for (int trial = 0; trial < 10; ++trial) {
    SCOPED_TRACE(trial);
    std::vector<ClearingLevel> levels(4);
    for (ClearingLevel& level : levels) {
      std::vector<Ring> boxes;
      for (int i = 0; i < 6; ++i) {
        const Point2 c(300 * unit(random), 300 * unit(random));
        boxes.push_back(rectangle(c.x(), c.y(), c.x() + 2 + 30 * unit(random), c.y() + 2 + 8 * unit(random)));
      }
      level.centre = region(boxes);
    }
    const double reach = 20;  // one reach; per pair, by_levels (14 to 26 mm over these four levels)
    const std::vector<LevelPiece> order =
        per_pair ? scheduledOrder(PieceSchedule(levels, 26, by_levels)) : scheduledOrder(levels, reach);
    for (std::size_t i = 0; i < levels.size(); ++i) {
      double area = 0;
      for (const LevelPiece& piece : order)
        if (piece.level == i) area += regionArea(piece.rings);
      EXPECT_NEAR(area, regionArea(levels[i].centre), 1e-6);
    }
    for (std::size_t a = 0; a < order.size(); ++a)
      for (std::size_t b = 0; b < order.size(); ++b)
        if (order[a].level < order[b].level &&
            !regionEmpty(intersect(
                offsetRegion(order[a].rings, per_pair ? by_levels(order[a].level, order[b].level) : reach),
                order[b].rings))) {
          ++near_pairs;
          EXPECT_LT(a, b) << "a piece cut before one above it within the reach";
        }
  }
  EXPECT_GT(near_pairs, 10);
}

INSTANTIATE_TEST_SUITE_P(OneOrPerPair, PieceOrderReach, testing::Bool());

// Two pockets under one top level: the tool finishes one pocket, level by level, before it crosses to the other.
TEST(PieceOrder, APocketIsFinishedBeforeTheToolCrossesToTheNext) {
  std::vector<ClearingLevel> levels(5);
  levels[0].centre = region({rectangle(0, 0, 300, 60)});
  for (std::size_t i = 1; i < levels.size(); ++i)
    levels[i].centre = region({rectangle(10, 10, 50, 50), rectangle(250, 10, 290, 50)});
  const std::vector<LevelPiece> order = scheduledOrder(levels, 20);
  ASSERT_EQ(order.size(), 9u);
  int crossings = 0;
  for (std::size_t k = 2; k < order.size(); ++k) {
    const bool left = regionContains(order[k].rings, {30, 30}), was_left = regionContains(order[k - 1].rings, {30, 30});
    if (left != was_left) ++crossings;
  }
  EXPECT_EQ(crossings, 1);
  for (std::size_t k = 1; k < 5; ++k) EXPECT_EQ(order[k].level, k);  // down the first pocket
}

// The next piece is the one nearest where the tool ended, not the one nearest the last piece's box: under a long top
// level that ends at its right end, the tool goes down the right pocket first (by boxes both pockets lay as near).
TEST(PieceOrder, TheNextPieceIsTheOneNearestTheTool) {
  std::vector<ClearingLevel> levels(2);
  levels[0].centre = region({rectangle(0, 0, 300, 60)});
  levels[1].centre = region({rectangle(10, 10, 50, 50), rectangle(250, 10, 290, 50)});
  for (const double end : {295.0, 5.0}) {
    SCOPED_TRACE(end);
    PieceSchedule schedule(levels, 20);
    const std::size_t top = schedule.next(std::nullopt);
    ASSERT_LT(top, schedule.pieces().size());
    EXPECT_EQ(schedule.pieces()[top].level, 0u);
    const std::size_t pocket = schedule.next(Point2(end, 30));
    ASSERT_LT(pocket, schedule.pieces().size());
    EXPECT_TRUE(regionContains(schedule.pieces()[pocket].rings, {end < 150 ? 30.0 : 270.0, 30}));
    const std::size_t other = schedule.next(Point2(end, 30));
    ASSERT_LT(other, schedule.pieces().size());
    EXPECT_EQ(schedule.next(Point2(end, 30)), schedule.pieces().size());
  }
}
