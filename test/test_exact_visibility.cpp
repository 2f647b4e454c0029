// The exact visibility oracle (polygon clipping) on scenes whose answer is known by construction: the visible
// fraction of a triangle follows from the shapes in front of it, worked out by hand in each test.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "art2part/visibility/exact_visibility.h"
#include "art2part/visibility/visibility.h"
#include "test_meshes.h"

using namespace art2part;

namespace {

// Appends the triangle (a, b, c) with its own vertices; returns its index.
int addTriangle(Mesh& mesh, const Vec3& a, const Vec3& b, const Vec3& c) {
  const int base = static_cast<int>(mesh.vertices.size());
  mesh.vertices.insert(mesh.vertices.end(), {a, b, c});
  mesh.triangles.push_back({base, base + 1, base + 2});
  return mesh.triangleCount() - 1;
}

// An axis-aligned rectangle [x0, x1] x [y0, y1] at height z as two triangles facing +z (up) or -z.
void addRectangle(Mesh& mesh, double x0, double y0, double x1, double y1, double z, bool up = true) {
  const Vec3 a(x0, y0, z), b(x1, y0, z), c(x1, y1, z), d(x0, y1, z);
  if (up) {
    addTriangle(mesh, a, b, c);
    addTriangle(mesh, a, c, d);
  } else {
    addTriangle(mesh, a, c, b);
    addTriangle(mesh, a, d, c);
  }
}

// The floor triangle of most scenes: right angle at the origin, legs of 2 along x and y, facing up; area 2.
int addFloor(Mesh& mesh) { return addTriangle(mesh, Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(0, 2, 0)); }

// Whether the ray p + s d, s > 0, meets triangle u of the mesh (Moller-Trumbore, both sides): an independent check of
// the oracle's witness points.
bool rayMeets(const Mesh& mesh, int u, const Vec3& p, const Vec3& d) {
  const Vec3 a = mesh.corner(u, 0), e1 = mesh.corner(u, 1) - a, e2 = mesh.corner(u, 2) - a;
  const Vec3 q = d.cross(e2);
  const double det = e1.dot(q);
  if (std::abs(det) < 1e-15) return false;
  const Vec3 s = p - a;
  const double b1 = s.dot(q) / det, r = s.cross(e1).dot(d) / det, t = s.cross(e1).dot(e2) / det;
  return b1 >= 0 && r >= 0 && b1 + r <= 1 && t > 0;
}

}  // namespace

TEST(ExactVisibility, AloneItIsVisibleWholeAlongAnyFrontDirection) {
  Mesh mesh;
  const int t = addFloor(mesh);
  for (const Vec3& d : {Vec3(0, 0, 1), Vec3(0.3, -0.2, 1), Vec3(1, 1, 0.05)}) {
    const ExactPair pair = exactVisibility(mesh, t, d);
    EXPECT_TRUE(pair.visible);
    EXPECT_NEAR(pair.uncovered, 1.0, 1e-6);
  }
}

TEST(ExactVisibility, BackFacingAndEdgeOnAreNeverVisible) {
  Mesh mesh;
  const int t = addFloor(mesh);
  for (const Vec3& d : {Vec3(0, 0, -1), Vec3(0.5, 0.5, -0.01), Vec3(1, 0, 0), Vec3(1, -1, 0)}) {
    const ExactPair pair = exactVisibility(mesh, t, d);
    EXPECT_FALSE(pair.visible) << d.transpose();
    EXPECT_EQ(pair.uncovered, 0.0) << d.transpose();
  }
}

TEST(ExactVisibility, ABiggerTriangleInFrontHidesItWhole) {
  Mesh mesh;
  const int t = addFloor(mesh);
  // Above the floor, facing down (back-facing along +z: it hides all the same), its shadow holds the floor whole.
  addTriangle(mesh, Vec3(-1, -1, 1), Vec3(-1, 5, 1), Vec3(5, -1, 1));
  const ExactPair up = exactVisibility(mesh, t, Vec3(0, 0, 1));
  EXPECT_FALSE(up.visible);
  EXPECT_LT(up.uncovered, 1e-9);
  // Along (1, 0, 1) the ray from (x, y, 0) reaches the occluder's height at (x + 1, y): inside it (x >= -1, y >= -1,
  // x + y <= 4) for every point of the floor (x + y <= 2).
  const ExactPair tilted = exactVisibility(mesh, t, Vec3(1, 0, 1));
  EXPECT_FALSE(tilted.visible);
  // Tilted far towards -x the shadow slides off: along (-3, 0, 1) the ray from (x, y, 0) reaches z = 1 at x - 3,
  // inside the occluder when x - 3 >= -1, i.e. x >= 2: only the corner (2, 0). Everything else sees out.
  const ExactPair away = exactVisibility(mesh, t, Vec3(-3, 0, 1));
  EXPECT_TRUE(away.visible);
  EXPECT_NEAR(away.uncovered, 1.0, 1e-6);
}

