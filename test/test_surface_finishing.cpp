// Surface finishing (issue 17, item 5): the drop-cutter against a brute-force oracle, finished parts judged by the
// simulation (gouges, collisions), scallops measured on simulated stock, 5-axis tilt where the 3-axis holder collides.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <functional>
#include <random>

#include <BRepAlgoAPI_Cut.hxx>
#include <BRepAlgoAPI_Fuse.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeSphere.hxx>
#include <gp_Pnt.hxx>

#include "art2part/finishing/drop_cutter.h"
#include "art2part/finishing/finishing.h"
#include "art2part/finishing/surface_finishing.h"
#include "art2part/roughing/shadow.h"
#include "art2part/simulation/tool_solid.h"
#include "art2part/simulation/verify.h"
#include "test_meshes.h"
#include "test_solids.h"
#include "test_tools.h"

using namespace art2part;
using art2part::test::ball6;
using art2part::test::cutter;
using art2part::test::facesOfType;

namespace {

// ---- the oracle: written from the tool's outline alone, sharing nothing with the drop-cutter -----------------------

// Radius of the cutting solid at height h above the tip (the cutter continued upwards as a cylinder); < 0 below it.
double cutterRadius(const Tool& tool, double h) {
  const double R = 0.5 * tool.diameter;
  if (h <= 0) return -1;
  switch (tool.type) {
    case ToolType::Flat: return R;
    case ToolType::Ball: return h >= R ? R : std::sqrt(R * R - (R - h) * (R - h));
    case ToolType::Bull: {
      const double r = tool.corner_radius;
      return h >= r ? R : (R - r) + std::sqrt(r * r - (r - h) * (r - h));
    }
    default: return -1;
  }
}

bool insideTool(const Tool& tool, const Vec3& p, double x, double y, double tip) {
  return std::hypot(p.x() - x, p.y() - y) < cutterRadius(tool, p.z() - tip);
}

// The lowest tip height at (x, y) at which point p is not inside the tool: bisection on insideTool. -inf when p lies
// outside the footprint.
double clearTip(const Tool& tool, const Vec3& p, double x, double y) {
  const double R = 0.5 * tool.diameter;
  if (std::hypot(p.x() - x, p.y() - y) >= R) return -std::numeric_limits<double>::infinity();
  double lo = p.z() - 2 * R - 1, hi = p.z();  // inside at lo (the cylinder part), never inside at hi
  for (int i = 0; i < 80; ++i) {
    const double mid = 0.5 * (lo + hi);
    (insideTool(tool, p, x, y, mid) ? lo : hi) = mid;
  }
  return hi;
}

// The highest clearTip over one triangle: a dense barycentric grid, then compass search from the best sample with
// shrinking steps. clearTip(p) = p.z - f(|p - c|) is concave in the barycentric coordinates (linear minus a convex
// nondecreasing function of a convex one) on a convex domain (triangle and disc), so the local search ends at the
// maximum.
double oracleTriangle(const Tool& tool, const Vec3& a, const Vec3& b, const Vec3& c, double x, double y) {
  const double R = 0.5 * tool.diameter;
  if (std::max({a.x(), b.x(), c.x()}) < x - R || std::min({a.x(), b.x(), c.x()}) > x + R ||
      std::max({a.y(), b.y(), c.y()}) < y - R || std::min({a.y(), b.y(), c.y()}) > y + R)
    return -std::numeric_limits<double>::infinity();
  auto point = [&](double u, double v) { return Vec3(a + u * (b - a) + v * (c - a)); };
  auto value = [&](double u, double v) {
    if (u < 0 || v < 0 || u + v > 1) return -std::numeric_limits<double>::infinity();
    return clearTip(tool, point(u, v), x, y);
  };
  const int n = 60;
  double best = -std::numeric_limits<double>::infinity(), bu = 0, bv = 0;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; i + j <= n; ++j) {
      const double val = value(double(i) / n, double(j) / n);
      if (val > best) best = val, bu = double(i) / n, bv = double(j) / n;
    }
  // Along each edge too (the domain's corners at the disc can be thin slivers the grid misses).
  for (int e = 0; e < 3; ++e)
    for (int k = 0; k <= 2000; ++k) {
      const double t = k / 2000.0;
      const double u = e == 0 ? t : (e == 1 ? 1 - t : 0), v = e == 0 ? 0 : (e == 1 ? t : 1 - t);
      const double val = value(u, v);
      if (val > best) best = val, bu = u, bv = v;
    }
  // And on the rim of the footprint, where the flat end mill's contacts lie (the compass search cannot follow a
  // curved boundary): points of the circle just inside the radius, mapped into the triangle's plane.
  const Vec3 normal = (b - a).cross(c - a);
  if (std::abs(normal.z()) > 1e-9 * normal.norm()) {
    const double rho = 0.5 * tool.diameter * (1 - 1e-12);
    auto rim = [&](double th, double& u, double& v) {  // barycentric (u, v) of the rim point at angle th
      const double px = x + rho * std::cos(th), py = y + rho * std::sin(th);
      const double e1x = b.x() - a.x(), e1y = b.y() - a.y(), e2x = c.x() - a.x(), e2y = c.y() - a.y();
      const double det = e1x * e2y - e1y * e2x;
      u = ((px - a.x()) * e2y - (py - a.y()) * e2x) / det;
      v = (e1x * (py - a.y()) - e1y * (px - a.x())) / det;
      return value(u, v);
    };
    const int steps = 8000;
    double best_th = 0, rim_best = -std::numeric_limits<double>::infinity();
    for (int k = 0; k < steps; ++k) {
      double u, v;
      const double th = 2 * M_PI * k / steps, val = rim(th, u, v);
      if (val > rim_best) rim_best = val, best_th = th;
    }
    if (std::isfinite(rim_best)) {  // golden-section refinement between the neighbouring samples
      double lo = best_th - 2 * M_PI / steps, hi = best_th + 2 * M_PI / steps, u, v;
      for (int i = 0; i < 100; ++i) {
        const double m1 = lo + 0.382 * (hi - lo), m2 = lo + 0.618 * (hi - lo);
        (rim(m1, u, v) < rim(m2, u, v) ? lo : hi) = (rim(m1, u, v) < rim(m2, u, v) ? m1 : m2);
      }
      const double val = rim(0.5 * (lo + hi), u, v);
      if (val > best) best = val, bu = u, bv = v;
    }
  }
  if (!std::isfinite(best)) return best;
  const double dirs[8][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}, {1, -1}, {-1, 1}, {1, 1}, {-1, -1}};
  for (double step = 1.0 / n; step > 1e-12;) {
    bool moved = false;
    for (const auto& d : dirs) {
      const double val = value(bu + step * d[0], bv + step * d[1]);
      if (val > best) {
        best = val, bu += step * d[0], bv += step * d[1];
        moved = true;
      }
    }
    if (!moved) step *= 0.5;
  }
  return best;
}

