// Repair, orientation, adjacency and checks on meshes whose answers are known exactly.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "art2part/geometry/adjacency.h"
#include "art2part/geometry/repair.h"
#include "test_meshes.h"

using namespace art2part;
using art2part::test::box;

namespace {
constexpr double kPi = 3.14159265358979323846;
}

TEST(Repair, MergesStlStyleVerticesIntoAClosedBox) {
  Mesh m = test::unshared(box(Vec3(0, 0, 0), Vec3(10, 20, 30)));
  ASSERT_EQ(m.vertices.size(), 36u);
  std::vector<int> kept;
  const RepairReport r = repairMesh(m, &kept);
  EXPECT_EQ(m.vertices.size(), 8u);
  EXPECT_EQ(r.merged_vertices, 28);
  EXPECT_EQ(r.flipped, 0);
  const MeshCheck c = checkMesh(m);
  EXPECT_TRUE(c.closed);
  EXPECT_TRUE(c.manifold);
  EXPECT_EQ(c.components, 1);
  EXPECT_NEAR(c.volume, 6000.0, 1e-9);
  EXPECT_NEAR(c.area, 2 * (200 + 600 + 300), 1e-9);
  EXPECT_NEAR(c.box.size().x(), 10.0, 0.0);
}

TEST(Repair, OrientsFlippedTrianglesOutwardAndSaysSo) {
  Mesh m = box(Vec3(0, 0, 0), Vec3(1, 1, 1));
  const Mesh reference = m;
  for (int t : {1, 4, 9}) std::swap(m.triangles[t][1], m.triangles[t][2]);
  const RepairReport r = repairMesh(m);
  EXPECT_EQ(r.flipped, 3);
  ASSERT_FALSE(r.notes.empty());
  for (int t = 0; t < m.triangleCount(); ++t)
    EXPECT_GT(triangleNormal(m, t).dot(triangleNormal(reference, t)), 0.999) << "triangle " << t;
  EXPECT_NEAR(signedVolume(m), 1.0, 1e-12);
}

TEST(Repair, TurnsAnInsideOutBoxOutward) {
  Mesh m = box(Vec3(0, 0, 0), Vec3(2, 2, 2));
  test::flipAll(m);
  EXPECT_LT(signedVolume(m), 0);
  EXPECT_EQ(repairMesh(m).flipped, 12);
  EXPECT_NEAR(signedVolume(m), 8.0, 1e-12);
}

TEST(Repair, KeepsAVoidPointingIntoTheVoid) {
  Mesh m = box(Vec3(0, 0, 0), Vec3(10, 10, 10));
  test::append(m, box(Vec3(4, 4, 4), Vec3(6, 6, 6)));  // wrongly outward: must become inward
  repairMesh(m);
  EXPECT_NEAR(signedVolume(m), 1000.0 - 8.0, 1e-9);
  EXPECT_EQ(checkMesh(m).components, 2);
}

TEST(Repair, DropsDegenerateAndDuplicateTrianglesKeepingOrder) {
  Mesh m = box(Vec3(0, 0, 0), Vec3(1, 1, 1));
  m.vertices.emplace_back(0.5, 0.0, 0.0);                           // on the edge 0-1: collinear
  m.triangles.insert(m.triangles.begin() + 3, Triangle{0, 1, 8});   // zero area
  m.triangles.insert(m.triangles.begin() + 7, Triangle{2, 2, 5});   // repeated corner
  m.triangles.push_back(m.triangles[0]);                            // duplicate of the first
  std::vector<int> kept;
  const RepairReport r = repairMesh(m, &kept);
  EXPECT_EQ(r.dropped_degenerate, 2);
  EXPECT_EQ(r.dropped_duplicate, 1);
  ASSERT_EQ(m.triangleCount(), 12);
  const std::vector<int> expected = {0, 1, 2, 4, 5, 6, 8, 9, 10, 11, 12, 13};
  EXPECT_EQ(kept, expected);
  EXPECT_TRUE(checkMesh(m).closed);
}

