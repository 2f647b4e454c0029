// Clearing one slab: coverage, containment, entries, links and heights of clearLevel's moves.
#include "art2part/roughing/clearing_paths.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <optional>
#include <random>
#include <set>

#include "region_shapes.h"

using namespace art2part;
using namespace art2part::test;

namespace {

constexpr double kPi = 3.14159265358979323846;

Region region(const std::vector<Ring>& rings) { return regionFromPolygons(rings); }

ClearingLevel levelOf(const Region& centre, const Region& air = {}) {
  ClearingLevel level;
  level.z = -3;
  level.top = 0;
  level.centre = centre;
  level.air = air;
  return level;
}

ClearingOptions optionsOf(double stepover = 4, double angle_deg = 0, bool contour = true) {
  ClearingOptions options;
  options.stepover = stepover;
  options.angle_deg = angle_deg;
  options.clearance_z = 10;
  options.safe_height = 1;
  options.ramp_angle_deg = 3;
  options.contour_pass = contour;
  return options;
}

Point2 xy(const ClearingPoint& m) { return m.tip.head<2>(); }

struct Segment {
  Point2 a, b;
};

// Feed moves from a point at the level to a point at the level.
std::vector<Segment> feedsAtLevel(const std::vector<ClearingPoint>& moves, double z) {
  std::vector<Segment> out;
  for (std::size_t i = 1; i < moves.size(); ++i)
    if (moves[i].move == ClearingMove::Feed && moves[i - 1].tip.z() == z && moves[i].tip.z() == z)
      out.push_back({xy(moves[i - 1]), xy(moves[i])});
  return out;
}

double distanceToSegment(const Point2& p, const Segment& s) {
  const Point2 d = s.b - s.a;
  const double t = d.squaredNorm() > 0 ? std::clamp((p - s.a).dot(d) / d.squaredNorm(), 0.0, 1.0) : 0.0;
  return (s.a + t * d - p).norm();
}

// The feeds at the level, and the edges of the region's rings lying in `air` (where the contour pass has nothing to
// cut: clearing_paths.h).
std::vector<Segment> feedsAndAirEdges(const Region& centre, const std::vector<ClearingPoint>& moves, double z,
                                      const Region& air) {
  std::vector<Segment> cuts = feedsAtLevel(moves, z);
  if (!regionEmpty(air))
    for (const Ring& ring : regionRings(centre))
      for (std::size_t i = 0; i < ring.size(); ++i) {
        const Point2& next = ring[(i + 1) % ring.size()];
        if (segmentInside(air, ring[i], next)) cuts.push_back({ring[i], next});
      }
  return cuts;
}

// The largest distance from a point of a `grid` mm lattice in `region` to the nearest of `cuts` (0 when none lies in
// the region).
double farthestFromCuts(const Region& region, const std::vector<Segment>& cuts, double grid) {
  Point2 lo(1e9, 1e9), hi(-1e9, -1e9);
  for (const Ring& ring : regionRings(region))
    for (const Point2& p : ring) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  double worst = 0;
  for (double x = std::floor(lo.x()); x <= hi.x(); x += grid)
    for (double y = std::floor(lo.y()); y <= hi.y(); y += grid) {
      const Point2 p(x, y);
      if (!regionContains(region, p)) continue;
      double best = 1e9;
      for (const Segment& s : cuts) best = std::min(best, distanceToSegment(p, s));
      worst = std::max(worst, best);
    }
  return worst;
}

// The largest distance from a point of a `grid` mm lattice in the region to the nearest feed at the level, or to an
// edge of the region's rings lying in `air`.
double worstCoverage(const Region& centre, const std::vector<ClearingPoint>& moves, double z, double grid = 0.5,
                     const Region& air = {}) {
  return farthestFromCuts(centre, feedsAndAirEdges(centre, moves, z, air), grid);
}

// The largest distance, less the cutter radius r, from a point of a `grid` mm lattice within r of the region (the
// stock the level is to take) to the nearest feed at the level or edge of the region's rings lying in `air` (no stock
// lies within r of one): at most 0 (to within the lattice) when the cutter sweeps all of it.
double worstSweep(const Region& centre, const std::vector<ClearingPoint>& moves, double z, double r,
                  double grid = 0.5, const Region& air = {}) {
  return farthestFromCuts(offsetRegion(centre, r), feedsAndAirEdges(centre, moves, z, air), grid) - r;
}

int upwardRetracts(const std::vector<ClearingPoint>& moves, double clearance_z) {
  int n = 0;
  for (std::size_t i = 1; i < moves.size(); ++i)
    if (moves[i].move == ClearingMove::Rapid && moves[i].tip.z() == clearance_z && moves[i - 1].tip.z() < clearance_z)
      ++n;
  return n;
}

// A sideways rapid below the clearance plane with stay-down links: over this level's centre at the safe height or
// above, or over a cleared level's centre at its z + safe height or above; neither where the column over the level
// is not known clear (ClearingLevel::column_clear).
bool provenClear(const ClearingLevel& level, const ClearingOptions& options, const Point2& a, const Point2& b,
                 double height) {
  if (level.clear_height && level.clear_height(a, b, height, height + 1) <= height) return true;  // the stock model
  if (!level.column_clear) return false;
  if (height >= level.top + options.safe_height - 1e-12 && segmentInside(level.centre, a, b)) return true;
  for (const ClearedLevel& cleared : level.cleared)
    if (height >= cleared.z + options.safe_height - 1e-12 && segmentInside(cleared.centre, a, b)) return true;
  return false;
}

// The properties every result must have: rapids only at the clearance plane or straight down to the safe height
// (with stay-down links, also sideways where provenClear says, and no retract at the end);
// cutting points in `centre` at heights in [z, top + safe]; cutting segments inside `centre` (within 1 um: the
// region's own segment test rounds midpoints of boundary edges to its grid); nothing steeper than the ramp angle but
// plunges, which go straight down to the level, in `air` unless counted, or (descents not known clear) to the safe
// height; no repeated points; stats consistent with the moves.
void expectSound(const ClearingLevel& level, const ClearingOptions& options, const std::vector<ClearingPoint>& moves,
                 const ClearingStats& stats) {
  ASSERT_GE(moves.size(), 3u);
  const double safe = level.top + options.safe_height, slope = std::tan(options.ramp_angle_deg * kPi / 180);
  const Region near_centre = offsetRegion(level.centre, 0.001);
  EXPECT_EQ(moves.front().move, ClearingMove::Rapid);
  if (!level.from) {
    EXPECT_EQ(moves.front().tip.z(), options.clearance_z);
  }
  if (!options.stay_down) {
    EXPECT_EQ(moves.back().move, ClearingMove::Rapid);
    EXPECT_EQ(moves.back().tip.z(), options.clearance_z);
  } else {
    EXPECT_NE(moves.back().move, ClearingMove::Rapid);
  }
  int plunges_into_stock = 0, column_plunges = 0, bad_points = 0, bad_segments = 0, steep = 0;
  for (std::size_t i = 1; i < moves.size(); ++i) {
    const ClearingPoint &m = moves[i], &prev = moves[i - 1];
    ASSERT_GT((m.tip - prev.tip).norm(), 1e-9) << "repeated point at move " << i;
    const double run = (xy(m) - xy(prev)).norm(), dz = m.tip.z() - prev.tip.z();
    switch (m.move) {
      case ClearingMove::Rapid:
        EXPECT_GE(m.tip.z(), safe - 1e-12) << "rapid below the safe height at move " << i;
        if (run > 0) {
          EXPECT_EQ(m.tip.z(), prev.tip.z()) << "slanted rapid at move " << i;
          if (m.tip.z() != options.clearance_z) {
            EXPECT_TRUE(options.stay_down && provenClear(level, options, xy(prev), xy(m), m.tip.z()))
                << "sideways rapid off the clearance plane and not proven clear at move " << i;
          }
        }
        continue;
      case ClearingMove::Plunge:
        EXPECT_EQ(run, 0) << "slanted plunge at move " << i;
        if (m.tip.z() != level.z) {
          EXPECT_FALSE(level.descents_clear) << "plunge above the level at move " << i;
          EXPECT_EQ(m.tip.z(), safe) << "plunge to neither the level nor the safe height at move " << i;
          ++column_plunges;
          break;
        }
        if (!regionContains(level.air, xy(m))) ++plunges_into_stock;
        break;
      case ClearingMove::Feed:
        EXPECT_EQ(m.tip.z(), level.z) << "feed off the level at move " << i;
        [[fallthrough]];
      case ClearingMove::Ramp:
        if (-dz > slope * run + 1e-9) ++steep;
        break;
    }
    if (!regionContains(level.centre, xy(m)) || m.tip.z() < level.z || m.tip.z() > safe + 1e-12) ++bad_points;
    if (run > 0 && !segmentInside(near_centre, xy(prev), xy(m))) ++bad_segments;
  }
  EXPECT_EQ(bad_points, 0) << "cutting points outside the region or the slab";
  EXPECT_EQ(bad_segments, 0) << "cutting segments leaving the region";
  EXPECT_EQ(steep, 0) << "cutting moves steeper than the ramp angle";
  EXPECT_EQ(plunges_into_stock, stats.plunges_into_stock);
  EXPECT_EQ(column_plunges, stats.column_plunges);
  const bool retract_from = options.stay_down && level.from && level.from->z() < options.clearance_z &&
                            moves.front().tip.z() == options.clearance_z;  // straight up from the level before
  EXPECT_EQ(upwardRetracts(moves, options.clearance_z) + (retract_from ? 1 : 0), stats.retracts);
  // Every descent into the slab ends at the level before any cut: the last cutting point is at the level.
  EXPECT_EQ(moves[moves.size() - (options.stay_down ? 1 : 2)].tip.z(), level.z);
}

std::vector<ClearingPoint> clearChecked(const ClearingLevel& level, const ClearingOptions& options,
                                        ClearingStats& stats) {
  std::vector<ClearingPoint> moves = clearLevel(level, options, &stats);
  expectSound(level, options, moves, stats);
  return moves;
}

// v of a point across lines at `angle_deg`.
double across(const Point2& p, double angle_deg) {
  const double a = angle_deg * kPi / 180;
  return -std::sin(a) * p.x() + std::cos(a) * p.y();
}

}  // namespace