double oracleDrop(const Tool& tool, const Mesh& mesh, double x, double y, double floor) {
  double best = floor;
  for (int t = 0; t < mesh.triangleCount(); ++t)
    best = std::max(best, oracleTriangle(tool, mesh.corner(t, 0), mesh.corner(t, 1), mesh.corner(t, 2), x, y));
  return best;
}

// Random triangles in a 16 x 16 mm square: any orientation (vertical and overhanging ones too), sizes from a sliver
// to larger than the tool, some sharing edges and vertices.
Mesh randomTriangles(unsigned seed, int count) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> pos(-8, 8), height(-4, 4), size(0.2, 9);
  Mesh m;
  for (int i = 0; i < count; ++i) {
    const Vec3 centre(pos(rng), pos(rng), height(rng));
    const int base = static_cast<int>(m.vertices.size());
    const int kind = i % 5;
    for (int k = 0; k < 3; ++k) {
      Vec3 p = centre + size(rng) * test::randomDirections(1, rng())[0];
      if (kind == 1) p.x() = centre.x();  // vertical triangle (in a plane x = const)
      m.vertices.push_back(p);
    }
    if (kind == 2 && i > 0) {  // shares an edge with the previous triangle
      m.triangles.push_back({base - 3, base - 2, base});
      continue;
    }
    m.triangles.push_back({base, base + 1, base + 2});
  }
  return m;
}

}  // namespace

TEST(DropCutter, MatchesBruteForceOracleOnRandomTriangles) {
  const std::vector<Tool> tools = {cutter("ball6", ToolType::Ball, 6), cutter("flat6", ToolType::Flat, 6),
                                   cutter("bull6", ToolType::Bull, 6, 1.0), cutter("bull8", ToolType::Bull, 8, 2.5)};
  int queries = 0, touched = 0;
  double worst = 0;
  for (unsigned seed = 1; seed <= 6; ++seed) {
    const Mesh mesh = randomTriangles(seed, 12);
    std::mt19937 rng(100 + seed);
    std::uniform_real_distribution<double> pos(-10, 10);
    for (const Tool& tool : tools) {
      const DropCutter dc(mesh.vertices, mesh.triangles, tool);
      for (int q = 0; q < 25; ++q) {
        double x = pos(rng), y = pos(rng);
        if (q % 5 == 0) {  // right over a vertex, or over an edge's middle: the special contacts
          const int t = rng() % mesh.triangleCount();
          const Vec3 p = q % 10 == 0 ? mesh.corner(t, 0) : Vec3(0.5 * (mesh.corner(t, 0) + mesh.corner(t, 1)));
          x = p.x() + 0.01 * (q % 3);
          y = p.y();
        }
        const double floor = -100;
        int triangle = -2;
        const double fast = dc.drop(x, y, floor, &triangle);
        const double slow = oracleDrop(tool, mesh, x, y, floor);
        ++queries;
        if (slow > floor) ++touched;
        EXPECT_GE(fast, slow - 1e-7) << tool.id << " seed " << seed << " at " << x << ", " << y;  // never gouges
        EXPECT_LE(fast, slow + 1e-4) << tool.id << " seed " << seed << " at " << x << ", " << y;  // never floats
        EXPECT_EQ(triangle >= 0, fast > floor);
        worst = std::max(worst, std::abs(fast - slow));
      }
    }
  }
  std::printf("drop-cutter vs oracle: %d queries (%d touching), worst difference %.2e mm\n", queries, touched, worst);
  EXPECT_GT(touched, queries / 2);
}

TEST(DropCutter, RefusesADrill) {
  Tool drill = cutter("drill6", ToolType::Drill, 6);
  const Mesh m = test::box(Vec3(0, 0, 0), Vec3(1, 1, 1));
  EXPECT_THROW(DropCutter(m.vertices, m.triangles, drill), InputError);
}

