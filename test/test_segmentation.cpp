// Segmentation of meshes into planes, cylinders and free-form, checked against known shapes and B-rep faces.
#include <gtest/gtest.h>

#include <cmath>

#include "art2part/geometry/part.h"
#include "art2part/geometry/segmentation.h"
#include "art2part/geometry/step_import.h"
#include "art2part/geometry/surface_fit.h"
#include "test_meshes.h"

using namespace art2part;

namespace {

constexpr double kPi = 3.14159265358979323846;

// A square plate with a round through-hole of `facets` strips: the hole's outward normals point at its axis.
Mesh plateWithHole(double side, double thickness, double radius, int facets, const Vec3& centre) {
  Mesh m;
  auto add = [&m](const Vec3& p) {
    m.vertices.push_back(p);
    return static_cast<int>(m.vertices.size()) - 1;
  };
  std::vector<int> bottom_ring, top_ring, bottom_corner, top_corner;
  for (int i = 0; i < facets; ++i) {
    const double a = 2 * kPi * i / facets;
    const Vec3 p = centre + Vec3(radius * std::cos(a), radius * std::sin(a), 0);
    bottom_ring.push_back(add(p));
    top_ring.push_back(add(p + Vec3(0, 0, thickness)));
  }
  const double h = side / 2;
  const Vec3 corners[4] = {{h, h, 0}, {-h, h, 0}, {-h, -h, 0}, {h, -h, 0}};  // at 45 + 90q degrees
  for (const Vec3& c : corners) {
    bottom_corner.push_back(add(centre + c));
    top_corner.push_back(add(centre + c + Vec3(0, 0, thickness)));
  }
  // Top and bottom: each ring segment of quadrant q fans to corner q; where the quadrant changes, one triangle
  // joins the ring to both corners.
  auto cornerOf = [&](int i) { return (i * 4) / facets; };
  for (int i = 0; i < facets; ++i) {
    const int j = (i + 1) % facets, ci = cornerOf(i), cj = cornerOf(j);
    m.triangles.push_back({top_ring[i], top_corner[ci], top_ring[j]});
    m.triangles.push_back({bottom_ring[i], bottom_ring[j], bottom_corner[ci]});
    if (ci != cj) {
      m.triangles.push_back({top_ring[j], top_corner[ci], top_corner[cj]});
      m.triangles.push_back({bottom_ring[j], bottom_corner[cj], bottom_corner[ci]});
    }
    // The hole wall, facing the axis.
    m.triangles.push_back({bottom_ring[i], top_ring[i], top_ring[j]});
    m.triangles.push_back({bottom_ring[i], top_ring[j], bottom_ring[j]});
  }
  for (int c = 0; c < 4; ++c) {  // outer sides
    const int d = (c + 1) % 4;
    m.triangles.push_back({bottom_corner[c], bottom_corner[d], top_corner[d]});
    m.triangles.push_back({bottom_corner[c], top_corner[d], top_corner[c]});
  }
  return m;
}

}  // namespace

TEST(Segmentation, FindsTheHoleOfAPlateWithItsRadiusAndAxis) {
  const Vec3 centre(12, -7, 3);
  for (int facets : {12, 32, 64}) {
    const Part part = partFromMesh(plateWithHole(100, 10, 15, facets, centre), "plate");
    ASSERT_TRUE(part.check.closed) << facets;
    const FaceCounts c = countFaces(part.faces);
    EXPECT_EQ(c.plane, 6) << facets;
    ASSERT_EQ(c.cylinder, 1) << facets;
    for (const Face& f : part.faces)
      if (f.type == SurfaceType::Cylinder) {
        EXPECT_NEAR(f.radius, 15.0, 1e-6) << facets;
        EXPECT_NEAR(std::abs(f.axis.z()), 1.0, 1e-9);
        const Vec3 d = f.point - centre;
        EXPECT_NEAR((d - d.dot(f.axis) * f.axis).norm(), 0.0, 1e-6) << "the axis passes through the centre";
        EXPECT_TRUE(f.concave) << "a hole";
        EXPECT_EQ(f.triangle_count, 2 * facets);
      }
  }
}

