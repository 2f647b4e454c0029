// Volume visibility (thesis 3.2.5): the delta volume and the per-voxel cones against analytic answers (boxes, a
// slot) and an independent brute-force ray-triangle test.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "art2part/sphere/direction_set.h"
#include "art2part/visibility/volume_visibility.h"
#include "test_meshes.h"

using namespace art2part;
using art2part::test::append;
using art2part::test::box;

namespace {

struct Aabb {
  Vec3 lo, hi;
};

// Slab test: does the ray p + t d, t >= 0, meet the closed box grown by r on every side?
bool rayHitsBox(const Vec3& p, const Vec3& d, const Aabb& b, double r = 0) {
  double t0 = 0, t1 = std::numeric_limits<double>::infinity();
  for (int a = 0; a < 3; ++a) {
    const double lo = b.lo[a] - r, hi = b.hi[a] + r;
    if (std::abs(d[a]) < 1e-15) {
      if (p[a] < lo || p[a] > hi) return false;
      continue;
    }
    double ta = (lo - p[a]) / d[a], tb = (hi - p[a]) / d[a];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta), t1 = std::min(t1, tb);
    if (t0 > t1) return false;
  }
  return true;
}

bool escapesBoxes(const Vec3& p, const Vec3& d, const std::vector<Aabb>& boxes, double r = 0) {
  for (const Aabb& b : boxes)
    if (rayHitsBox(p, d, b, r)) return false;
  return true;
}

// Moller-Trumbore in double, every triangle: the independent reference.
bool escapesMesh(const Mesh& m, const Vec3& p, const Vec3& d) {
  for (int t = 0; t < m.triangleCount(); ++t) {
    const Vec3 &a = m.corner(t, 0), e1 = m.corner(t, 1) - a, e2 = m.corner(t, 2) - a;
    const Vec3 q = d.cross(e2);
    const double det = e1.dot(q);
    if (std::abs(det) < 1e-14) continue;
    const Vec3 s = p - a;
    const double u = s.dot(q) / det;
    if (u < 0 || u > 1) continue;
    const Vec3 r = s.cross(e1);
    const double v = d.dot(r) / det;
    if (v < 0 || u + v > 1) continue;
    if (e2.dot(r) / det > 0) return false;
  }
  return true;
}

// The ray and eight parallel ones at distance r around it all escape: the answer cannot hinge on a voxel-sized
// detail, so the voxel method must agree.
bool clearlyEscapesMesh(const Mesh& m, const Vec3& p, const Vec3& d, double r) {
  const Vec3 a = d.unitOrthogonal(), b = d.cross(a);
  for (int k = 0; k < 9; ++k) {
    const double angle = k * 3.14159265358979 / 4;
    const Vec3 o = k == 8 ? Vec3::Zero() : Vec3(r * (std::cos(angle) * a + std::sin(angle) * b));
    if (!escapesMesh(m, p + o, d)) return false;
  }
  return true;
}

Mesh boxesMesh(const std::vector<Aabb>& boxes) {
  Mesh m;
  for (const Aabb& b : boxes) append(m, box(b.lo, b.hi));
  return m;
}

VolumeVisibilityOptions unitVoxels(int threads = 2) {
  VolumeVisibilityOptions o;
  o.voxel_size = 1.0;
  o.margin = 5.0;
  o.threads = threads;
  return o;
}

// The voxel answer is one-sided (never "reachable" when the centre's ray is blocked) and exact when the ray stays
// more than 0.4 voxel from every box (the method's false blocks stay within a pixel diagonal, 0.35 voxel).
// Returns how many directions had to agree.
int checkAgainstBoxes(const VolumeVisibility& vv, const std::vector<Vec3>& dirs, const std::vector<Aabb>& boxes,
                      const Vec3& centre) {
  const int v = vv.grid.voxelAt(centre);
  EXPECT_GE(v, 0);
  EXPECT_TRUE(vv.outsidePart(v));
  EXPECT_NEAR((vv.grid.centre(v) - centre).norm(), 0, 1e-9) << "pick a voxel centre";
  int strict = 0;
  for (int d = 0; d < static_cast<int>(dirs.size()); ++d) {
    const bool exact = escapesBoxes(centre, dirs[d], boxes);
    if (vv.reachable(v, d)) {
      EXPECT_TRUE(exact) << "false reachable at " << centre.transpose() << " d " << d;
    }
    if (escapesBoxes(centre, dirs[d], boxes, 0.4 * vv.grid.voxel)) {
      ++strict;
      EXPECT_TRUE(vv.reachable(v, d)) << "false blocked at " << centre.transpose() << " d " << dirs[d].transpose();
    }
  }
  return strict;
}

}  // namespace