namespace {

// ---- parts made with OpenCASCADE, written to STEP and loaded (B-rep faces with their radii) ------------------------

Part stepPart(const TopoDS_Shape& shape, const std::string& name, double chordal = 0.01) {
  LoadOptions options;
  options.chordal_tolerance = chordal;
  return test::stepPart(shape, name, options);
}

// A 40 x 40 x 10 block with a hemisphere of radius 15 on its top, everything grown by `grow` (the stock: the part
// and a skin; the block's edges stay sharp, so it holds a little more than the skin there).
TopoDS_Shape dome(double grow) {
  const TopoDS_Shape block =
      BRepPrimAPI_MakeBox(gp_Pnt(-20 - grow, -20 - grow, -grow), gp_Pnt(20 + grow, 20 + grow, 10 + grow)).Shape();
  const TopoDS_Shape cap = BRepPrimAPI_MakeSphere(gp_Pnt(0, 0, 10), 15 + grow, 0, M_PI / 2).Shape();
  return BRepAlgoAPI_Fuse(block, cap).Shape();
}



// ---- the scallop on simulated stock: a fine lattice of rays along the surface normal over a small window ----------

struct WindowScallop {
  double max_mm = 0;       // the highest material left above the surface on a reached ray
  double deepest_mm = 0;   // the deepest the tool went below the surface (a gouge)
  int rays = 0, reached = 0;
};

// Rays at `pitch` over a square of side 2 half_width around p, along n: on each the part's surface (the mesh, exactly)
// and the lowest point the flutes reach over the feed moves' poses (every pitch / 2 along each move): the cusp is the
// difference. Independent of the planner: the tool's solid from the simulation, the poses from the toolpath alone.
WindowScallop measureScallop(const Mesh& mesh, const Toolpath& path, const Tool& tool, const Vec3& p, const Vec3& n,
                             double half_width, double pitch) {
  const Vec3 e1 = n.unitOrthogonal(), e2 = n.cross(e1);
  const int k = static_cast<int>(std::ceil(half_width / pitch));
  const int side = 2 * k + 1;
  const double depth = 2.0;
  std::vector<double> surface(side * side, std::nan("")), lowest(side * side, std::numeric_limits<double>::infinity());
  // The part along each ray (Moller-Trumbore against the triangles near the window).
  for (int t = 0; t < mesh.triangleCount(); ++t) {
    const Vec3 &a = mesh.corner(t, 0), &b = mesh.corner(t, 1), &c = mesh.corner(t, 2);
    if ((triangleCentroid(mesh, t) - p).norm() > 2 * half_width + 5) continue;
    for (int i = 0; i < side; ++i)
      for (int j = 0; j < side; ++j) {
        const Vec3 o = p + (i - k) * pitch * e1 + (j - k) * pitch * e2 + depth * n, d = -n;
        const Vec3 ab = b - a, ac = c - a, q = d.cross(ac);
        const double det = ab.dot(q);
        if (std::abs(det) < 1e-14) continue;
        const Vec3 s = o - a;
        const double u = s.dot(q) / det;
        const Vec3 r = s.cross(ab);
        const double v = d.dot(r) / det, tt = ac.dot(r) / det;
        if (u < 0 || v < 0 || u + v > 1 || tt < 0 || tt > 2 * depth) continue;
        double& w = surface[i * side + j];
        w = std::isnan(w) ? depth - tt : std::max(w, depth - tt);
      }
  }
  const ToolSolid solid = toolSolid(tool);
  const double R = 0.5 * tool.diameter;
  for (std::size_t m = 1; m < path.size(); ++m) {
    if (path[m].move != MoveKind::Feed) continue;
    const Vec3 A = path[m - 1].tip, B = path[m].tip;
    const Vec3 ab = B - A;
    const double len = ab.norm();
    const double t0 = len > 0 ? std::clamp((p - A).dot(ab) / (len * len), 0.0, 1.0) : 0.0;
    if ((A + t0 * ab - p).norm() > 2 * R + 2 * half_width + 1) continue;
    const int steps = std::max(1, static_cast<int>(std::ceil(len / (0.5 * pitch))));
    for (int s = 0; s <= steps; ++s) {
      const double t = static_cast<double>(s) / steps;
      const Vec3 axis = ((1 - t) * path[m - 1].axis + t * path[m].axis).normalized();
      const Vec3 tip = A + t * ab - p;
      ToolPose pose;
      pose.tip = Vec3(tip.dot(e1), tip.dot(e2), tip.dot(n));
      pose.axis = Vec3(axis.dot(e1), axis.dot(e2), axis.dot(n));
      if ((pose.tip + R * pose.axis).head<2>().norm() > R + 1.5 * half_width) continue;
      for (const ToolPiece& piece : solid.pieces) {
        if (piece.zone != ToolZone::Flutes) continue;
        const Box box = pieceBox(piece, pose);
        const int i0 = std::max(0, static_cast<int>(std::floor(box.min.x() / pitch)) + k);
        const int i1 = std::min(side - 1, static_cast<int>(std::ceil(box.max.x() / pitch)) + k);
        const int j0 = std::max(0, static_cast<int>(std::floor(box.min.y() / pitch)) + k);
        const int j1 = std::min(side - 1, static_cast<int>(std::ceil(box.max.y() / pitch)) + k);
        for (int i = i0; i <= i1; ++i)
          for (int j = j0; j <= j1; ++j) {
            Span span;
            if (rayPieceSpan(piece, pose, Vec3((i - k) * pitch, (j - k) * pitch, 0), 2, span))
              lowest[i * side + j] = std::min(lowest[i * side + j], span.lo);
          }
      }
    }
  }
  WindowScallop out;
  for (int r = 0; r < side * side; ++r) {
    if (std::isnan(surface[r])) continue;
    ++out.rays;
    if (!std::isfinite(lowest[r]) || lowest[r] > surface[r] + 1.0) continue;  // no cut passed over this ray
    ++out.reached;
    out.max_mm = std::max(out.max_mm, lowest[r] - surface[r]);
    out.deepest_mm = std::max(out.deepest_mm, surface[r] - lowest[r]);
  }
  return out;
}

Vec3 onDome(double polar_deg, double azimuth_deg) {
  const double a = polar_deg * M_PI / 180, b = azimuth_deg * M_PI / 180;
  return Vec3(std::sin(a) * std::cos(b), std::sin(a) * std::sin(b), std::cos(a));
}

}  // namespace