TEST(ClearingPaths, EmptyRegionGivesNoMoves) {
  ClearingStats stats;
  EXPECT_TRUE(clearLevel(levelOf({}), optionsOf(), &stats).empty());
  EXPECT_EQ(stats.passes, 0);
}

// A level's own step-over (a thin slab's wider one) replaces the options': lines that far apart, every point of the
// region within half of it of a feed.
TEST(ClearingPaths, ALevelsOwnStepoverSetsItsLines) {
  ClearingLevel level = levelOf(region({rectangle(0, 0, 40, 20)}));
  level.stepover = 10;
  ClearingStats stats;
  const std::vector<ClearingPoint> moves = clearChecked(level, optionsOf(4, 0, false), stats);
  EXPECT_LE(worstCoverage(level.centre, moves, level.z), 5 + 1e-6);
  EXPECT_GT(worstCoverage(level.centre, moves, level.z), 2 + 1e-6);
  std::set<long> lines;  // heights of the long feeds, in um
  for (const Segment& s : feedsAtLevel(moves, level.z))
    if (std::abs(s.b.x() - s.a.x()) > 30) lines.insert(std::lround(s.a.y() * 1000));
  EXPECT_EQ(lines, (std::set<long>{5000, 15000}));
}

TEST(ClearingPaths, RectangleIsCoveredByCentredLinesInOnePass) {
  const ClearingLevel level = levelOf(region({rectangle(0, 0, 40, 20)}));
  ClearingStats stats;
  const std::vector<ClearingPoint> moves = clearChecked(level, optionsOf(4, 0, false), stats);
  EXPECT_LE(worstCoverage(level.centre, moves, level.z), 2 + 1e-6);
  std::set<long> lines;  // heights of the long feeds, in um
  for (const Segment& s : feedsAtLevel(moves, level.z))
    if (std::abs(s.b.x() - s.a.x()) > 30) lines.insert(std::lround(s.a.y() * 1000));
  EXPECT_EQ(lines, (std::set<long>{2000, 6000, 10000, 14000, 18000}));
  EXPECT_EQ(stats.passes, 1);
  EXPECT_EQ(stats.retracts, 1);  // only the last
  EXPECT_EQ(stats.ramps, 1);
  EXPECT_EQ(stats.plunges_in_air + stats.plunges_into_stock, 0);

  ClearingStats with_contour;
  const std::vector<ClearingPoint> contoured = clearChecked(level, optionsOf(4, 0, true), with_contour);
  EXPECT_EQ(with_contour.contours, 1);
  EXPECT_EQ(with_contour.retracts, 1);  // the contour is joined at the level
  EXPECT_LE(worstCoverage(level.centre, contoured, level.z), 2 + 1e-6);
}

