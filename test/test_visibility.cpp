// The visibility stage as a whole: side correction, cones, the two backends against each other on real parts, and
// the files of the `art2part visibility` contract.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "art2part/geometry/mesh_io.h"
#include "art2part/visibility/analysis.h"
#include "art2part/visibility/cones.h"
#include "art2part/visibility/side_correction.h"
#include "test_meshes.h"

using namespace art2part;

namespace {

const std::string kParts = ART2PART_SHARED_PARTS;
const std::string kExample = std::string(ART2PART_SOURCE_DIR) + "/examples/nist_ctc_01_asme1_rd.stp";
constexpr double kPi = 3.14159265358979323846;

int directionNearest(const DirectionSet& set, const Vec3& v) {
  int best = 0;
  for (int d = 1; d < set.size(); ++d)
    if (set.directions[d].dot(v) > set.directions[best].dot(v)) best = d;
  return best;
}

}  // namespace

TEST(SideCorrection, WallsOfABoxBecomeVisibleAlongTheVerticalButNotTheFloor) {
  const Part part = partFromMesh(test::box(Vec3(0, 0, 0), Vec3(30, 20, 10)), "box");
  VisibilityOptions options;
  options.level = 2;
  options.side_correction = false;
  VisibilityResult direct = analyseVisibility(part, options);
  const int up = directionNearest(direct.directions, Vec3::UnitZ());
  ASSERT_GT(direct.directions.directions[up].z(), 1 - 1e-12) << "+z is a special direction of a box";
  VisibilityResult corrected = direct;
  const long long added = sideCorrection(corrected.map, part.mesh, corrected.directions);
  EXPECT_GT(added, 0);
  for (int t = 0; t < part.mesh.triangleCount(); ++t) {
    const Vec3 n = triangleNormal(part.mesh, t);
    EXPECT_EQ(direct.map.bits.get(t, up), n.z() > 0.5) << "direct: only the top along +z";
    EXPECT_EQ(corrected.map.bits.get(t, up), n.z() > -0.5) << "sideways: the walls too, never the bottom";
  }
}

TEST(Cones, ABoxTopSeesAHemisphereAndCommonConesIntersect) {
  const Part part = partFromMesh(test::box(Vec3(0, 0, 0), Vec3(10, 10, 10)), "box");
  VisibilityOptions options;
  options.level = 3;
  options.side_correction = false;
  const VisibilityResult r = analyseVisibility(part, options);
  std::vector<int> top;
  for (int t = 0; t < part.mesh.triangleCount(); ++t)
    if (triangleNormal(part.mesh, t).z() > 0.5) top.push_back(t);
  ASSERT_EQ(top.size(), 2u);
  // The top sees every direction with d.z > 0: the cells of the upper hemisphere, about 2 pi.
  EXPECT_NEAR(coneSolidAngle(triangleCone(r.map, top[0]), r.directions), 2 * kPi, 0.25);
  const Cone both = commonCone(r.map, top);
  EXPECT_EQ(coneSize(both), coneSize(triangleCone(r.map, top[0])));
  std::vector<int> top_and_side = {top[0], 0};
  EXPECT_LT(coneSize(commonCone(r.map, top_and_side)), coneSize(unionCone(r.map, top_and_side)));
  EXPECT_TRUE(invisibleTriangles(r.map).empty());
}

// Issue 3's accuracy figure at a level small enough for a test: agreement of the two backends on (triangle, direction)
// pairs, leaving out pairs within 2 degrees of grazing. The target is 99.5% (bench_visibility accuracy prints
// it on every part at level 4, bench_visibility judge asks the exact oracle who is right where they differ); measured
// at level 2: CTC 1 0.99986, ktoolcav 0.99906, mount_rush 0.99778 (before the render backend's ray fallback and the
// ray backend's edge-end samples: 0.972, 0.992, 0.979).
TEST(Backends, RayAndRenderMostlyAgreeOnRealParts) {
  for (const std::string name : {"nist_ctc_01_asme1_rd.stp", "ktoolcav.stl", "mount_rush.stl"}) {
    LoadOptions load;
    const Part part = loadPart(kParts + "/" + name, load);
    VisibilityOptions options;
    options.level = 2;
    options.side_correction = false;
    const VisibilityResult ray = analyseVisibility(part, options);
    options.backend = VisibilityBackend::Render;
    const VisibilityResult render = analyseVisibility(part, options);
    ASSERT_EQ(ray.map.directions(), render.map.directions());
    long long compared = 0, differ = 0;
    const double grazing = std::sin(2.0 * kPi / 180.0);
    for (int t = 0; t < part.mesh.triangleCount(); ++t) {
      const Vec3 n = triangleNormal(part.mesh, t);
      for (int d = 0; d < ray.map.directions(); ++d) {
        if (std::abs(n.dot(ray.directions.directions[d])) < grazing) continue;
        ++compared;
        differ += ray.map.bits.get(t, d) != render.map.bits.get(t, d);
      }
    }
    const double agreement = 1.0 - static_cast<double>(differ) / compared;
    std::printf("%-26s %lld pairs compared, agreement %.5f\n", name.c_str(), compared, agreement);
    EXPECT_GE(agreement, 0.995) << name;
  }
}