TEST(VolumeVisibility, BoxDeltaVolumeExcludesThePart) {
  const std::vector<Aabb> part = {{Vec3(0, 0, 0), Vec3(10, 10, 10)}};
  const VolumeVisibility vv = volumeVisibility(boxesMesh(part), sampleSphere(2).directions, unitVoxels());
  EXPECT_EQ(vv.grid.nx, 20);
  EXPECT_EQ(vv.grid.nz, 20);
  EXPECT_EQ(vv.deltaVoxels(), 20u * 20 * 20 - 1000);
  EXPECT_FALSE(vv.outsidePart(vv.grid.voxelAt(Vec3(5.5, 5.5, 5.5))));
  EXPECT_FALSE(vv.outsidePart(vv.grid.voxelAt(Vec3(0.5, 9.5, 0.5))));
  EXPECT_TRUE(vv.outsidePart(vv.grid.voxelAt(Vec3(-0.5, 5.5, 5.5))));
  EXPECT_TRUE(vv.outsidePart(vv.grid.voxelAt(Vec3(5.5, 5.5, 10.5))));
}

TEST(VolumeVisibility, VoxelsAroundABoxMatchTheAnalyticRay) {
  const std::vector<Aabb> part = {{Vec3(0, 0, 0), Vec3(10, 10, 10)}};
  const DirectionSet set = sampleSphere(3);
  const VolumeVisibility vv = volumeVisibility(boxesMesh(part), set.directions, unitVoxels());
  // Just above the top face, well above it, above a corner, beside a side face, below and off a corner.
  for (const Vec3& c : {Vec3(5.5, 5.5, 10.5), Vec3(5.5, 5.5, 14.5), Vec3(0.5, 9.5, 11.5), Vec3(12.5, 5.5, 5.5),
                        Vec3(-3.5, -3.5, -3.5)}) {
    EXPECT_GT(checkAgainstBoxes(vv, set.directions, part, c), set.size() / 3) << c.transpose();
  }
  // Right above the middle of the top face every upward direction is clear and no downward one is.
  const int v = vv.grid.voxelAt(Vec3(5.5, 5.5, 10.5));
  for (int d = 0; d < set.size(); ++d)
    if (std::abs(set.directions[d].z()) > 0.2) {
      EXPECT_EQ(vv.reachable(v, d), set.directions[d].z() > 0) << d;
    }
}

TEST(VolumeVisibility, BottomOfASlotSeesOnlyItsOpening) {
  // Two blocks on a base leave a slot 8 wide and 10 deep along y.
  const std::vector<Aabb> part = {{Vec3(0, 0, -5), Vec3(30, 20, 0)},
                                  {Vec3(0, 0, 0), Vec3(10, 20, 10)},
                                  {Vec3(18, 0, 0), Vec3(30, 20, 10)}};
  const DirectionSet set = sampleSphere(3);
  const VolumeVisibility vv = volumeVisibility(boxesMesh(part), set.directions, unitVoxels());
  const Vec3 bottom(12.5, 10.5, 0.5);
  EXPECT_GT(checkAgainstBoxes(vv, set.directions, part, bottom), set.size() / 8);
  const int v = vv.grid.voxelAt(bottom);
  int up_seen = 0, up_blocked = 0;
  for (int d = 0; d < set.size(); ++d) {
    const Vec3& dir = set.directions[d];
    if (dir.z() <= 0) continue;
    // Leaving through the top needs the ray within the walls 2.5 to the left and 5.5 to the right over 9.5 up,
    // or it leaves through an open end of the slot first (along y, 9.5 either way).
    const double t_top = 9.5 / dir.z(), t_end = 9.5 / std::max(std::abs(dir.y()), 1e-12);
    const double x_at_exit = bottom.x() + dir.x() * std::min(t_top, t_end);
    const bool opening = x_at_exit > 10 && x_at_exit < 18;
    ++(vv.reachable(v, d) ? up_seen : up_blocked);
    if (vv.reachable(v, d)) {
      EXPECT_TRUE(opening) << dir.transpose();
    }
    if (x_at_exit > 10.5 && x_at_exit < 17.5) {
      EXPECT_TRUE(vv.reachable(v, d)) << dir.transpose();
    }
  }
  EXPECT_GT(up_seen, 3);
  EXPECT_GT(up_blocked, 3);
}