TEST(ClearingPaths, RampsAlongTheFirstIntervalAndPlungesOnlyInAir) {
  const Region centre = region({rectangle(0, 0, 40, 20)});
  ClearingStats ramped;
  const std::vector<ClearingPoint> moves = clearChecked(levelOf(centre), optionsOf(), ramped);
  std::size_t ramp_moves = 0;
  for (const ClearingPoint& m : moves) {
    if (m.move != ClearingMove::Ramp) continue;
    ++ramp_moves;
    EXPECT_NEAR(m.tip.y(), 2, 1e-3);  // along the first line
  }
  EXPECT_GE(ramp_moves, 2u);  // 4 mm down at 3 degrees: 76 mm, more than the 40 mm line
  EXPECT_EQ(ramped.plunges_in_air + ramped.plunges_into_stock, 0);

  // Air at the far end of the only pass: the pass is turned round and entered there by a plunge.
  const ClearingLevel level = levelOf(centre, region({rectangle(35, -5, 45, 25)}));
  ClearingStats stats;
  const std::vector<ClearingPoint> plunged = clearChecked(level, optionsOf(), stats);
  EXPECT_EQ(stats.plunges_in_air, 1);
  EXPECT_EQ(stats.ramps, 0);
  EXPECT_EQ(stats.plunges_into_stock, 0);
}

TEST(ClearingPaths, TinyPieceWithNoRoomToRampIsCountedAsPlunge) {
  const ClearingLevel level = levelOf(region({rectangle(0, 0, 40, 20), rectangle(50, 5, 50.3, 5.3)}));
  ClearingStats stats;
  const std::vector<ClearingPoint> moves = clearChecked(level, optionsOf(4, 0, false), stats);
  EXPECT_EQ(stats.plunges_into_stock, 1);
  EXPECT_EQ(stats.ramps, 1);
  EXPECT_EQ(stats.passes, 2);
}

TEST(ClearingPaths, IslandIsNeverCrossedAndNeedsRetracts) {
  const Region island = region({rectangle(20, 10, 40, 30)});
  const ClearingLevel level = levelOf(subtract(region({rectangle(0, 0, 60, 40)}), island));
  ClearingStats stats;
  const std::vector<ClearingPoint> moves = clearChecked(level, optionsOf(), stats);
  EXPECT_LE(worstCoverage(level.centre, moves, level.z), 2 + 1e-6);
  const Region inner = offsetRegion(island, -0.001);
  int inside_island = 0;
  for (std::size_t i = 1; i < moves.size(); ++i) {
    if (moves[i].move == ClearingMove::Rapid) continue;
    for (int k = 0; k <= 50; ++k)
      if (regionContains(inner, xy(moves[i - 1]) + k / 50.0 * (xy(moves[i]) - xy(moves[i - 1])))) ++inside_island;
  }
  EXPECT_EQ(inside_island, 0);
  EXPECT_GE(stats.passes, 2);
  EXPECT_GE(stats.retracts, 2);  // at least one between passes, and the last
  EXPECT_EQ(stats.contours, 2);
}

TEST(ClearingPaths, LinksGoRoundARoundIsland) {
  // A straight link between two points of a convex island's boundary cuts through it: links follow the ring instead,
  // so the lines either side of the island need no more than one extra pass.
  const ClearingLevel level = levelOf(subtract(region({rectangle(0, 0, 60, 40)}), region({circle({25, 20}, 8)})));
  for (double angle : {0.0, 60.0}) {
    SCOPED_TRACE(angle);
    ClearingStats stats;
    const std::vector<ClearingPoint> moves = clearChecked(level, optionsOf(2, angle), stats);
    EXPECT_LE(stats.passes, 2);
    EXPECT_LE(stats.retracts, 3);
    EXPECT_LE(worstCoverage(level.centre, moves, level.z), 1 + 1e-3);
  }
}

TEST(ClearingPaths, SegmentAlongTheBoundaryThatLeavesThroughAVertexIsOutside) {
  // Two boxes with their bottoms on one line: a segment along both bottoms crosses the gap between them, touching
  // the region's rings only at vertices and along edges (contour links rely on segmentInside seeing this).
  const Region boxes = region({rectangle(0, 0, 10, 5), rectangle(15, 0, 25, 5)});
  EXPECT_FALSE(segmentInside(boxes, {5, 0}, {25, 0}));  // its middle is a vertex of the second box
  EXPECT_FALSE(segmentInside(boxes, {10, 0}, {15, 0}));
  EXPECT_TRUE(segmentInside(boxes, {2, 0}, {10, 0}));      // along an edge
  EXPECT_TRUE(segmentInside(boxes, {10, 0}, {10, 5}));     // a whole edge
  EXPECT_TRUE(segmentInside(boxes, {0.3, 0}, {9.7, 4.1}));  // from the boundary inwards
  EXPECT_FALSE(segmentInside(boxes, {5, 2}, {20, 2}));
}

