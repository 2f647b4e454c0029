// The Gaussian sphere: Algorithm 1's sampling, its neighbourhood graph, point location, and special directions.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>

#include "art2part/geometry/part.h"
#include "art2part/sphere/direction_set.h"
#include "art2part/sphere/special_directions.h"
#include "test_meshes.h"

using namespace art2part;

namespace {

const double kPi = 3.14159265358979323846;
const std::string kExample = std::string(ART2PART_SOURCE_DIR) + "/examples/nist_ctc_01_asme1_rd.stp";

// The three edge-plane tests of d against cell c (all >= 0 when c contains d).
std::array<double, 3> edgeTests(const DirectionSet& set, int c, const Vec3& d) {
  std::array<double, 3> out{};
  for (int e = 0; e < 3; ++e)
    out[e] = set.corners[set.cells[c][e]].cross(set.corners[set.cells[c][(e + 1) % 3]]).dot(d);
  return out;
}

void expectContains(const DirectionSet& set, int c, const Vec3& d) {
  ASSERT_GE(c, 0);
  ASSERT_LT(c, set.cellCount());
  for (double v : edgeTests(set, c, d)) EXPECT_GE(v, 0.0) << "cell " << c << " does not contain " << d.transpose();
}

int sharedCorners(const DirectionSet& set, int a, int b) {
  int n = 0;
  for (int i : set.cells[a])
    for (int j : set.cells[b]) n += i == j;
  return n;
}

using test::randomDirections;

bool hasDirection(const std::vector<SpecialDirection>& list, const Vec3& d, double tol = 1e-9) {
  for (const SpecialDirection& s : list)
    if ((s.direction - d).norm() < tol) return true;
  return false;
}

Part boxPart() { return partFromMesh(test::box(Vec3(0, 0, 0), Vec3(40, 30, 20)), "box"); }

}  // namespace

TEST(SampleSphere, CellCounts) {
  for (int level = 0; level <= 7; ++level) {
    EXPECT_EQ(sampleSphere(level, SphereBase::Tetrahedron).cellCount(), 4 << (2 * level)) << "level " << level;
    if (level <= 5) {
      EXPECT_EQ(sampleSphere(level, SphereBase::Icosahedron).cellCount(), 20 << (2 * level)) << "level " << level;
    }
  }
  EXPECT_THROW(sampleSphere(-1), std::invalid_argument);
}

TEST(SampleSphere, AreasSumToFourPiAndDirectionsAreCentroids) {
  for (SphereBase base : {SphereBase::Tetrahedron, SphereBase::Icosahedron})
    for (int level : {0, 1, 3, 6}) {
      const DirectionSet set = sampleSphere(level, base);
      double sum = 0.0;
      for (double a : set.cell_area) {
        EXPECT_GT(a, 0.0);
        sum += a;
      }
      EXPECT_NEAR(sum, 4.0 * kPi, 1e-9) << "level " << level;
      ASSERT_EQ(set.size(), set.cellCount());
      for (int c = 0; c < set.cellCount(); ++c) {
        EXPECT_NEAR(set.directions[c].norm(), 1.0, 1e-12);
        EXPECT_EQ(set.cell_of[c], c);
        EXPECT_EQ(set.special[c], 0);
        for (int k : set.cells[c]) EXPECT_NEAR(set.corners[k].norm(), 1.0, 1e-12);
      }
    }
  EXPECT_NEAR(sampleSphere(0).cell_area[0], kPi, 1e-12);  // a regular tetrahedron: four equal quarters
}

TEST(SampleSphere, LevelSevenAreasSumToFourPi) {
  const DirectionSet set = sampleSphere(7);
  double sum = 0.0;
  for (double a : set.cell_area) sum += a;
  EXPECT_NEAR(sum, 4.0 * kPi, 1e-9);
  // Midpoint subdivision of a tetrahedron is uneven (cells near its corners shrink, ratio about 6.6 from level 5);
  // the icosahedron stays within 1.31. These bounds catch a broken subdivision or area formula.
  EXPECT_LT(cellAreaRatio(set), 6.7);
  EXPECT_GT(cellAreaRatio(set), 6.4);
  EXPECT_LT(cellAreaRatio(sampleSphere(5, SphereBase::Icosahedron)), 1.31);
  EXPECT_NEAR(cellAreaRatio(sampleSphere(1)), 3.0, 1e-9);  // 3 corner cells and 1 middle cell per base face
}