TEST(SurfaceFinishing, ScallopStepoverIsTheExactCusp) {
  // Flat: the notes' table (6 mm ball: 0.346, 0.489, 0.692 mm at 0.005, 0.01, 0.02 mm).
  EXPECT_NEAR(scallopStepover(3, 0.005, std::numeric_limits<double>::infinity()), 0.346, 5e-4);
  EXPECT_NEAR(scallopStepover(3, 0.01, std::numeric_limits<double>::infinity()), 0.489, 5e-4);
  EXPECT_NEAR(scallopStepover(5, 0.01, std::numeric_limits<double>::infinity()), 0.632, 5e-4);
  // Curved: two balls phi apart on a circle of centres; the cusp where they meet, computed directly.
  for (double rho : {20.0, -20.0, 8.0, -4.5, 1000.0}) {
    const double R = 3, h = 0.01;
    const double c = scallopStepover(R, h, rho);
    const double D = rho > 0 ? rho + R : -rho - R, phi = c / D;
    // Ball centres at angle +-phi/2 on the circle of radius D around the origin; the surface is the circle |rho|.
    const Eigen::Vector2d c1(D * std::sin(phi / 2), D * std::cos(phi / 2));
    // The meeting point on the bisector (x = 0): |(0, y) - c1| = R, on the surface's side.
    const double dy = std::sqrt(R * R - c1.x() * c1.x());
    const double y = rho > 0 ? c1.y() - dy : c1.y() + dy;
    const double cusp = rho > 0 ? y - rho : -rho - y;
    EXPECT_NEAR(cusp, h, 1e-9) << rho;
    // And the notes' first-order form on the surface: h = (w^2 / 8)(1/R + 1/rho), w = c rho / (rho + R).
    const double w = std::abs(c * rho / D);
    EXPECT_NEAR(w * w / 8 * (1 / R + 1 / rho), h, 0.02 * h) << rho;
  }
  EXPECT_THROW(scallopStepover(3, 0.01, -2.5), InputError);
  EXPECT_THROW(scallopStepover(0, 0.01, 10), InputError);
  EXPECT_DOUBLE_EQ(scallopStepover(3, 5, 10), 6);
}

TEST(SurfaceFinishing, DomeFinishedWithoutGougesOrCollisionsAndTheScallopHolds) {
  const Part part = stepPart(dome(0), "dome");
  const Part stock = stepPart(dome(0.3), "dome_stock");
  const std::vector<int> spheres = facesOfType(part, SurfaceType::Sphere);
  ASSERT_EQ(spheres.size(), 1u);
  const Tool tool = ball6();
  SurfaceFinishingOptions options;
  const SurfaceFinishingResult r = finishSurfaces3Axis(part, spheres, setupFrame(part, Vec3::UnitZ()), tool, 0, options);
  const double area = part.faces[spheres[0]].area;
  std::printf("dome: %zu points, stepover %.3f (rows %.3f, levels %.3f), %d raster runs, %d levels, %d contours, "
              "%d retracts, %ld drops, %.2f s; planned %.0f of %.0f mm2, skipped %.0f, unreached %.0f\n",
              r.path.size(), r.stepover_mm, r.raster_stepover_mm, r.height_step_mm, r.raster_passes,
              r.waterline_levels, r.waterline_contours, r.retracts, r.drops, r.seconds, r.planned_area_mm2, area,
              r.skipped_area_mm2, r.unreached_area_mm2);
  ASSERT_GT(r.path.size(), 100u);
  EXPECT_GT(r.raster_passes, 10);
  EXPECT_GT(r.waterline_contours, 10);
  // The ball reaches the hemisphere down to where it meets the block's top: cos(polar) >= R / (15 + R).
  EXPECT_NEAR(r.planned_area_mm2 / area, 1 - 3.0 / 18, 0.03);
  EXPECT_EQ(r.skipped_area_mm2, 0);

  VerifyOptions vo;
  vo.stock_mesh = &stock.mesh;
  const VerificationReport report = verifyToolpath(part.mesh, part.triangle_face, r.path, {tool}, vo);
  std::printf("dome verified: %d gouges (worst %.4f), %d collisions, %d moves, %.1f s at %.3f mm\n", report.gouges,
              report.worst_gouge_mm, report.collisions, report.moves, report.seconds_total, report.resolution_mm);
  EXPECT_EQ(report.gouges, 0);
  EXPECT_EQ(report.collisions, 0);

  // The scallop on simulated stock, at a twentieth of the stepover: on the shallow top (raster) and the steep side
  // (waterline), each window away from where the two regions overlap.
  const double pitch = r.stepover_mm / 20;
  for (const auto& [polar, what] : {std::pair{18.0, "raster"}, std::pair{28.0, "raster"}, std::pair{62.0, "waterline"},
                                    std::pair{72.0, "waterline"}}) {
    const Vec3 n = onDome(polar, 35);
    const WindowScallop w = measureScallop(part.mesh, r.path, tool, Vec3(0, 0, 10) + 15 * n, n, 0.6, pitch);
    std::printf("scallop at polar %.0f deg (%s): %.4f mm (target %.3f), deepest cut %.4f, %d of %d rays reached\n",
                polar, what, w.max_mm, options.scallop, w.deepest_mm, w.reached, w.rays);
    EXPECT_GT(w.reached, w.rays * 9 / 10);
    EXPECT_LE(w.max_mm, 1.1 * options.scallop) << what;
    EXPECT_LE(w.deepest_mm, 0.01) << what;
  }
}

