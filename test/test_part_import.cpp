// Loading parts: STEP with B-rep faces, meshes through assimp, units, and every kind of bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "art2part/geometry/mesh_io.h"
#include "art2part/geometry/part.h"
#include "test_meshes.h"

using namespace art2part;

namespace {

const std::string kParts = ART2PART_SHARED_PARTS;
const std::string kExample = std::string(ART2PART_SOURCE_DIR) + "/examples/nist_ctc_01_asme1_rd.stp";

std::string errorOf(const std::string& path, const LoadOptions& options = {}) {
  try {
    loadPart(path, options);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

void expectOneLineError(const std::string& message, const std::string& must_contain) {
  EXPECT_FALSE(message.empty()) << "no error for a bad input (" << must_contain << ")";
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  EXPECT_NE(message.find(must_contain), std::string::npos) << message;
}

// Every triangle of a plane face lies in its plane and faces its outward normal; cylinder triangles lie on it.
void expectTrianglesOnTheirSurfaces(const Part& part) {
  const double tol = 1e-3 * part.check.box.diagonal();
  for (int t = 0; t < part.mesh.triangleCount(); ++t) {
    const Face& f = part.faces.at(part.triangle_face.at(t));
    if (f.type == SurfaceType::Plane) {
      EXPECT_GT(triangleNormal(part.mesh, t).dot(f.normal), 0.999) << "triangle " << t;
      for (int k = 0; k < 3; ++k) EXPECT_NEAR(f.normal.dot(part.mesh.corner(t, k)), f.offset, tol);
    } else if (f.type == SurfaceType::Cylinder) {
      for (int k = 0; k < 3; ++k) {
        const Vec3 d = part.mesh.corner(t, k) - f.point;
        EXPECT_NEAR((d - d.dot(f.axis) * f.axis).norm(), f.radius, tol) << "triangle " << t;
      }
      // A hole's outward normals point towards its axis.
      const Vec3 c = triangleCentroid(part.mesh, t) - f.point;
      const Vec3 radial = c - c.dot(f.axis) * f.axis;
      if (radial.norm() > 0.5 * f.radius) {
        EXPECT_EQ(triangleNormal(part.mesh, t).dot(radial) < 0, f.concave);
      }
    }
  }
}

}  // namespace

TEST(Step, NistCtc1HasItsBRepFacesOnAClosedMesh) {
  const Part part = loadPart(kExample);
  EXPECT_EQ(part.face_source, FaceSource::BRep);
  const FaceCounts c = countFaces(part.faces);
  EXPECT_EQ(c.total(), 139);
  EXPECT_EQ(c.plane, 80);
  EXPECT_EQ(c.cylinder, 57);
  EXPECT_EQ(c.cone, 2);
  EXPECT_TRUE(part.check.closed);
  EXPECT_TRUE(part.check.manifold);
  EXPECT_GT(part.check.volume, 0.0);
  EXPECT_EQ(part.repairs.flipped, 0) << "OCCT face orientation must give outward triangles";
  ASSERT_EQ(part.triangle_face.size(), part.mesh.triangles.size());
  for (const Face& f : part.faces) EXPECT_GT(f.triangle_count, 0);
  expectTrianglesOnTheirSurfaces(part);
}

TEST(Step, InchFileComesOutInMillimetres) {
  const Part part = loadPart(kParts + "/featuretype.STEP");
  const Vec3 size = part.check.box.size();
  EXPECT_NEAR(size.maxCoeff(), 5.0 * 25.4, 1e-3);
  EXPECT_NEAR(size.minCoeff(), 1.375 * 25.4, 1e-3);
  EXPECT_TRUE(part.check.closed);
  expectTrianglesOnTheirSurfaces(part);
}

TEST(Step, EverySharedStepPartLoadsClosed) {
  for (const char* name : {"ANC101.stp", "nist_ctc_02_asme1_rc.stp"}) {
    const Part part = loadPart(kParts + "/" + name);
    EXPECT_TRUE(part.check.closed) << name;
    EXPECT_GT(part.check.volume, 0.0) << name;
    EXPECT_GT(countFaces(part.faces).total(), 50) << name;
  }
}

TEST(Step, FinerToleranceGivesMoreTrianglesAndTheSameVolume) {
  LoadOptions coarse, fine;
  coarse.chordal_tolerance = 0.5;
  fine.chordal_tolerance = 0.05;
  const Part a = loadPart(kExample, coarse), b = loadPart(kExample, fine);
  EXPECT_GT(b.mesh.triangleCount(), a.mesh.triangleCount());
  EXPECT_NEAR(a.check.volume / b.check.volume, 1.0, 5e-3);
}

TEST(Mesh, BinaryStlKeepsTriangleOrder) {
  const std::string dir = test::tempDir();
  Mesh m = test::box(Vec3(0, 0, 0), Vec3(10, 10, 10));
  test::append(m, test::box(Vec3(20, 0, 0), Vec3(25, 5, 5)));
  writeBinaryStl(m, dir + "/two.stl", "solid looking header");
  const Part part = loadPart(dir + "/two.stl");
  ASSERT_EQ(part.mesh.triangleCount(), m.triangleCount());
  for (int t = 0; t < m.triangleCount(); ++t)
    EXPECT_LT((triangleCentroid(part.mesh, t) - triangleCentroid(m, t)).norm(), 1e-5) << "triangle " << t;
  EXPECT_EQ(part.mesh.vertices.size(), 16u);
  EXPECT_EQ(part.check.components, 2);
  EXPECT_NEAR(part.check.volume, 1125.0, 1e-3);
}

TEST(Mesh, AsciiStlObjAndPlyLoad) {
  const std::string dir = test::tempDir();
  const Mesh cube = test::box(Vec3(0, 0, 0), Vec3(4, 4, 4));
  test::writeText(dir + "/cube.stl", test::asciiStl(cube));
  std::string obj;
  for (const Vec3& v : cube.vertices) obj += "v " + std::to_string(v.x()) + " " + std::to_string(v.y()) + " " + std::to_string(v.z()) + "\n";
  // Quads, as OBJ files often have: triangulated on reading.
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) obj += "f " + std::to_string(q[0] + 1) + " " + std::to_string(q[1] + 1) + " " + std::to_string(q[2] + 1) + " " + std::to_string(q[3] + 1) + "\n";
  test::writeText(dir + "/cube.obj", obj);
  std::string ply = "ply\nformat ascii 1.0\nelement vertex 8\nproperty float x\nproperty float y\nproperty float z\n"
                    "element face 12\nproperty list uchar int vertex_indices\nend_header\n";
  for (const Vec3& v : cube.vertices) ply += std::to_string(v.x()) + " " + std::to_string(v.y()) + " " + std::to_string(v.z()) + "\n";
  for (const Triangle& t : cube.triangles) ply += "3 " + std::to_string(t[0]) + " " + std::to_string(t[1]) + " " + std::to_string(t[2]) + "\n";
  test::writeText(dir + "/cube.ply", ply);
  for (const char* name : {"cube.stl", "cube.obj", "cube.ply"}) {
    const Part part = loadPart(dir + "/" + name);
    EXPECT_EQ(part.mesh.triangleCount(), 12) << name;
    EXPECT_TRUE(part.check.closed) << name;
    EXPECT_NEAR(part.check.volume, 64.0, 1e-6) << name;
    EXPECT_EQ(countFaces(part.faces).plane, 6) << name << ": segmentation must find the six sides";
  }
}

TEST(Mesh, EverySharedMeshLoads) {
  for (const char* name : {"ktoolcav.stl", "mount_rush.stl", "Ailette001Solid-nohole-decimated-smoothed.stl",
                           "nist_ctc_02_asme1_rc_fine_tess.stl"}) {
    const Part part = loadPart(kParts + "/" + name);
    EXPECT_GT(part.mesh.triangleCount(), 1000) << name;
    EXPECT_EQ(part.triangle_face.size(), part.mesh.triangles.size());
  }
  // SOURCES.md: the relief is open and dirty, the blade is watertight.
  EXPECT_FALSE(loadPart(kParts + "/mount_rush.stl").check.closed);
  EXPECT_TRUE(loadPart(kParts + "/Ailette001Solid-nohole-decimated-smoothed.stl").check.closed);
}

TEST(Mesh, UnitsScaleAMeshFile) {
  const std::string dir = test::tempDir();
  writeBinaryStl(test::box(Vec3(0, 0, 0), Vec3(2, 1, 1)), dir + "/inch.stl");
  LoadOptions inch;
  inch.unit = LengthUnit::Inch;
  EXPECT_NEAR(loadPart(dir + "/inch.stl", inch).check.box.size().x(), 50.8, 1e-9);
}

TEST(BadInput, MissingEmptyFolderAndNotAMesh) {
  const std::string dir = test::tempDir();
  expectOneLineError(errorOf(dir + "/nothing.stl"), "no such file");
  test::writeText(dir + "/empty.stl", "");
  expectOneLineError(errorOf(dir + "/empty.stl"), "empty file");
  expectOneLineError(errorOf(dir), "folder");
  test::writeText(dir + "/notes.stl", "this is a shopping list, not a mesh\nmilk\neggs\n");
  expectOneLineError(errorOf(dir + "/notes.stl"), "notes.stl");
  test::writeText(dir + "/notes.stp", "this is not STEP either\n");
  expectOneLineError(errorOf(dir + "/notes.stp"), "notes.stp");
}

TEST(BadInput, NanZeroSizeAndWrongUnits) {
  const std::string dir = test::tempDir();
  Mesh nan = test::box(Vec3(0, 0, 0), Vec3(10, 10, 10));
  nan.vertices[3].z() = std::nan("");
  writeBinaryStl(nan, dir + "/nan.stl");
  expectOneLineError(errorOf(dir + "/nan.stl"), "not a finite number");

  Mesh point = test::box(Vec3(1, 1, 1), Vec3(1, 1, 1));
  writeBinaryStl(point, dir + "/point.stl");
  expectOneLineError(errorOf(dir + "/point.stl"), "zero size");

  writeBinaryStl(test::box(Vec3(0, 0, 0), Vec3(0.12, 0.05, 0.03)), dir + "/metres.stl");
  expectOneLineError(errorOf(dir + "/metres.stl"), "metres");
  LoadOptions metres;
  metres.unit = LengthUnit::Metre;
  EXPECT_NEAR(loadPart(dir + "/metres.stl", metres).check.box.size().x(), 120.0, 1e-3);

  writeBinaryStl(test::box(Vec3(0, 0, 0), Vec3(120000, 50000, 30000)), dir + "/microns.stl");
  expectOneLineError(errorOf(dir + "/microns.stl"), "micrometres");
}

TEST(BadInput, HolesFlipsAndDegeneratesAreRepairedOrReported) {
  const std::string dir = test::tempDir();
  Mesh m = test::box(Vec3(0, 0, 0), Vec3(10, 10, 10));
  std::swap(m.triangles[2][1], m.triangles[2][2]);         // one flipped
  m.vertices.emplace_back(5, 0, 0);
  m.triangles.insert(m.triangles.begin() + 5, Triangle{0, 1, 8});  // degenerate
  writeBinaryStl(m, dir + "/dirty.stl");
  const Part part = loadPart(dir + "/dirty.stl");
  EXPECT_EQ(part.repairs.flipped, 1);
  EXPECT_EQ(part.repairs.dropped_degenerate, 1);
  EXPECT_TRUE(part.check.closed);
  EXPECT_NEAR(part.check.volume, 1000.0, 1e-3);
  EXPECT_GE(part.repairs.notes.size(), 3u);  // merged, dropped, flipped

  Mesh open = test::box(Vec3(0, 0, 0), Vec3(10, 10, 10));
  open.triangles.resize(10);
  writeBinaryStl(open, dir + "/open.stl");
  const Part holed = loadPart(dir + "/open.stl");
  EXPECT_FALSE(holed.check.closed);
  const auto warnings = partWarnings(holed);
  ASSERT_FALSE(warnings.empty());
  EXPECT_NE(warnings[0].find("open: 4 boundary edges"), std::string::npos) << warnings[0];
}
