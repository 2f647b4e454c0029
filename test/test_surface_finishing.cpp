// Surface finishing (issue 17, item 5): the drop-cutter against a brute-force oracle, finished parts judged by the
// simulation (gouges, collisions), scallops measured on simulated stock, 5-axis tilt where the 3-axis holder collides.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <random>

#include "art2part/finishing/drop_cutter.h"
#include "art2part/finishing/surface_finishing.h"
#include "test_meshes.h"

using namespace art2part;

namespace {

Tool cutter(const std::string& id, ToolType type, double diameter, double corner = 0) {
  Tool t;
  t.id = id;
  t.type = type;
  t.diameter = diameter;
  t.corner_radius = type == ToolType::Ball ? diameter / 2 : corner;
  t.flute_length = 3 * diameter;
  t.shank_diameter = diameter;
  t.stickout = 5 * diameter;
  t.holder = {{4 * diameter, 40}};
  return t;
}

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
