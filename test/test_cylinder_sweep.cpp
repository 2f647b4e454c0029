// Exact sweeps of cylinders (cylinder_sweep.h): against the definition of the swept solid point by point, against
// volumes known in closed form, and against the pose-by-pose sweep of the verification.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "art2part/geometry/part.h"
#include "art2part/simulation/cylinder_sweep.h"
#include "art2part/simulation/sweep.h"
#include "test_meshes.h"

using namespace art2part;

namespace {

constexpr double kPi = 3.14159265358979323846;

// The definition: a point is in the solid when its height above the start tip along the axis lies in [h0, h1] and
// its projection on the plane square to the axis lies within the radius of the move's projection there.
double outside(const SweptCylinder& c, const Vec3& p) {
  const Vec3 rel = p - c.from, move = c.to - c.from;
  const double h = rel.dot(c.axis);
  const Vec3 flat = rel - h * c.axis;
  const double length2 = move.squaredNorm();
  const double f = length2 > 0 ? std::clamp(flat.dot(move) / length2, 0.0, 1.0) : 0.0;
  const double across = (flat - f * move).norm() - c.radius;
  return std::max({across, c.h0 - h, h - c.h1});  // > 0 outside, < 0 inside (a bound on the distance)
}

Vec3 randomUnit(std::mt19937& rng) {
  std::normal_distribution<double> n;
  return Vec3(n(rng), n(rng), n(rng)).normalized();
}

ToolPiece flutes(double radius, double h0, double h1) {
  ToolPiece p;
  p.zone = ToolZone::Flutes;
  p.r0 = p.r1 = radius;
  p.h0 = h0;
  p.h1 = h1;
  return p;
}

}  // namespace

TEST(CylinderSweep, EachRayMeetsTheSolidWhereItsDefinitionSays) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(0, 1);
  int hits = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const Vec3 axis = trial % 3 == 0 ? Vec3::UnitZ() : randomUnit(rng);
    const Vec3 sideways = axis.cross(randomUnit(rng)).normalized();
    const double length = trial % 5 == 0 ? 0.0 : 40 * unit(rng);
    const ToolPiece piece = flutes(1 + 9 * unit(rng), 5 * unit(rng), 10 + 30 * unit(rng));
    const Vec3 tip(20 * unit(rng), 20 * unit(rng), 20 * unit(rng));
    std::vector<SweptCylinder> level;
    ASSERT_TRUE(sweptCylinders(piece, {tip, axis}, {tip + length * sideways, axis}, 0.1, level));
    ASSERT_EQ(level.size(), 1u);
    const SweptCylinder& c = level[0];
    for (int r = 0; r < 40; ++r) {
      const int family = r % 3;
      const Vec3 origin = tip + Vec3(60 * unit(rng) - 30, 60 * unit(rng) - 30, 60 * unit(rng) - 30);
      Span span;
      const bool hit = rayThroughSweptCylinder(c, family, origin, span);
      hits += hit;
      // Every point of the ray: inside the span it is in the solid, outside it is not (a margin for rounding).
      for (double t = -100; t <= 100; t += 0.25) {
        Vec3 p = origin;
        p[family] = origin[family] + t;
        const double d = outside(c, p);
        const bool in = hit && t >= span.lo - origin[family] && t <= span.hi - origin[family];
        if (std::abs(d) < 1e-6) continue;
        ASSERT_EQ(in, d < 0) << "trial " << trial << " ray " << r << " t " << t << " d " << d;
      }
    }
  }
  EXPECT_GT(hits, 1000);  // the rays test the solids, not the air round them
}

TEST(CylinderSweep, ARampIsSweptInPiecesWithinItsSlackAndATurnIsNotSwept) {
  const ToolPiece piece = flutes(5, 0, 20);
  const Vec3 z = Vec3::UnitZ();
  std::vector<SweptCylinder> c;
  EXPECT_TRUE(sweptCylinders(piece, {Vec3(0, 0, 5), z}, {Vec3(30, 10, 5), z}, 0.25, c));  // level: exact
  ASSERT_EQ(c.size(), 1u);
  c.clear();
  EXPECT_TRUE(sweptCylinders(piece, {Vec3(0, 0, 5), z}, {Vec3(0, 0, -5), z}, 0.25, c));  // a plunge: a taller cylinder
  ASSERT_EQ(c.size(), 1u);
  EXPECT_NEAR(c[0].h0, -10, 1e-12);
  EXPECT_NEAR(c[0].h1, 20, 1e-12);
  c.clear();
  EXPECT_FALSE(sweptCylinders(piece, {Vec3(0, 0, 5), z}, {Vec3(30, 0, 5), Vec3(0.6, 0, 0.8)}, 0.25, c));  // a turn
  ToolPiece cone = piece;
  cone.r1 = 6;
  EXPECT_FALSE(sweptCylinders(cone, {Vec3(0, 0, 5), z}, {Vec3(30, 0, 5), z}, 0.25, c));
  EXPECT_TRUE(c.empty());

  // A ramp along a tilted axis, falling 1 mm over 20: four pieces. Every point of the true sweep (the cylinder at
  // poses along the ramp) is in a piece, and every point of a piece lies within the slack of it along the axis (below
  // its floor, above its top).
  const Vec3 axis = Vec3(0.2, 0.1, 1).normalized(), d = axis.cross(Vec3::UnitX()).normalized();
  const Vec3 from(3, 4, 5), to = from + 20 * d - 1.0 * axis;
  const double slack = 0.25;
  ASSERT_TRUE(sweptCylinders(piece, {from, axis}, {to, axis}, slack, c));
  ASSERT_EQ(c.size(), 4u);
  const auto inTrueSweep = [&](const Vec3& p, double margin) {
    for (int k = 0; k <= 2000; ++k) {
      SweptCylinder still;
      still.from = still.to = from + (to - from) * (k / 2000.0);
      still.axis = axis;
      still.radius = piece.r0;
      still.h0 = piece.h0;
      still.h1 = piece.h1;
      if (outside(still, p) < -margin) return true;
    }
    return false;
  };
  const auto inPieces = [&](const Vec3& p) {
    return std::any_of(c.begin(), c.end(), [&](const SweptCylinder& s) { return outside(s, p) < 0; });
  };
  // The ramp's lowest points, just over the tip at its end (a piece not stretched down misses them).
  const Vec3 side = axis.cross(d);
  for (const double w : {-4.0, 0.0, 4.0}) EXPECT_TRUE(inPieces(to + 0.05 * axis + w * side)) << w;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> near(-7, 7), height(-2, 22);
  int inside_pieces = 0;
  for (int k = 0; k < 1500; ++k) {
    const Vec3 p = from + (to - from) * ((k % 100) / 99.0) + near(rng) * d + near(rng) * side + height(rng) * axis;
    const bool in = inPieces(p);
    inside_pieces += in;
    if (inTrueSweep(p, 0.02)) {
      EXPECT_TRUE(in) << k;
    }
    if (in) {
      bool within = false;
      for (double s = -slack - 0.02; s <= slack + 0.02 && !within; s += 0.01)
        within = inTrueSweep(p - s * axis, -0.02);
      EXPECT_TRUE(within) << k;
    }
  }
  EXPECT_GT(inside_pieces, 300);
}