TEST(ExactVisibility, WhatLiesBehindItsPlaneDoesNotHide) {
  Mesh mesh;
  const int t = addFloor(mesh);
  addRectangle(mesh, -1, -1, 5, 5, -1);        // below the floor, facing up
  addRectangle(mesh, -1, -1, 5, 5, -2, false); // below that, facing down
  EXPECT_NEAR(exactVisibility(mesh, t, Vec3(0, 0, 1)).uncovered, 1.0, 1e-6);
  // ... while the floor hides most of the rectangle under it along +z: of its 36, the floor's 2 are covered.
  EXPECT_NEAR(exactVisibility(mesh, 1, Vec3(0, 0, 1)).uncovered + exactVisibility(mesh, 2, Vec3(0, 0, 1)).uncovered,
              2.0 - 2.0 / 18.0, 1e-6);
}

TEST(ExactVisibility, HalfHiddenUnderAnOverhang) {
  Mesh mesh;
  const int t = addFloor(mesh);
  addRectangle(mesh, 1, -1, 4, 4, 1, false);  // a roof over x >= 1
  // Along +z the floor's part with x >= 1 (a triangle of legs 1: area 1/2) is hidden: 3/4 of it sees out.
  const ExactPair up = exactVisibility(mesh, t, Vec3(0, 0, 1));
  EXPECT_TRUE(up.visible);
  EXPECT_NEAR(up.uncovered, 0.75, 1e-6);
  // Along (1, 0, 1) the ray from (x, y, 0) meets the roof's height at x + 1: hidden when x >= 0, everywhere.
  EXPECT_FALSE(exactVisibility(mesh, t, Vec3(1, 0, 1)).visible);
  // Along (-1, 0, 1) hidden when x - 1 >= 1, i.e. x >= 2: only the corner. Whole again.
  EXPECT_NEAR(exactVisibility(mesh, t, Vec3(-1, 0, 1)).uncovered, 1.0, 1e-6);
  // The witness of the visible part sees out: no triangle of the mesh on its ray.
  const Vec3 w = up.witness;
  EXPECT_LT(w.x(), 1.0);
  EXPECT_NEAR(w.z(), 0.0, 1e-12);
  for (int u = 1; u < mesh.triangleCount(); ++u) EXPECT_FALSE(rayMeets(mesh, u, w, Vec3(0, 0, 1))) << u;
}

TEST(ExactVisibility, ASliverSeenThroughAGap) {
  Mesh mesh;
  // A sliver 2 long and 0.002 wide along y = 1, under two plates leaving a gap 0.001 wide over y in [1, 1.001].
  const int sliver = addTriangle(mesh, Vec3(0, 0.999, 0), Vec3(2, 1.0, 0), Vec3(0, 1.001, 0));
  addRectangle(mesh, -1, -1, 3, 1.0, 1, false);
  addRectangle(mesh, -1, 1.001, 3, 3, 1, false);
  // Along +z the sliver shows in the gap: the part with y in [1, 1.001], the upper half of its width, which is
  // the triangle (0, 1) (2, 1) (0, 1.001): half its area.
  const ExactPair up = exactVisibility(mesh, sliver, Vec3(0, 0, 1));
  EXPECT_TRUE(up.visible);
  EXPECT_NEAR(up.uncovered, 0.5, 1e-5);
  EXPECT_GT(up.witness.y(), 1.0);
  EXPECT_LT(up.witness.y(), 1.001);
  for (int u = 1; u < mesh.triangleCount(); ++u) EXPECT_FALSE(rayMeets(mesh, u, up.witness, Vec3(0, 0, 1))) << u;
  // Tilted across the gap by 0.01 per unit of height, the gap's shadow (y in [0.99, 0.991]) misses the sliver.
  EXPECT_FALSE(exactVisibility(mesh, sliver, Vec3(0, 0.01, 1)).visible);
  // Tilted along the gap, it still shows.
  EXPECT_TRUE(exactVisibility(mesh, sliver, Vec3(0.5, 0, 1)).visible);
}

