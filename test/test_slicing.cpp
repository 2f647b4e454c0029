// Slicing (thesis 4.1.1): boxes, frames with holes and islands, vertices on the plane, a tilted plane, an open and a
// non-manifold mesh, real parts; contours closed, oriented with the material on the left, nested, on the plane.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>

#include "art2part/geometry/part.h"
#include "art2part/roughing/slicing.h"
#include "test_meshes.h"

using namespace art2part;

namespace {

constexpr double kPi = 3.14159265358979323846;
const std::string kParts = ART2PART_SHARED_PARTS;

// A right-handed slice frame with the given normal.
struct Frame {
  Vec3 origin = Vec3::Zero();
  Vec3 x = Vec3::UnitX(), y = Vec3::UnitY(), z = Vec3::UnitZ();
};

Frame frameAlong(const Vec3& normal, const Vec3& origin = Vec3::Zero()) {
  Frame f;
  f.origin = origin;
  f.z = normal.normalized();
  f.x = f.z.unitOrthogonal();
  f.y = f.z.cross(f.x);
  return f;
}

Slice slice(const Mesh& mesh, double z, const Frame& f = {}) {
  return sliceMesh(mesh, buildAdjacency(mesh), f.origin, f.x, f.y, f.z, z);
}

double signedAreaSum(const Slice& s) {
  double sum = 0;
  for (const SliceContour& c : s.contours) sum += c.area_mm2;
  return sum;
}

// A prism between heights z0 and z1 over the ring `outer` (counter-clockwise in x, y) with the hole `hole` (also
// given counter-clockwise, same vertex count, vertex i of the hole facing vertex i of the outer ring, so the caps
// are quad strips; empty for no hole, then the outer ring must be convex). Closed, outward, vertices shared.
Mesh extrude(const Ring& outer, const Ring& hole, double z0, double z1) {
  Mesh m;
  const int n = static_cast<int>(outer.size());
  // Vertices: outer bottom [0, n), outer top [n, 2n), hole bottom [2n, 3n), hole top [3n, 4n).
  for (const Ring* ring : {&outer, &hole})
    for (double z : {z0, z1})
      for (const Point2& p : *ring) m.vertices.emplace_back(p.x(), p.y(), z);
  auto quad = [&](int a, int b, int c, int d) {
    m.triangles.push_back({a, b, c});
    m.triangles.push_back({a, c, d});
  };
  const int ob = 0, ot = n, hb = 2 * n, ht = 3 * n;
  for (int i = 0; i < n; ++i) {
    const int j = (i + 1) % n;
    quad(ob + i, ob + j, ot + j, ot + i);  // outer wall: material on the left of i -> j, normal to the right
    if (hole.empty()) continue;
    quad(hb + j, hb + i, ht + i, ht + j);  // hole wall, run clockwise
    quad(ot + i, ot + j, ht + j, ht + i);  // top cap strip, normal +z
    quad(ob + j, ob + i, hb + i, hb + j);  // bottom cap strip, normal -z
  }
  if (hole.empty())
    for (int i = 1; i + 1 < n; ++i) {
      m.triangles.push_back({ot, ot + i, ot + i + 1});
      m.triangles.push_back({ob, ob + i + 1, ob + i});
    }
  return m;
}

Ring rectangle(double x0, double y0, double x1, double y1) { return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}; }

// One index per distinct position: meshes built from pieces then share the vertices they touch at.
Mesh mergeVertices(const Mesh& in) {
  Mesh out;
  std::map<std::array<double, 3>, int> index;
  std::vector<int> remap;
  for (const Vec3& v : in.vertices) {
    const auto [it, added] = index.emplace(std::array<double, 3>{v.x(), v.y(), v.z()}, out.vertices.size());
    if (added) out.vertices.push_back(v);
    remap.push_back(it->second);
  }
  for (const Triangle& t : in.triangles) out.triangles.push_back({remap[t[0]], remap[t[1]], remap[t[2]]});
  return out;
}

void transform(Mesh& m, const Eigen::Matrix3d& rotation, const Vec3& shift) {
  for (Vec3& v : m.vertices) v = rotation * v + shift;
}