TEST(SampleSphere, NeighbourhoodIsExactAndSymmetric) {
  for (SphereBase base : {SphereBase::Tetrahedron, SphereBase::Icosahedron}) {
    const DirectionSet set = sampleSphere(3, base);
    ASSERT_EQ(static_cast<int>(set.edge_neighbours.size()), set.cellCount());
    int nine = 0;
    for (int c = 0; c < set.cellCount(); ++c) {
      ASSERT_EQ(set.edge_neighbours[c].size(), 3u) << "cell " << c;
      for (int n : set.edge_neighbours[c]) {
        EXPECT_NE(n, c);
        EXPECT_EQ(sharedCorners(set, c, n), 2);
        const auto& back = set.edge_neighbours[n];
        EXPECT_NE(std::find(back.begin(), back.end(), c), back.end()) << c << " -> " << n << " not symmetric";
      }
      for (int n : set.vertex_neighbours[c]) {
        EXPECT_EQ(sharedCorners(set, c, n), 1);
        const auto& back = set.vertex_neighbours[n];
        EXPECT_NE(std::find(back.begin(), back.end(), c), back.end());
      }
      nine += set.vertex_neighbours[c].size() == 9;
    }
    EXPECT_GT(nine, set.cellCount() / 2);  // valence-6 corners everywhere but near the base corners
    // Every cell sharing a corner with c is either an edge or a vertex neighbour.
    const int c = 17;
    for (int o = 0; o < set.cellCount(); ++o) {
      const int s = sharedCorners(set, c, o);
      const auto& e = set.edge_neighbours[c];
      const auto& v = set.vertex_neighbours[c];
      if (o == c) continue;
      EXPECT_EQ(s == 2, std::find(e.begin(), e.end(), o) != e.end());
      EXPECT_EQ(s == 1, std::find(v.begin(), v.end(), o) != v.end());
    }
  }
}

TEST(SampleSphere, NeighboursOfADirection) {
  DirectionSet set = sampleSphere(2);
  const int d = 5;
  const std::vector<int> n = set.neighbours(d);
  EXPECT_EQ(n.size(), set.edge_neighbours[d].size() + set.vertex_neighbours[d].size());
  EXPECT_EQ(std::count(n.begin(), n.end(), d), 0);
  // An extra direction in cell 5 is a neighbour of 5 and of 5's neighbours, and has them as neighbours.
  set.directions.push_back(set.directions[d]);
  set.cell_of.push_back(d);
  set.special.push_back(1);
  const int extra = set.size() - 1;
  const std::vector<int> n5 = set.neighbours(d);
  EXPECT_NE(std::find(n5.begin(), n5.end(), extra), n5.end());
  const std::vector<int> ne = set.neighbours(extra);
  EXPECT_NE(std::find(ne.begin(), ne.end(), d), ne.end());
  EXPECT_EQ(ne.size(), n.size() + 1);
  const int e0 = set.edge_neighbours[d][0];
  const std::vector<int> ny = set.neighbours(e0);
  EXPECT_NE(std::find(ny.begin(), ny.end(), extra), ny.end());
}

TEST(CellContaining, CentroidsRandomEdgesAndCorners) {
  for (SphereBase base : {SphereBase::Tetrahedron, SphereBase::Icosahedron})
    for (int level : {0, 1, 4, 7}) {
      const DirectionSet set = sampleSphere(level, base);
      const int step = std::max(1, set.cellCount() / 5000);
      for (int c = 0; c < set.cellCount(); c += step) EXPECT_EQ(cellContaining(set, set.directions[c]), c);
      for (const Vec3& d : randomDirections(2000, 7 + level)) expectContains(set, cellContaining(set, d), d);
      // On an edge: the edge test is exactly antisymmetric, so one of its two cells passes strictly.
      for (int c = 0; c < set.cellCount(); c += step) {
        const Vec3 on_edge = (set.corners[set.cells[c][0]] + set.corners[set.cells[c][1]]).normalized();
        expectContains(set, cellContaining(set, on_edge), on_edge);
        // Exactly on a corner, any cell around it contains it.
        const int k = set.cells[c][2];
        const int found = cellContaining(set, set.corners[k]);
        const auto& fc = set.cells[found];
        EXPECT_TRUE(fc[0] == k || fc[1] == k || fc[2] == k) << "corner " << k << " level " << level;
      }
    }
}

TEST(CellContaining, AxisDirectionsOnTetrahedronCorners) {
  // The tetrahedron's edge midpoints are the six axis directions: corners of every level >= 1.
  const DirectionSet set = sampleSphere(4);
  for (int i = 0; i < 3; ++i)
    for (double s : {-1.0, 1.0}) {
      const Vec3 d = s * Vec3::Unit(i);
      expectContains(set, cellContaining(set, d), d);
    }
}