TEST(ExactVisibility, OnlyThePartOfAnOccluderInFrontHides) {
  Mesh mesh;
  const int t = addFloor(mesh);
  // A plane slanting through the floor's plane along x = 1: above it for x < 1, below for x > 1. Seen along +z it
  // hides the floor's part with x < 1, a trapezoid of area 2 - 1/2 = 3/2: a quarter of the floor sees out.
  addTriangle(mesh, Vec3(-1, -1, 2), Vec3(3, -1, -2), Vec3(3, 5, -2));
  addTriangle(mesh, Vec3(-1, -1, 2), Vec3(3, 5, -2), Vec3(-1, 5, 2));
  const ExactPair up = exactVisibility(mesh, t, Vec3(0, 0, 1));
  EXPECT_TRUE(up.visible);
  EXPECT_NEAR(up.uncovered, 0.25, 1e-6);
}

TEST(ExactVisibility, CoplanarNeighboursDoNotHideEachOther) {
  Mesh mesh = test::box(Vec3(0, 0, 0), Vec3(3, 2, 1));
  for (int t = 0; t < mesh.triangleCount(); ++t) {
    const Vec3 n = triangleNormal(mesh, t);
    for (const Vec3& d : test::randomDirections(20, 7)) {
      const ExactPair pair = exactVisibility(mesh, t, d);
      // A convex part: visibility is the normal test, the whole triangle at once.
      EXPECT_EQ(pair.visible, n.dot(d) > 0) << t << " " << d.transpose();
      if (n.dot(d) > 0) {
        EXPECT_NEAR(pair.uncovered, 1.0, 1e-6) << t;
      }
    }
  }
}

TEST(ExactVisibility, AWallShadesTheFloorBesideIt) {
  // A floor at z = 1 over [0, 2] x [0, 1] (triangles 0: (0,0) (2,0) (2,1) and 1: (0,0) (2,1) (0,1)) and a wall at
  // x = 2 rising to z = 3, facing the floor.
  Mesh mesh;
  addRectangle(mesh, 0, 0, 2, 1, 1);
  addTriangle(mesh, Vec3(2, 0, 1), Vec3(2, 1, 3), Vec3(2, 1, 1));
  addTriangle(mesh, Vec3(2, 0, 1), Vec3(2, 0, 3), Vec3(2, 1, 3));
  for (int t = 0; t < 2; ++t) {
    // Along (1, 0, 1) the ray from (x, y, 1) reaches x = 2 at height 3 - x, within the wall: all hidden.
    EXPECT_FALSE(exactVisibility(mesh, t, Vec3(1, 0, 1)).visible) << t;
    // Along (-1, 0, 1) it runs away from the wall.
    EXPECT_NEAR(exactVisibility(mesh, t, Vec3(-1, 0, 1)).uncovered, 1.0, 1e-6) << t;
  }
  // Along (1, 0, 2) it reaches x = 2 at height 5 - 2x: hidden for x >= 1. Of triangle 0 (under y = x / 2) that is
  // the integral of x / 2 over [1, 2], 3/4 of its area 1; of triangle 1, 1/4.
  EXPECT_NEAR(exactVisibility(mesh, 0, Vec3(1, 0, 2)).uncovered, 0.25, 1e-6);
  EXPECT_NEAR(exactVisibility(mesh, 1, Vec3(1, 0, 2)).uncovered, 0.75, 1e-6);
}

TEST(ExactVisibility, TheMatrixMatchesThePairs) {
  Mesh mesh = test::box(Vec3(0, 0, 0), Vec3(4, 4, 1));
  test::append(mesh, test::box(Vec3(1, 1, 1), Vec3(2, 3, 3)));  // a block standing on the bigger one
  const std::vector<Vec3> directions = test::randomDirections(24, 3);
  const VisibilityMap map = exactVisibility(mesh, directions);
  ASSERT_EQ(map.triangles(), mesh.triangleCount());
  ASSERT_EQ(map.directions(), 24);
  int visible = 0;
  for (int t = 0; t < mesh.triangleCount(); ++t)
    for (int d = 0; d < 24; ++d) {
      EXPECT_EQ(map.bits.get(t, d), exactVisibility(mesh, t, directions[d]).visible) << t << " " << d;
      visible += map.bits.get(t, d);
    }
  EXPECT_GT(visible, 100);
  // The block's bottom (12, 13) lies on the lower box's top: every ray from it runs into the lower box.
  for (int t : {12, 13}) EXPECT_EQ(map.bits.rowCount(t), 0) << t;
  // The lower box's bottom (0, 1) has nothing below it: the normal test alone.
  for (int d = 0; d < 24; ++d) EXPECT_EQ(map.bits.get(0, d), directions[d].z() < 0) << d;
}