TEST(Segmentation, TellsABossFromAHole) {
  Mesh boss;
  const int n = 24;
  for (int i = 0; i < n; ++i) {
    const double a = 2 * kPi * i / n;
    boss.vertices.emplace_back(5 * std::cos(a), 5 * std::sin(a), 0);
    boss.vertices.emplace_back(5 * std::cos(a), 5 * std::sin(a), 20);
  }
  boss.vertices.emplace_back(0, 0, 0);
  boss.vertices.emplace_back(0, 0, 20);
  for (int i = 0; i < n; ++i) {
    const int j = (i + 1) % n;
    boss.triangles.push_back({2 * i, 2 * j, 2 * j + 1});
    boss.triangles.push_back({2 * i, 2 * j + 1, 2 * i + 1});
    boss.triangles.push_back({2 * n, 2 * j, 2 * i});
    boss.triangles.push_back({2 * n + 1, 2 * i + 1, 2 * j + 1});
  }
  const Part part = partFromMesh(boss, "boss");
  const FaceCounts c = countFaces(part.faces);
  EXPECT_EQ(c.plane, 2);
  ASSERT_EQ(c.cylinder, 1);
  for (const Face& f : part.faces)
    if (f.type == SurfaceType::Cylinder) {
      EXPECT_FALSE(f.concave) << "a boss";
      EXPECT_NEAR(f.radius, 5.0, 1e-6);
    }
}

// The measure of issue 2: STEP tessellation exported as an STL (float32 vertices), segmented, compared with the
// B-rep faces. Prismatic parts must match on 95% of their triangles or better.
TEST(Segmentation, RecoversTheBRepFacesOfPrismaticParts) {
  const std::string parts = ART2PART_SHARED_PARTS;
  for (const char* name : {"nist_ctc_01_asme1_rd.stp", "ANC101.stp", "featuretype.STEP"}) {
    const Part brep = loadPart(parts + "/" + name);
    Mesh exported = brep.mesh;
    for (Vec3& v : exported.vertices) v = v.cast<float>().cast<double>();
    const Part mesh_part = partFromMesh(exported, name);
    ASSERT_EQ(mesh_part.mesh.triangleCount(), brep.mesh.triangleCount()) << name;
    const SegmentationScore s =
        scoreSegmentation(mesh_part.triangle_face, mesh_part.faces, brep.triangle_face, brep.faces);
    EXPECT_GE(s.matched_fraction, 0.95) << name;
    EXPECT_GE(s.type_agreement, 0.95) << name;
    std::printf("%-28s matched %.4f  type agreement %.4f  segments %d  reference faces %d\n", name,
                s.matched_fraction, s.type_agreement, s.segments, s.reference_faces);
  }
}

// The least-squares fits behind segmentation, from a start a rough normal estimate gives: they end on the surface
// the points were sampled from.
TEST(SurfaceFit, CylinderFromATiltedAxisGuessEndsOnTheSurface) {
  const Vec3 axis = Vec3(0.2, -0.1, 1).normalized(), point(3, -2, 1);
  const Vec3 u = axis.cross(Vec3::UnitX()).normalized(), w = axis.cross(u);
  std::vector<Vec3> points;
  for (int i = 0; i < 40; ++i)  // a 120 degree arc, 10 mm tall: a fillet-like patch, not a whole tube
    points.push_back(point + 7.5 * (std::cos(i * 0.05) * u + std::sin(i * 0.05) * w) + (i % 5) * 2.5 * axis);
  CylinderSurface cylinder;
  ASSERT_TRUE(fitCylinder(points, (axis + Vec3(0.05, 0.05, 0)).normalized(), cylinder));
  EXPECT_NEAR(cylinder.radius, 7.5, 1e-6);
  EXPECT_NEAR(std::abs(cylinder.axis.dot(axis)), 1.0, 1e-9);
  for (const Vec3& p : points) EXPECT_NEAR(distanceToCylinder(cylinder, p), 0.0, 1e-6);
}

TEST(SurfaceFit, ConeFromAPerturbedGuessEndsOnTheSurface) {
  ConeSurface truth;
  truth.apex = Vec3(1, 2, 3);
  truth.axis = Vec3(0, 0.3, 1).normalized();
  truth.half_angle = 0.5;
  const Vec3 u = truth.axis.cross(Vec3::UnitX()).normalized(), w = truth.axis.cross(u);
  std::vector<Vec3> points;
  for (int i = 0; i < 60; ++i) {
    const double along = 4 + (i % 6), around = i * 0.1;
    points.push_back(truth.apex + along * truth.axis +
                     along * std::tan(truth.half_angle) * (std::cos(around) * u + std::sin(around) * w));
  }
  ConeSurface guess = truth;
  guess.apex += Vec3(0.3, -0.2, 0.4);
  guess.axis = (truth.axis + Vec3(0.05, 0, 0)).normalized();
  guess.half_angle = 0.45;
  ConeSurface cone;
  ASSERT_TRUE(fitCone(points, guess, cone));
  EXPECT_NEAR(cone.half_angle, truth.half_angle, 1e-6);
  EXPECT_NEAR((cone.apex - truth.apex).norm(), 0.0, 1e-5);
  for (const Vec3& p : points) EXPECT_NEAR(distanceToCone(cone, p), 0.0, 1e-6);
}