TEST(VisibilityFiles, FollowTheContractToTheLetter) {
  const Part part = loadPart(kExample);
  VisibilityOptions options;
  options.level = 2;
  const VisibilityResult r = analyseVisibility(part, options);
  const std::string dir = test::tempDir();
  writeVisibilityFiles(part, r, dir);

  const Part stl = loadPart(dir + "/mesh.stl");
  ASSERT_EQ(stl.mesh.triangleCount(), part.mesh.triangleCount());
  for (int t = 0; t < part.mesh.triangleCount(); t += 97)
    EXPECT_LT((triangleCentroid(stl.mesh, t) - triangleCentroid(part.mesh, t)).norm(), 1e-3) << t;

  std::ifstream csv(dir + "/directions.csv");
  std::string line;
  int lines = 0;
  while (std::getline(csv, line)) {
    double x, y, z;
    char c1, c2;
    std::istringstream in(line);
    ASSERT_TRUE(in >> x >> c1 >> y >> c2 >> z) << line;
    EXPECT_EQ(c1, ',');
    EXPECT_NEAR(std::sqrt(x * x + y * y + z * z), 1.0, 1e-12);
    EXPECT_NEAR(x, r.directions.directions[lines].x(), 1e-15);
    ++lines;
  }
  EXPECT_EQ(lines, r.directions.size());

  const int D = r.directions.size(), bytes = (D + 7) / 8;
  std::ifstream bits(dir + "/visibility.bits", std::ios::binary);
  std::vector<unsigned char> raw((std::istreambuf_iterator<char>(bits)), {});
  ASSERT_EQ(raw.size(), static_cast<std::size_t>(bytes) * part.mesh.triangleCount());
  const std::vector<double> radius = cellRadii(r.directions);
  for (int t = 0; t < part.mesh.triangleCount(); ++t) {
    const Vec3 n = triangleNormal(part.mesh, t);
    for (int d = 0; d < D; ++d) {
      const bool set = (raw[t * bytes + d / 8] >> (d % 8)) & 1;
      ASSERT_EQ(set, r.map.bits.get(t, d));
      // Never visible from behind: at most sideways, within the direction's cell.
      if (set) {
        EXPECT_GT(n.dot(r.directions.directions[d]), -std::sin(radius[d]) - 1e-9) << t << " " << d;
      }
    }
  }
}

// The progress contract (common/progress.h) for both backends: reports of the "visibility" stage with a share that
// never goes back; asked to stop, the analysis returns flagged cancelled instead of throwing.
TEST(Progress, ReportsTheShareAndStopsWhenAskedWithoutThrowing) {
  const Part part = partFromMesh(test::box(Vec3(0, 0, 0), Vec3(30, 20, 10)), "box");
  for (const VisibilityBackend backend : {VisibilityBackend::Ray, VisibilityBackend::Render}) {
    VisibilityOptions options;
    options.level = 2;
    options.backend = backend;
    std::vector<ProgressReport> reports;
    const VisibilityResult whole = analyseVisibility(part, options, [&](const ProgressReport& p) {
      reports.push_back(p);
      return true;
    });
    EXPECT_FALSE(whole.cancelled);
    ASSERT_FALSE(reports.empty());
    for (std::size_t i = 0; i < reports.size(); ++i) {
      EXPECT_EQ(reports[i].stage, "visibility");
      if (i > 0) {
        EXPECT_GE(reports[i].fraction, reports[i - 1].fraction);
      }
    }
    VisibilityResult stopped;
    EXPECT_NO_THROW(stopped = analyseVisibility(part, options, [](const ProgressReport&) { return false; }));
    EXPECT_TRUE(stopped.cancelled);
  }
}