TEST(Repair, AbsorbsASliverAtATJunctionAndStaysClosed) {
  // A unit box whose top has a vertex m in the middle of edge 4-5, and the zero-area sliver (4, 5, m) that a CAD
  // mesher leaves there so the mesh is closed.
  Mesh m = box(Vec3(0, 0, 0), Vec3(1, 1, 1));
  m.vertices.emplace_back(0.5, 0, 1);  // vertex 8
  m.triangles[2] = {4, 8, 7};
  m.triangles[3] = {8, 5, 7};
  m.triangles.insert(m.triangles.begin() + 4, Triangle{4, 7, 6});
  m.triangles.push_back({4, 5, 8});  // the sliver
  ASSERT_TRUE(checkMesh(m).closed);
  const int side = 6;  // {0, 5, 4}: the side triangle across the sliver's long edge
  ASSERT_EQ(m.triangles[side], (Triangle{0, 5, 4}));
  std::vector<int> kept;
  const RepairReport r = repairMesh(m, &kept);
  EXPECT_EQ(r.dropped_degenerate, 1);
  EXPECT_EQ(r.split_neighbours, 1);
  const MeshCheck c = checkMesh(m);
  EXPECT_TRUE(c.closed);
  EXPECT_TRUE(c.manifold);
  EXPECT_NEAR(c.volume, 1.0, 1e-12);
  EXPECT_EQ(m.triangleCount(), 14);
  EXPECT_EQ(std::count(kept.begin(), kept.end(), side), 2) << "both halves keep the input index";
  EXPECT_TRUE(std::is_sorted(kept.begin(), kept.end())) << "input order preserved";
}

TEST(Repair, ReportsAnOpenMesh) {
  Mesh m = box(Vec3(0, 0, 0), Vec3(1, 1, 1));
  m.triangles.pop_back();
  repairMesh(m);
  const MeshCheck c = checkMesh(m);
  EXPECT_FALSE(c.closed);
  EXPECT_EQ(c.boundary_edges, 3);
  EXPECT_TRUE(c.manifold);
}

TEST(Validate, RejectsNanWithThePlace) {
  Mesh m = box(Vec3(0, 0, 0), Vec3(1, 1, 1));
  m.vertices[5].y() = std::nan("");
  try {
    validateMesh(m, "part.stl");
    FAIL() << "NaN accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("part.stl: vertex 5"), std::string::npos) << e.what();
  }
  EXPECT_THROW(validateMesh(Mesh{}, "empty.stl"), InputError);
}

TEST(Adjacency, BoxEdgesAreConvexRightAngles) {
  const Mesh m = box(Vec3(0, 0, 0), Vec3(3, 2, 1));
  const Adjacency a = buildAdjacency(m);
  EXPECT_EQ(a.edges, 18);
  EXPECT_TRUE(a.closed());
  EXPECT_TRUE(a.manifold());
  int convex = 0, smooth = 0;
  for (int t = 0; t < m.triangleCount(); ++t)
    for (int e = 0; e < 3; ++e) {
      const int u = a.neighbour[t][e];
      ASSERT_GE(u, 0);
      // symmetric: u sees t across the same edge
      bool back = false;
      for (int f = 0; f < 3; ++f) back |= a.neighbour[u][f] == t;
      EXPECT_TRUE(back);
      if (a.klass[t][e] == EdgeClass::Convex) {
        ++convex;
        EXPECT_NEAR(a.dihedral[t][e], kPi / 2, 1e-12);
      } else {
        ++smooth;
        EXPECT_NEAR(a.dihedral[t][e], 0.0, 1e-12);  // the diagonal inside a square face
      }
    }
  EXPECT_EQ(convex, 24);  // 12 box edges seen from both sides
  EXPECT_EQ(smooth, 12);  // 6 diagonals seen from both sides
}

TEST(Adjacency, ADentedTopHasConcaveValleys) {
  // A 2 mm box whose top face is replaced by four triangles down to a point below the top: an inverted pyramid.
  Mesh m = box(Vec3(0, 0, 0), Vec3(2, 2, 2));
  m.triangles.erase(m.triangles.begin() + 2, m.triangles.begin() + 4);  // the top quad {4,5,7,6}
  m.vertices.emplace_back(1, 1, 1);                                       // vertex 8, depth 1 below the top
  for (auto e : {std::array<int, 2>{4, 5}, {5, 7}, {7, 6}, {6, 4}}) m.triangles.push_back({e[0], e[1], 8});
  const Adjacency a = buildAdjacency(m);
  ASSERT_TRUE(a.closed());
  int concave = 0;
  for (int t = 0; t < m.triangleCount(); ++t)
    for (int e = 0; e < 3; ++e)
      if (a.klass[t][e] == EdgeClass::Concave) {
        ++concave;
        // neighbouring pyramid faces have normals (0,1,1)/sqrt2 and (-1,0,1)/sqrt2: 60 degrees apart
        EXPECT_NEAR(a.dihedral[t][e], -kPi / 3, 1e-9);
      }
  EXPECT_EQ(concave, 8);  // the four valleys, from both sides
  EXPECT_NEAR(signedVolume(m), 8.0 - 4.0 / 3.0, 1e-12);
}
