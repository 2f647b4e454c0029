// Constant-engagement clearing: the engagement the cutter meets, measured by an independent pixel sweep
// (engagement_sweep.h), stays under the angle asked wherever the bound is claimed; the slab is cleared; the cuts stay
// in the centre region.
#include "art2part/roughing/engagement_clearing.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "engagement_sweep.h"
#include "region_shapes.h"

using namespace art2part;
using namespace art2part::test;

namespace {

constexpr double kPi = 3.14159265358979323846;
// mm a rapid down into the slab keeps between the cutter's disc and the material left: more than a pixel model or the
// planner's regions can be off by (mount_rush's step-up pass: 0.05 mm inside the cleared ground, a rapid met 0.044 mm
// of stock in the simulation).
constexpr double kRapidClearance = 0.1;

ClearingOptions optionsOf() {
  ClearingOptions options;
  options.clearance_z = 10;
  options.safe_height = 1;
  options.ramp_angle_deg = 3;
  options.stay_down = true;
  return options;
}

// A slab as roughing makes one: the tool centre anywhere its disc, grown by the allowance, misses the islands (the
// part), up to `beyond` outside the stock; air where the disc misses the stock.
struct Slab {
  Region stock, islands;
  ClearingLevel level;
};

Slab slabOf(const Region& stock, const Region& islands, double r) {
  Slab slab{stock, islands, {}};
  slab.level.z = -5;
  slab.level.top = 0;
  slab.level.centre = subtract(offsetRegion(stock, r + 0.5), offsetRegion(islands, r + 0.3));
  slab.level.stock_reach = offsetRegion(stock, r + 0.05);
  slab.level.air = subtract(slab.level.centre, slab.level.stock_reach);
  return slab;
}

// Stock everywhere round `centre`: a slab with no air (a pocket).
Slab enclosedSlab(const Region& stock, const Region& centre, double r) {
  Slab slab;
  slab.stock = stock;
  slab.level.z = -5;
  slab.level.top = 0;
  slab.level.centre = centre;
  slab.level.stock_reach = offsetRegion(stock, r + 0.05);
  return slab;
}

struct Measured {
  EngagementFigures figures;
  ClearingStats stats;
  long left = 0;             // material pixels left that the cutter could reach
  bool inside = true;        // every cut at the level lies in the centre region
  double feed_mm = 0, rapid_mm = 0;  // the moves' lengths
};

Measured clearAndMeasure(const Slab& slab, double r, double angle_deg) {
  EngagementOptions engagement;
  engagement.tool_radius = r;
  engagement.max_engagement_deg = angle_deg;
  Measured m;
  const std::vector<ClearingPoint> moves = clearLevelByEngagement(slab.level, optionsOf(), engagement, &m.stats);
  const double pixel = 0.04;
  EngagementSweep sweep(slab.stock, offsetRegion(slab.level.centre, r + 1), pixel);
  // The limit with the measure's own error: two pixels of depth on a straight cut at the angle, seen on a circle a
  // pixel and a half wider than the cutter.
  const double depth = r * (1 - std::cos(angle_deg * kPi / 180));
  const double slack = 180 / kPi * std::acos((r - depth - 2 * pixel) / (r + 1.5 * pixel)) - angle_deg;
  m.figures = sweep.sweep(
      moves, slab.level.z, r, angle_deg + slack, [&](std::size_t i) { return moves[i].move == ClearingMove::Feed; },
      slab.level.top, kRapidClearance);
  // Material the cutter could reach: within r (less two pixels) of the centre region.
  m.left = sweep.materialIn(offsetRegion(slab.level.centre, r - 2 * pixel));
  m.feed_mm = clearingLength(moves, true);
  m.rapid_mm = clearingLength(moves, false);
  const Region grown = offsetRegion(slab.level.centre, 0.001);
  for (std::size_t i = 1; i < moves.size(); ++i)
    if (moves[i].move == ClearingMove::Feed && moves[i].tip.z() == slab.level.z && moves[i - 1].tip.z() == slab.level.z)
      m.inside = m.inside && segmentInside(grown, moves[i - 1].tip.head<2>(), moves[i].tip.head<2>());
  return m;
}

}  // namespace

