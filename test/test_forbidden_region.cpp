// The forbidden region of 3-axis roughing, grown level by level from what is new (forbidden_region.h), against the
// same region computed whole at every level from its definition; and the polygon simplification and point location
// it relies on.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <thread>

#include "art2part/geometry/part.h"
#include "art2part/roughing/forbidden_region.h"
#include "art2part/roughing/roughing.h"
#include "art2part/roughing/shadow.h"
#include "art2part/setup/setup_plan.h"
#include "test_meshes.h"

using namespace art2part;

namespace {

constexpr double kPi = 3.14159265358979323846;

// A closed, outward UV sphere of radius `radius` at the origin: every level cuts it, and the shadow grows at every
// level down to the equator.
Mesh sphere(double radius, int rings, int segments) {
  Mesh m;
  m.vertices.emplace_back(0, 0, radius);
  for (int i = 1; i < rings; ++i) {
    const double polar = kPi * i / rings;
    for (int j = 0; j < segments; ++j) {
      const double azimuth = 2 * kPi * j / segments;
      m.vertices.emplace_back(radius * std::sin(polar) * std::cos(azimuth), radius * std::sin(polar) * std::sin(azimuth),
                              radius * std::cos(polar));
    }
  }
  m.vertices.emplace_back(0, 0, -radius);
  const int south = static_cast<int>(m.vertices.size()) - 1;
  auto at = [&](int ring, int j) { return 1 + (ring - 1) * segments + (j % segments); };
  for (int j = 0; j < segments; ++j) {
    m.triangles.push_back({0, at(1, j), at(1, j + 1)});
    for (int i = 1; i + 1 < rings; ++i) {
      m.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      m.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
    m.triangles.push_back({at(rings - 1, j), south, at(rings - 1, j + 1)});
  }
  return m;
}

Region square(double x0, double y0, double x1, double y1) {
  return regionFromPolygons({{Point2(x0, y0), Point2(x1, y0), Point2(x1, y1), Point2(x0, y1)}});
}

}  // namespace

TEST(SimplifyRegion, StaysWithinTheToleranceBothWays) {
  // A wavy ring: a circle of radius 20 with a 0.02 mm ripple, 2000 vertices.
  std::mt19937 random(7);
  std::uniform_real_distribution<double> ripple(-0.02, 0.02);
  Ring ring;
  for (int k = 0; k < 2000; ++k) {
    const double a = 2 * kPi * k / 2000, r = 20 + ripple(random);
    ring.emplace_back(r * std::cos(a), r * std::sin(a));
  }
  const Region original = regionFromPolygons({ring});
  for (double tolerance : {0.01, 0.05, 0.2}) {
    const Region simple = simplifyRegion(original, tolerance);
    std::size_t before = 0, after = 0;
    for (const auto& p : original) before += p.size();
    for (const auto& p : simple) after += p.size();
    // Below the ripple's amplitude most vertices stay; above it, most go.
    EXPECT_LT(after, tolerance < 0.02 ? before : before / 4) << "tolerance " << tolerance;
    // Each covers the other once grown by the tolerance (plus the arcs' chord error): nothing left over.
    const double grow = tolerance + 2 * kArcTolerance;
    EXPECT_LT(regionArea(subtract(original, offsetRegion(simple, grow))), 1e-6) << "tolerance " << tolerance;
    EXPECT_LT(regionArea(subtract(simple, offsetRegion(original, grow))), 1e-6) << "tolerance " << tolerance;
    // And the simplification was not for nothing: without the growth something sticks out.
    EXPECT_GT(regionArea(subtract(original, simple)) + regionArea(subtract(simple, original)), 0);
  }
  // A ring too small to simplify stays as it is (dropping it would lose material).
  const Region tiny = regionFromPolygons({{Point2(0, 0), Point2(0.01, 0), Point2(0.01, 0.002), Point2(0.005, 0.003),
                                           Point2(0, 0.002)}});
  EXPECT_NEAR(regionArea(simplifyRegion(tiny, 0.05)), regionArea(tiny), 1e-12);
}

TEST(SimplifyRegion, NeverTurnsARingOver) {
  // Thin jagged bands, 40 um wide, simplified at 0.2 mm: the two long sides collapse onto one line, and a ring whose
  // sides cross would wind the other way (an outer ring turned over cuts a hole out of a region: CTC-02's forbidden
  // region lost the part's shadow 27 mm deep that way). Every ring keeps its sense and its area within its perimeter
  // times the tolerance.
  std::mt19937 random(7);
  std::uniform_real_distribution<double> jitter(-0.02, 0.02), step(0.05, 0.4);
  int turned_before = 0;
  for (int trial = 0; trial < 200; ++trial) {
    Ring ring;
    for (double x = 0; x < 30; x += step(random)) ring.emplace_back(x, 0.02 + jitter(random));
    for (double x = 30; x > 0; x -= step(random)) ring.emplace_back(x, -0.02 + jitter(random));
    Region region;
    ClipperLib::Path path;
    for (const Point2& p : ring) path.push_back(toRegionPoint(p));
    if (ClipperLib::Area(path) < 0) std::reverse(path.begin(), path.end());
    region.push_back(path);
    const Region simple = simplifyRegion(region, 0.2);
    ASSERT_EQ(simple.size(), 1u);
    const double before = ClipperLib::Area(path), after = ClipperLib::Area(simple[0]);
    double perimeter = 0;
    for (std::size_t k = 0; k < path.size(); ++k)
      perimeter += std::hypot(static_cast<double>(path[(k + 1) % path.size()].X - path[k].X),
                              static_cast<double>(path[(k + 1) % path.size()].Y - path[k].Y));
    EXPECT_GT(after, 0) << "trial " << trial;
    EXPECT_LE(std::abs(after - before), perimeter * 0.2 * kRegionScale + 1) << "trial " << trial;
    turned_before += after <= 0;
  }
  EXPECT_EQ(turned_before, 0);
}

TEST(RegionLocator, AnswersAsRegionContainsInsideOutsideAndOnTheBoundary) {
  // Unions of random discs and boxes with holes cut out, and two rings laid over each other unmerged (winding 2):
  // random points, every vertex, points on edges (horizontal ones included) and a hair beside them.
  std::mt19937 random(11);
  std::uniform_real_distribution<double> u(-50, 50), radius(1, 15);
  int checked = 0, inside = 0, vertices = 0, boundary = 0;
  for (int trial = 0; trial < 30; ++trial) {
    Region region;
    for (int k = 0; k < 6; ++k) {
      const double x = u(random), y = u(random), r = radius(random);
      Region piece = k % 2 ? square(x - r, y - r / 2, x + r, y + r / 2) : offsetRegion(square(x, y, x + 0.1, y + 0.1), r);
      region = k == 5 ? subtract(region, piece) : unite(region, piece);
    }
    if (trial % 5 == 0) {  // overlapping rings as they are
      const Region extra = square(-10, -10, 10, 10);
      region.insert(region.end(), extra.begin(), extra.end());
    }
    const RegionLocator locator(region);
    std::vector<Point2> points;
    for (int k = 0; k < 2000; ++k) points.emplace_back(u(random), u(random));
    for (const ClipperLib::Path& path : region)
      for (std::size_t i = 0; i < path.size(); ++i) {
        const Point2 a = fromRegionPoint(path[i]), b = fromRegionPoint(path[(i + 1) % path.size()]);
        points.push_back(a);
        points.push_back(0.5 * (a + b));
        points.push_back(0.5 * (a + b) + Point2(0, 1e-4));
        points.push_back(0.5 * (a + b) - Point2(1e-4, 0));
      }
    for (const Point2& p : points) {
      const bool expected = regionContains(region, p);
      ASSERT_EQ(locator.contains(p), expected) << "trial " << trial << " at " << p.transpose();
      ++checked;
      inside += expected;
    }
    for (const ClipperLib::Path& path : region)  // vertices lie on the boundary: inside
      for (const ClipperLib::IntPoint& v : path) boundary += locator.contains(fromRegionPoint(v)), ++vertices;
  }
  EXPECT_GT(inside, checked / 10);
  EXPECT_LT(inside, checked * 9 / 10);
  EXPECT_GT(vertices, 1000);
  EXPECT_EQ(boundary, vertices);
  EXPECT_FALSE(RegionLocator(Region{}).contains(Point2(0, 0)));
}

TEST(OffsetRegion, GrowsARegionWhoseHoleTouchesItsLowestVertex) {
  // A square with a small hole through the vertex Clipper's offset takes for the lowest (largest y, then smallest x),
  // the hole listed first, as Clipper's own results may list them: the offset took the hole for the outer ring and
  // turned every ring over, so the square shrank instead of growing (CTC-02: a holder kept 12 mm from stock instead
  // of 20.5, 1,302 collisions).
  Region region;
  ClipperLib::Path hole{toRegionPoint(Point2(0, 10)), toRegionPoint(Point2(0.5, 9)), toRegionPoint(Point2(1, 9.5))};
  if (ClipperLib::Orientation(hole)) ClipperLib::ReversePath(hole);
  ClipperLib::Path outer{toRegionPoint(Point2(0, 0)), toRegionPoint(Point2(10, 0)), toRegionPoint(Point2(10, 10)),
                         toRegionPoint(Point2(0, 10))};
  region.push_back(hole);
  region.push_back(outer);
  const Region grown = offsetRegion(region, 1.0);
  const double exact = 100 + 4 * 10 + kPi;  // the square's Minkowski sum with a unit disc (the hole closes)
  EXPECT_NEAR(regionArea(grown), exact, 0.05);
  EXPECT_TRUE(regionContains(grown, Point2(-0.5, 5)));
  EXPECT_TRUE(regionContains(grown, Point2(5, 5)));
  const Region shrunk = offsetRegion(region, -1.0);  // erosion: the hole grows, the square shrinks
  EXPECT_LT(regionArea(shrunk), 64);
  EXPECT_GT(regionArea(shrunk), 50);
}

namespace {

std::vector<double> sphereLevels() {
  std::vector<double> levels;
  for (double z = 30; z >= -30; z -= 1) levels.push_back(z);
  return levels;
}

// The region grown level by level from `shadows` (at `levels`) against the definition, whole, at every level.
void expectGrownIsTheWholeRegion(const ShadowStack& shadows, const std::vector<double>& levels) {
  const double r = 5.3;  // cutter radius + allowance
  const std::vector<BodyZone> zones{{12, 40, 6}, {40, 80, 20}};
  const double margin = 0.5;
  ForbiddenRegion grown(shadows, r, zones, margin, true);
  ForbiddenRegion against_part(shadows, r, zones, margin, false);
  // The stock left in each slab: the slab's shadow with a skin that grows downwards (a part section is always in it),
  // and a lump at a place of its own in a few slabs (stock a tool could not reach).
  std::vector<Region> remaining;
  std::vector<StockLeft> left_above;
  remaining.reserve(levels.size());
  double top = 40;
  Region part_shadow_union;
  for (std::size_t i = 0; i < levels.size(); ++i) {
    const double z = levels[i];
    const Region& forbidden = grown.at(z, left_above);
    const Region& forbidden_part = against_part.at(z, {});
    // The definition, whole: the cutter against the shadow at z, each zone against the stock left in every slab
    // reaching above its bottom and the part above it; and without stock, each zone against the part alone.
    Region whole = offsetRegion(shadows.at(z), r), whole_part = whole;
    for (const BodyZone& zone : zones) {
      Region left = shadows.at(z + zone.from);  // redundant with the stock left, which holds the part's sections
      for (const StockLeft& s : left_above)
        if (s.top > z + zone.from) left = unite(left, *s.remaining);
      whole = unite(whole, offsetRegion(left, zone.radius + margin));
      whole_part = unite(whole_part, offsetRegion(shadows.at(z + zone.from), zone.radius + margin));
    }
    for (const auto& [got, want, what] : {std::tuple{&forbidden, &whole, "with stock"},
                                          std::tuple{&forbidden_part, &whole_part, "part only"}}) {
      // Never smaller than the definition (a hair of integer rounding aside), and larger only by the tolerances:
      // 0.1 mm of radius on the body zones (here at most 0.11 mm times the perimeter).
      EXPECT_LT(regionArea(subtract(*want, *got)), 1e-4) << what << " at z " << z;
      EXPECT_LT(regionArea(subtract(*got, *want)), 0.11 * 2 * kPi * 80) << what << " at z " << z;
    }
    const Region section = shadows.at(z);
    Region left = unite(section, offsetRegion(section, 0.5 + 0.05 * i));
    if (i % 10 == 3) left = unite(left, square(40, -5 + static_cast<double>(i) / 10, 45, 0));
    remaining.push_back(left);
    left_above.push_back({top, &remaining.back()});
    top = z;
  }
}

}  // namespace

TEST(ForbiddenRegion, GrownLevelByLevelIsTheWholeRegionUpToItsTolerances) {
  const Mesh part = sphere(25, 48, 96);
  expectGrownIsTheWholeRegion(ShadowStack(part.vertices, part.triangles, sphereLevels()), sphereLevels());
}

// A setup's passes share their shadows: a stack taken after others at other heights (coarser levels, levels between
// its own, out of order) has the same shadows as one of its own, and gains that grow the same region (each of its
// gains lists those of the heights kept between its level and the one above).
TEST(ForbiddenRegion, GrownFromShadowsSharedWithOtherLevelsIsTheWholeRegion) {
  const Mesh part = sphere(25, 48, 96);
  SetupShadows shared(part.vertices, part.triangles);
  shared.stack({-25.5, 24.5, 10, -0.25});
  std::vector<double> between;
  for (double z = -29.5; z <= 30; z += 3) between.push_back(z);
  shared.stack(between);
  const ShadowStack shadows = shared.stack(sphereLevels());
  const ShadowStack own(part.vertices, part.triangles, sphereLevels());
  Region gained;  // the union of the stack's gains down to the level
  for (const double z : sphereLevels()) {
    const Region& a = shadows.at(z);
    const Region& b = own.at(z);
    EXPECT_LT(regionArea(subtract(a, b)) + regionArea(subtract(b, a)), 1e-4) << "z " << z;
    if (shadows.indexAt(z) >= 0) gained = unite(gained, shadows.gain(shadows.indexAt(z)));
    EXPECT_LT(regionArea(subtract(a, gained)), 1e-3) << "z " << z;
  }
  expectGrownIsTheWholeRegion(shadows, sphereLevels());
}

// Shadows of `part` seen along `frame` at the levels of a flat10 rest pass after flat20 (2 and 10 mm step-downs plus
// the critical heights): each a proper region (not negative: an outline taken for a hole) and covered at every level
// by the region grown from the shadow's gains with a flat10's radius and allowance. Returns the levels missed.
namespace {

int levelsMissed(const Part& part, const SetupFrame& frame) {
  const std::vector<Vec3> vertices = toFrame(part.mesh.vertices, frame);
  RoughingOptions options;
  double top = -1e300, bottom = 1e300;
  for (const Vec3& p : toFrame(roughingStock(part, options).vertices, frame)) {
    top = std::max(top, p.z());
    bottom = std::min(bottom, p.z());
  }
  std::vector<double> heights;
  for (const RoughingLevel& l : roughingLevels(part, vertices, top, bottom, 10.0, options)) heights.push_back(l.z);
  for (const RoughingLevel& l : roughingLevels(part, vertices, top, bottom, 2.0, options)) heights.push_back(l.z);
  std::sort(heights.begin(), heights.end(), std::greater<double>());
  heights.erase(std::unique(heights.begin(), heights.end()), heights.end());
  const ShadowStack shadows(vertices, part.mesh.triangles, heights);
  ForbiddenRegion grown(shadows, 5.35, {}, 0, false);
  int missed = 0;
  for (double z : heights) {
    EXPECT_GE(regionArea(shadows.at(z)), 0) << "level " << z;
    missed += regionArea(subtract(shadows.at(z), grown.at(z, {}))) > 1e-3 ? 1 : 0;
  }
  return missed;
}

}  // namespace

TEST(ForbiddenRegion, CoversTheShadowOfAPrismaticPartAtEveryLevel) {
  // CTC-01 from +z: hundreds of zero-area rings in the shadow made Clipper take its outline for a hole at 51 of 86
  // levels; the grown region then missed up to 8,984 mm2 of shadow (CTC-02: a rest pass gouged 27 mm deep).
  const Part part = loadPart(std::string(ART2PART_SHARED_PARTS) + "/nist_ctc_01_asme1_rd.stp");
  EXPECT_EQ(levelsMissed(part, setupFrame(part, Vec3::UnitZ())), 0);
}

TEST(ForbiddenRegion, CoversTheShadowOfAPartSeenAHairOffItsAxis) {
  // CTC-02 from its plan's first setup, 2.8 deg off z: at one level 565 slivers (1e-6 to 1e-3 mm2, walls seen nearly
  // edge-on) made Clipper turn the shadow's outline clockwise in a union (area -668,490 mm2 instead of 165,575); the
  // region grown from the gains lost 237,807 mm2 of shadow from there down, and 357 levels of the whole plan fell back
  // to the slow direct offset while its holders collided 1,337 times. Clipper's results are checked for that now.
  const Part part = loadPart(std::string(ART2PART_SHARED_PARTS) + "/nist_ctc_02_asme1_rc.stp");
  SetupFrame frame;  // as plan.json gave it
  frame.origin = Vec3(-7.789229747795405, 382.2107702522046, 63.054355936715524);
  frame.x = Vec3(0.9993913240270815, -0.0005184869639782556, 0.03488140809464474);
  frame.y = Vec3(-0.0006987470723531331, 0.9993914338032633, 0.03487511710642036);
  frame.z = Vec3(-0.03487826274237065, -0.03487826274237065, 0.9987827659587186);
  EXPECT_EQ(levelsMissed(part, frame), 0);
}

// The roughing stage's diagnostic of Clipper failures counts what its own thread met while it planned: not a
// process-wide counter read as a difference, which a plan on another thread (two goals in a node) would add to.
TEST(RegionFailureTally, CountsThisThreadsFailuresAndNests) {
  RegionFailureTally::countFailure();  // no tally open: counted nowhere
  const RegionFailureTally outer;
  RegionFailureTally::countFailure();
  {
    const RegionFailureTally inner;
    RegionFailureTally::countFailure();
    RegionFailureTally::countFailure();
    std::thread other([] {
      const RegionFailureTally own;
      RegionFailureTally::countFailure();
      EXPECT_EQ(own.count(), 1);
    });
    other.join();
    EXPECT_EQ(inner.count(), 2);
    EXPECT_EQ(outer.count(), 1);
  }
  EXPECT_EQ(outer.count(), 3) << "the inner tally's count goes to the one it was opened in";
}
