// Ray-casting visibility (Embree) and the visibility bit matrix and file.
//
// Expected answers come from geometry the test computes on its own: for unions of axis-aligned boxes, a sample point
// is hidden along d exactly when the ray from it enters the open interior of one of the boxes; for a real part, a
// brute-force ray against every triangle.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "art2part/geometry/part.h"
#include "art2part/visibility/visibility.h"
#include "art2part/visibility/visibility_map.h"
#include "test_meshes.h"

namespace art2part {
namespace {

struct AlignedBox {
  Vec3 lo, hi;
};

using test::randomDirections;

std::vector<Vec3> axisDirections() {
  return {Vec3::UnitX(), -Vec3::UnitX(), Vec3::UnitY(), -Vec3::UnitY(), Vec3::UnitZ(), -Vec3::UnitZ()};
}

// Whether the ray p + t d, t > 0, passes through the open interior of the box. A ray that starts on a face and
// leaves, or runs along a face, does not.
bool entersBox(const Vec3& p, const Vec3& d, const AlignedBox& box) {
  double t0 = 0.0, t1 = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 3; ++k) {
    if (d[k] == 0.0) {
      if (p[k] <= box.lo[k] || p[k] >= box.hi[k]) return false;
      continue;
    }
    double a = (box.lo[k] - p[k]) / d[k], b = (box.hi[k] - p[k]) / d[k];
    if (a > b) std::swap(a, b);
    t0 = std::max(t0, a);
    t1 = std::min(t1, b);
  }
  return t0 < t1;
}

// The sample points the definition uses: the centroid, then 60% of the way towards each corner.
std::vector<Vec3> samplePoints(const Mesh& mesh, int t, int samples) {
  const Vec3 a = mesh.corner(t, 0), b = mesh.corner(t, 1), c = mesh.corner(t, 2);
  const std::vector<Vec3> all = {(a + b + c) / 3.0, 0.6 * a + 0.2 * b + 0.2 * c, 0.2 * a + 0.6 * b + 0.2 * c,
                                 0.2 * a + 0.2 * b + 0.6 * c};
  return std::vector<Vec3>(all.begin(), all.begin() + samples);
}

// The visibility of a union of boxes, worked out from the boxes.
VisibilityMap expectedForBoxes(const Mesh& mesh, const std::vector<AlignedBox>& boxes,
                               const std::vector<Vec3>& directions, int samples) {
  VisibilityMap map{BitMatrix(mesh.triangleCount(), static_cast<int>(directions.size()))};
  for (int t = 0; t < mesh.triangleCount(); ++t)
    for (int d = 0; d < static_cast<int>(directions.size()); ++d) {
      if (triangleNormal(mesh, t).dot(directions[d]) <= 0.0) continue;
      for (const Vec3& p : samplePoints(mesh, t, samples)) {
        bool blocked = false;
        for (const AlignedBox& box : boxes) blocked = blocked || entersBox(p, directions[d], box);
        if (!blocked) {
          map.bits.set(t, d);
          break;
        }
      }
    }
  return map;
}

Mesh meshOf(const std::vector<AlignedBox>& boxes) {
  Mesh mesh;
  for (const AlignedBox& box : boxes) test::append(mesh, test::box(box.lo, box.hi));
  return mesh;
}

// Lists the pairs that differ, for a readable failure.
std::string differences(const VisibilityMap& got, const VisibilityMap& want, const std::vector<Vec3>& directions) {
  std::string out;
  int shown = 0;
  for (int t = 0; t < want.triangles(); ++t)
    for (int d = 0; d < want.directions(); ++d)
      if (got.bits.get(t, d) != want.bits.get(t, d) && shown++ < 10)
        out += "triangle " + std::to_string(t) + " direction (" + std::to_string(directions[d].x()) + ", " +
               std::to_string(directions[d].y()) + ", " + std::to_string(directions[d].z()) + "): got " +
               std::to_string(got.bits.get(t, d)) + "\n";
  return out;
}

// A box's top face is its triangles 2 and 3 (test::box makes bottom, top, front, back, left, right).
constexpr int kTopA = 2, kTopB = 3;

// ---- ray casting ----------------------------------------------------------------------------------------------------

// Ray casting with `samples` samples equals the independent box-geometry answer; returns that answer.
VisibilityMap expectBoxAnswer(const Mesh& mesh, const std::vector<AlignedBox>& boxes,
                              const std::vector<Vec3>& directions, int samples) {
  RayVisibilityOptions options;
  options.samples_per_triangle = samples;
  const VisibilityMap got = rayVisibility(mesh, directions, options);
  VisibilityMap want = expectedForBoxes(mesh, boxes, directions, samples);
  EXPECT_TRUE(got.bits == want.bits) << "samples " << samples << "\n" << differences(got, want, directions);
  return want;
}

TEST(RayVisibility, ConvexBoxFaceVisibleExactlyWhereItFaces) {
  // Far from the origin on purpose: coordinates must be taken relative to the part, not cast to float as they are.
  const Vec3 offset(2.0e5, -3.0e5, 1.0e5);
  const Mesh mesh = test::box(offset, offset + Vec3(1.0, 1.0, 1.0));
  std::vector<Vec3> directions = randomDirections(200, 1);
  for (const Vec3& d : axisDirections()) directions.push_back(d);
  for (int samples : {1, 4}) {
    RayVisibilityOptions options;
    options.samples_per_triangle = samples;
    const VisibilityMap map = rayVisibility(mesh, directions, options);
    ASSERT_EQ(map.triangles(), 12);
    ASSERT_EQ(map.directions(), static_cast<int>(directions.size()));
    for (int t = 0; t < 12; ++t)
      for (std::size_t d = 0; d < directions.size(); ++d)
        EXPECT_EQ(map.bits.get(t, int(d)), triangleNormal(mesh, t).dot(directions[d]) > 0.0)
            << "triangle " << t << " direction " << d << " samples " << samples;
  }
  // Along +z only the top: the side faces have n . d = 0 and are not visible by definition.
  const VisibilityMap up = rayVisibility(mesh, {Vec3::UnitZ()});
  for (int t = 0; t < 12; ++t) EXPECT_EQ(up.bits.get(t, 0), t == kTopA || t == kTopB) << "triangle " << t;
}

TEST(RayVisibility, GrazingDirectionsDoNotHideAConvexPart) {
  // A rotated box: faces meet at edges that are not axis-aligned, and the two triangles of a face share a diagonal.
  Mesh mesh = test::box(Vec3(-40, -25, -10), Vec3(40, 25, 10));
  const Eigen::Matrix3d rotation =
      (Eigen::AngleAxisd(0.3, Vec3::UnitZ()) * Eigen::AngleAxisd(0.7, Vec3(1, 1, 0).normalized())).toRotationMatrix();
  for (Vec3& v : mesh.vertices) v = rotation * v + Vec3(1500, 800, -300);
  // Directions that skim each face, tilted off it by n . d = 1e-4 ... 1e-7: along the diagonal its two triangles
  // share, and along an edge, across that diagonal from one triangle over the other.
  std::vector<Vec3> directions;
  for (int t = 0; t < 12; t += 2) {
    const Vec3 n = triangleNormal(mesh, t);
    const Vec3 diagonal = (mesh.corner(t, 2) - mesh.corner(t, 0)).normalized();
    const Vec3 edge = (mesh.corner(t, 1) - mesh.corner(t, 0)).normalized();
    for (const Vec3& along : {diagonal, edge, Vec3(-edge)})
      for (double tilt : {1e-4, 1e-5, 1e-6, 1e-7}) directions.push_back((along + tilt * n).normalized());
  }
  const VisibilityMap map = rayVisibility(mesh, directions);
  for (int t = 0; t < 12; ++t)
    for (std::size_t d = 0; d < directions.size(); ++d) {
      // Faces the direction runs along (n . d = 0 up to rounding, 1e-17) are a toss-up of the last bit.
      const double nd = triangleNormal(mesh, t).dot(directions[d]);
      if (std::abs(nd) > 1e-12) {
        EXPECT_EQ(map.bits.get(t, int(d)), nd > 0.0) << "triangle " << t << " n.d " << nd;
      }
    }
}

// A step: a low block A and a tall block B beside it; B shades A's top along directions leaning towards +x.
const std::vector<AlignedBox> kStep = {{Vec3(0, 0, 0), Vec3(1, 1, 1)}, {Vec3(1, 0, 0), Vec3(2, 1, 2)}};

TEST(RayVisibility, StepLowerTopHiddenBehindTheUpperBlock) {
  const Mesh mesh = meshOf(kStep);
  ASSERT_TRUE(triangleNormal(mesh, kTopA).isApprox(Vec3::UnitZ()));
  const std::vector<Vec3> named = {Vec3::UnitZ(),
                                   Vec3(1, 0, 1).normalized(),
                                   Vec3(-1, 0, 1).normalized(),
                                   Vec3(3, 0, 1).normalized(),
                                   Vec3(1, 0, 2).normalized(),
                                   Vec3(1, 0, 4).normalized()};
  RayVisibilityOptions one;
  one.samples_per_triangle = 1;
  const VisibilityMap map = rayVisibility(mesh, named, one);
  for (int t : {kTopA, kTopB}) {
    EXPECT_TRUE(map.bits.get(t, 0)) << "straight up";
    EXPECT_FALSE(map.bits.get(t, 1)) << "45 degrees towards the upper block";
    EXPECT_TRUE(map.bits.get(t, 2)) << "45 degrees away from it";
  }
  // Leaning towards B with slope s (rise per run): from a centroid at x = cx the ray meets the plane x = 1 at
  // z = 1 + s (1 - cx), hidden while that is below B's top at z = 2. kTopA has cx = 2/3 (hidden for s < 3), kTopB
  // has cx = 1/3 (hidden for s < 1.5).
  ASSERT_NEAR(triangleCentroid(mesh, kTopA).x(), 2.0 / 3, 1e-12);
  ASSERT_NEAR(triangleCentroid(mesh, kTopB).x(), 1.0 / 3, 1e-12);
  EXPECT_FALSE(map.bits.get(kTopA, 3)) << "s = 1/3";
  EXPECT_FALSE(map.bits.get(kTopB, 3)) << "s = 1/3";
  EXPECT_FALSE(map.bits.get(kTopA, 4)) << "s = 2";
  EXPECT_TRUE(map.bits.get(kTopB, 4)) << "s = 2";
  EXPECT_TRUE(map.bits.get(kTopA, 5)) << "s = 4";
  EXPECT_TRUE(map.bits.get(kTopB, 5)) << "s = 4";
  // B's top is visible along every upward direction.
  for (int d = 0; d < map.directions(); ++d) EXPECT_TRUE(map.bits.get(12 + kTopA, d));
}

TEST(RayVisibility, StepMatchesTheBoxGeometryForRandomDirections) {
  const Mesh mesh = meshOf(kStep);
  const std::vector<Vec3> directions = randomDirections(300, 2);
  for (int samples : {1, 4}) expectBoxAnswer(mesh, kStep, directions, samples);
}

TEST(RayVisibility, MoreSamplesSeeMore) {
  const Mesh mesh = meshOf(kStep);
  const std::vector<Vec3> directions = randomDirections(300, 3);
  RayVisibilityOptions options;
  options.samples_per_triangle = 1;
  const VisibilityMap one = rayVisibility(mesh, directions, options);
  options.samples_per_triangle = 4;
  const VisibilityMap four = rayVisibility(mesh, directions, options);
  int gained = 0;
  for (int t = 0; t < mesh.triangleCount(); ++t)
    for (int d = 0; d < one.directions(); ++d) {
      EXPECT_TRUE(!one.bits.get(t, d) || four.bits.get(t, d)) << "triangle " << t << " direction " << d;
      gained += four.bits.get(t, d) && !one.bits.get(t, d);
    }
  EXPECT_GT(gained, 0) << "a corner of A's top sees past B where its centroid does not";
}

// A square hole, width w and depth D, its floor the top of block F, walled in on four sides. (The outer size 5.3
// keeps every sample point off the edges where the boxes touch, where "clear" would be a matter of rounding.)
constexpr double kHoleWidth = 2.0, kHoleDepth = 8.0, kHalf = kHoleWidth / 2, kOut = 5.3;
const std::vector<AlignedBox> kHole = {
    {Vec3(-kHalf, -kHalf, 0), Vec3(kHalf, kHalf, 1)},  // F: the floor at z = 1
    {Vec3(-kOut, -kOut, 0), Vec3(-kHalf, kOut, 1 + kHoleDepth)},
    {Vec3(kHalf, -kOut, 0), Vec3(kOut, kOut, 1 + kHoleDepth)},
    {Vec3(-kHalf, -kOut, 0), Vec3(kHalf, -kHalf, 1 + kHoleDepth)},
    {Vec3(-kHalf, kHalf, 0), Vec3(kHalf, kOut, 1 + kHoleDepth)}};

TEST(RayVisibility, DeepHoleFloorOnlyWithinItsCone) {
  const Mesh mesh = meshOf(kHole);
  // Centroid only: a floor triangle with centroid x = cx is visible leaning towards +x by theta exactly while
  // cx + D tan(theta) < w / 2. The two floor triangles have cx = +w/6 and -w/6.
  std::vector<Vec3> directions;
  for (int t : {kTopA, kTopB}) {
    const double cx = triangleCentroid(mesh, t).x();
    const double edge = std::atan((kHalf - cx) / kHoleDepth);
    for (double theta : {edge - 0.01, edge + 0.01}) directions.push_back(Vec3(std::sin(theta), 0, std::cos(theta)));
  }
  RayVisibilityOptions one;
  one.samples_per_triangle = 1;
  const VisibilityMap map = rayVisibility(mesh, directions, one);
  for (int i = 0; i < 2; ++i) {
    const int t = i == 0 ? kTopA : kTopB;
    EXPECT_TRUE(map.bits.get(t, 2 * i)) << "just inside the cone, triangle " << t;
    EXPECT_FALSE(map.bits.get(t, 2 * i + 1)) << "just outside, triangle " << t;
  }

  // No point of the floor sees out beyond atan(diagonal / depth), whatever the azimuth and sample count; every
  // point sees out straight up.
  const double limit = std::atan(std::sqrt(2.0) * kHoleWidth / kHoleDepth) + 0.01;
  std::vector<Vec3> outside = {Vec3::UnitZ()};
  for (int k = 0; k < 16; ++k) {
    const double azimuth = k * M_PI / 8;
    outside.push_back(Vec3(std::sin(limit) * std::cos(azimuth), std::sin(limit) * std::sin(azimuth), std::cos(limit)));
  }
  RayVisibilityOptions all;
  all.samples_per_triangle = 7;
  const VisibilityMap cone = rayVisibility(mesh, outside, all);
  for (int t : {kTopA, kTopB}) {
    EXPECT_TRUE(cone.bits.get(t, 0));
    EXPECT_EQ(cone.bits.rowCount(t), 1) << "triangle " << t;
  }
}

TEST(RayVisibility, HoleMatchesTheBoxGeometryForRandomDirections) {
  const Mesh mesh = meshOf(kHole);
  std::vector<Vec3> directions = randomDirections(300, 4);
  for (Vec3& d : directions) d.z() = std::abs(d.z()) + 2.0;  // most of them steep enough to reach the floor
  for (Vec3& d : directions) d.normalize();
  for (int samples : {1, 4}) {
    const VisibilityMap want = expectBoxAnswer(mesh, kHole, directions, samples);
    EXPECT_GT(want.bits.rowCount(kTopA), 0);
    EXPECT_LT(want.bits.rowCount(kTopA), 300);
  }
}

TEST(RayVisibility, SameAnswerWithAnyThreadCountAndDirectionLength) {
  const Mesh mesh = meshOf(kHole);
  const std::vector<Vec3> directions = randomDirections(150, 5);
  RayVisibilityOptions options;
  options.threads = 1;
  const VisibilityMap reference = rayVisibility(mesh, directions, options);
  for (int threads : {0, 2, 3}) {
    options.threads = threads;
    EXPECT_TRUE(rayVisibility(mesh, directions, options).bits == reference.bits) << threads << " threads";
  }
  std::vector<Vec3> scaled = directions;
  for (Vec3& d : scaled) d *= 7.5;
  options.threads = 2;
  EXPECT_TRUE(rayVisibility(mesh, scaled, options).bits == reference.bits);
}

TEST(RayVisibility, ProgressAndCancel) {
  const Mesh mesh = meshOf(kStep);
  const std::vector<Vec3> directions = randomDirections(64, 6);
  std::vector<double> seen;
  rayVisibility(mesh, directions, {}, [&](double f) {
    seen.push_back(f);
    return true;
  });
  ASSERT_GE(seen.size(), 2u);
  EXPECT_EQ(seen.front(), 0.0);
  EXPECT_EQ(seen.back(), 1.0);
  for (std::size_t i = 1; i < seen.size(); ++i) EXPECT_GE(seen[i], seen[i - 1]);

  try {
    rayVisibility(mesh, directions, {}, [](double) { return false; });
    FAIL() << "not cancelled";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "cancelled");
  }
}