TEST(ExactVisibility, DegenerateTrianglesNeitherShowNorHide) {
  Mesh mesh;
  const int t = addFloor(mesh);
  const int flat = addTriangle(mesh, Vec3(-1, -1, 1), Vec3(5, 5, 1), Vec3(2, 2, 1));  // collinear corners
  EXPECT_NEAR(exactVisibility(mesh, t, Vec3(0, 0, 1)).uncovered, 1.0, 1e-6);
  EXPECT_FALSE(exactVisibility(mesh, flat, Vec3(0, 0, 1)).visible);
  EXPECT_FALSE(exactVisibility(mesh, t, Vec3(0, 0, 0)).visible);  // no direction at all
}

TEST(ExactVisibility, AFinelyTessellatedFloorHalfUnderARoof) {
  // A floor of 20 x 20 unit squares (800 triangles) under a roof over x >= 10 at height 1; the grid of the view plane
  // must find the roof for the squares under it and nothing for the others, along +z and tilted along y.
  Mesh mesh;
  for (int i = 0; i < 20; ++i)
    for (int j = 0; j < 20; ++j) addRectangle(mesh, i, j, i + 1, j + 1, 0);
  const int roof = mesh.triangleCount();
  addRectangle(mesh, 10, -50, 30, 70, 1, false);
  const std::vector<Vec3> directions = {Vec3(0, 0, 1), Vec3(0, 3, 1), Vec3(-0.5, 0, 1)};
  std::vector<std::pair<int, int>> pairs;
  for (int t = 0; t < roof; ++t)
    for (int d = 0; d < 3; ++d) pairs.emplace_back(t, d);
  const std::vector<ExactPair> answers = exactVisibility(mesh, directions, pairs);
  ASSERT_EQ(answers.size(), pairs.size());
  const VisibilityMap map = exactVisibility(mesh, directions);
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    const int t = pairs[i].first, d = pairs[i].second;
    const double x = triangleCentroid(mesh, t).x();
    // Along (-0.5, 0, 1) the roof's shadow begins at x = 10.5, splitting column 10 (checked below).
    if (d == 2 && x > 10 && x < 11) continue;
    const double boundary = d == 2 ? 10.5 : 10.0;
    EXPECT_EQ(answers[i].visible, x < boundary) << t << " " << d;
    EXPECT_NEAR(answers[i].uncovered, x < boundary ? 1.0 : 0.0, 1e-6) << t << " " << d;
    EXPECT_EQ(map.bits.get(t, d), answers[i].visible) << t << " " << d;
  }
  // Column 10 along (-0.5, 0, 1): the part with x in [10, 10.5] sees out. Of a square's first triangle (under its
  // diagonal, y - j <= x - 10) that is the integral of (x - 10) over [10, 10.5], 1/8 of its 1/2; of the second, 3/8.
  for (int t = 0; t < roof; ++t) {
    const double x = triangleCentroid(mesh, t).x();
    if (x > 10 && x < 11) {
      EXPECT_NEAR(exactVisibility(mesh, t, directions[2]).uncovered, t % 2 ? 0.75 : 0.25, 1e-6) << t;
    }
  }
}

// ---- the backends against the oracle, on the cases their sampling was tuned for ------------------------------------

namespace {

// A unit square on the floor split along its diagonal: A = (0,0) (1,0) (1,1) below it, B = (0,0) (1,1) (0,1) above,
// sharing the diagonal; and a roof at height 1 over {y >= x, x <= 0.9}, which hides all of B but the corner x > 0.9
// (1% of it) along +z and none of A.
Mesh squareUnderARoofWithAWindow() {
  Mesh mesh;
  mesh.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)};
  mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  addTriangle(mesh, Vec3(-2, -2, 1), Vec3(0.9, 5, 1), Vec3(0.9, 0.9, 1));  // facing down
  addTriangle(mesh, Vec3(-2, -2, 1), Vec3(-2, 5, 1), Vec3(0.9, 5, 1));
  return mesh;
}

}  // namespace

