// Visibility by rendering triangle ids (OSMesa): exactly decidable scenes, occlusion by back faces, threads agree,
// progress and cancelling.
#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <stdexcept>

#include "art2part/visibility/visibility.h"
#include "test_meshes.h"

using namespace art2part;
using art2part::test::append;
using art2part::test::box;

namespace {

RenderVisibilityOptions withResolution(int resolution, int threads = 1) {
  RenderVisibilityOptions options;
  options.resolution = resolution;
  options.threads = threads;
  return options;
}

std::set<int> visibleAlong(const VisibilityMap& map, int d) {
  std::set<int> out;
  for (int t = 0; t < map.triangles(); ++t)
    if (map.bits.get(t, d)) out.insert(t);
  return out;
}

// Triangles whose normal is (numerically) `normal`, counted from `first` to `first + count`.
std::set<int> facing(const Mesh& mesh, const Vec3& normal, int first = 0, int count = -1) {
  std::set<int> out;
  const int end = count < 0 ? mesh.triangleCount() : first + count;
  for (int t = first; t < end; ++t)
    if (triangleNormal(mesh, t).dot(normal.normalized()) > 1 - 1e-9) out.insert(t);
  return out;
}

// Roughly even directions (a Fibonacci spiral), so the tests need nothing from the sphere module.
std::vector<Vec3> spiral(int n) {
  std::vector<Vec3> out;
  const double golden = M_PI * (3 - std::sqrt(5.0));
  for (int i = 0; i < n; ++i) {
    const double z = 1 - (2 * i + 1.0) / n, r = std::sqrt(1 - z * z);
    out.emplace_back(r * std::cos(golden * i), r * std::sin(golden * i), z);
  }
  return out;
}

// A big slab (triangles 0..11) over a small thin box (12..23) with a gap of 1.5 mm between them.
Mesh slabOverSmallBox() {
  Mesh mesh = box(Vec3(0, 0, 2), Vec3(4, 4, 3));
  append(mesh, box(Vec3(1, 1, 0), Vec3(3, 3, 0.5)));
  return mesh;
}

}  // namespace

TEST(RenderVisibility, UnitBoxFromAbove) {
  const Mesh mesh = box(Vec3(0, 0, 0), Vec3(1, 1, 1));
  const VisibilityMap map = renderVisibility(mesh, {Vec3(0, 0, 1), Vec3(0, 0, -3)}, withResolution(128));
  ASSERT_EQ(map.triangles(), 12);
  ASSERT_EQ(map.directions(), 2);
  const std::set<int> top = facing(mesh, Vec3(0, 0, 1)), bottom = facing(mesh, Vec3(0, 0, -1));
  ASSERT_EQ(top.size(), 2u);
  EXPECT_EQ(visibleAlong(map, 0), top);     // the sides are edge-on: n.d = 0 is not visible
  EXPECT_EQ(visibleAlong(map, 1), bottom);  // directions need not be unit
}

TEST(RenderVisibility, UnitBoxFromACorner) {
  const Mesh mesh = box(Vec3(0, 0, 0), Vec3(1, 1, 1));
  // The auto resolution (64 here: a tiny part) is enough for faces seen at 55 degrees.
  const VisibilityMap map = renderVisibility(mesh, {Vec3(1, 1, 1).normalized()});
  std::set<int> expected;
  for (int t = 0; t < mesh.triangleCount(); ++t)
    if (triangleNormal(mesh, t).minCoeff() > -0.5) expected.insert(t);  // +x, +y or +z
  ASSERT_EQ(expected.size(), 6u);
  EXPECT_EQ(visibleAlong(map, 0), expected);
}

TEST(RenderVisibility, SmallBoxStandingOnABigOne) {
  Mesh mesh = box(Vec3(0, 0, 0), Vec3(4, 4, 1));  // 0..11
  append(mesh, box(Vec3(1, 1, 1), Vec3(3, 3, 3)));  // 12..23, its bottom on the lower box's top
  const VisibilityMap map = renderVisibility(mesh, {Vec3(0, 0, 1), Vec3(1, 0, 0)}, withResolution(256));
  std::set<int> up = facing(mesh, Vec3(0, 0, 1));  // both tops: each lower-top triangle shows outside the upper box
  EXPECT_EQ(visibleAlong(map, 0), up);
  EXPECT_EQ(visibleAlong(map, 1), facing(mesh, Vec3(1, 0, 0)));
}

TEST(RenderVisibility, SlabHidesTheBoxBelowIt) {
  const Mesh mesh = slabOverSmallBox();
  const std::set<int> small_top = facing(mesh, Vec3(0, 0, 1), 12, 12);
  const std::set<int> small_bottom = facing(mesh, Vec3(0, 0, -1), 12, 12);
  const std::set<int> slab_bottom = facing(mesh, Vec3(0, 0, -1), 0, 12);
  ASSERT_EQ(small_top.size(), 2u);
  // Slightly tilted from +z the slab still covers the small box (a ray from its top moves 0.15 mm sideways
  // before reaching the slab); tilted far towards +x its top escapes through the gap.
  const std::vector<Vec3> directions = {Vec3(0, 0, 1), Vec3(0.1, 0, 1), Vec3(0, 0, -1), Vec3(1, 0, 0.2)};
  const VisibilityMap map = renderVisibility(mesh, directions, withResolution(256));
  for (int t : small_top) {
    EXPECT_FALSE(map.bits.get(t, 0)) << t;
    EXPECT_FALSE(map.bits.get(t, 1)) << t;
    EXPECT_TRUE(map.bits.get(t, 3)) << t;
  }
  std::set<int> from_below = small_bottom;
  from_below.insert(slab_bottom.begin(), slab_bottom.end());  // the slab's bottom shows around the small box
  EXPECT_EQ(visibleAlong(map, 2), from_below);
  EXPECT_EQ(visibleAlong(map, 0), facing(mesh, Vec3(0, 0, 1), 0, 12));  // the slab's top alone
}