TEST(RayVisibility, EmptyInputs) {
  const VisibilityMap none = rayVisibility(Mesh{}, randomDirections(5, 7));
  EXPECT_EQ(none.triangles(), 0);
  EXPECT_EQ(none.directions(), 5);
  const VisibilityMap no_directions = rayVisibility(test::box(Vec3::Zero(), Vec3::Ones()), {});
  EXPECT_EQ(no_directions.triangles(), 12);
  EXPECT_EQ(no_directions.directions(), 0);
}

// An independent check on a real part: every (triangle, direction) pair against a brute-force ray from the
// centroid to every other triangle, in double.
bool bruteForceVisible(const Mesh& mesh, int t, const Vec3& d) {
  if (triangleNormal(mesh, t).dot(d) <= 0.0) return false;
  const Vec3 p = triangleCentroid(mesh, t);
  const double tiny = 1e-9 * boundingBox(mesh).diagonal();
  for (int o = 0; o < mesh.triangleCount(); ++o) {
    if (o == t) continue;
    const Vec3 a = mesh.corner(o, 0), e1 = mesh.corner(o, 1) - a, e2 = mesh.corner(o, 2) - a;
    const Vec3 q = d.cross(e2);
    const double det = e1.dot(q);
    if (det == 0.0) continue;
    const Vec3 s = p - a, r = s.cross(e1);
    const double u = s.dot(q) / det, v = d.dot(r) / det, distance = e2.dot(r) / det;
    if (u >= 0 && v >= 0 && u + v <= 1 && distance > tiny) return false;
  }
  return true;
}