TEST(BackendsAgainstTheOracle, ACornerPeekingOutNextToAVisibleNeighbour) {
  const Mesh mesh = squareUnderARoofWithAWindow();
  const std::vector<Vec3> up = {Vec3(0, 0, 1)};
  const ExactPair b = exactVisibility(mesh, 1, up[0]);
  ASSERT_TRUE(b.visible);
  ASSERT_NEAR(b.uncovered, 0.01, 1e-6);
  ASSERT_NEAR(exactVisibility(mesh, 0, up[0]).uncovered, 1.0, 1e-6);
  // Every interior sample of B lies under the roof: the plain sample model misses the corner ...
  RayVisibilityOptions samples;
  samples.samples_per_triangle = 7;
  EXPECT_FALSE(rayVisibility(mesh, up, samples).bits.get(1, 0));
  // ... and edge refinement from A finds it from the end of the shared diagonal, as does the renderer's fallback at
  // a resolution whose pixels (about 0.1) are as wide as the window.
  const VisibilityMap ray = rayVisibility(mesh, up, defaultRayOptions());
  EXPECT_TRUE(ray.bits.get(0, 0));
  EXPECT_TRUE(ray.bits.get(1, 0));
  RenderVisibilityOptions render;
  render.resolution = 96;
  render.threads = 1;
  const VisibilityMap rendered = renderVisibility(mesh, up, render);
  EXPECT_TRUE(rendered.bits.get(0, 0));
  EXPECT_TRUE(rendered.bits.get(1, 0));
}

TEST(BackendsAgainstTheOracle, AHiddenCentreWithCornersOutsideIsRescued) {
  // A big floor triangle alone (no neighbour to spread from) under a closed box standing on it over its centroid:
  // the centroid sees out along no direction, the corners along every upward one.
  Mesh mesh;
  const int floor = addTriangle(mesh, Vec3(0, 0, 0), Vec3(10, 0, 0), Vec3(0, 10, 0));
  test::append(mesh, test::box(Vec3(2, 2, 0), Vec3(5, 5, 1)));
  const std::vector<Vec3> directions = test::randomDirections(40, 11);
  RayVisibilityOptions centroid;
  centroid.samples_per_triangle = 1;
  EXPECT_EQ(rayVisibility(mesh, directions, centroid).bits.rowCount(floor), 0);
  const VisibilityMap rescued = rayVisibility(mesh, directions, defaultRayOptions());
  int upward = 0;
  for (int d = 0; d < 40; ++d) {
    if (directions[d].z() < 0.2) continue;  // low directions: the box may hide the sample corners
    ++upward;
    EXPECT_TRUE(exactVisibility(mesh, floor, directions[d]).visible) << d;
    EXPECT_TRUE(rescued.bits.get(floor, d)) << d;
  }
  EXPECT_GT(upward, 10);
}

TEST(BackendsAgainstTheOracle, ASliverThinnerThanAPixelSeenThroughAGap) {
  Mesh mesh;
  const int sliver = addTriangle(mesh, Vec3(0, 0.999, 0), Vec3(2, 1.0, 0), Vec3(0, 1.001, 0));
  addRectangle(mesh, -1, -1, 3, 1.0, 1, false);
  addRectangle(mesh, -1, 1.001, 3, 3, 1, false);
  const std::vector<Vec3> directions = {Vec3(0, 0, 1), Vec3(0.5, 0, 1), Vec3(0, 0.01, 1)};
  RenderVisibilityOptions render;
  render.resolution = 64;  // pixels about 0.1 wide: 100 times the gap
  render.threads = 1;
  const VisibilityMap rendered = renderVisibility(mesh, directions, render);
  const VisibilityMap ray = rayVisibility(mesh, directions, defaultRayOptions());
  for (int d = 0; d < 3; ++d) {
    const bool exact = exactVisibility(mesh, sliver, directions[d]).visible;
    EXPECT_EQ(exact, d < 2) << d;
    EXPECT_EQ(rendered.bits.get(sliver, d), exact) << d;
    EXPECT_EQ(ray.bits.get(sliver, d), exact) << d;
  }
}