TEST(ClearingPaths, PieceWhoseMiddleLineIsTooShortGetsALineWhereItIsWide) {
  // An hourglass whose neck, on the one line centred over it, is narrower than min_segment.
  const ClearingLevel level = levelOf(region({{{0, 0}, {10, 0}, {5.02, 1}, {10, 2}, {0, 2}, {4.98, 1}}}));
  ClearingStats stats;
  const std::vector<ClearingPoint> moves = clearChecked(level, optionsOf(4, 0, false), stats);
  EXPECT_EQ(stats.passes, 1);
  double longest = 0;
  for (const Segment& s : feedsAtLevel(moves, level.z)) longest = std::max(longest, (s.b - s.a).norm());
  EXPECT_GT(longest, 5);
}

TEST(ClearingPaths, TwoProngedRegionIsCoveredWithFewRetracts) {
  // A U: a base 60 x 15 and two prongs 15 wide, 25 long; cut across the prongs and along them.
  const Region u = region({rectangle(0, 0, 60, 15), rectangle(0, 15, 15, 40), rectangle(45, 15, 60, 40)});
  for (double angle : {0.0, 90.0, 180.0}) {
    SCOPED_TRACE(angle);
    const ClearingLevel level = levelOf(u);
    ClearingStats stats;
    const std::vector<ClearingPoint> moves = clearChecked(level, optionsOf(4, angle), stats);
    EXPECT_LE(worstCoverage(level.centre, moves, level.z), 2 + 1e-3);
    EXPECT_LE(stats.retracts, 3);
    EXPECT_LE(stats.passes, 2);
  }
}

TEST(ClearingPaths, HeightsStayInTheSlabAndCutsEndAtTheLevel) {
  ClearingLevel level = levelOf(subtract(region({circle({0, 0}, 25)}), region({circle({5, 3}, 6)})));
  level.z = -7.5;
  level.top = -4;
  ClearingOptions options = optionsOf(3, 17);
  options.safe_height = 0.5;
  ClearingStats stats;
  const std::vector<ClearingPoint> moves = clearChecked(level, options, stats);
  double lowest = 1e9, highest_cut = -1e9;
  for (const ClearingPoint& m : moves) {
    lowest = std::min(lowest, m.tip.z());
    if (m.move != ClearingMove::Rapid) highest_cut = std::max(highest_cut, m.tip.z());
  }
  EXPECT_EQ(lowest, level.z);
  EXPECT_LE(highest_cut, level.top + options.safe_height);
  // A ramp's last point is exactly at the level, and feeds follow it there.
  for (std::size_t i = 0; i + 1 < moves.size(); ++i) {
    if (moves[i].move == ClearingMove::Ramp && moves[i + 1].move != ClearingMove::Ramp) {
      EXPECT_EQ(moves[i].tip.z(), level.z);
    }
  }
  EXPECT_GE(stats.ramps, 1);
}

TEST(ClearingPaths, AngleTurnsTheLines) {
  const double angle = 30, stepover = 2.5;
  const ClearingLevel level = levelOf(region({circle({10, -4}, 20, 180)}));
  ClearingStats stats;
  const std::vector<ClearingPoint> moves = clearChecked(level, optionsOf(stepover, angle, false), stats);
  double along = 0, total = 0;
  int others = 0;
  std::set<long> heights;
  for (const Segment& s : feedsAtLevel(moves, level.z)) {
    const double dv = across(s.b, angle) - across(s.a, angle), length = (s.b - s.a).norm();
    total += length;
    if (std::abs(dv) < 1e-3) {
      along += length;
      heights.insert(std::lround(across(s.a, angle) / stepover * 100));
    } else if (std::abs(std::abs(dv) - stepover) > 1e-3) {
      ++others;  // neither along the lines nor a link between neighbouring lines
    }
  }
  EXPECT_EQ(others, 0);
  EXPECT_GT(along, 0.8 * total);
  EXPECT_EQ(heights.size(), 16u);  // 40 mm across at 2.5 mm
  std::set<long> fractions;        // the lines lie on one grid of pitch `stepover`
  for (long h : heights) fractions.insert(((h % 100) + 100) % 100);
  EXPECT_EQ(fractions.size(), 1u);
  // Lines alone leave crescents at the boundary between their ends; the contour pass takes them.
  ClearingStats contoured;
  const std::vector<ClearingPoint> all = clearChecked(level, optionsOf(stepover, angle, true), contoured);
  EXPECT_LE(worstCoverage(level.centre, all, level.z), stepover / 2 + 1e-3);
}

TEST(ClearingPaths, NarrowPieceBetweenLinesGetsALine) {
  // Lines centred over the whole region would miss the strip: each piece has its own.
  const ClearingLevel level = levelOf(region({rectangle(0, 0, 40, 20), rectangle(0, 22.3, 30, 23.3)}));
  ClearingStats stats;
  const std::vector<ClearingPoint> moves = clearChecked(level, optionsOf(4, 0, false), stats);
  EXPECT_LE(worstCoverage(level.centre, moves, level.z, 0.25), 2 + 1e-6);
  EXPECT_EQ(stats.passes, 2);
}

TEST(ClearingPaths, LargeRegionWithIslandsIsQuick) {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> x(5, 195), y(5, 145), r(1.5, 6);
  std::vector<Ring> circles;
  for (int i = 0; i < 50; ++i) circles.push_back(circle({x(random), y(random)}, r(random), 48));
  // The tool centre's region for a 6 mm tool: round offsets make dense rings, as in roughing.
  const Region islands = offsetRegion(region(circles), 3);
  ClearingLevel level = levelOf(subtract(region({rectangle(0, 0, 200, 150)}), islands));
  level.air = subtract(level.centre, region({rectangle(10, 10, 190, 140)}));
  const ClearingOptions options = optionsOf(2, 0, true);
  std::size_t vertices = 0;
  for (const auto& path : level.centre) vertices += path.size();

  clearLevel(level, options);  // warm up
  const int runs = 5;
  const auto start = std::chrono::steady_clock::now();
  std::vector<ClearingPoint> moves;
  for (int i = 0; i < runs; ++i) moves = clearLevel(level, options);
  const double ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count() / runs;
  ClearingStats stats;
  moves = clearChecked(level, options, stats);
  std::printf("[ timing   ] 200x150 mm, %zu rings, %zu vertices: %.1f ms, %zu moves, cut %.0f mm, rapid %.0f mm, "
              "%d passes, %d contours, %d ramps, %d plunges in air, %d into stock, %d retracts\n",
              level.centre.size(), vertices, ms, moves.size(), clearingLength(moves, true),
              clearingLength(moves, false), stats.passes, stats.contours, stats.ramps, stats.plunges_in_air,
              stats.plunges_into_stock, stats.retracts);
  EXPECT_LT(ms, 100);  // aim: well under 50 ms with -O2
  EXPECT_LE(worstCoverage(level.centre, moves, level.z, 2.5, level.air), 1 + 1e-3);
  EXPECT_EQ(stats.plunges_into_stock, 0);
}

