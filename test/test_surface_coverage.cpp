// Surface coverage (issue 17's area figure): passes over planes whose covered share is worked out by hand, and random
// 5-axis moves over a curved surface checked sample by sample against a brute-force distance to the tool's outline.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "art2part/simulation/surface_coverage.h"
#include "test_meshes.h"

using namespace art2part;

namespace {

Tool endMill(const std::string& id, ToolType type, double diameter, double corner = 0) {
  Tool t;
  t.id = id;
  t.type = type;
  t.diameter = diameter;
  t.corner_radius = type == ToolType::Ball ? diameter / 2 : corner;
  t.flute_length = 20;
  t.shank_diameter = diameter;
  t.stickout = 35;
  t.holder = {{30, 40}};
  return t;
}

const Tool kFlat10 = endMill("flat10", ToolType::Flat, 10);
const Tool kBall6 = endMill("ball6", ToolType::Ball, 6);
const Tool kBull8 = endMill("bull8", ToolType::Bull, 8, 1.5);

CutterLocation at(const std::string& tool, MoveKind move, const Vec3& tip, const Vec3& axis = Vec3::UnitZ()) {
  CutterLocation c;
  c.tool = tool;
  c.move = move;
  c.tip = tip;
  c.axis = axis.normalized();
  return c;
}

// Rectangles in the plane z, one face each: [x0, x1] x [y0, y1] as two triangles facing +z.
struct Rect {
  double x0, x1, y0, y1, z;
};

struct Surface {
  Mesh mesh;
  std::vector<int> triangle_face;
  std::vector<Face> faces;
};

Surface rectangles(const std::vector<Rect>& rects) {
  Surface s;
  for (const Rect& r : rects) {
    const int base = static_cast<int>(s.mesh.vertices.size());
    s.mesh.vertices.insert(s.mesh.vertices.end(), {Vec3(r.x0, r.y0, r.z), Vec3(r.x1, r.y0, r.z), Vec3(r.x1, r.y1, r.z),
                                                   Vec3(r.x0, r.y1, r.z)});
    s.mesh.triangles.push_back({base, base + 1, base + 2});
    s.mesh.triangles.push_back({base, base + 2, base + 3});
    const int face = static_cast<int>(s.faces.size());
    s.triangle_face.insert(s.triangle_face.end(), {face, face});
    Face f;
    f.type = SurfaceType::Plane;
    f.normal = Vec3::UnitZ();
    f.offset = r.z;
    s.faces.push_back(f);
  }
  return s;
}

// Passes along x from x0 to x1 at each y, tip at height z, linked by feeds (a zig-zag), from a rapid above.
Toolpath raster(const std::string& tool, const std::vector<double>& ys, double x0, double x1, double z) {
  Toolpath path{at(tool, MoveKind::Rapid, Vec3(x0, ys.front(), z + 20))};
  for (std::size_t i = 0; i < ys.size(); ++i) {
    const bool forward = i % 2 == 0;
    path.push_back(at(tool, MoveKind::Feed, Vec3(forward ? x0 : x1, ys[i], z)));
    path.push_back(at(tool, MoveKind::Feed, Vec3(forward ? x1 : x0, ys[i], z)));
  }
  path.push_back(at(tool, MoveKind::Rapid, path.back().tip + Vec3(0, 0, 20)));
  return path;
}

CoverageOptions fine(double spacing = 0.1) {
  CoverageOptions o;
  o.sample_spacing = spacing;
  return o;
}

}  // namespace