namespace {

// A block with a hemisphere of radius 8 on it and, 8 mm beside the hemisphere, a wall 30 mm tall: from above, a
// holder wider than that gap hits the wall's top while the ball works on the hemisphere's side near it.
TopoDS_Shape domeByWall(double grow) {
  const TopoDS_Shape block =
      BRepPrimAPI_MakeBox(gp_Pnt(-30 - grow, -20 - grow, -grow), gp_Pnt(30 + grow, 20 + grow, 10 + grow)).Shape();
  const TopoDS_Shape wall =
      BRepPrimAPI_MakeBox(gp_Pnt(16 - grow, -20 - grow, 10), gp_Pnt(20 + grow, 20 + grow, 40 + grow)).Shape();
  const TopoDS_Shape cap = BRepPrimAPI_MakeSphere(gp_Pnt(0, 0, 10), 8 + grow, 0, M_PI / 2).Shape();
  return BRepAlgoAPI_Fuse(BRepAlgoAPI_Fuse(block, wall).Shape(), cap).Shape();
}

}  // namespace

TEST(SurfaceFinishing, FiveAxisTiltsWhereTheThreeAxisHolderCollides) {
  const Part part = stepPart(domeByWall(0), "dome_by_wall");
  const Part stock = stepPart(domeByWall(0.3), "dome_by_wall_stock");
  const std::vector<int> spheres = facesOfType(part, SurfaceType::Sphere);
  ASSERT_EQ(spheres.size(), 1u);
  Tool tool = ball6();
  tool.stickout = 20;
  tool.holder = {{40, 30}};
  const SetupFrame frame = setupFrame(part, Vec3::UnitZ());
  SurfaceFinishingOptions options;
  const SurfaceFinishingResult three = finishSurfaces3Axis(part, spheres, frame, tool, 0, options);
  const Vec3 away(-std::sin(40 * M_PI / 180), 0, std::cos(40 * M_PI / 180));
  const SurfaceFinishingResult five = finishSurfaces5Axis(part, spheres, frame, away, tool, 0, options);
  std::printf("3-axis: %zu points, planned %.0f mm2, skipped %.0f (holder), %.2f s\n", three.path.size(),
              three.planned_area_mm2, three.skipped_area_mm2, three.seconds);
  std::printf("5-axis: %zu points, planned %.0f mm2, skipped %.0f, %.2f s\n", five.path.size(), five.planned_area_mm2,
              five.skipped_area_mm2, five.seconds);
  EXPECT_GT(three.skipped_area_mm2, 50);
  EXPECT_GT(five.planned_area_mm2, three.planned_area_mm2 + 0.5 * three.skipped_area_mm2);

  // The tilt: never beyond the face's direction, never above max_tilt, turning at most max_tilt_rate per mm.
  double most = 0, fastest = 0;
  int tilted = 0;
  for (std::size_t k = 0; k < five.path.size(); ++k) {
    const double tilt = std::acos(std::clamp(five.path[k].axis.z(), -1.0, 1.0)) * 180 / M_PI;
    most = std::max(most, tilt);
    tilted += tilt > 0.5;
    EXPECT_LE(five.path[k].axis.y(), 1e-9);
    EXPECT_LE(five.path[k].axis.x(), 1e-9);  // leaning towards -x, the face's side
    if (k > 0 && five.path[k].move == MoveKind::Feed && five.path[k - 1].move == MoveKind::Feed) {
      const Vec3 c0 = five.path[k - 1].tip + 3 * five.path[k - 1].axis, c1 = five.path[k].tip + 3 * five.path[k].axis;
      const double turn = std::acos(std::clamp(five.path[k].axis.dot(five.path[k - 1].axis), -1.0, 1.0)) * 180 / M_PI;
      if ((c1 - c0).norm() > 1e-6) fastest = std::max(fastest, turn / (c1 - c0).norm());
    }
  }
  std::printf("5-axis tilt: at most %.1f deg, %d poses tilted, fastest turn %.2f deg/mm along a pass\n", most, tilted,
              fastest);
  EXPECT_GT(tilted, 100);
  EXPECT_LE(most, 40 + 1e-6);
  EXPECT_LE(fastest, options.max_tilt_rate_deg_mm + 1e-3);

  VerifyOptions vo;
  vo.stock_mesh = &stock.mesh;
  vo.resolution = 0.15;
  for (const auto* r : {&three, &five}) {
    const VerificationReport report = verifyToolpath(part.mesh, part.triangle_face, r->path, {tool}, vo);
    std::printf("%s verified: %d gouges (worst %.4f), %d collisions (worst %.3f), %d moves, %.1f s\n",
                r == &three ? "3-axis" : "5-axis", report.gouges, report.worst_gouge_mm, report.collisions,
                report.worst_collision_mm, report.moves, report.seconds_total);
    EXPECT_EQ(report.gouges, 0);
    EXPECT_EQ(report.collisions, 0);
  }
  // The same ball centres with the axis upright, along the stretch of the path that leans most: the holder meets the
  // wall.
  std::size_t most_at = 0;
  for (std::size_t k = 0; k < five.path.size(); ++k)
    if (five.path[k].move == MoveKind::Feed && five.path[k].axis.z() < five.path[most_at].axis.z()) most_at = k;
  Toolpath upright;
  for (std::size_t k = most_at; k < five.path.size() && five.path[k].move == MoveKind::Feed && upright.size() < 40; ++k) {
    CutterLocation c = five.path[k];
    c.tip = c.tip + 3 * c.axis - 3 * Vec3::UnitZ();
    c.axis = Vec3::UnitZ();
    upright.push_back(c);
  }
  const VerificationReport report = verifyToolpath(part.mesh, part.triangle_face, upright, {tool}, vo);
  std::printf("the 5-axis centres with the axis upright (%zu poses): %d collisions (worst %.2f mm)\n", upright.size(),
              report.collisions, report.worst_collision_mm);
  EXPECT_GT(report.collisions, 0);
}