// The contour pass follows no ring edge in air: round a block the centre region's outer ring runs a tool radius and
// 1 mm beyond the stock, and a lap there cuts nothing. Without it every point of the stock (the block less the part's
// disc) is still within the tool radius of a feed, and the cut is shorter by about that ring's length.
TEST(ClearingPaths, ContoursSkipRingEdgesInAirAndStillSweepAllTheStock) {
  const double r = 5;
  const Region part = region({circle({30, 20}, 8, 64)});
  const Region stock = subtract(region({rectangle(0, 0, 60, 40)}), part);
  const Region centre = subtract(offsetRegion(stock, r + 1), offsetRegion(part, r));
  const ClearingLevel level = levelOf(centre, subtract(centre, offsetRegion(stock, r + 0.1)));
  ClearingStats stats, all_stats;
  const std::vector<ClearingPoint> moves = clearChecked(level, optionsOf(4), stats);
  const std::vector<ClearingPoint> all = clearChecked(levelOf(centre), optionsOf(4), all_stats);
  const std::vector<Segment> feeds = feedsAtLevel(moves, level.z);
  int stock_points = 0;
  for (double x = 0.25; x < 60; x += 0.5)
    for (double y = 0.25; y < 40; y += 0.5) {
      const Point2 p(x, y);
      if (!regionContains(stock, p)) continue;
      ++stock_points;
      double nearest = 1e9;
      for (const Segment& s : feeds) nearest = std::min(nearest, distanceToSegment(p, s));
      EXPECT_LE(nearest, r) << "stock at " << x << ", " << y << " not swept";
    }
  EXPECT_GT(stock_points, 8000);
  const double outer_ring = 2 * (60 + 40) + 2 * kPi * (r + 1);
  EXPECT_LT(clearingLength(moves, true), clearingLength(all, true) - 0.9 * outer_ring);
  EXPECT_EQ(stats.plunges_into_stock, 0);
  EXPECT_EQ(stats.contours, 1);  // the ring round the part only
}

// A contour stretch open at both ends (the rest of its ring in air) is entered at the end nearer the tool: a level
// cut below one that ended at its far end starts where the tool is, instead of going back along the stretch to its
// first point (featuretype's reach pass in its second setup traversed 150-250 mm back at each of its levels).
TEST(ClearingPaths, AnOpenContourStretchStartsAtTheEndNearerTheTool) {
  // A U-shaped band 5 mm wide, open at the top; stock only along its inner side, so its outer edges lie in air.
  const Region inner = region({rectangle(5, 5, 55, 40)});
  const Region centre = subtract(region({rectangle(0, 0, 60, 40)}), inner);
  ClearingLevel level = levelOf(centre, subtract(centre, offsetRegion(inner, 2)));
  level.cleared.push_back({level.top, offsetRegion(centre, 1)});
  ClearingOptions options = optionsOf(8);
  options.stay_down = true;
  for (const Point2& end : {Point2(0, 40), Point2(60, 40)}) {
    SCOPED_TRACE(end.x());
    level.from = Eigen::Vector3d(end.x(), end.y(), level.top);
    ClearingStats stats;
    const std::vector<ClearingPoint> moves = clearChecked(level, options, stats);
    EXPECT_EQ(stats.contours, 1);
    EXPECT_EQ(stats.passes, 0);  // the band is narrower than the step-over: the contour alone sweeps it
    const auto first_cut = std::find_if(moves.begin(), moves.end(),
                                        [](const ClearingPoint& m) { return m.move != ClearingMove::Rapid; });
    ASSERT_NE(first_cut, moves.end());
    EXPECT_LE((xy(*first_cut) - end).norm(), 1.0);
    EXPECT_LE(clearingLength(moves, false), 2.0);  // straight down to the level: no way back along the band
  }
}

// The same band where nothing is known clear over the slab (a rest pass's or a later setup's level): the contour
// starts straight below where the tool stands, at the end of the level above (a reach pass's profile, level after
// level: featuretype's op 21 climbed 18 mm to the clearance plane and fed back down at every level). The way up the
// column and back ends where it began: the tool goes no higher than the safe height over the slab.
TEST(ClearingPaths, ACutStraightBelowTheToolIsEnteredWithoutClimbing) {
  const Region inner = region({rectangle(5, 5, 55, 40)});
  const Region centre = subtract(region({rectangle(0, 0, 60, 40)}), inner);
  ClearingLevel level = levelOf(centre, subtract(centre, offsetRegion(inner, 2)));
  level.column_clear = level.descents_clear = false;
  ClearingOptions options = optionsOf(8);
  options.stay_down = true;
  const Point2 end(0, 40);
  level.from = Eigen::Vector3d(end.x(), end.y(), level.top);
  ClearingStats stats;
  const std::vector<ClearingPoint> moves = clearChecked(level, options, stats);
  const auto first_cut = std::find_if(moves.begin(), moves.end(),
                                      [](const ClearingPoint& m) { return m.move != ClearingMove::Rapid; });
  ASSERT_NE(first_cut, moves.end());
  EXPECT_LE((xy(*first_cut) - end).norm(), 1.0);
  double highest = -1e9;
  for (const ClearingPoint& m : moves) highest = std::max(highest, m.tip.z());
  EXPECT_LE(highest, level.top + options.safe_height + 1e-9) << "the clearance plane is at " << options.clearance_z;
  EXPECT_EQ(stats.retracts, 0);
}