TEST(SurfaceCoverage, FlatFaceMillingCoversWithinItsReachAndNothingBeyond) {
  // Face 0 is wholly under two passes of a 10 mm flat at stepover 7 (y 0 and 7 reach -5.05..12.05); face 1 starts
  // 0.5 mm past the reach.
  const Surface s = rectangles({{0, 40, 0, 12, 0}, {0, 40, 12.55, 25, 0}});
  const CoverageReport r =
      surfaceCoverage(s.mesh, s.triangle_face, s.faces, raster("flat10", {0, 7}, -10, 50, 0), {kFlat10}, fine());
  ASSERT_EQ(r.faces.size(), 2u);
  EXPECT_NEAR(r.faces[0].share(), 1.0, 1e-12);
  EXPECT_EQ(r.faces[0].covered_samples, r.faces[0].samples);
  EXPECT_EQ(r.faces[1].covered_samples, 0);
  EXPECT_NEAR(r.area_mm2, 40 * 12 + 40 * 12.45, 1e-9);
  EXPECT_NEAR(r.faces[0].area_mm2, 480, 1e-9);
  ASSERT_EQ(r.types.size(), 1u);
  EXPECT_EQ(r.types[0].type, SurfaceType::Plane);
  EXPECT_NEAR(r.types[0].covered_mm2, 480, 1e-9);
  EXPECT_GT(r.samples, 40000);
  EXPECT_GT(r.poses, 2 * 600);
  std::printf("flat face milling: %ld samples, %lld poses, %lld queries, %.3f s\n", r.samples, r.poses, r.pose_queries,
              r.seconds);
}

TEST(SurfaceCoverage, OnePassCoversItsRadiusPlusTheTolerance) {
  // A pass at y = 5 of a 10 mm flat covers y <= 10.05 of a 20 mm wide face: 50.25 %.
  const Surface s = rectangles({{0, 40, 0, 20, 0}});
  const CoverageReport r =
      surfaceCoverage(s.mesh, s.triangle_face, s.faces, raster("flat10", {5}, -10, 50, 0), {kFlat10}, fine());
  EXPECT_NEAR(r.share(), 10.05 / 20, 0.004);
}

TEST(SurfaceCoverage, BallRasterCoversWhenItsCuspIsWithinTheTolerance) {
  // A 3 mm ball over a plane at stepover s: a sample x from the nearest pass is sqrt(9 + x^2) - 3 from the ball, within
  // 0.05 mm for x <= sqrt(3.05^2 - 9) = 0.5501. Stepover 1.0 (cusp 0.042): all covered; 1.2 (cusp 0.061): the
  // share 2 * 0.5501 / 1.2 = 0.9168 between passes.
  for (double s : {1.0, 1.2}) {
    std::vector<double> ys;
    for (int i = 0; i <= 12; ++i) ys.push_back(i * s);
    const Surface surface = rectangles({{0, 30, 2 * s, 10 * s, 0}});  // whole periods between the passes
    const CoverageReport r =
        surfaceCoverage(surface.mesh, surface.triangle_face, surface.faces, raster("ball6", ys, -5, 35, 0), {kBall6},
                        fine(0.05));
    const double expected = s == 1.0 ? 1.0 : 2 * std::sqrt(3.05 * 3.05 - 9) / 1.2;
    EXPECT_NEAR(r.share(), expected, 0.004) << "stepover " << s;
    std::printf("ball raster at %.1f: %ld samples, %lld poses, %lld queries, %.3f s\n", s, r.samples, r.poses,
                r.pose_queries, r.seconds);
  }
}

TEST(SurfaceCoverage, ToolAFewHundredthsAboveCoversOnlyWithinTheTolerance) {
  const Surface s = rectangles({{0, 40, 0, 20, 0}});
  // 0.06 mm above: no sample is within 0.05.
  for (const Tool& tool : {kFlat10, kBall6}) {
    const CoverageReport above =
        surfaceCoverage(s.mesh, s.triangle_face, s.faces, raster(tool.id, {10}, -10, 50, 0.06), {tool}, fine());
    EXPECT_EQ(above.covered_mm2, 0.0) << tool.id;
  }
  // 0.04 mm above: the flat covers its width (to 5 + sqrt(0.05^2 - 0.04^2) = 5.03 from the pass), the ball the band
  // within sqrt(3.05^2 - 3.04^2) = 0.2468 of it.
  const CoverageReport flat =
      surfaceCoverage(s.mesh, s.triangle_face, s.faces, raster("flat10", {10}, -10, 50, 0.04), {kFlat10}, fine(0.05));
  EXPECT_NEAR(flat.share(), 2 * 5.03 / 20, 0.003);
  const CoverageReport ball =
      surfaceCoverage(s.mesh, s.triangle_face, s.faces, raster("ball6", {10}, -10, 50, 0.04), {kBall6}, fine(0.02));
  EXPECT_NEAR(ball.share(), 2 * std::sqrt(3.05 * 3.05 - 3.04 * 3.04) / 20, 0.002);
  // Rapids never cover, even through the surface.
  Toolpath rapids = raster("flat10", {10}, -10, 50, 0);
  for (CutterLocation& c : rapids) c.move = MoveKind::Rapid;
  EXPECT_EQ(surfaceCoverage(s.mesh, s.triangle_face, s.faces, rapids, {kFlat10}, fine()).covered_mm2, 0.0);
}