namespace {

// Roughing's slabs (the setup frame's) of a stock made of `part_section(z)` (the part's section at the slab's
// bottom, grown by the allowance) and a tower of stock over the box [lo, hi] no roughing tool took: 10 mm slabs from
// the tower's top down to `bottom`.
std::vector<SlabState> slabsWithTower(const SetupFrame& frame, const Vec3& lo, const Vec3& hi, double bottom,
                                      const std::function<double(double)>& section_radius) {
  auto ring = [&](const std::vector<Vec3>& points) {
    Ring out;
    for (const Vec3& p : toFrame(points, frame)) out.push_back(Point2(p.x(), p.y()));
    return out;
  };
  std::vector<SlabState> slabs;
  const double z0 = toFrame({Vec3::Zero()}, frame)[0].z();  // the frame's z of the part frame's origin
  for (double top = hi.z(); top > bottom + 1e-9; top -= 10) {
    const double z = std::max(bottom, top - 10);
    std::vector<Ring> rings{ring({Vec3(lo.x(), lo.y(), z), Vec3(hi.x(), lo.y(), z), Vec3(hi.x(), hi.y(), z),
                                  Vec3(lo.x(), hi.y(), z)})};
    const double radius = section_radius(z);
    if (radius > 0) {
      std::vector<Vec3> disc;
      for (int k = 0; k < 90; ++k)
        disc.push_back(Vec3(radius * std::cos(k * M_PI / 45), radius * std::sin(k * M_PI / 45), z));
      rings.push_back(ring(disc));
    }
    slabs.push_back({z + z0, top + z0, regionFromPolygons(rings)});
  }
  return slabs;
}

// The plans made knowing only the part (`blind`) and knowing the stock roughing left (`aware`), each simulated
// against that stock at 0.25 mm (the shank meets it by millimetres): neither gouges; the blind one collides (the case
// is real), the aware one does not.
void expectOnlyTheBlindPlanCollides(const Part& part, const Mesh& stock, const Tool& tool,
                                    const SurfaceFinishingResult& blind, const SurfaceFinishingResult& aware) {
  VerifyOptions vo;
  vo.stock_mesh = &stock;
  vo.resolution = 0.25;
  for (const auto* r : {&blind, &aware}) {
    const VerificationReport report = verifyToolpath(part.mesh, part.triangle_face, r->path, {tool}, vo);
    std::printf("%s: planned %.0f mm2, skipped %.0f; verified: %d gouges, %d collisions (worst %.2f mm)\n",
                r == &blind ? "part only" : "with the stock left", r->planned_area_mm2, r->skipped_area_mm2,
                report.gouges, report.collisions, report.worst_collision_mm);
    EXPECT_EQ(report.gouges, 0);
    if (r == &blind)
      EXPECT_GT(report.collisions, 0);
    else
      EXPECT_EQ(report.collisions, 0);
  }
}

}  // namespace