// A strip cut by lines across it, one boustrophedon pass from end to end, with its far end in air: a pass began at
// its end in air whatever that cost, so the tool crossed the whole strip to plunge there (featuretype's thin levels
// crossed the part, 120-170 mm, to begin bands round it). The start is the cheaper by time: on a thin level, where a
// ramp is short, a ramp at the near end beats the rapid to the far one; on a deep level, where a ramp is long, the
// plunge in air at the far end still wins.
TEST(ClearingPaths, APassBeginsAtTheEndThatTakesLessTimeToReachAndEnter) {
  ClearingOptions options = optionsOf(4, 90, false);  // lines along y, across the strip
  options.stay_down = true;
  options.ramp_angle_deg = 10;
  options.feed_mm_min = 1000;
  options.rapid_mm_min = 5000;
  for (const double depth : {0.5, 20.0}) {
    SCOPED_TRACE(depth);
    ClearingLevel level = levelOf(region({rectangle(0, 0, 200, 10)}), region({rectangle(195, -5, 210, 15)}));
    level.z = level.top - depth;
    level.cleared.push_back({level.top, region({rectangle(-20, -20, 220, 30)})});
    const Point2 tool(-5, 5);
    level.from = Eigen::Vector3d(tool.x(), tool.y(), level.top);
    // By time: the rapid to the far end and a plunge there, or a ramp forth and back at the near end.
    const double drop = level.top + options.safe_height - level.z;
    const double far_s = 60 * (205 / options.rapid_mm_min + drop / options.feed_mm_min);
    const double near_s = 60 * 2 * drop / std::tan(options.ramp_angle_deg * kPi / 180) / options.feed_mm_min;
    const bool near = near_s < far_s;
    EXPECT_EQ(near, depth < 1);  // the two cases this test is for
    ClearingStats stats;
    const std::vector<ClearingPoint> moves = clearChecked(level, options, stats);
    EXPECT_EQ(stats.passes, 1);
    const auto first_cut = std::find_if(moves.begin(), moves.end(),
                                        [](const ClearingPoint& m) { return m.move != ClearingMove::Rapid; });
    ASSERT_NE(first_cut, moves.end());
    EXPECT_LE(std::abs(xy(*first_cut).x() - (near ? 0.0 : 200.0)), 5.0);
  }
}

// Open stock whose edge lies in air along one side (the band round a block, a pocket open to the outside): the
// zig-zag, kept zigzagInset inside the rings, no longer reaches the air band, and each pass used to ramp down at its
// start (ANC101's first setups ramped 44 m in all, 18 % of their cutting). A pass within a diameter of air is entered
// from the side: a plunge in the air, a straight feed to its start; so is a closed contour ring near air.
TEST(ClearingPaths, PassesNearAirAreEnteredFromTheSideNotByARamp) {
  const Region centre = region({rectangle(0, 0, 80, 40)});
  const ClearingLevel level = levelOf(centre, region({rectangle(-1, -1, 1, 41)}));
  ClearingOptions options = optionsOf(4, 90, true);  // lines along y: each pass starts a line away from the band
  options.tool_radius = 5;
  ClearingStats stats;
  const std::vector<ClearingPoint> moves = clearChecked(level, options, stats);
  EXPECT_EQ(stats.ramps, 0);
  EXPECT_GE(stats.plunges_in_air, 1);
  const auto first_cut = std::find_if(moves.begin(), moves.end(),
                                      [](const ClearingPoint& m) { return m.move != ClearingMove::Rapid; });
  ASSERT_NE(first_cut, moves.end());
  EXPECT_EQ(first_cut->move, ClearingMove::Plunge);
  EXPECT_TRUE(regionContains(level.air, xy(*first_cut)));
  EXPECT_LE(worstSweep(centre, moves, level.z, options.tool_radius, 1.0, level.air), 0.06);

  // Where a ramp is quicker (steep enough that ramping 4 mm down takes less than the plunge and the feed in), a ramp.
  options.ramp_angle_deg = 60;
  ClearingStats steep;
  clearChecked(level, options, steep);
  EXPECT_GE(steep.ramps, 1);

  // A band round a part, its outer edge in air: the contour alone sweeps it, and its closed ring round the part, 9 mm
  // from the air, is entered from there rather than by a ramp round the part.
  const Region band = subtract(region({rectangle(0, 0, 60, 40)}), region({rectangle(10, 10, 50, 30)}));
  const ClearingLevel round = levelOf(band, subtract(band, region({rectangle(1, 1, 59, 39)})));
  ClearingOptions contour_only = optionsOf(12, 0, true);
  contour_only.tool_radius = 6;
  ClearingStats ring_stats;
  const std::vector<ClearingPoint> ring_moves = clearChecked(round, contour_only, ring_stats);
  EXPECT_EQ(ring_stats.passes, 0);
  EXPECT_EQ(ring_stats.contours, 1);
  EXPECT_EQ(ring_stats.ramps, 0);
  EXPECT_EQ(ring_stats.plunges_in_air, 1);
  EXPECT_LE(worstSweep(band, ring_moves, round.z, contour_only.tool_radius, 1.0, round.air), 0.06);
}

