// Cone thinning (thesis 4.1.3.1) on the level-4 sphere (1024 directions; mean spacing sqrt(4 pi / 1024) = 6.3
// degrees, the width of one peeled layer). The skeleton is the last layer, one cell width thick, so the tolerances
// below are in cell widths. The figures each test measures are printed.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>

#include "art2part/roughing/cone_thinning.h"
#include "art2part/sphere/special_directions.h"

using namespace art2part;

namespace {

constexpr double kPi = 3.14159265358979323846;
const double kCell = std::sqrt(4 * kPi / 1024) * 180 / kPi;  // degrees

double degrees(const Vec3& a, const Vec3& b) {
  return std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0)) * 180 / kPi;
}

Cone cap(const DirectionSet& set, const Vec3& axis, double half_angle_deg) {
  return reachCone(set, axis, half_angle_deg);
}

Cone none(const DirectionSet& set) { return Cone((set.size() + 63) / 64, 0); }

Cone unite(Cone a, const Cone& b) {
  for (std::size_t w = 0; w < a.size(); ++w) a[w] |= b[w];
  return a;
}

std::vector<int> members(const DirectionSet& set, const Cone& c) {
  std::vector<int> out;
  for (int d = 0; d < set.size(); ++d)
    if (coneHas(c, d)) out.push_back(d);
  return out;
}

// The definition, by brute force: depth = angle to the nearest direction outside the region (all of them, not only
// those touching it), last layer = candidates within one cell width of the deepest candidate.
Cone referenceLastLayer(const DirectionSet& set, const Cone& region, const Cone& candidates) {
  const double width = std::sqrt(4 * kPi / set.cellCount());
  std::vector<double> depth(set.size(), -1);
  bool bounded = false;
  for (int d : members(set, candidates)) {
    double nearest = kPi;
    for (int o = 0; o < set.size(); ++o)
      if (!coneHas(region, o)) {
        bounded = true;
        nearest = std::min(nearest, std::acos(std::clamp(set.directions[d].dot(set.directions[o]), -1.0, 1.0)));
      }
    depth[d] = nearest;
  }
  if (!bounded) return candidates;
  const double deepest = *std::max_element(depth.begin(), depth.end());
  Cone out = none(set);
  for (int d : members(set, candidates))
    if (depth[d] >= deepest - width - 1e-9) out[d >> 6] |= std::uint64_t(1) << (d & 63);
  return out;
}

Cone randomCone(const DirectionSet& set, std::mt19937& random, int caps) {
  std::normal_distribution<double> gauss;
  std::uniform_real_distribution<double> angle(5, 70);
  Cone cone = none(set);
  for (int k = 0; k < caps; ++k)
    cone = unite(cone, cap(set, Vec3(gauss(random), gauss(random), gauss(random)), angle(random)));
  return cone;
}

const DirectionSet& sphere4() {
  static const DirectionSet set = sampleSphere(4);
  return set;
}

// Axes with the tetrahedron's corners, edge midpoints and face centres (where the cells are the most uneven) and
// random ones.
std::vector<Vec3> testAxes() {
  std::vector<Vec3> axes = {Vec3(1, 1, 1), Vec3(-1, -1, -1), Vec3(1, 0, 0), Vec3(0, 0, 1), Vec3(1, 2, 3),
                            Vec3(-1, 0.2, -0.5)};
  std::mt19937 random(3);
  std::normal_distribution<double> gauss;
  for (int k = 0; k < 60; ++k) axes.emplace_back(gauss(random), gauss(random), gauss(random));
  for (Vec3& a : axes) a.normalize();
  return axes;
}

double nearestSample(const DirectionSet& set, const Vec3& axis) {
  double best = 180;
  for (const Vec3& d : set.directions) best = std::min(best, degrees(d, axis));
  return best;
}

