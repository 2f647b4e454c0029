// Scallop probe (issue 17's scallop figure): ball rasters over a plane, over a cylinder and inside one, whose cusps are
// known in closed form (the exact intersection of two neighbouring passes' balls, and the textbook approximation).
#include <gtest/gtest.h>

#include <cmath>

#include "art2part/simulation/scallop_probe.h"

using namespace art2part;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kR = 3;  // the ball's radius

Tool ball6() {
  Tool t;
  t.id = "ball6";
  t.type = ToolType::Ball;
  t.diameter = 2 * kR;
  t.corner_radius = kR;
  t.flute_length = 20;
  t.shank_diameter = 6;
  t.stickout = 35;
  t.holder = {{30, 40}};
  return t;
}

CutterLocation at(MoveKind move, const Vec3& tip, const Vec3& axis) {
  CutterLocation c;
  c.tool = "ball6";
  c.move = move;
  c.tip = tip;
  c.axis = axis.normalized();
  return c;
}

struct Surface {
  Mesh mesh;
  std::vector<int> triangle_face;
};

void addQuad(Surface& s, const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, int face) {
  const int base = static_cast<int>(s.mesh.vertices.size());
  s.mesh.vertices.insert(s.mesh.vertices.end(), {a, b, c, d});
  s.mesh.triangles.push_back({base, base + 1, base + 2});
  s.mesh.triangles.push_back({base, base + 2, base + 3});
  s.triangle_face.insert(s.triangle_face.end(), {face, face});
}

// Passes along x over [x0, x1], one per (tip, axis) across, zig-zag, from a rapid above the first.
Toolpath passes(const std::vector<ToolPose>& across, double x0, double x1) {
  Toolpath path{at(MoveKind::Rapid, across.front().tip + Vec3(x0, 0, 0) + 20 * across.front().axis, across.front().axis)};
  for (std::size_t i = 0; i < across.size(); ++i) {
    const bool forward = i % 2 == 0;
    path.push_back(at(MoveKind::Feed, across[i].tip + Vec3(forward ? x0 : x1, 0, 0), across[i].axis));
    path.push_back(at(MoveKind::Feed, across[i].tip + Vec3(forward ? x1 : x0, 0, 0), across[i].axis));
  }
  return path;
}

// A sector (angles +-20 deg) of a cylinder of radius rho around the x axis, x in [0, 30], facing out (or in, a hole).
Surface cylinderSector(double rho, bool hole, int segments = 400) {
  Surface s;
  const double half = 20 * kPi / 180;
  auto point = [&](double x, double angle) { return Vec3(x, rho * std::sin(angle), rho * std::cos(angle)); };
  for (int i = 0; i < segments; ++i) {
    const double a0 = -half + 2 * half * i / segments, a1 = -half + 2 * half * (i + 1) / segments;
    if (hole) addQuad(s, point(0, a0), point(0, a1), point(30, a1), point(30, a0), 0);
    else addQuad(s, point(0, a0), point(30, a0), point(30, a1), point(0, a1), 0);
  }
  return s;
}

// The cusp between two balls of radius R whose centres lie at distance D from the cylinder's axis, phi apart: the
// nearer (convex, the ridge stands out from the axis) or farther (concave) intersection of the two circles, measured
// from the surface at rho.
double exactCusp(double rho, double phi, bool hole) {
  const double D = hole ? rho - kR : rho + kR;
  const double along = D * std::cos(phi / 2), across = std::sqrt(kR * kR - std::pow(D * std::sin(phi / 2), 2));
  return hole ? rho - (along + across) : (along - across) - rho;
}

ScallopProbeOptions probe(double stepover) {
  ScallopProbeOptions o;
  o.windows = 24;
  o.half_width = stepover;
  o.pitch = stepover / 20;
  return o;
}

void expectEveryWindow(const ScallopReport& r, double cusp, double within, const char* what) {
  ASSERT_FALSE(r.windows.empty());
  for (const ScallopWindow& w : r.windows) {
    EXPECT_TRUE(w.fullyReached()) << what << " at " << w.point.transpose() << ": " << w.reached << " of " << w.rays;
    EXPECT_NEAR(w.max_mm, cusp, within * cusp) << what << " at " << w.point.transpose();
    // Inside the hole the mesh's chords stand 20 (1 - cos 0.05 deg) = 7.6e-6 mm into it, where the ball reaches.
    EXPECT_LT(w.deepest_cut_mm, 1e-5) << what;
    EXPECT_GT(w.mean_mm, 0.2 * cusp) << what;
    EXPECT_LT(w.mean_mm, w.max_mm) << what;
  }
  EXPECT_EQ(r.fullyReachedCount(), static_cast<int>(r.windows.size()));
  EXPECT_DOUBLE_EQ(r.shareWithin(cusp * (1 + within)), 1.0);
  std::printf("%s: cusp %.5f, windows' max %.5f .. %.5f (median %.5f), %lld ray-piece tests, %.3f s\n", what, cusp,
              r.quantile(0), r.quantile(1), r.quantile(0.5), r.ray_piece_tests, r.seconds);
}

}  // namespace