TEST(VolumeVisibility, RandomPairsAgreeWithBruteForceRays) {
  Mesh part = boxesMesh({{Vec3(0, 0, -5), Vec3(30, 20, 0)},
                         {Vec3(0, 0, 0), Vec3(10, 20, 10)},
                         {Vec3(18, 0, 0), Vec3(30, 20, 10)}});
  // A tilted block over the right one, so that faces are not axis-aligned.
  Mesh tilted = box(Vec3(-3, -3, -3), Vec3(3, 3, 3));
  const Eigen::Matrix3d turn = Eigen::AngleAxisd(0.6, Vec3(1, 2, 0.5).normalized()).toRotationMatrix();
  for (Vec3& p : tilted.vertices) p = turn * p + Vec3(24, 10, 16);
  append(part, tilted);
  const DirectionSet set = sampleSphere(3);
  const VolumeVisibility vv = volumeVisibility(part, set.directions, unitVoxels());
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> any_voxel(0, static_cast<int>(vv.grid.size()) - 1), any_dir(0, set.size() - 1);
  int pairs = 0, clear = 0, reachable = 0;
  while (pairs < 200) {
    const int v = any_voxel(rng), d = any_dir(rng);
    if (!vv.outsidePart(v)) continue;
    ++pairs;
    const Vec3 c = vv.grid.centre(v), dir = set.directions[d];
    const bool got = vv.reachable(v, d);
    reachable += got;
    if (got) {
      EXPECT_TRUE(escapesMesh(part, c, dir)) << "false reachable " << c.transpose() << " / " << dir.transpose();
    }
    if (clearlyEscapesMesh(part, c, dir, vv.grid.voxel)) {
      ++clear;
      EXPECT_TRUE(got) << "false blocked " << c.transpose() << " / " << dir.transpose();
    }
  }
  EXPECT_GT(clear, 60);  // the check is not vacuous
  EXPECT_GT(reachable, 60);
}

TEST(VolumeVisibility, SameResultOnOneAndTwoThreadsAndCompact) {
  const Mesh part = boxesMesh({{Vec3(0, 0, 0), Vec3(10, 20, 10)}, {Vec3(14, 0, 0), Vec3(20, 20, 6)}});
  const std::vector<Vec3> dirs = sampleSphere(3).directions;
  const VolumeVisibility one = volumeVisibility(part, dirs, unitVoxels(1));
  const VolumeVisibility two = volumeVisibility(part, dirs, unitVoxels(2));
  EXPECT_EQ(one.cone_of_voxel, two.cone_of_voxel);
  EXPECT_EQ(one.cone_words, two.cone_words);
  // Never more than the index beyond a bitset per voxel (the cones barely repeat this close to a small part).
  EXPECT_LE(one.bytes(), one.grid.size() * (4 + dirs.size() / 8));
  EXPECT_EQ(one.cone(one.cone_of_voxel[0]).size(), dirs.size() / 64);
}

TEST(VolumeVisibility, RefusesAGridTooFine) {
  VolumeVisibilityOptions o;
  o.voxel_size = 0.01;
  try {
    volumeVisibility(box(Vec3(0, 0, 0), Vec3(100, 100, 100)), sampleSphere(1).directions, o);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("voxel size 0.01"), std::string::npos) << e.what();
  }
  o.voxel_size = 0;
  EXPECT_THROW(volumeVisibility(box(Vec3(0, 0, 0), Vec3(1, 1, 1)), {}, o), InputError);
}