TEST(SurfaceFinishing, ShankAndHolderKeepClearOfTheStockRoughingLeft) {
  // The dome of the first test, and beside it a tower of stock 30 mm tall that roughing left (a wall its tools could
  // not reach, say): finishing that knows only the part runs its shank into the tower; given roughing's slabs it
  // leaves out what the shank cannot reach and cuts the rest, and the simulation finds no collision.
  const Part part = stepPart(dome(0), "dome");
  const Vec3 lo(16.5, -20.3, 10), hi(20.3, 20.3, 40);
  const TopoDS_Shape tower = BRepPrimAPI_MakeBox(gp_Pnt(lo.x(), lo.y(), 9), gp_Pnt(hi.x(), hi.y(), hi.z())).Shape();
  const Part stock = stepPart(BRepAlgoAPI_Fuse(dome(0.3), tower).Shape(), "dome_tower_stock");
  const std::vector<int> spheres = facesOfType(part, SurfaceType::Sphere);
  ASSERT_EQ(spheres.size(), 1u);
  const Tool tool = ball6();
  const SetupFrame frame = setupFrame(part, Vec3::UnitZ());
  const std::vector<SlabState> slabs = slabsWithTower(frame, lo, hi, 10, [](double z) {
    return z < 25 ? std::sqrt(15.0 * 15.0 - (z - 10) * (z - 10)) + 0.3 : 0.0;
  });
  SurfaceFinishingOptions options;
  const SurfaceFinishingResult blind = finishSurfaces3Axis(part, spheres, frame, tool, 0, options);
  const SurfaceFinishingResult aware = finishSurfaces3Axis(
      part, spheres, frame, tool, 0, options,
      stockBeyondSkin(slabs, options.skin, toFrame(part.mesh.vertices, frame), part.mesh.triangles));
  expectOnlyTheBlindPlanCollides(part, stock.mesh, tool, blind, aware);
  EXPECT_GT(aware.skipped_area_mm2, 20);
  // The dome away from the tower is still finished: its far half at least.
  EXPECT_GT(aware.planned_area_mm2, 0.5 * blind.planned_area_mm2);
  EXPECT_LT(aware.planned_area_mm2, blind.planned_area_mm2);
}

TEST(SurfaceFinishing, AThinPillarOfStockApartFromThePartIsKeptWholeAndClearOf) {
  // Roughing left a pillar 0.9 mm wide standing 2.2 mm off the dome's foot (a core between passes, say). The stock
  // beyond the skin is each slab's stock less the skin band round the part's shadow: the pillar stays whole, the
  // dome's skin goes. An erosion of every slab by the skin lost such a pillar, and the shank met it (mount_rush: 17
  // collisions in one surface operation).
  const Part part = stepPart(dome(0), "dome");
  const Vec3 lo(17.5, -0.45, 10), hi(18.4, 0.45, 40);
  const TopoDS_Shape pillar_box =
      BRepPrimAPI_MakeBox(gp_Pnt(lo.x(), lo.y(), 9), gp_Pnt(hi.x(), hi.y(), hi.z())).Shape();
  const Part stock = stepPart(BRepAlgoAPI_Fuse(dome(0.3), pillar_box).Shape(), "dome_pillar_stock");
  const std::vector<int> spheres = facesOfType(part, SurfaceType::Sphere);
  ASSERT_EQ(spheres.size(), 1u);
  const Tool tool = ball6();
  const SetupFrame frame = setupFrame(part, Vec3::UnitZ());
  auto section = [](double z) { return z < 25 ? std::sqrt(15.0 * 15.0 - (z - 10) * (z - 10)) : 0.0; };
  const std::vector<SlabState> slabs =
      slabsWithTower(frame, lo, hi, 10, [&](double z) { return z < 25 ? section(z) + 0.3 : 0.0; });
  SurfaceFinishingOptions options;
  const std::vector<SlabState> beyond =
      stockBeyondSkin(slabs, options.skin, toFrame(part.mesh.vertices, frame), part.mesh.triangles);
  ASSERT_EQ(beyond.size(), slabs.size());
  Ring around;  // the pillar grown by 0.5 mm, in the frame
  for (const Vec3& p : toFrame({Vec3(lo.x() - 0.5, lo.y() - 0.5, 0), Vec3(hi.x() + 0.5, lo.y() - 0.5, 0),
                                Vec3(hi.x() + 0.5, hi.y() + 0.5, 0), Vec3(lo.x() - 0.5, hi.y() + 0.5, 0)},
                               frame))
    around.push_back(Point2(p.x(), p.y()));
  const Region near_pillar = regionFromPolygons({around});
  const double z0 = toFrame({Vec3::Zero()}, frame)[0].z();
  for (const SlabState& slab : beyond) {
    const double pillar = regionArea(intersect(slab.remaining, near_pillar));
    EXPECT_NEAR(pillar, 0.81, 0.005) << "slab at z " << slab.z - z0;
    // Less the pillar, what is left is the dome's shadow over the slab: its skin (0.3 mm) is gone. From the block's
    // top down the block's shadow holds the whole section, skin and all.
    const double r = slab.z - z0 > 10 + 1e-9 ? section(slab.z - z0) : 15.3;
    EXPECT_NEAR(regionArea(slab.remaining) - pillar, M_PI * r * r, 0.02 * M_PI * r * r + 0.01)
        << "slab at z " << slab.z - z0;
  }

  const SurfaceFinishingResult blind = finishSurfaces3Axis(part, spheres, frame, tool, 0, options);
  const SurfaceFinishingResult aware = finishSurfaces3Axis(part, spheres, frame, tool, 0, options, beyond);
  expectOnlyTheBlindPlanCollides(part, stock.mesh, tool, blind, aware);
  EXPECT_GT(aware.planned_area_mm2, 0.5 * blind.planned_area_mm2);  // the dome away from the pillar is finished
}