TEST(RayVisibility, RealPartAgreesWithBruteForce) {
  const Part part = loadPart(std::string(ART2PART_SHARED_PARTS) + "/ktoolcav.stl");
  const Mesh& mesh = part.mesh;
  const std::vector<Vec3> directions = randomDirections(12, 8);
  RayVisibilityOptions one;
  one.samples_per_triangle = 1;
  const VisibilityMap map = rayVisibility(mesh, directions, one);
  long long pairs = 0, visible = 0, mismatches = 0;
  for (int t = 0; t < mesh.triangleCount(); ++t)
    for (int d = 0; d < map.directions(); ++d) {
      const bool want = bruteForceVisible(mesh, t, directions[d]);
      ++pairs;
      visible += want;
      mismatches += want != map.bits.get(t, d);
    }
  EXPECT_GT(visible, pairs / 10);
  EXPECT_LT(visible, pairs / 2);
  // Only rays that graze an edge may go either way.
  EXPECT_LE(mismatches, pairs / 5000) << mismatches << " of " << pairs;
}

// ---- the bit matrix and the file ------------------------------------------------------------------------------------

TEST(BitMatrix, SetGetResetCountTranspose) {
  BitMatrix m(5, 130);
  EXPECT_EQ(m.rows(), 5);
  EXPECT_EQ(m.columns(), 130);
  EXPECT_EQ(m.wordsPerRow(), 3);
  for (int r = 0; r < 5; ++r)
    for (int c = 0; c < 130; ++c) EXPECT_FALSE(m.get(r, c));
  const std::vector<std::pair<int, int>> ones = {{0, 0}, {0, 63}, {0, 64}, {1, 129}, {4, 65}, {4, 127}};
  for (auto [r, c] : ones) m.set(r, c);
  for (auto [r, c] : ones) EXPECT_TRUE(m.get(r, c));
  EXPECT_FALSE(m.get(0, 1));
  EXPECT_FALSE(m.get(1, 128));
  EXPECT_EQ(m.rowCount(0), 3);
  EXPECT_EQ(m.rowCount(2), 0);
  EXPECT_EQ(m.row(0)[1], 1u);  // column 64: word 1, bit 0
  m.reset(0, 63);
  EXPECT_FALSE(m.get(0, 63));
  EXPECT_EQ(m.rowCount(0), 2);

  const BitMatrix t = m.transposed();
  EXPECT_EQ(t.rows(), 130);
  EXPECT_EQ(t.columns(), 5);
  for (int r = 0; r < 5; ++r)
    for (int c = 0; c < 130; ++c) EXPECT_EQ(t.get(c, r), m.get(r, c));
  EXPECT_TRUE(t.transposed() == m);
  BitMatrix other = m;
  other.set(3, 3);
  EXPECT_FALSE(other == m);
}