namespace {

// Brute-force distance from p to the flutes of `tool` at `pose`, when it is under `reach` (else a lower bound above
// it): the meridian outline from toolRadiusAt sampled every micrometre of height near p's height, the bottom and top
// discs closing it.
double bruteDistance(const Tool& tool, const ToolPose& pose, const Vec3& p, double reach) {
  const Vec3 w = p - pose.tip;
  const double h = w.dot(pose.axis), rho = std::sqrt(std::max(0.0, w.squaredNorm() - h * h));
  const double top = tool.flute_length;
  const double bound = std::max({-h, h - top, rho - 0.5 * tool.diameter});  // no flute point is nearer
  if (bound > reach) return bound;
  if (h >= 0 && h <= top && rho <= toolRadiusAt(tool, h)) return 0;
  auto segment = [&](double h0, double r0, double h1, double r1) {
    const double dh = h1 - h0, dr = r1 - r0, l2 = dh * dh + dr * dr;
    const double f = l2 > 0 ? std::clamp(((h - h0) * dh + (rho - r0) * dr) / l2, 0.0, 1.0) : 0.0;
    return std::hypot(h - h0 - f * dh, rho - r0 - f * dr);
  };
  double best = std::min(segment(0, 0, 0, toolRadiusAt(tool, 0)), segment(top, 0, top, toolRadiusAt(tool, top)));
  const double lo = std::max(0.0, h - reach), hi = std::min(top, h + reach), dh = 0.001;
  for (double h0 = lo; h0 < hi; h0 += dh) {
    const double h1 = std::min(hi, h0 + dh);
    best = std::min(best, segment(h0, toolRadiusAt(tool, h0), h1, toolRadiusAt(tool, h1)));
  }
  return best;
}

Vec3 slerp(const Vec3& a, const Vec3& b, double f) {
  const double angle = std::acos(std::clamp(a.dot(b), -1.0, 1.0));
  if (angle < 1e-9) return a;
  return (std::sin((1 - f) * angle) * a + std::sin(f * angle) * b).normalized() ;
}

}  // namespace