// The sampling itself bounds how close an access direction can be: the nearest sampled direction to an arbitrary
// axis is up to 7 degrees off at level 4 (cells differ in area by 6.5x). So: caps about sampled directions must give
// an access direction within 5 degrees; caps about arbitrary axes within 5 degrees of the best possible. Skeleton
// members are within 2.5 cell widths (16 degrees): the last layer is one cell width deep, measured from an outside
// that the sampling places up to a (coarse) cell beyond the cap.
void expectCentred(const DirectionSet& set, double half_angle, const char* what) {
  double worst_member = 0, worst_access = 0, sum_access = 0, worst_excess = 0, worst_on_sample = 0;
  const std::vector<Vec3> axes = testAxes();
  for (const Vec3& axis : axes) {
    const Cone cone = cap(set, axis, half_angle);
    const std::vector<int> s = members(set, thinCone(set, cone));
    ASSERT_FALSE(s.empty());
    for (int d : s) worst_member = std::max(worst_member, degrees(set.directions[d], axis));
    const int access = accessDirection(set, cone);
    ASSERT_GE(access, 0);
    const double error = degrees(set.directions[access], axis);
    worst_access = std::max(worst_access, error);
    sum_access += error;
    worst_excess = std::max(worst_excess, error - nearestSample(set, axis));
  }
  for (int d = 0; d < set.size(); d += 16) {
    const Vec3& axis = set.directions[d];
    worst_on_sample = std::max(worst_on_sample, degrees(set.directions[accessDirection(set, cap(set, axis, half_angle))], axis));
  }
  std::printf("%s, %zu axes: skeleton members at most %.1f deg off the axis; access direction at most %.1f (mean %.1f), "
              "at most %.1f beyond the nearest sampled direction; about sampled directions at most %.1f\n",
              what, axes.size(), worst_member, worst_access, sum_access / axes.size(), worst_excess, worst_on_sample);
  EXPECT_LT(worst_member, 2.5 * kCell);
  EXPECT_LT(worst_excess, 5);
  EXPECT_LT(sum_access / axes.size(), 5);
  EXPECT_LT(worst_on_sample, 5);
}

}  // namespace

TEST(ConeThinning, ACapThinsToItsAxis) { expectCentred(sphere4(), 40, "40-degree caps"); }
TEST(ConeThinning, AHemisphereThinsToItsPole) { expectCentred(sphere4(), 90, "hemispheres"); }
TEST(ConeThinning, ANarrowCapThinsToItsAxis) { expectCentred(sphere4(), 15, "15-degree caps"); }

TEST(ConeThinning, SkeletonLiesInTheConeIsNeverEmptyAndMatchesTheDefinition) {
  const DirectionSet& set = sphere4();
  std::mt19937 random(7);
  for (int trial = 0; trial < 200; ++trial) {
    const Cone cone = randomCone(set, random, 1 + trial % 4);
    const Cone skeleton = thinCone(set, cone);
    const std::vector<int> s = members(set, skeleton);
    ASSERT_FALSE(s.empty()) << trial;
    for (int d : s) EXPECT_TRUE(coneHas(cone, d)) << trial;
    EXPECT_EQ(skeleton, referenceLastLayer(set, cone, cone)) << trial;
    const int access = accessDirection(set, cone);
    ASSERT_GE(access, 0);
    EXPECT_TRUE(coneHas(skeleton, access)) << trial;
  }
}

TEST(ConeThinning, EmptyAndFullCones) {
  const DirectionSet& set = sphere4();
  EXPECT_TRUE(members(set, thinCone(set, none(set))).empty());
  EXPECT_EQ(accessDirection(set, none(set)), -1);
  // Every direction: no boundary, the whole sphere is its own skeleton; restricted to a reach, the whole reach, whose
  // member nearest its mean is its axis.
  const Cone all = cap(set, Vec3::UnitZ(), 180);
  ASSERT_EQ(coneSize(all), set.size());
  EXPECT_EQ(thinCone(set, all), all);
  const Cone reach = cap(set, Vec3(1, 2, 2), 50);
  EXPECT_EQ(restrictedThinning(set, all, reach), reach);
  EXPECT_LT(degrees(set.directions[accessDirection(set, all, &reach)], Vec3(1, 2, 2)), kCell);
  // A single direction is its own skeleton.
  Cone one = none(set);
  one[0] |= 1u;
  EXPECT_EQ(thinCone(set, one), one);
  EXPECT_THROW(reachCone(set, Vec3::Zero(), 10), std::invalid_argument);
}