TEST(RenderVisibility, BackFacesOcclude) {
  // An open mesh: a downward-facing square above a small box. Along +z the square is back-facing (not visible)
  // but still hides the box's top.
  Mesh mesh;
  mesh.vertices = {Vec3(0, 0, 2), Vec3(4, 0, 2), Vec3(4, 4, 2), Vec3(0, 4, 2)};
  mesh.triangles = {{0, 2, 1}, {0, 3, 2}};  // clockwise from above: normal -z
  append(mesh, box(Vec3(1, 1, 0), Vec3(3, 3, 0.5)));
  const VisibilityMap map = renderVisibility(mesh, {Vec3(0, 0, 1), Vec3(0, 0, -1)}, withResolution(128));
  EXPECT_TRUE(visibleAlong(map, 0).empty());
  const std::set<int> from_below = visibleAlong(map, 1);
  EXPECT_TRUE(from_below.count(0) && from_below.count(1));  // the square seen from below, around the box
}

// On a convex part visibility is the normal test alone, except for faces seen too obliquely to cover a pixel.
void expectNormalTest(const Mesh& mesh, int resolution, double min_nd) {
  const std::vector<Vec3> directions = spiral(150);
  const VisibilityMap map = renderVisibility(mesh, directions, withResolution(resolution));
  for (int d = 0; d < map.directions(); ++d)
    for (int t = 0; t < map.triangles(); ++t) {
      const double nd = triangleNormal(mesh, t).dot(directions[d]);
      if (nd <= 0) {
        EXPECT_FALSE(map.bits.get(t, d)) << t << " " << d;
      } else if (nd > min_nd) {
        EXPECT_TRUE(map.bits.get(t, d)) << t << " " << d << " n.d " << nd;
      }
    }
}

TEST(RenderVisibility, InsideOutShellStillOccludes) {
  // Closed, but the upper box is inside out: its top now faces down. Back faces must still be drawn (no culling),
  // so its top hides its own bottom, which faces up.
  Mesh mesh = box(Vec3(0, 0, 0), Vec3(4, 4, 1));
  Mesh inverted = box(Vec3(1, 1, 2), Vec3(3, 3, 3));
  art2part::test::flipAll(inverted);
  append(mesh, inverted);
  const VisibilityMap map = renderVisibility(mesh, {Vec3(0, 0, 1)}, withResolution(128));
  EXPECT_EQ(visibleAlong(map, 0), facing(mesh, Vec3(0, 0, 1), 0, 12));  // the lower box's top alone
  EXPECT_EQ(facing(mesh, Vec3(0, 0, 1), 12, 12).size(), 2u);            // the upper box's bottom, hidden
}

TEST(RenderVisibility, MatchesTheNormalTestOnAConvexPart) {
  expectNormalTest(box(Vec3(-1, 0, 0), Vec3(1, 2, 0.5)), 256, 0.05);
  // Long and thin, far from the origin: only the box's shadow in each view is read back.
  expectNormalTest(box(Vec3(995, 100, 50), Vec3(1005, 101, 50.5)), 512, 0.2);
}

TEST(RenderVisibility, ThreadsGiveTheSameBits) {
  Mesh mesh = slabOverSmallBox();
  append(mesh, box(Vec3(5, 0, 0), Vec3(6, 1, 4)));  // a pillar beside them, shading both
  const std::vector<Vec3> directions = spiral(130);  // not a multiple of 64: a partial last word
  const VisibilityMap one = renderVisibility(mesh, directions, withResolution(200, 1));
  const VisibilityMap two = renderVisibility(mesh, directions, withResolution(200, 2));
  const VisibilityMap three = renderVisibility(mesh, directions, withResolution(200, 3));
  int bits = 0;
  for (int t = 0; t < one.triangles(); ++t) bits += one.bits.rowCount(t);
  EXPECT_GT(bits, 200);
  EXPECT_TRUE(one.bits == two.bits);
  EXPECT_TRUE(one.bits == three.bits);
}

TEST(RenderVisibility, ReportsProgressAndCancels) {
  const Mesh mesh = slabOverSmallBox();
  const std::vector<Vec3> directions = spiral(40);
  std::vector<double> seen;
  renderVisibility(mesh, directions, withResolution(64, 2), [&](double f) {
    seen.push_back(f);
    return true;
  });
  ASSERT_GE(seen.size(), 2u);
  EXPECT_EQ(seen.front(), 0.0);
  EXPECT_EQ(seen.back(), 1.0);
  for (size_t i = 1; i < seen.size(); ++i) EXPECT_LE(seen[i - 1], seen[i]);

  // Cancelled at the second call, whether that comes mid-way or at the end.
  int calls = 0;
  try {
    renderVisibility(mesh, directions, withResolution(64, 2), [&](double) { return ++calls < 2; });
    FAIL() << "not cancelled";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "cancelled");
  }
  EXPECT_EQ(calls, 2);  // no call after cancelling
}

TEST(RenderVisibility, EmptyInputsAndBadDirections) {
  const Mesh mesh = box(Vec3(0, 0, 0), Vec3(1, 1, 1));
  const VisibilityMap none = renderVisibility(mesh, {});
  EXPECT_EQ(none.triangles(), 12);
  EXPECT_EQ(none.directions(), 0);
  EXPECT_EQ(renderVisibility(Mesh(), {Vec3(0, 0, 1)}).directions(), 1);
  EXPECT_THROW(renderVisibility(mesh, {Vec3(0, 0, 0)}), std::invalid_argument);
}