// Every contour point, taken back to 3D, lies on the plane and on an edge of the mesh that crosses it (the crossings
// computed here independently, all of them, sorted by x for the look-up).
void expectOnPlaneAndEdges(const Mesh& mesh, const Slice& s, const Frame& f, double z) {
  std::vector<Vec3> crossings;
  for (const Triangle& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) {
      const Vec3 &a = mesh.vertices[t[k]], &b = mesh.vertices[t[(k + 1) % 3]];
      const double ha = (a - f.origin).dot(f.z) - z, hb = (b - f.origin).dot(f.z) - z;
      if ((ha >= 0) != (hb >= 0)) crossings.push_back(a + ha / (ha - hb) * (b - a));
    }
  std::sort(crossings.begin(), crossings.end(), [](const Vec3& a, const Vec3& b) { return a.x() < b.x(); });
  const double tol = 1e-9;
  int far_from_plane = 0, off_edges = 0;
  for (const SliceContour& c : s.contours)
    for (const Point2& p : c.points) {
      const Vec3 q = f.origin + p.x() * f.x + p.y() * f.y + z * f.z;
      if (std::abs((q - f.origin).dot(f.z) - z) >= tol) ++far_from_plane;
      auto it = std::lower_bound(crossings.begin(), crossings.end(), q.x() - tol,
                                 [](const Vec3& a, double x) { return a.x() < x; });
      bool found = false;
      for (; it != crossings.end() && it->x() <= q.x() + tol && !found; ++it) found = (*it - q).norm() < tol;
      if (!found) ++off_edges;
    }
  EXPECT_EQ(far_from_plane, 0);
  EXPECT_EQ(off_edges, 0);
}

TEST(Slicing, BoxAtMidHeightIsOneCounterClockwiseContour) {
  const Mesh box = test::box(Vec3(-1, 0.5, 0), Vec3(2, 2.5, 1));
  const Slice s = slice(box, 0.5);
  EXPECT_EQ(s.z, 0.5);
  EXPECT_EQ(s.open_chains, 0);
  ASSERT_EQ(s.contours.size(), 1u);
  const SliceContour& c = s.contours[0];
  EXPECT_TRUE(c.closed);
  EXPECT_EQ(c.parent, -1);
  EXPECT_EQ(c.depth, 0);
  EXPECT_NEAR(c.area_mm2, 3.0 * 2.0, 1e-9);  // positive: counter-clockwise seen from +z
  for (const Point2& p : c.points) {
    const bool on_wall = std::abs(p.x() + 1) < 1e-12 || std::abs(p.x() - 2) < 1e-12 ||
                         std::abs(p.y() - 0.5) < 1e-12 || std::abs(p.y() - 2.5) < 1e-12;
    EXPECT_TRUE(on_wall) << p.transpose();
  }
  EXPECT_NEAR(regionArea(sliceRegion(s)), 6.0, 1e-9);
  expectOnPlaneAndEdges(box, s, Frame{}, 0.5);
}

TEST(Slicing, BoxSeenFromBelowIsStillCounterClockwise) {
  // Looking along -z (frame x, -y, -z) the section is the same rectangle, still with the material on the left.
  const Mesh box = test::box(Vec3(0, 0, 0), Vec3(2, 3, 1));
  Frame f;
  f.y = -Vec3::UnitY();
  f.z = -Vec3::UnitZ();
  const Slice s = slice(box, -0.25, f);
  ASSERT_EQ(s.contours.size(), 1u);
  EXPECT_NEAR(s.contours[0].area_mm2, 6.0, 1e-9);
  for (const Point2& p : s.contours[0].points) EXPECT_LE(p.y(), 1e-12);
}