TEST(ConeThinning, RestrictedThinningStaysInTheReachAndGoesDeepIntoTheCone) {
  const DirectionSet& set = sphere4();
  // Visible within 60 degrees of +x, reachable within 60 degrees of +z: a lens between 30 and 60 degrees from +x.
  const Cone primary = cap(set, Vec3::UnitX(), 60), reach = cap(set, Vec3::UnitZ(), 60);
  const Cone skeleton = restrictedThinning(set, primary, reach);
  const std::vector<int> s = members(set, skeleton);
  ASSERT_FALSE(s.empty());
  double closest = 180;  // the lens's direction deepest in the primary
  for (int d : members(set, primary))
    if (coneHas(reach, d)) closest = std::min(closest, degrees(set.directions[d], Vec3::UnitX()));
  double worst = 0;
  for (int d : s) {
    EXPECT_TRUE(coneHas(primary, d));
    EXPECT_TRUE(coneHas(reach, d));
    worst = std::max(worst, degrees(set.directions[d], Vec3::UnitX()));
  }
  std::printf("restricted: lens from %.1f deg of +x; skeleton within %.1f deg of +x\n", closest, worst);
  EXPECT_LT(worst, 60 - kCell);          // deeper than the lens's far edge by more than a cell
  EXPECT_LT(worst, closest + 1.5 * kCell);  // and in the lens's last layer
  EXPECT_EQ(skeleton, referenceLastLayer(set, primary, [&] {
              Cone both = primary;
              for (std::size_t w = 0; w < both.size(); ++w) both[w] &= reach[w];
              return both;
            }()));
  const int access = accessDirection(set, primary, &reach);
  ASSERT_GE(access, 0);
  EXPECT_TRUE(coneHas(skeleton, access));
  // Nothing in reach: nothing.
  const Cone behind = cap(set, -Vec3::UnitX(), 20);
  EXPECT_TRUE(members(set, restrictedThinning(set, primary, behind)).empty());
  EXPECT_EQ(accessDirection(set, primary, &behind), -1);
}

TEST(ConeThinning, ABandThinsToACurveAlongItsMiddle) {
  const DirectionSet& set = sphere4();
  // Within 10 degrees of the equator, longitudes 0..120.
  Cone band = none(set);
  for (int d = 0; d < set.size(); ++d) {
    const Vec3& v = set.directions[d];
    const double lat = std::asin(std::clamp(v.z(), -1.0, 1.0)) * 180 / kPi;
    const double lon = std::atan2(v.y(), v.x()) * 180 / kPi;
    if (std::abs(lat) <= 10 && lon >= 0 && lon <= 120) band[d >> 6] |= std::uint64_t(1) << (d & 63);
  }
  const std::vector<int> s = members(set, thinCone(set, band));
  double lat_max = 0, lat_sum = 0, lon_min = 360, lon_max = -360;
  for (int d : s) {
    const Vec3& v = set.directions[d];
    lat_max = std::max(lat_max, std::abs(std::asin(v.z()) * 180 / kPi));
    lat_sum += std::asin(v.z()) * 180 / kPi;
    const double lon = std::atan2(v.y(), v.x()) * 180 / kPi;
    lon_min = std::min(lon_min, lon);
    lon_max = std::max(lon_max, lon);
  }
  std::printf("band (%d directions): skeleton of %zu within %.1f deg of the equator (mean latitude %.1f), longitudes "
              "%.0f..%.0f\n", coneSize(band), s.size(), lat_max, lat_sum / s.size(), lon_min, lon_max);
  ASSERT_GE(s.size(), 5u) << "a curve, not a point";
  EXPECT_LT(lat_max, 1.5 * kCell);  // the band's middle third: the layer is a cell deep, the outside sampled coarsely
  EXPECT_LT(std::abs(lat_sum / s.size()), 2);
  EXPECT_GT(lon_max - lon_min, 60) << "the skeleton runs along the band";
  const int access = accessDirection(set, band);
  ASSERT_GE(access, 0);
  EXPECT_TRUE(coneHas(band, access));
}