TEST(EngagementStepover, StraightLimitAndTighterOnTurns) {
  const double r = 5, angle = 40, c = std::cos(angle * kPi / 180);
  EXPECT_NEAR(engagementStepover(r, 0, angle), r * (1 - c), 1e-12);
  EXPECT_NEAR(engagementStepover(r, 1e9, angle), r * (1 - c), 1e-6);
  EXPECT_NEAR(engagementStepover(r, r, angle), 2 * r * (1 - std::cos(angle * kPi / 360)), 1e-12);
  EXPECT_LT(engagementStepover(r, r, angle), engagementStepover(r, 2 * r, angle));
  EXPECT_LT(engagementStepover(r, 2 * r, angle), engagementStepover(r, 0, angle));
  EXPECT_THROW(engagementStepover(0, r, angle), std::invalid_argument);
  EXPECT_THROW(engagementStepover(r, r, 0), std::invalid_argument);
}

TEST(EngagementClearing, BlockWithIslandsIsClearedUnderTheAngle) {
  const double r = 5;
  const Slab slab = slabOf(regionFromPolygons({rectangle(0, 0, 80, 50)}),
                           regionFromPolygons({circle({25, 25}, 8), rectangle(50, 15, 65, 40)}), r);
  const Measured m = clearAndMeasure(slab, r, 40);
  std::printf("block: %.0f mm cut, %.1f mm over the angle (worst %.0f deg), %.1f mm unbounded, %d fronts, %d hops, "
              "%ld pixels left, %.0f mm climb, %.0f mm conventional\n",
              m.figures.cut_mm, m.figures.over_mm, m.figures.worst_deg, m.stats.unbounded_mm, m.stats.passes,
              m.stats.hops, m.left, m.figures.climb_mm, m.figures.conventional_mm);
  EXPECT_TRUE(m.inside);
  // Climb milling: the material on the right of the feed (the spindle turning clockwise), all but where a front
  // meets material on both sides.
  EXPECT_GT(m.figures.climb_mm, 20 * m.figures.conventional_mm);
  EXPECT_EQ(m.left, 0);
  EXPECT_LE(m.figures.over_mm, m.stats.unbounded_mm + 0.01 * m.figures.cut_mm);
}

TEST(EngagementClearing, ClosedPocketStartsWithAHelix) {
  const double r = 4;
  const Slab slab = enclosedSlab(regionFromPolygons({rectangle(-20, -20, 80, 60)}),
                                 regionFromPolygons({rectangle(10, 10, 50, 35)}), r);
  const Measured m = clearAndMeasure(slab, r, 40);
  std::printf("pocket: %.0f mm cut, %.1f mm over the angle (worst %.0f deg), %.1f mm unbounded, %d helices, %ld left, "
              "%.0f mm climb, %.0f mm conventional\n",
              m.figures.cut_mm, m.figures.over_mm, m.figures.worst_deg, m.stats.unbounded_mm, m.stats.contours, m.left,
              m.figures.climb_mm, m.figures.conventional_mm);
  EXPECT_EQ(m.stats.contours, 1);
  EXPECT_GT(m.figures.climb_mm, 20 * m.figures.conventional_mm);
  EXPECT_TRUE(m.inside);
  EXPECT_EQ(m.left, 0);
  // The moves' time at the test's rates (feed 1,000, rapid 10,000 mm/min): the first fronts round the helix are whole
  // rings, each entered at its vertex nearest the tool, not at its first (5.19 min: 5,123 mm of feed and 687 of
  // rapid; from the first vertex 5.21); the stretches start where the front leaves the ground cleared before, not at
  // the far end of a wall edge that ground shares (4.93 min: 4,825 mm of feed, 1,081 of rapid, the gaps along the
  // walls hopped over where that is quicker).
  const ClearingOptions rates = optionsOf();
  const double minutes = m.feed_mm / rates.feed_mm_min + m.rapid_mm / rates.rapid_mm_min;
  std::printf("pocket: %.0f mm of feed, %.0f of rapid, %.2f min\n", m.feed_mm, m.rapid_mm, minutes);
  EXPECT_LT(minutes, 5.0);
}