TEST(SpecialDirections, BoxGivesTheSixAxes) {
  const Part part = boxPart();
  const std::vector<SpecialDirection> special = specialDirections(part);
  ASSERT_EQ(special.size(), 6u);
  for (int i = 0; i < 3; ++i)
    for (double s : {-1.0, 1.0}) EXPECT_TRUE(hasDirection(special, s * Vec3::Unit(i))) << s * Vec3::Unit(i);
  for (size_t i = 1; i < special.size(); ++i) EXPECT_GE(special[i - 1].weight, special[i].weight);
  // Face area plus the four edges along each axis: +-z carries 40 x 30 and 4 x 20 mm of edges.
  for (const SpecialDirection& s : special) {
    if (std::abs(s.direction.z()) > 0.5) {
      EXPECT_NEAR(s.weight, 40.0 * 30.0 + 4 * 20.0, 1e-6);
    }
  }
}

TEST(SpecialDirections, BoxEdgesAloneGiveTheAxes) {
  SpecialDirectionOptions options;
  options.plane_normals = false;
  options.cylinder_axes = false;
  const std::vector<SpecialDirection> special = specialDirections(boxPart(), options);
  ASSERT_EQ(special.size(), 6u);
  EXPECT_NEAR(special[0].weight, 4 * 40.0, 1e-9);  // the four 40 mm edges along x, each sense
  EXPECT_NEAR(std::abs(special[0].direction.x()), 1.0, 1e-12);
  options.min_edge_fraction = 0.6;  // the diagonal is 53.9 mm: only the 40 mm edges (0.74) remain long
  EXPECT_EQ(specialDirections(boxPart(), options).size(), 2u);
}

TEST(SpecialDirections, NistCtc1HasTopBottomAndSides) {
  const Part part = loadPart(kExample);
  const std::vector<SpecialDirection> special = specialDirections(part);
  EXPECT_TRUE(hasDirection(special, Vec3(0, 0, 1), 1e-6));
  EXPECT_TRUE(hasDirection(special, Vec3(0, 0, -1), 1e-6));
  for (const Vec3& side : {Vec3(1, 0, 0), Vec3(-1, 0, 0), Vec3(0, 1, 0), Vec3(0, -1, 0)})
    EXPECT_TRUE(hasDirection(special, side, 1e-6)) << side.transpose();
  // Deduplicated: no two within the merge angle; heaviest first.
  const double min_cos = std::cos(SpecialDirectionOptions{}.merge_angle);
  for (size_t i = 0; i < special.size(); ++i) {
    EXPECT_NEAR(special[i].direction.norm(), 1.0, 1e-12);
    if (i > 0) {
      EXPECT_GE(special[i - 1].weight, special[i].weight);
    }
    for (size_t j = i + 1; j < special.size(); ++j) EXPECT_LT(special[i].direction.dot(special[j].direction), min_cos);
  }
  // Inserted, each one sits in the cell that contains it.
  DirectionSet set = sampleSphere(4);
  insertSpecialDirections(set, special);
  for (const SpecialDirection& s : special) {
    int found = -1;
    for (int i = 0; i < set.size(); ++i)
      if ((set.directions[i] - s.direction).norm() < 1e-12) found = i;
    ASSERT_GE(found, 0) << s.direction.transpose();
    EXPECT_TRUE(set.special[found]);
    expectContains(set, set.cell_of[found], s.direction);
  }
}

TEST(InsertSpecialDirections, ReplaceThenAppendThenSkip) {
  DirectionSet set = sampleSphere(3);
  const int cells = set.cellCount();
  const int c = 40;
  const Vec3 centroid = set.directions[c];
  // Two directions inside cell c (towards two of its corners) and a third one equal to the heavier.
  const Vec3 a = (3 * centroid + set.corners[set.cells[c][0]]).normalized();
  const Vec3 b = (3 * centroid + set.corners[set.cells[c][1]]).normalized();
  insertSpecialDirections(set, {{b, 1.0}, {a, 5.0}, {a, 0.5}});
  EXPECT_EQ(set.directions[c], a);  // the heavier replaces the centroid
  EXPECT_EQ(set.special[c], 1);
  ASSERT_EQ(set.size(), cells + 1);  // the lighter is appended, the repeat is not
  EXPECT_EQ(set.directions[cells], b);
  EXPECT_EQ(set.cell_of[cells], c);
  EXPECT_EQ(set.special[cells], 1);
  // Inserting the same list again changes nothing.
  insertSpecialDirections(set, {{b, 1.0}, {a, 5.0}});
  EXPECT_EQ(set.size(), cells + 1);
  // Box directions go into the cells that contain them.
  DirectionSet fresh = sampleSphere(4, SphereBase::Icosahedron);
  const std::vector<SpecialDirection> special = specialDirections(boxPart());
  insertSpecialDirections(fresh, special);
  EXPECT_EQ(fresh.size(), fresh.cellCount());
  EXPECT_EQ(std::count(fresh.special.begin(), fresh.special.end(), 1), 6);
  for (int d = 0; d < fresh.size(); ++d)
    if (fresh.special[d]) {
      EXPECT_TRUE(hasDirection(special, fresh.directions[d]));
      expectContains(fresh, fresh.cell_of[d], fresh.directions[d]);
    }
}