TEST(ScallopProbe, BallRasterOnAPlaneLeavesItsCusp) {
  // Stepover 0.6 with a 3 mm ball: R - sqrt(R^2 - s^2 / 4) = 0.015038 mm, measured at pitch s / 20 within 2 %.
  const double s = 0.6;
  Surface plane;
  addQuad(plane, Vec3(0, 0, 0), Vec3(40, 0, 0), Vec3(40, 30, 0), Vec3(0, 30, 0), 0);
  std::vector<ToolPose> across;
  for (int i = 0; i * s <= 30 + 1e-9; ++i) across.push_back({Vec3(0, i * s, 0), Vec3::UnitZ()});
  const ScallopReport r = probeScallops(plane.mesh, plane.triangle_face, {0}, passes(across, -5, 45), {ball6()}, probe(s));
  expectEveryWindow(r, kR - std::sqrt(kR * kR - s * s / 4), 0.02, "plane");
}

TEST(ScallopProbe, BallRasterOnAndInACylinderMatchesTheCurvatureFormula) {
  // Passes along the axis of a cylinder of radius 20, the tool's axis along the surface normal, w = 0.6 mm apart on
  // the surface: the cusp is (w^2 / 8)(1/R + 1/rho) on it, (w^2 / 8)(1/R - 1/rho) inside it (a hole), to ~5 %; the
  // probe reads the exact cusp within 2 %.
  const double rho = 20, w = 0.6, phi = w / rho;
  for (bool hole : {false, true}) {
    const Surface s = cylinderSector(rho, hole);
    std::vector<ToolPose> across;
    for (double angle = -22 * kPi / 180; angle <= 22 * kPi / 180 + 1e-9; angle += phi) {
      const Vec3 radial(0, std::sin(angle), std::cos(angle));
      across.push_back({rho * radial, hole ? Vec3(-radial) : radial});
    }
    const ScallopReport r = probeScallops(s.mesh, s.triangle_face, {0}, passes(across, -5, 35), {ball6()}, probe(w));
    const double exact = exactCusp(rho, phi, hole);
    const double formula = w * w / 8 * (1 / kR + (hole ? -1 : 1) / rho);
    EXPECT_NEAR(exact, formula, 0.05 * formula) << "the formula itself";
    expectEveryWindow(r, exact, 0.02, hole ? "inside a cylinder" : "on a cylinder");
    EXPECT_NEAR(r.quantile(0.5), formula, 0.05 * formula);
  }
}

TEST(ScallopProbe, WindowsNoPoseReachesAreReportedAndGougesMeasured) {
  // Face 0 is rastered 0.05 mm too deep; face 1, beside it, is never passed over.
  Surface s;
  addQuad(s, Vec3(0, 0, 0), Vec3(20, 0, 0), Vec3(20, 10, 0), Vec3(0, 10, 0), 0);
  addQuad(s, Vec3(40, 0, 0), Vec3(60, 0, 0), Vec3(60, 10, 0), Vec3(40, 10, 0), 1);
  std::vector<ToolPose> across;
  for (int i = 0; i <= 20; ++i) across.push_back({Vec3(0, i * 0.5, -0.05), Vec3::UnitZ()});
  const Toolpath path = passes(across, -5, 25);
  ScallopProbeOptions o = probe(0.5);
  const ScallopReport cut = probeScallops(s.mesh, s.triangle_face, {0}, path, {ball6()}, o);
  for (const ScallopWindow& w : cut.windows) {
    EXPECT_EQ(w.face, 0);
    EXPECT_NEAR(w.deepest_cut_mm, 0.05, 1e-3);
  }
  const ScallopReport untouched = probeScallops(s.mesh, s.triangle_face, {1}, path, {ball6()}, o);
  for (const ScallopWindow& w : untouched.windows) {
    EXPECT_EQ(w.face, 1);
    EXPECT_GT(w.rays, 0);
    EXPECT_EQ(w.reached, 0);
    EXPECT_FALSE(w.fullyReached());
  }
  EXPECT_EQ(untouched.fullyReachedCount(), 0);
  EXPECT_EQ(untouched.shareWithin(1.0), 0.0);
  // The same windows whatever the thread count.
  ScallopProbeOptions one = o, three = o;
  one.threads = 1;
  three.threads = 3;
  const ScallopReport a = probeScallops(s.mesh, s.triangle_face, {0}, path, {ball6()}, one);
  const ScallopReport b = probeScallops(s.mesh, s.triangle_face, {0}, path, {ball6()}, three);
  for (std::size_t i = 0; i < a.windows.size(); ++i) EXPECT_EQ(a.windows[i].max_mm, b.windows[i].max_mm);
}

TEST(ScallopProbe, BadInputIsRefused) {
  Surface s;
  addQuad(s, Vec3(0, 0, 0), Vec3(20, 0, 0), Vec3(20, 10, 0), Vec3(0, 10, 0), 0);
  const Toolpath path = passes({{Vec3(0, 5, 0), Vec3::UnitZ()}}, 0, 20);
  EXPECT_THROW(probeScallops(s.mesh, s.triangle_face, {}, path, {ball6()}), InputError);
  EXPECT_THROW(probeScallops(s.mesh, s.triangle_face, {3}, path, {ball6()}), InputError);
  EXPECT_THROW(probeScallops(s.mesh, s.triangle_face, {0}, path, {}), InputError);
  ScallopProbeOptions bad;
  bad.pitch = 0;
  EXPECT_THROW(probeScallops(s.mesh, s.triangle_face, {0}, path, {ball6()}, bad), InputError);
}