std::vector<unsigned char> fileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::vector<unsigned char>(std::istreambuf_iterator<char>(in), {});
}

TEST(VisibilityBits, ByteLayoutAndRoundTrip) {
  VisibilityMap map{BitMatrix(3, 10)};  // 10 directions: 2 bytes per row
  map.bits.set(0, 0);
  map.bits.set(1, 9);  // row 1, byte 1, bit 1
  map.bits.set(2, 7);  // row 2, byte 0, bit 7
  map.bits.set(2, 8);  // row 2, byte 1, bit 0
  const std::string path = test::tempDir() + "/visibility.bits";
  writeVisibilityBits(map, path);
  const std::vector<unsigned char> bytes = fileBytes(path);
  EXPECT_EQ(bytes, (std::vector<unsigned char>{0x01, 0x00, 0x00, 0x02, 0x80, 0x01}));
  EXPECT_TRUE(readVisibilityBits(path, 3, 10).bits == map.bits);
}

TEST(VisibilityBits, RoundTripOfARealSizedMap) {
  const Mesh mesh = meshOf(kHole);
  const std::vector<Vec3> directions = randomDirections(200, 9);  // 25 bytes per row, rows span 4 words
  const VisibilityMap map = rayVisibility(mesh, directions);
  const std::string path = test::tempDir() + "/visibility.bits";
  writeVisibilityBits(map, path);
  EXPECT_EQ(fileBytes(path).size(), static_cast<std::size_t>(mesh.triangleCount()) * 25);
  EXPECT_TRUE(readVisibilityBits(path, mesh.triangleCount(), 200).bits == map.bits);
}

TEST(VisibilityBits, PaddingBitsInTheFileAreIgnored) {
  const std::string path = test::tempDir() + "/visibility.bits";
  test::writeText(path, std::string("\xff\xff", 2));
  const VisibilityMap map = readVisibilityBits(path, 1, 10);
  EXPECT_EQ(map.bits.rowCount(0), 10);
  BitMatrix all(1, 10);
  for (int c = 0; c < 10; ++c) all.set(0, c);
  EXPECT_TRUE(map.bits == all);
}

TEST(VisibilityBits, SizeMismatchIsAnInputError) {
  VisibilityMap map{BitMatrix(3, 10)};
  const std::string path = test::tempDir() + "/visibility.bits";
  writeVisibilityBits(map, path);
  EXPECT_THROW(readVisibilityBits(path, 4, 10), InputError);
  EXPECT_THROW(readVisibilityBits(path, 3, 17), InputError);
  EXPECT_NO_THROW(readVisibilityBits(path, 3, 16));  // same byte count: the file cannot tell
  EXPECT_THROW(readVisibilityBits(path + ".missing", 3, 10), InputError);
}

}  // namespace
}  // namespace art2part