TEST(CylinderSweep, ALevelCutTakesTheStadiumItsFlutesSweep) {
  // A 10 mm mill cutting 4 mm deep along x through a 60 x 40 x 20 block: a slot with round ends inside the block.
  Box box;
  box.min = Vec3(0, 0, 0);
  box.max = Vec3(60, 40, 20);
  const DexelLattice lattice = DexelLattice::over(box, 0.5);
  Stock stock = boxStock(lattice);
  std::vector<SweptCylinder> c;
  ASSERT_TRUE(
      sweptCylinders(flutes(5, 0, 30), {Vec3(15, 20, 16), Vec3::UnitZ()}, {Vec3(45, 20, 16), Vec3::UnitZ()}, 0.1, c));
  removeSweptCylinders(stock, c);
  const double slot = (30 * 10 + kPi * 25) * 4;
  EXPECT_NEAR(60 * 40 * 20 - stock.volume(), slot, 0.01 * slot);
  // A thread count does not change the result.
  Stock one = boxStock(lattice);
  removeSweptCylinders(one, c, 1);
  for (int axis = 0; axis < 3; ++axis)
    for (std::size_t r = 0; r < stock.dexels[axis].size(); ++r) {
      ASSERT_EQ(one.dexels[axis][r].size(), stock.dexels[axis][r].size());
      for (std::size_t k = 0; k < stock.dexels[axis][r].size(); ++k) {
        EXPECT_EQ(one.dexels[axis][r][k].lo, stock.dexels[axis][r][k].lo);
        EXPECT_EQ(one.dexels[axis][r][k].hi, stock.dexels[axis][r][k].hi);
      }
    }
}

TEST(CylinderSweep, ItTakesWhatThePoseSweepTakesToWithinItsCusps) {
  // A zig-zag of level moves and plunges of a flat mill along a tilted axis through a block: the exact sweep and the
  // verification's pose sweep leave the same stock to within the cusps the poses leave (and the exact one never more).
  const Mesh block = test::box(Vec3(0, 0, 0), Vec3(50, 50, 30));
  const DexelLattice lattice = DexelLattice::over(boundingBox(block), 1.0);
  const Part far = partFromMesh(test::box(Vec3(200, 200, 200), Vec3(201, 201, 201)), "far");
  const MeshDexels part(far.mesh, lattice);
  const PartDistance distance(far.mesh);
  const Tool tool = test::flat6();
  const std::map<std::string, ToolSolid> solids{{tool.id, toolSolid(tool)}};
  const Vec3 axis = Vec3(0.3, -0.2, 1).normalized(), d = axis.cross(Vec3::UnitY()).normalized(), e = axis.cross(d);
  const Vec3 start(40, 40, 20);  // the passes run towards -x, stepping towards -y
  Toolpath path;
  auto add = [&](const Vec3& tip) {
    CutterLocation c;
    c.tool = tool.id;
    c.tip = tip;
    c.axis = axis;
    path.push_back(c);
  };
  add(start + 12 * axis);
  add(start);  // a plunge
  for (int pass = 0; pass < 4; ++pass) {
    add(path.back().tip + (pass % 2 ? -30.0 : 30.0) * d);
    add(path.back().tip + 4 * e);
  }
  Stock posed = meshStock(MeshDexels(block, lattice));
  SweepOptions options;
  options.cusp_step = false;
  sweepToolpath(posed, part, distance, path, solids, options);
  std::vector<SweptCylinder> exact;
  for (std::size_t i = 1; i < path.size(); ++i)
    ASSERT_TRUE(sweptCylinders(solids.at(tool.id).pieces[0], {path[i - 1].tip, axis}, {path[i].tip, axis}, 0.1, exact))
        << i;
  ASSERT_EQ(exact.size(), path.size() - 1);  // level moves and a plunge: one exact solid each
  Stock swept = meshStock(MeshDexels(block, lattice));
  removeSweptCylinders(swept, exact);
  const double taken = 50 * 50 * 30 - swept.volume(), by_poses = 50 * 50 * 30 - posed.volume();
  EXPECT_GT(taken, 4000) << by_poses;
  EXPECT_GE(taken, by_poses - 1e-6);
  EXPECT_NEAR(taken, by_poses, 0.005 * taken);
}