// A piece of the centre region with no air and too thin for a helix (a channel 0.08 mm wide) is still cut: a lap
// round it.
TEST(EngagementClearing, ThinPieceWithNoAirIsCutByALap) {
  const double r = 3;
  const Slab slab = enclosedSlab(regionFromPolygons({rectangle(-10, -10, 40, 20)}),
                                 regionFromPolygons({rectangle(5, 4.96, 25, 5.04)}), r);
  const Measured m = clearAndMeasure(slab, r, 40);
  EXPECT_EQ(m.stats.contours, 1);
  EXPECT_GT(m.figures.cut_mm, 39.0);  // once round: 2 x 20 mm
  EXPECT_TRUE(m.inside);
  EXPECT_EQ(m.left, 0);
}

TEST(EngagementClearing, RandomSlabsAreClearedUnderTheAngle) {
  std::mt19937 rng(1919);
  std::uniform_real_distribution<double> u(0, 1);
  for (int trial = 0; trial < 4; ++trial) {
    const double r = trial % 2 ? 3 : 5;
    std::vector<Ring> stock{rectangle(0, 0, 50 + 30 * u(rng), 30 + 30 * u(rng))};
    std::vector<Ring> islands;
    const int n = 1 + trial % 3;
    for (int k = 0; k < n; ++k) {
      const Point2 c(10 + 40 * u(rng), 8 + 25 * u(rng));
      if (u(rng) < 0.5)
        islands.push_back(circle(c, 3 + 6 * u(rng), 40));
      else
        islands.push_back(rectangle(c.x(), c.y(), c.x() + 4 + 10 * u(rng), c.y() + 4 + 10 * u(rng)));
    }
    const Slab slab = slabOf(regionFromPolygons(stock), regionFromPolygons(islands), r);
    const Measured m = clearAndMeasure(slab, r, 40);
    std::printf("trial %d: %.0f mm cut, %.1f mm over (worst %.0f deg), %.1f mm unbounded, %ld left, rapids down "
                "into the slab %.2f mm or more from the material\n",
                trial, m.figures.cut_mm, m.figures.over_mm, m.figures.worst_deg, m.stats.unbounded_mm, m.left,
                m.figures.least_rapid_gap);
    EXPECT_TRUE(m.inside) << "trial " << trial;
    EXPECT_EQ(m.left, 0) << "trial " << trial;
    EXPECT_LE(m.figures.over_mm, m.stats.unbounded_mm + 0.01 * m.figures.cut_mm) << "trial " << trial;
    EXPECT_EQ(m.figures.rapids_near_material, 0) << "trial " << trial << ": least gap " << m.figures.least_rapid_gap;
  }
}