namespace {

// A 50 x 40 x 20 block with a spherical pocket of radius 12 sunk 8 mm into its top (a concave face), grown by `grow`.
TopoDS_Shape pocket(double grow) {
  const TopoDS_Shape block =
      BRepPrimAPI_MakeBox(gp_Pnt(-25 - grow, -20 - grow, -grow), gp_Pnt(25 + grow, 20 + grow, 20 + grow)).Shape();
  const TopoDS_Shape ball = BRepPrimAPI_MakeSphere(gp_Pnt(0, 0, 24), 12 - grow).Shape();
  return BRepAlgoAPI_Cut(block, ball).Shape();
}

}  // namespace

TEST(SurfaceFinishing, ConcavePocketScallopHoldsAndBullAndFlatMillsDoNotGouge) {
  const Part part = stepPart(pocket(0), "pocket");
  const Part stock = stepPart(pocket(0.3), "pocket_stock");
  const std::vector<int> spheres = facesOfType(part, SurfaceType::Sphere);
  ASSERT_EQ(spheres.size(), 1u);
  ASSERT_TRUE(part.faces[spheres[0]].concave);
  const SetupFrame frame = setupFrame(part, Vec3::UnitZ());
  VerifyOptions vo;
  vo.stock_mesh = &stock.mesh;
  vo.resolution = 0.15;
  SurfaceFinishingOptions options;
  Tool bull = cutter("bull8", ToolType::Bull, 8, 1.0);
  bull.flute_length = 16, bull.stickout = 32, bull.holder = {{32, 20}, {40, 44}};
  Tool flat = cutter("flat6", ToolType::Flat, 6);
  flat.flute_length = 16, flat.stickout = 28, flat.holder = {{32, 20}, {40, 44}};
  for (const Tool& tool : {ball6(), bull, flat}) {
    // A flat end mill leaves a staircase on a curved face: a coarser target keeps its passes few.
    options.scallop = tool.type == ToolType::Flat ? 0.05 : 0.01;
    const SurfaceFinishingResult r = finishSurfaces3Axis(part, spheres, frame, tool, 0, options);
    const VerificationReport report = verifyToolpath(part.mesh, part.triangle_face, r.path, {tool}, vo);
    std::printf("pocket, %s: %zu points, centre spacing %.3f, rows %.3f, levels %.3f, radius %.1f, planned %.0f mm2, "
                "%.2f s; %d gouges (worst %.4f), %d collisions\n",
                tool.id.c_str(), r.path.size(), r.stepover_mm, r.raster_stepover_mm, r.height_step_mm,
                r.least_radius_mm, r.planned_area_mm2, r.seconds, report.gouges, report.worst_gouge_mm,
                report.collisions);
    EXPECT_GT(r.path.size(), 50u);
    EXPECT_EQ(report.gouges, 0) << tool.id;
    EXPECT_EQ(report.collisions, 0) << tool.id;
    if (tool.type != ToolType::Ball) continue;
    // The concave radius (12 mm, the B-rep's) tightens the spacing below the flat's.
    EXPECT_NEAR(r.least_radius_mm, -12, 1e-6);
    const double pitch = scallopStepover(3, options.scallop, -12) / 20;
    // The pocket's floor (raster) and its side (waterline): the sphere's points at polar angles from its bottom.
    for (const auto& [polar, what] : {std::pair{12.0, "raster"}, std::pair{62.0, "waterline"}}) {
      const Vec3 down = onDome(180 - polar, 35);  // from the sphere's centre to the pocket's surface
      const WindowScallop w = measureScallop(part.mesh, r.path, tool, Vec3(0, 0, 24) + 12 * down, -down, 0.6, pitch);
      std::printf("pocket scallop at polar %.0f deg (%s): %.4f mm (target %.3f), deepest cut %.4f, %d of %d rays\n",
                  polar, what, w.max_mm, options.scallop, w.deepest_mm, w.reached, w.rays);
      EXPECT_GT(w.reached, w.rays * 9 / 10);
      EXPECT_LE(w.max_mm, 1.1 * options.scallop) << what;
    }
  }
}

TEST(SurfaceFinishing, RefusesWhatItCannotDo) {
  Mesh block = test::box(Vec3(0, 0, 0), Vec3(20, 20, 10));
  const Part part = partFromMesh(block, "block");
  const SetupFrame frame = setupFrame(part, Vec3::UnitZ());
  const Tool ball = ball6();
  EXPECT_THROW(finishSurfaces3Axis(part, {}, frame, ball, 0), InputError);
  EXPECT_THROW(finishSurfaces3Axis(part, {static_cast<int>(part.faces.size())}, frame, ball, 0), InputError);
  EXPECT_THROW(finishSurfaces3Axis(part, {0}, frame, cutter("drill6", ToolType::Drill, 6), 0), InputError);
  EXPECT_THROW(finishSurfaces5Axis(part, {0}, frame, Vec3::UnitZ(), cutter("flat6", ToolType::Flat, 6), 0),
               InputError);
  EXPECT_THROW(finishSurfaces5Axis(part, {0}, frame, Vec3::Zero(), ball, 0), InputError);
  SurfaceFinishingOptions bad;
  bad.scallop = 0;
  EXPECT_THROW(finishSurfaces3Axis(part, {0}, frame, ball, 0, bad), InputError);
  bad = {};
  bad.steep_angle_deg = 89;
  EXPECT_THROW(finishSurfaces3Axis(part, {0}, frame, ball, 0, bad), InputError);
}
