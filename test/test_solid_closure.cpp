// The solid of an open mesh (solid_closure.h): closed chains, and volumes worked out independently.
#include <gtest/gtest.h>

#include <cmath>

#include "art2part/geometry/part.h"
#include "art2part/geometry/solid_closure.h"
#include "art2part/simulation/mesh_dexels.h"
#include "test_meshes.h"

using namespace art2part;

namespace {

const std::string kParts = ART2PART_SHARED_PARTS;

// Divergence theorem: the volume a closed, outward mesh encloses (overlapping pieces count with their windings).
double divergenceVolume(const Mesh& m) {
  double v = 0;
  for (int t = 0; t < m.triangleCount(); ++t) v += m.corner(t, 0).dot(m.corner(t, 1).cross(m.corner(t, 2))) / 6;
  return v;
}

double height(double x, double y) { return 3 + std::sin(x) + 0.5 * std::cos(1.7 * y) + 0.1 * x * y; }

// A height field z = height(x, y) over [0, 4] x [0, 3], n x n cells, facing up; open everywhere below.
Mesh relief(int n) {
  Mesh m;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const double x = 4.0 * i / n, y = 3.0 * j / n;
      m.vertices.emplace_back(x, y, height(x, y));
    }
  auto at = [n](int i, int j) { return j * (n + 1) + i; };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      m.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      m.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  return m;
}

}  // namespace

TEST(SolidClosure, AnOpenPyramidBecomesItsSolid) {
  // Four faces up to the apex (0, 0, 2) over the square [-1, 1]^2, no base: its boundary lies on the floor (no skirt).
  Mesh m;
  m.vertices = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}, {0, 0, 2}};
  m.triangles = {{0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {3, 0, 4}};
  EXPECT_EQ(boundaryChainEdges(m), 4);
  const SolidClosure c = closeOpenMesh(m);
  EXPECT_EQ(c.boundary_edges, 4);
  EXPECT_EQ(c.skirt_triangles, 0);
  EXPECT_EQ(c.cap_triangles, 4);
  EXPECT_TRUE(c.direction.isApprox(-Vec3::UnitZ()));
  EXPECT_NEAR(c.floor, 0.0, 0.0);
  EXPECT_EQ(boundaryChainEdges(c.mesh), 0);
  EXPECT_NEAR(divergenceVolume(c.mesh), 4.0 * 2 / 3, 1e-12);
}

TEST(SolidClosure, AReliefIsTheSolidUnderItDownToItsLowestPoint) {
  const Mesh m = relief(24);
  const SolidClosure c = closeOpenMesh(m);
  EXPECT_EQ(c.boundary_edges, 4 * 24);
  EXPECT_EQ(c.skirt_triangles, 2 * 4 * 24);
  EXPECT_EQ(boundaryChainEdges(c.mesh), 0);
  double low = 1e300;
  for (const Vec3& p : m.vertices) low = std::min(low, p.z());
  EXPECT_NEAR(-c.floor, low, 1e-12);
  // Over each triangle a prism down to the floor: its plan area times its mean height above the floor.
  double expected = 0;
  for (int t = 0; t < m.triangleCount(); ++t) {
    const Vec3 &a = m.corner(t, 0), &b = m.corner(t, 1), &d = m.corner(t, 2);
    const double area = 0.5 * ((b - a).x() * (d - a).y() - (b - a).y() * (d - a).x());
    expected += area * ((a.z() + b.z() + d.z()) / 3 - low);
  }
  EXPECT_NEAR(divergenceVolume(c.mesh), expected, 1e-9 * expected);
  // The same relief turned to face -x closes towards +x.
  Mesh turned = m;
  for (Vec3& p : turned.vertices) p = Vec3(-p.z(), p.y(), p.x());
  const SolidClosure t = closeOpenMesh(turned);
  EXPECT_TRUE(t.direction.isApprox(Vec3::UnitX()));
  EXPECT_NEAR(divergenceVolume(t.mesh), expected, 1e-9 * expected);
}

TEST(SolidClosure, AClosedMeshIsLeftAlone) {
  const Mesh m = test::box(Vec3(0, 0, 0), Vec3(10, 20, 30));
  const SolidClosure c = closeOpenMesh(m);
  EXPECT_TRUE(c.closed());
  EXPECT_EQ(c.mesh.triangles.size(), m.triangles.size());
  EXPECT_EQ(c.mesh.vertices.size(), m.vertices.size());
}