// A strip open to air at both short ends only. Two faults showed there: the fronts grew from both ends at once, and
// the tool crossed the strip between them at every front (featuretype's first level cut by engagement: three 143 mm
// crossings; on this strip 90), and a front edge running along a wall from ground cleared before (the union merges a
// wall's collinear vertices into one edge) counted as moved whole, so the tool fed along the wall over ground cut
// before, front after front (6,206 of 13,831 mm of feed ran along the walls; 8,440 mm cut in all now).
TEST(EngagementClearing, StripOpenAtBothEndsIsClearedFromOneEndWithoutFeedingAlongItsWalls) {
  const double r = 5;
  Slab slab = enclosedSlab(regionFromPolygons({rectangle(0, -20, 150, 50)}),
                           regionFromPolygons({rectangle(-10, 0, 160, 30)}), r);
  slab.level.air = subtract(slab.level.centre, slab.level.stock_reach);
  EngagementOptions engagement;
  engagement.tool_radius = r;
  const std::vector<ClearingPoint> moves = clearLevelByEngagement(slab.level, optionsOf(), engagement);
  int crossings = 0;        // moves at any height spanning more than half the strip
  double along_walls = 0;   // feed at the level with both ends within 0.2 mm of a long wall (y = 0 or y = 30)
  for (std::size_t i = 1; i < moves.size(); ++i) {
    const Eigen::Vector3d &a = moves[i - 1].tip, &b = moves[i].tip;
    if ((b.head<2>() - a.head<2>()).norm() > 85) ++crossings;
    const auto onWall = [](double y) { return std::abs(y) < 0.2 || std::abs(y - 30) < 0.2; };
    if (moves[i].move == ClearingMove::Feed && a.z() == slab.level.z && b.z() == slab.level.z && onWall(a.y()) &&
        onWall(b.y()) && std::abs(a.y() - b.y()) < 0.4)
      along_walls += (b - a).norm();
  }
  const Measured m = clearAndMeasure(slab, r, 40);
  std::printf("strip: %.0f mm cut (%.0f along the walls), %.0f mm rapid, %d crossings, %.1f mm over the angle "
              "(worst %.0f deg), %.1f mm unbounded, %ld left\n",
              m.feed_mm, along_walls, m.rapid_mm, crossings, m.figures.over_mm, m.figures.worst_deg,
              m.stats.unbounded_mm, m.left);
  EXPECT_LE(crossings, 1);
  EXPECT_LT(along_walls, 0.1 * m.feed_mm);
  EXPECT_TRUE(m.inside);
  EXPECT_EQ(m.left, 0);
  // Not the 1 % the other slabs keep: the fronts fan out from the corners where the air meets the walls (each new
  // front's fillet passes through the corner), 2.2 % of the cut over the angle, by at most 6 degrees. A known
  // exception (engagement_clearing.h), held here so that it does not grow.
  EXPECT_LE(m.figures.over_mm, m.stats.unbounded_mm + 0.025 * m.figures.cut_mm);
  EXPECT_LE(m.figures.worst_deg, 47.0);
}

// Over 90 degrees (a thin slab's wider engagement) the band is wider than the radius, and where the fronts close a
// hole of material whose half-width lies between r and the band, the last front has no ring: every centre of the
// hole counted as cleared though none was visited (ANC101's first level, 1.7 mm thick at 120 degrees with a 20 mm
// cutter: a strip 2.8 mm wide and 227 mm long stood over the slab, and the next level's rapid at the safe height went
// through it). Plates of several heights, so that the last hole closes at half-widths either side of r.
TEST(EngagementClearing, WideEngagementClearsTheHoleTheLastFrontCloses) {
  const double r = 10;
  // The band 12.7 mm: the last holes close at half-widths of about 7.7, 10.2, 11.4 and (a third front) 1.0 mm.
  for (const double height : {46.0, 51.0, 53.5, 58.0}) {
    const Slab slab = slabOf(regionFromPolygons({rectangle(0, 0, 100, height)}), {}, r);
    const Measured m = clearAndMeasure(slab, r, 120);
    std::printf("plate %.1f mm: %.0f mm cut, %.0f mm rapid, %.1f mm over (worst %.0f deg), %.1f mm unbounded, "
                "%ld left\n",
                height, m.feed_mm, m.rapid_mm, m.figures.over_mm, m.figures.worst_deg, m.stats.unbounded_mm, m.left);
    EXPECT_TRUE(m.inside) << "plate " << height;
    EXPECT_EQ(m.left, 0) << "plate " << height;
    EXPECT_LE(m.figures.over_mm, m.stats.unbounded_mm + 0.01 * m.figures.cut_mm) << "plate " << height;
  }
}