TEST(ClearingPaths, RandomRegionsAreSound) {
  std::mt19937 random(11);
  std::uniform_real_distribution<double> unit(0, 1);
  for (int trial = 0; trial < 40; ++trial) {
    SCOPED_TRACE(trial);
    // Overlapping discs and boxes, less a few discs: cusps, thin necks, islands, separate pieces.
    std::vector<Ring> solid, holes;
    for (int i = 0; i < 6; ++i) {
      const Point2 c(60 * unit(random), 40 * unit(random));
      if (unit(random) < 0.5) solid.push_back(circle(c, 3 + 10 * unit(random), 40));
      else solid.push_back(rectangle(c.x(), c.y(), c.x() + 2 + 25 * unit(random), c.y() + 0.5 + 12 * unit(random)));
    }
    for (int i = 0; i < 4; ++i) holes.push_back(circle({60 * unit(random), 40 * unit(random)}, 1 + 5 * unit(random), 30));
    const Region centre = subtract(region(solid), region(holes));
    if (regionEmpty(centre)) continue;
    ClearingLevel level = levelOf(centre, intersect(centre, region({circle({30, 20}, 15 * unit(random))})));
    ClearingOptions options = optionsOf(0.5 + 4 * unit(random), 180 * unit(random), unit(random) < 0.7);
    options.ramp_angle_deg = 1 + 10 * unit(random);
    if (unit(random) < 0.5) {  // stay-down links, over a cleared level above that covered part of the region
      options.stay_down = true;
      const Region disc = region({circle({30, 20}, 40 * unit(random))});
      level.cleared.push_back({level.top + 2, intersect(offsetRegion(centre, 2), disc)});
      if (unit(random) < 0.5) level.from = Eigen::Vector3d(60 * unit(random), 40 * unit(random), level.top);
    }
    // A cutter wider than the stepover (as the library's are), which the zig-zag keeps inside the rings by
    // zigzagInset in most trials.
    const double r = options.stepover * (0.55 + 1.5 * unit(random));
    if (unit(random) < 0.6) options.tool_radius = r;
    ClearingStats stats;
    const std::vector<ClearingPoint> moves = clearChecked(level, options, stats);
    if (options.contour_pass) {
      // A point between the zig-zag and the rings is within the inset of the contour, and one in the eroded piece
      // within stepover/2 of a line or of the eroded rings.
      const double inset = zigzagInset(options.stepover, options.tool_radius);
      EXPECT_LE(worstCoverage(centre, moves, level.z, 1.0, level.air), options.stepover / 2 + inset + 0.06);
      EXPECT_LE(worstSweep(centre, moves, level.z, r, 1.0, level.air), 0.06) << "stock the cutter never swept";
    }
  }
}

// With the cutter's radius known the zig-zag stops zigzagInset short of the rings: the contour pass sweeps that band,
// cutting at most a stepover into it, and every point of stock within the radius of the region is still swept, for
// less cutting than lines that run to the rings the contour then retraces.
TEST(ClearingPaths, TheZigzagLeavesTheContourABandAtMostAStepoverWide) {
  const ClearingLevel level = levelOf(region({rectangle(0, 0, 80, 40)}));
  ClearingOptions options = optionsOf(4, 0, true);
  ClearingStats full_stats;
  const std::vector<ClearingPoint> full = clearChecked(level, options, full_stats);
  options.tool_radius = 5;
  const double inset = zigzagInset(options.stepover, options.tool_radius);
  EXPECT_NEAR(inset, 2.0, 0.06);
  EXPECT_DOUBLE_EQ(zigzagInset(8, 5), 1.0 - 0.05);  // radius - stepover/2 when that is smaller
  EXPECT_DOUBLE_EQ(zigzagInset(8, 3), 0.0);         // no room: lines to the rings
  ClearingStats stats;
  const std::vector<ClearingPoint> moves = clearChecked(level, options, stats);
  EXPECT_LE(worstSweep(level.centre, moves, level.z, options.tool_radius), 0.02);
  EXPECT_LE(worstCoverage(level.centre, moves, level.z), options.stepover / 2 + 1e-6);
  std::vector<Segment> inner;  // the zig-zag's feeds and links: off the rectangle's rings
  for (const Segment& s : feedsAtLevel(moves, level.z)) {
    const auto off = [](const Point2& p) { return std::min({p.x(), 80 - p.x(), p.y(), 40 - p.y()}); };
    if (off(s.a) > 0.01 && off(s.b) > 0.01) {  // not the contour, nor a link to it
      EXPECT_GE(std::min(off(s.a), off(s.b)), inset - 0.01);
      inner.push_back(s);
    }
  }
  ASSERT_FALSE(inner.empty());
  double widest = 0;  // the contour's radial engagement: from a point of the ring to the nearest zig-zag feed
  for (double t = 0; t < 240; t += 0.25) {
    const Point2 p = t < 80 ? Point2(t, 0) : t < 120 ? Point2(80, t - 80) : t < 200 ? Point2(200 - t, 40)
                                                                               : Point2(0, 240 - t);
    double best = 1e9;
    for (const Segment& s : inner) best = std::min(best, distanceToSegment(p, s));
    widest = std::max(widest, best);
  }
  EXPECT_LE(widest, options.stepover + 1e-6);
  EXPECT_LT(clearingLength(moves, true), clearingLength(full, true) - 0.9 * 10 * 2 * inset)
      << "ten lines, each shorter by the inset at both ends";
}

// Stay-down links (issue 19): round an island that the level above did not have, the tool hops over the island at
// that level's height instead of retracting; between passes it feeds along the level or hops; the level ends where
// its last cut ends. Less time than the clearance-plane links at the same rates, and the same coverage.
TEST(ClearingPaths, StayDownLinksHopOverClearedMaterialInsteadOfRetracting) {
  const Region island = region({rectangle(20, 10, 40, 30)});
  ClearingLevel level = levelOf(subtract(region({rectangle(0, 0, 60, 40)}), island));
  level.cleared.push_back({level.top, region({rectangle(-5, -5, 65, 45)})});
  level.from = Eigen::Vector3d(50, 20, level.top);
  auto seconds = [](const std::vector<ClearingPoint>& moves, const ClearingOptions& options) {
    return 60 * (clearingLength(moves, true) / options.feed_mm_min + clearingLength(moves, false) / options.rapid_mm_min);
  };
  ClearingOptions clearance = optionsOf(), stay = optionsOf();
  stay.stay_down = true;
  ClearingStats over_clearance, stayed;
  const std::vector<ClearingPoint> retracting = clearChecked(level, clearance, over_clearance);
  const std::vector<ClearingPoint> moves = clearChecked(level, stay, stayed);
  EXPECT_EQ(stayed.retracts, 0);
  EXPECT_GE(stayed.hops + stayed.level_links, 1);
  EXPECT_GE(over_clearance.retracts, 2);
  EXPECT_LE(worstCoverage(level.centre, moves, level.z), 2 + 1e-6);
  EXPECT_DOUBLE_EQ(moves.front().tip.x(), 50);  // from where the level before left the tool, straight up
  EXPECT_DOUBLE_EQ(moves.front().tip.y(), 20);
  EXPECT_LT(seconds(moves, stay), seconds(retracting, clearance));
  EXPECT_LT(clearingLength(moves, false), 0.5 * clearingLength(retracting, false));
}