TEST(SolidClosure, AReliefWithAHoleAndACrackStaysOneSolid) {
  // Two triangles cut out of the middle (a hole whose skirt runs down inside the solid) and one cell's diagonal split
  // into two edges (a crack): the chain still closes, and the volume is the relief's less the hole's prism.
  Mesh m = relief(12);
  const int hole = 2 * (6 * 12 + 6);
  const Vec3 &a = m.corner(hole, 0), &b = m.corner(hole, 1), &d = m.corner(hole, 2);
  const Vec3 &e = m.corner(hole + 1, 0), &f = m.corner(hole + 1, 1), &g = m.corner(hole + 1, 2);
  double low = 1e300;
  for (const Vec3& p : m.vertices) low = std::min(low, p.z());
  auto prism = [low](const Vec3& p, const Vec3& q, const Vec3& r) {
    return 0.5 * ((q - p).x() * (r - p).y() - (q - p).y() * (r - p).x()) * ((p.z() + q.z() + r.z()) / 3 - low);
  };
  const double hole_volume = prism(a, b, d) + prism(e, f, g);
  const double whole = divergenceVolume(closeOpenMesh(m).mesh);
  m.triangles.erase(m.triangles.begin() + hole, m.triangles.begin() + hole + 2);
  // The crack: the next cell's second triangle gets its own copy of the diagonal's ends.
  Triangle& cracked = m.triangles[hole + 1];
  for (int k = 0; k < 3; ++k) {
    m.vertices.push_back(m.vertices[cracked[k]]);
    cracked[k] = static_cast<int>(m.vertices.size()) - 1;
  }
  const SolidClosure c = closeOpenMesh(m);
  EXPECT_EQ(boundaryChainEdges(c.mesh), 0);
  EXPECT_NEAR(divergenceVolume(c.mesh), whole - hole_volume, 1e-9 * whole);
}

TEST(SolidClosure, MountRushIsASolidTheSimulationSees) {
  // An open, non-manifold relief in 284 pieces: its closure's chain is closed and the simulation's dexels, which
  // count windings ray by ray, find the volume the divergence theorem gives.
  const Part part = loadPart(kParts + "/mount_rush.stl");
  ASSERT_FALSE(part.check.closed);
  SolidClosure closure;
  const Part solid = machiningSolid(part, &closure);
  EXPECT_GT(closure.boundary_edges, 0);
  EXPECT_TRUE(closure.direction.isApprox(-Vec3::UnitZ()));
  EXPECT_EQ(boundaryChainEdges(solid.mesh), 0);
  EXPECT_EQ(solid.triangle_face.size(), solid.mesh.triangles.size());
  const double volume = divergenceVolume(solid.mesh);
  const Box box = boundingBox(part.mesh);
  EXPECT_GT(volume, 0.3 * box.size().prod());
  EXPECT_LT(volume, box.size().prod());
  // The simulation's part is the solid under the surface: where one sheet of the relief, facing up, lies over a spot,
  // just under it is part and just over it is not (the mesh also holds thin two-sided plates, under which the
  // closure is rightly air). Sheets over a spot found by brute force over the triangles.
  const MeshDexels dexels(solid.mesh, DexelLattice::over(box, 0.25));
  int under = 0, over = 0, spots = 0;
  for (int i = 0; i < 400; ++i) {
    const double x = box.min.x() + box.size().x() * (0.5 + i % 20) / 20;
    const double y = box.min.y() + box.size().y() * (0.5 + i / 20) / 20;
    double top = -1e300;
    int sheets = 0;
    bool up = false;
    for (int t = 0; t < part.mesh.triangleCount(); ++t) {
      const Vec3 &a = part.mesh.corner(t, 0), &b = part.mesh.corner(t, 1), &d = part.mesh.corner(t, 2);
      const double det = (b - a).x() * (d - a).y() - (b - a).y() * (d - a).x();
      if (std::abs(det) < 1e-12) continue;
      const double u = ((x - a.x()) * (d - a).y() - (y - a.y()) * (d - a).x()) / det;
      const double v = ((b - a).x() * (y - a.y()) - (b - a).y() * (x - a.x())) / det;
      if (u < 0 || v < 0 || u + v > 1) continue;
      top = std::max(top, a.z() + u * (b - a).z() + v * (d - a).z());
      ++sheets;
      up = det > 0;
    }
    if (sheets != 1 || !up || top < box.min.z() + 1) continue;  // off the footprint, at its floor or not one sheet
    ++spots;
    under += dexels.containsNear(Vec3(x, y, top - 0.5)) ? 1 : 0;
    over += dexels.containsNear(Vec3(x, y, top + 0.5)) ? 1 : 0;
  }
  std::printf("mount_rush closed: %d boundary edges, %d skirt + %d cap triangles, %.0f mm3 (dexels %.0f mm3); "
              "of %d spots part under the top %d, over it %d\n",
              closure.boundary_edges, closure.skirt_triangles, closure.cap_triangles, volume, dexels.volume(), spots,
              under, over);
  ASSERT_GT(spots, 200);
  EXPECT_GE(under, 0.98 * spots);
  EXPECT_LE(over, 0.02 * spots);
}