TEST(SurfaceCoverage, RandomTiltedMovesAgreeWithABruteForceDistanceOnEverySample) {
  // A wavy 12 x 12 mm surface of small triangles (each one sample: spacing 0.4 keeps them whole), and random 5-axis
  // feed moves of a ball and a bull mill near it. The oracle measures each triangle's centroid against every pose
  // (poses placed as the header says) with the brute-force distance; samples whose distance is within 1.5 micrometres
  // of the tolerance are left out (the outline is sampled).
  Surface s;
  const int n = 60;
  auto height = [](double x, double y) { return 0.8 * std::sin(0.5 * x) * std::cos(0.4 * y); };
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) s.mesh.vertices.emplace_back(0.2 * i, 0.2 * j, height(0.2 * i, 0.2 * j));
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int v = j * (n + 1) + i;
      s.mesh.triangles.push_back({v, v + 1, v + n + 2});
      s.mesh.triangles.push_back({v, v + n + 2, v + n + 1});
    }
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> unit(0, 1), tilt(-0.5, 0.5);
  for (const Tool& tool : {kBall6, kBull8}) {
    Toolpath path{at(tool.id, MoveKind::Rapid, Vec3(6, 6, 30))};
    for (int m = 0; m < 12; ++m) {
      const double x = 12 * unit(rng), y = 12 * unit(rng);
      const Vec3 axis = Vec3(tilt(rng), tilt(rng), 1).normalized();
      const Vec3 tip(x, y, height(x, y) + 0.3 * unit(rng) - 0.05);
      path.push_back(at(tool.id, m % 4 == 0 ? MoveKind::Rapid : MoveKind::Feed, tip, axis));
    }
    CoverageOptions options = fine(0.4);
    options.pose_step = 0.1;
    const CoverageReport r = surfaceCoverage(s.mesh, {}, {}, path, {tool}, options);
    ASSERT_EQ(r.samples, s.mesh.triangleCount());
    // The oracle.
    const double top = tool.flute_length;
    double expected = 0, ambiguous = 0, area = 0;
    for (int t = 0; t < s.mesh.triangleCount(); ++t) {
      const Vec3 c = triangleCentroid(s.mesh, t);
      double best = 1e9;
      for (std::size_t row = 1; row < path.size(); ++row) {
        if (path[row].move != MoveKind::Feed) continue;
        const ToolPose a{path[row - 1].tip, path[row - 1].axis}, b{path[row].tip, path[row].axis};
        const double angle = std::acos(std::clamp(a.axis.dot(b.axis), -1.0, 1.0));
        const int steps = std::max(1, static_cast<int>(std::ceil(((b.tip - a.tip).norm() + angle * top) / 0.1 - 1e-9)));
        for (int k = 0; k <= steps && best > 0; ++k) {
          const double f = static_cast<double>(k) / steps;
          const ToolPose pose{a.tip + f * (b.tip - a.tip), slerp(a.axis, b.axis, f)};
          best = std::min(best, bruteDistance(tool, pose, c, 0.06));
        }
      }
      const double piece = triangleArea(s.mesh, t);
      area += piece;
      if (std::abs(best - options.tolerance) < 0.0015) ambiguous += piece;
      else if (best <= options.tolerance) expected += piece;
    }
    EXPECT_NEAR(r.area_mm2, area, 1e-9);
    EXPECT_GT(expected, 0.05 * area) << tool.id << ": the moves must cover something";
    EXPECT_LT(expected, 0.95 * area) << tool.id << ": and leave something";
    EXPECT_GE(r.covered_mm2, expected - 1e-9) << tool.id;
    EXPECT_LE(r.covered_mm2, expected + ambiguous + 1e-9) << tool.id;
    std::printf("%s: covered %.3f of %.3f mm^2 (oracle %.3f, ambiguous %.4f), %lld poses\n", tool.id.c_str(),
                r.covered_mm2, area, expected, ambiguous, r.poses);
    // The thread count does not change the answer.
    CoverageOptions one = options, three = options;
    one.threads = 1;
    three.threads = 3;
    EXPECT_EQ(surfaceCoverage(s.mesh, {}, {}, path, {tool}, one).covered_mm2,
              surfaceCoverage(s.mesh, {}, {}, path, {tool}, three).covered_mm2);
  }
}

TEST(SurfaceCoverage, BadInputIsRefused) {
  const Surface s = rectangles({{0, 10, 0, 10, 0}});
  const Toolpath path = raster("flat10", {5}, -10, 20, 0);
  EXPECT_THROW(surfaceCoverage(s.mesh, s.triangle_face, s.faces, path, {kBall6}), InputError);
  CoverageOptions bad;
  bad.pose_step = 0;
  EXPECT_THROW(surfaceCoverage(s.mesh, s.triangle_face, s.faces, path, {kFlat10}, bad), InputError);
  EXPECT_THROW(surfaceCoverage(s.mesh, {3, 3}, s.faces, path, {kFlat10}), InputError);
}