TEST(Slicing, PlaneThroughVerticesStillClosesContours) {
  const Mesh box = test::box(Vec3(0, 0, 0), Vec3(2, 3, 1));
  // At the top: the vertices there count as a hair above, so the section is the material just below.
  const Slice top = slice(box, 1.0);
  EXPECT_EQ(top.open_chains, 0);
  ASSERT_EQ(top.contours.size(), 1u);
  EXPECT_TRUE(top.contours[0].closed);
  EXPECT_NEAR(top.contours[0].area_mm2, 6.0, 1e-12);
  // At the bottom the whole box is above: nothing.
  EXPECT_TRUE(slice(box, 0.0).contours.empty());

  // A step: profile (x, z) of an L extruded along y; at the height of the lower top face the full lower section.
  const Ring profile = {{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};  // in (x, z)
  Mesh step;
  const int n = static_cast<int>(profile.size());
  for (double y : {0.0, 1.5})
    for (const Point2& p : profile) step.vertices.emplace_back(p.x(), y, p.y());
  // Counter-clockwise in (x, z) is counter-clockwise seen from -y. The caps are fans from corner 3 = (1, 1), around
  // which the L is star-shaped; the walls face away from the material, on the right of i -> j.
  for (int i = 0; i < n; ++i) {
    const int j = (i + 1) % n;
    if (i != 3 && j != 3) {
      step.triangles.push_back({3, i, j});              // y = 0 cap, normal -y
      step.triangles.push_back({n + 3, n + j, n + i});  // y = 1.5 cap, normal +y
    }
    step.triangles.push_back({i, n + j, j});
    step.triangles.push_back({i, n + i, n + j});
  }
  ASSERT_NEAR(signedVolume(step), 3 * 1.5, 1e-12);
  const Adjacency adjacency = buildAdjacency(step);
  ASSERT_TRUE(adjacency.closed() && adjacency.manifold());
  for (double z : {1.0, 2.0, 0.5, 1.5}) {
    const Slice s = slice(step, z);
    EXPECT_EQ(s.open_chains, 0) << z;
    ASSERT_EQ(s.contours.size(), 1u) << z;
    EXPECT_TRUE(s.contours[0].closed);
    EXPECT_NEAR(s.contours[0].area_mm2, (z <= 1 ? 2.0 : 1.0) * 1.5, 1e-12) << z;
    expectOnPlaneAndEdges(step, s, Frame{}, z);
  }

  // An octahedron cut through its four equator vertices: the contour is exactly those vertices.
  Mesh octahedron;
  octahedron.vertices = {{1, 0, 0}, {0, 1, 0}, {-1, 0, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  for (int i = 0; i < 4; ++i) {
    octahedron.triangles.push_back({i, (i + 1) % 4, 4});
    octahedron.triangles.push_back({(i + 1) % 4, i, 5});
  }
  ASSERT_GT(signedVolume(octahedron), 0);
  const Slice equator = slice(octahedron, 0.0);
  EXPECT_EQ(equator.open_chains, 0);
  ASSERT_EQ(equator.contours.size(), 1u);
  EXPECT_EQ(equator.contours[0].points.size(), 4u);
  EXPECT_NEAR(equator.contours[0].area_mm2, 2.0, 1e-15);
  // At the apex the section a hair below is a point: no contour of any size.
  for (const SliceContour& c : slice(octahedron, 1.0).contours) EXPECT_NEAR(c.area_mm2, 0.0, 1e-15);
}

TEST(Slicing, FrameHasAnOuterContourAHoleAndAnIsland) {
  const Ring outer = rectangle(-5, -5, 5, 5), hole = rectangle(-2, -3, 2, 3);
  Mesh part = extrude(outer, hole, 0, 4);
  ASSERT_NEAR(signedVolume(part), (100 - 24) * 4, 1e-9);
  test::append(part, test::box(Vec3(-1, -1, 1), Vec3(1, 2, 3)));  // an island in the hole, not touching it
  const Adjacency adjacency = buildAdjacency(part);
  ASSERT_TRUE(adjacency.closed() && adjacency.manifold());

  const Slice s = sliceMesh(part, adjacency, Vec3::Zero(), Vec3::UnitX(), Vec3::UnitY(), Vec3::UnitZ(), 2.0);
  EXPECT_EQ(s.open_chains, 0);
  ASSERT_EQ(s.contours.size(), 3u);
  int outer_i = -1, hole_i = -1, island_i = -1;
  for (int i = 0; i < 3; ++i) {
    const double a = s.contours[i].area_mm2;
    (std::abs(a - 100) < 1e-9 ? outer_i : std::abs(a + 24) < 1e-9 ? hole_i : island_i) = i;
  }
  ASSERT_GE(outer_i, 0);
  ASSERT_GE(hole_i, 0);
  ASSERT_GE(island_i, 0);
  EXPECT_NEAR(s.contours[island_i].area_mm2, 6, 1e-9);
  EXPECT_EQ(s.contours[outer_i].depth, 0);
  EXPECT_EQ(s.contours[outer_i].parent, -1);
  EXPECT_EQ(s.contours[hole_i].depth, 1);
  EXPECT_EQ(s.contours[hole_i].parent, outer_i);
  EXPECT_EQ(s.contours[island_i].depth, 2);
  EXPECT_EQ(s.contours[island_i].parent, hole_i);
  for (const SliceContour& c : s.contours) EXPECT_TRUE(c.closed);
  EXPECT_NEAR(regionArea(sliceRegion(s)), 100 - 24 + 6, 1e-9);

  // Above the island: the frame only, outer minus hole.
  const Slice above = sliceMesh(part, adjacency, Vec3::Zero(), Vec3::UnitX(), Vec3::UnitY(), Vec3::UnitZ(), 3.5);
  ASSERT_EQ(above.contours.size(), 2u);
  EXPECT_NEAR(regionArea(sliceRegion(above)), 100 - 24, 1e-9);
  EXPECT_NEAR(signedAreaSum(above), 100 - 24, 1e-9);

  // Machinable: a 12 x 12 stock section minus the part leaves the margin, the hole, less the island.
  const Region stock = regionFromPolygons({rectangle(-6, -6, 6, 6)});
  EXPECT_NEAR(regionArea(machinableRegion(stock, s)), 144 - 100 + 24 - 6, 1e-9);
  EXPECT_TRUE(regionContains(machinableRegion(stock, s), Point2(0, -2.5)));
  EXPECT_FALSE(regionContains(machinableRegion(stock, s), Point2(0, 0)));
}

TEST(Slicing, TiltedPlaneThroughATurnedFrameCutsTheAnalyticArea) {
  // A tall frame prism cut by a plane at 35 degrees to its axis: the section of the walls is the frame's area over
  // cos(35 deg). The whole thing is turned and moved arbitrarily.
  const double tilt = 35 * kPi / 180;
  Mesh part = extrude(rectangle(-5, -5, 5, 5), rectangle(-2, -2, 2, 2), -50, 50);
  const Eigen::Matrix3d turn =
      (Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()) * Eigen::AngleAxisd(-1.1, Vec3(0, 1, -1).normalized()))
          .toRotationMatrix();
  const Vec3 shift(12.5, -7.25, 3.0);
  transform(part, turn, shift);
  const Vec3 normal = turn * Vec3(std::sin(tilt) * std::cos(0.4), std::sin(tilt) * std::sin(0.4), std::cos(tilt));
  const Frame f = frameAlong(normal, Vec3(1, 2, 3));
  for (double offset : {-10.0, 0.0, 3.3, 17.0}) {
    const double z = (turn * Vec3(0, 0, offset) + shift - f.origin).dot(f.z);
    const Slice s = slice(part, z, f);
    EXPECT_EQ(s.open_chains, 0);
    ASSERT_EQ(s.contours.size(), 2u);
    const double expected = (100 - 16) / std::cos(tilt);
    EXPECT_NEAR(signedAreaSum(s), expected, 1e-9);
    const SliceContour& big = s.contours[0].area_mm2 > 0 ? s.contours[0] : s.contours[1];
    const SliceContour& small = s.contours[0].area_mm2 > 0 ? s.contours[1] : s.contours[0];
    EXPECT_NEAR(big.area_mm2, 100 / std::cos(tilt), 1e-9);
    EXPECT_NEAR(small.area_mm2, -16 / std::cos(tilt), 1e-9);
    EXPECT_EQ(small.depth, 1);
    EXPECT_EQ(&s.contours[small.parent], &big);
    EXPECT_NEAR(regionArea(sliceRegion(s)), expected, 1e-4 * expected);
    expectOnPlaneAndEdges(part, s, f, z);
  }
}

TEST(Slicing, OpenMeshGivesAnOpenChainNotACrash) {
  Mesh box = test::box(Vec3(0, 0, 0), Vec3(2, 3, 1));
  box.triangles.erase(box.triangles.begin() + 4);  // triangle (0, 1, 5) of the face y = 0
  const Slice s = slice(box, 0.5);
  EXPECT_EQ(s.open_chains, 1);
  ASSERT_EQ(s.contours.size(), 1u);
  EXPECT_FALSE(s.contours[0].closed);
  EXPECT_EQ(s.contours[0].parent, -1);
  // The chain runs around the three remaining walls, from one end of the gap to the other.
  EXPECT_GE(s.contours[0].points.size(), 4u);
  EXPECT_TRUE(regionEmpty(sliceRegion(s)));
  // The missing triangle (0, 1, 5) spans the whole height: every plane meets the gap once.
  for (double z : {0.1, 0.9, 1.0}) EXPECT_EQ(slice(box, z).open_chains, 1) << z;
}

TEST(Slicing, NonManifoldEdgeIsCrossedByMatchingTheEdge) {
  // Two boxes touching along a vertical edge, vertices merged: four triangles on that edge.
  Mesh two = test::box(Vec3(0, 0, 0), Vec3(1, 1, 1));
  test::append(two, test::box(Vec3(1, 1, 0), Vec3(2, 2, 1)));
  two = mergeVertices(two);
  const Adjacency adjacency = buildAdjacency(two);
  ASSERT_GT(adjacency.nonmanifold_edges, 0);
  const Slice s = sliceMesh(two, adjacency, Vec3::Zero(), Vec3::UnitX(), Vec3::UnitY(), Vec3::UnitZ(), 0.5);
  EXPECT_EQ(s.open_chains, 0);
  ASSERT_FALSE(s.contours.empty());
  for (const SliceContour& c : s.contours) {
    EXPECT_TRUE(c.closed);
    EXPECT_GT(c.area_mm2, 0);
  }
  EXPECT_NEAR(signedAreaSum(s), 2.0, 1e-12);
  EXPECT_NEAR(regionArea(sliceRegion(s)), 2.0, 1e-9);
}

// Real parts: at 20 heights along a direction every contour closes, the region has area, and it agrees with the
// signed contour areas.
void checkPart(const std::string& file, const Vec3& direction) {
  SCOPED_TRACE(file);
  const Part part = loadPart(kParts + "/" + file);
  ASSERT_TRUE(part.adjacency.closed());
  const Frame f = frameAlong(direction, part.mesh.vertices.front());
  double lo = INFINITY, hi = -INFINITY;
  for (const Vec3& v : part.mesh.vertices) {
    lo = std::min(lo, (v - f.origin).dot(f.z));
    hi = std::max(hi, (v - f.origin).dot(f.z));
  }
  for (int i = 0; i < 20; ++i) {
    const double z = lo + (hi - lo) * (i + 0.5) / 20;
    const Slice s = sliceMesh(part.mesh, part.adjacency, f.origin, f.x, f.y, f.z, z);
    EXPECT_EQ(s.open_chains, 0) << z;
    ASSERT_FALSE(s.contours.empty()) << z;
    for (const SliceContour& c : s.contours) {
      EXPECT_TRUE(c.closed);
      EXPECT_EQ(c.depth % 2 == 0, c.area_mm2 > 0) << z;  // outer boundaries counter-clockwise, holes clockwise
    }
    const double area = regionArea(sliceRegion(s));
    EXPECT_GT(area, 0) << z;
    EXPECT_NEAR(signedAreaSum(s), area, 1e-3 * area) << z;
    expectOnPlaneAndEdges(part.mesh, s, f, z);
  }
}

TEST(Slicing, NistCtc01AlongZ) { checkPart("nist_ctc_01_asme1_rd.stp", Vec3::UnitZ()); }
TEST(Slicing, NistCtc01Tilted) { checkPart("nist_ctc_01_asme1_rd.stp", Vec3(1, -2, 3)); }
TEST(Slicing, Anc101AlongItsInclinedFace) { checkPart("ANC101.stp", Vec3(0.5, 0, std::sqrt(3) / 2)); }
TEST(Slicing, BladeAlongX) { checkPart("Ailette001Solid-nohole-decimated-smoothed.stl", Vec3::UnitX()); }

TEST(Slicing, LargeMeshSlicesInMilliseconds) {
  const Part part = loadPart(kParts + "/nist_ctc_02_asme1_rc_fine_tess.stl");
  const Mesh& mesh = part.mesh;
  ASSERT_GT(mesh.triangleCount(), 100000);
  const Box box = boundingBox(mesh);
  const Frame f;
  sliceMesh(mesh, part.adjacency, f.origin, f.x, f.y, f.z, box.center().z());  // first call: caches warm
  const int count = 50;
  int contours = 0, open = 0;
  double seconds = 0;
  for (int i = 0; i < count; ++i) {
    const double z = box.min.z() + (box.max.z() - box.min.z()) * (i + 0.5) / count;
    const auto start = std::chrono::steady_clock::now();
    const Slice s = sliceMesh(mesh, part.adjacency, f.origin, f.x, f.y, f.z, z);
    seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    contours += static_cast<int>(s.contours.size());
    open += s.open_chains;
  }
  const double ms = 1e3 * seconds / count;
  std::printf("  %d triangles (%d boundary, %d non-manifold edges): %.3f ms per slice, %d contours, %d open chains "
              "over %d slices\n",
              mesh.triangleCount(), part.adjacency.boundary_edges, part.adjacency.nonmanifold_edges, ms, contours,
              open, count);
  EXPECT_LT(ms, 10.0);
  EXPECT_GT(contours, count);
}

}  // namespace