// Passes either side of an island: where going round the island's ring at the level takes less time than a hop and
// a ramp, the tool feeds round it, and the level is entered once.
TEST(ClearingPaths, LinksRoundAnIslandFeedAlongItsRingWhenThatIsQuicker) {
  const ClearingLevel level =
      levelOf(subtract(region({rectangle(0, 0, 100, 40)}), region({rectangle(30, 8, 70, 32)})));
  ClearingOptions stay = optionsOf();
  stay.stay_down = true;
  ClearingStats stats;
  const std::vector<ClearingPoint> moves = clearChecked(level, stay, stats);
  EXPECT_EQ(stats.hops, 0);
  EXPECT_EQ(stats.ramps, 1);
  EXPECT_GE(stats.level_links, 1);
  EXPECT_LE(worstCoverage(level.centre, moves, level.z), 2 + 1e-6);
  EXPECT_LE(clearingLength(moves, false), 20);  // the descent from the clearance plane only
}

// A rest pass's level: its levels above cleared only their own pieces, so skins may stand over its centre above the
// slab (column_clear false). With stay-down links and no stock model, no sideways rapid runs below the clearance
// plane (expectSound: provenClear holds none there): where the same level known clear hops, it feeds along the level
// or retracts.
TEST(ClearingPaths, RestLevelsNeverHopOverAColumnNotKnownClear) {
  const Region island = region({rectangle(20, 10, 40, 30)});
  ClearingLevel level = levelOf(subtract(region({rectangle(0, 0, 60, 40)}), island));
  level.cleared.push_back({level.top, region({rectangle(-5, -5, 65, 45)})});
  level.from = Eigen::Vector3d(50, 20, level.top);
  ClearingOptions stay = optionsOf();
  stay.stay_down = true;
  ClearingStats known, unknown;
  clearChecked(level, stay, known);
  ASSERT_GE(known.hops, 1) << "the level hops where its column is known clear";
  level.column_clear = false;
  const std::vector<ClearingPoint> moves = clearChecked(level, stay, unknown);
  EXPECT_EQ(unknown.hops, 0);
  EXPECT_GE(unknown.retracts + unknown.level_links, known.hops);
  EXPECT_LE(worstCoverage(level.centre, moves, level.z), 2 + 1e-6);
}

// A later setup's level: the in-process model's film may stand over its centre, so no rapid descends below what the
// stock model proves clear over the start (here 4 mm over the slab top, the safe height 1 mm); the tool plunges at the
// feed from there. Where descents are known clear the same level rapids down to the safe height.
TEST(ClearingPaths, DescentsNotKnownClearRapidOnlyDownToWhatTheModelProves) {
  const Region island = region({rectangle(20, 10, 40, 30)});
  ClearingLevel level = levelOf(subtract(region({rectangle(0, 0, 60, 40)}), island));
  const double proven = level.top + 4;
  level.clear_height = [proven](const Point2&, const Point2&, double lowest, double) { return std::max(lowest, proven); };
  for (const bool stay_down : {false, true}) {
    ClearingOptions options = optionsOf();
    options.stay_down = stay_down;
    ClearingStats known, unknown;
    level.column_clear = level.descents_clear = true;
    const std::vector<ClearingPoint> rapid = clearChecked(level, options, known);
    EXPECT_EQ(known.column_plunges, 0);
    const auto lowestRapid = [](const std::vector<ClearingPoint>& moves) {
      double lowest = 1e9;
      for (std::size_t i = 1; i < moves.size(); ++i)
        if (moves[i].move == ClearingMove::Rapid && xy(moves[i]) == xy(moves[i - 1]) &&
            moves[i].tip.z() < moves[i - 1].tip.z())
          lowest = std::min(lowest, moves[i].tip.z());
      return lowest;
    };
    EXPECT_NEAR(lowestRapid(rapid), level.top + 1, 1e-9) << stay_down;
    level.column_clear = level.descents_clear = false;
    const std::vector<ClearingPoint> moves = clearChecked(level, options, unknown);
    EXPECT_GE(unknown.column_plunges, 1) << stay_down;
    EXPECT_GE(lowestRapid(moves), proven - 1e-9) << stay_down;
    EXPECT_LE(worstCoverage(level.centre, moves, level.z), 2 + 1e-6);
  }
}

// A level cut with no tool position yet (a finishing floor piece, written after the pieces before it) but told where
// the tool comes from: it starts in the piece, and at the pass end, quickest to reach from there. Without it, each of
// featuretype's face-milled floor pieces began at its first pass whatever the tool's side, and the op crossed the part
// between them (110 and 137 mm).
TEST(ClearingPaths, ALevelStartsNearWhereTheToolComesFrom) {
  // Two squares, lines along x at y = 2, 6, ..., 18: each one boustrophedon pass from its bottom-left corner to its
  // top-right one, either way round.
  const ClearingLevel plain = levelOf(region({rectangle(0, 0, 20, 20), rectangle(100, 0, 120, 20)}));
  const ClearingOptions options = optionsOf(4);
  const std::vector<std::pair<Point2, Point2>> cases = {
      {{-5, -5}, {0, 2}}, {{25, 25}, {20, 18}}, {{95, -5}, {100, 2}}, {{125, 25}, {120, 18}}};
  for (const auto& [near, start] : cases) {
    SCOPED_TRACE(near.x() + 1000 * near.y());
    ClearingLevel level = plain;
    level.start_near = near;
    ClearingStats stats;
    const std::vector<ClearingPoint> moves = clearChecked(level, options, stats);
    ASSERT_FALSE(moves.empty());
    EXPECT_LE((xy(moves.front()) - start).norm(), 0.01);  // the region's grid
  }
}