// Extra special directions (beyond cellCount, sharing a cell) are peeled and counted like the others.
TEST(ConeThinning, ExtraDirectionsOfACell) {
  DirectionSet set = sampleSphere(4);
  const Vec3 axis = Vec3(0.3, -0.2, 1).normalized();
  const int c = cellContaining(set, axis);
  const Vec3 second = (0.6 * set.corners[set.cells[c][0]] + 0.4 * set.directions[c]).normalized();
  insertSpecialDirections(set, {{axis, 2.0}, {second, 1.0}});
  ASSERT_EQ(set.size(), set.cellCount() + 1);
  std::mt19937 random(11);
  for (int trial = 0; trial < 40; ++trial) {
    const Cone cone = trial == 0 ? cap(set, axis, 30) : randomCone(set, random, 1 + trial % 3);
    if (coneSize(cone) == 0) continue;
    EXPECT_EQ(thinCone(set, cone), referenceLastLayer(set, cone, cone)) << trial;
    EXPECT_NEAR(intersectionSolidAngle(set, cone, cone), coneSolidAngle(cone, set), 1e-12) << trial;
  }
  // The extra alone, and with its cell's representative: one cell either way.
  Cone extra = none(set);
  extra[set.cellCount() >> 6] |= std::uint64_t(1) << (set.cellCount() & 63);
  EXPECT_NEAR(intersectionSolidAngle(set, extra, extra), set.cell_area[c], 1e-15);
  Cone both = extra;
  both[c >> 6] |= std::uint64_t(1) << (c & 63);
  EXPECT_NEAR(intersectionSolidAngle(set, both, both), set.cell_area[c], 1e-15);
}

TEST(ConeThinning, IntersectionSolidAngle) {
  const DirectionSet& set = sphere4();
  const Cone a = cap(set, Vec3::UnitZ(), 30), b = cap(set, -Vec3::UnitZ(), 30), c = cap(set, Vec3::UnitX(), 70);
  EXPECT_NEAR(intersectionSolidAngle(set, a, a), coneSolidAngle(a, set), 1e-12);
  EXPECT_EQ(intersectionSolidAngle(set, a, b), 0.0);
  Cone ac = a;
  for (std::size_t w = 0; w < ac.size(); ++w) ac[w] &= c[w];
  EXPECT_NEAR(intersectionSolidAngle(set, a, c), coneSolidAngle(ac, set), 1e-12);
  EXPECT_GT(intersectionSolidAngle(set, a, c), 0.0);
  // A 30-degree cap is 2 pi (1 - cos 30) sr, to within the cells on its rim.
  EXPECT_NEAR(coneSolidAngle(a, set), 2 * kPi * (1 - std::cos(kPi / 6)), 0.1);
}

TEST(ConeThinning, Speed) {
  const DirectionSet& set = sphere4();
  const std::vector<Vec3> axes = testAxes();
  std::vector<Cone> cones;
  for (const Vec3& a : axes) cones.push_back(cap(set, a, 40));
  const Cone reach = cap(set, Vec3::UnitZ(), 60);
  const int rounds = 30;
  long sink = 0;
  auto start = std::chrono::steady_clock::now();
  for (int r = 0; r < rounds; ++r)
    for (const Cone& c : cones) sink += coneSize(thinCone(set, c));
  const double thin_us =
      std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start).count() / (rounds * cones.size());
  start = std::chrono::steady_clock::now();
  for (int r = 0; r < rounds; ++r)
    for (const Cone& c : cones) sink += accessDirection(set, c, &reach);
  const double access_us =
      std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start).count() / (rounds * cones.size());
  std::printf("40-degree cap at level 4: %.1f us per thinCone, %.1f us per accessDirection with a reach (%ld)\n",
              thin_us, access_us, sink);
  EXPECT_LT(thin_us, 1000);  // generous: a loaded 2-core machine
}
