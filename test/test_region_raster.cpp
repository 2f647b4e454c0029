// Regions grown on a grid (region_raster.h) against a brute-force distance from every node to every region: random
// polygons, slivers thinner than the pitch between nodes, regions reaching past the grid, holes.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "art2part/finishing/region_raster.h"
#include "art2part/geometry/mesh.h"

using namespace art2part;

namespace {

// Distance from p to the region: 0 inside (even-odd over the rings), else to the nearest edge.
double distanceTo(const Region& region, const Point2& p) {
  bool inside = false;
  double nearest = std::numeric_limits<double>::infinity();
  for (const Ring& ring : regionRings(region))
    for (std::size_t k = 0; k < ring.size(); ++k) {
      const Point2 &a = ring[k], &b = ring[(k + 1) % ring.size()];
      if ((a.y() > p.y()) != (b.y() > p.y()) && p.x() < a.x() + (p.y() - a.y()) * (b.x() - a.x()) / (b.y() - a.y()))
        inside = !inside;
      const Point2 ab = b - a;
      const double t = ab.squaredNorm() > 0 ? std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0) : 0;
      nearest = std::min(nearest, (a + t * ab - p).norm());
    }
  return inside ? 0 : nearest;
}

Ring randomPolygon(std::mt19937& rng, const Point2& centre, double size) {
  std::uniform_real_distribution<double> unit(0, 1);
  const int n = 3 + static_cast<int>(unit(rng) * 8);
  Ring ring;
  for (int k = 0; k < n; ++k) {
    const double angle = 2 * M_PI * (k + 0.8 * unit(rng)) / n, radius = size * (0.3 + 0.7 * unit(rng));
    ring.push_back(centre + radius * Point2(std::cos(angle), std::sin(angle)));
  }
  return ring;
}

// A sliver: a thin rectangle at a random angle, narrower than the pitch.
Ring sliver(std::mt19937& rng, const Point2& centre, double width, double length) {
  std::uniform_real_distribution<double> unit(0, 1);
  const double angle = M_PI * unit(rng);
  const Point2 along(std::cos(angle), std::sin(angle)), across(-along.y(), along.x());
  return {centre - 0.5 * length * along - 0.5 * width * across, centre + 0.5 * length * along - 0.5 * width * across,
          centre + 0.5 * length * along + 0.5 * width * across, centre - 0.5 * length * along + 0.5 * width * across};
}

}  // namespace

TEST(RegionRaster, EveryNodeNearARegionHasItsHeightAndNoneFarFromIt) {
  std::mt19937 rng(20261128);
  std::uniform_real_distribution<double> unit(0, 1);
  const double slack = 1e-9;
  long checked = 0, raised = 0, slivers = 0;
  for (int instance = 0; instance < 40; ++instance) {
    NodeGrid grid;
    grid.pitch = 0.2 + 0.8 * unit(rng);
    grid.x0 = -5 + 10 * unit(rng);
    grid.y0 = -5 + 10 * unit(rng);
    grid.nx = 8 + static_cast<int>(unit(rng) * 30);
    grid.ny = 8 + static_cast<int>(unit(rng) * 30);
    const Point2 low(grid.x0 - 4, grid.y0 - 4);
    const Point2 span(grid.nx * grid.pitch + 8, grid.ny * grid.pitch + 8);  // regions may reach past the grid
    std::vector<Region> regions;
    std::vector<RegionAtHeight> levels;
    const int count = 1 + static_cast<int>(unit(rng) * 4);
    regions.reserve(count);
    for (int l = 0; l < count; ++l) {
      std::vector<Ring> rings;
      for (int k = 0, n = 1 + static_cast<int>(unit(rng) * 3); k < n; ++k) {
        const Point2 centre = low + Point2(unit(rng) * span.x(), unit(rng) * span.y());
        if (unit(rng) < 0.4) {
          rings.push_back(sliver(rng, centre, 0.05 * grid.pitch, 0.3 + 3 * grid.pitch * unit(rng)));
          ++slivers;
        } else {
          rings.push_back(randomPolygon(rng, centre, 0.5 + 4 * unit(rng)));
        }
      }
      Region region = regionFromPolygons(rings);
      if (unit(rng) < 0.3) {  // a hole
        const Point2 centre = low + Point2(unit(rng) * span.x(), unit(rng) * span.y());
        region = subtract(region, regionFromPolygons({randomPolygon(rng, centre, 2)}));
      }
      regions.push_back(region);
    }
    for (int l = 0; l < count; ++l) levels.push_back({&regions[l], -10 + 20 * unit(rng)});
    const std::vector<double> radii{0, 3 * unit(rng), 2 + 6 * unit(rng)};
    // Cells of the grid's pitch, or finer: the pitch over a whole number, or a size that rounds down to one.
    const int f = 1 + static_cast<int>(unit(rng) * 3);
    const double cell = instance % 2 == 0 ? grid.pitch / f : grid.pitch / (f + 0.4);
    const double q = grid.pitch / std::ceil(grid.pitch / cell - 1e-9);
    const auto maps = highestNear(grid, levels, radii, cell);
    ASSERT_EQ(maps.size(), radii.size());
    for (int j = 0; j < grid.ny; ++j)
      for (int i = 0; i < grid.nx; ++i) {
        const Point2 node(grid.x(i), grid.y(j));
        std::vector<double> distance;
        for (const Region& region : regions) distance.push_back(distanceTo(region, node));
        for (std::size_t r = 0; r < radii.size(); ++r) {
          double must = -std::numeric_limits<double>::infinity(), may = must;
          for (int l = 0; l < count; ++l) {
            if (distance[l] <= radii[r] - slack) must = std::max(must, levels[l].height);
            if (distance[l] <= radii[r] + std::sqrt(2.0) * q + slack) may = std::max(may, levels[l].height);
          }
          const double got = maps[r][grid.node(i, j)];
          ASSERT_GE(got, must) << "instance " << instance << " node " << i << "," << j << " radius " << radii[r];
          ASSERT_LE(got, may) << "instance " << instance << " node " << i << "," << j << " radius " << radii[r];
          ++checked;
          raised += got > -std::numeric_limits<double>::infinity();
        }
      }
  }
  EXPECT_GT(slivers, 20);
  EXPECT_GT(raised, checked / 10);  // the instances do reach the grids
}

TEST(RegionRaster, ASliverBetweenNodesCountsAtTheNodesBesideIt) {
  // A strip 0.05 mm wide between two columns of nodes a millimetre apart: no node lies inside it.
  NodeGrid grid{0, 0, 1, 5, 5};
  const Region strip = regionFromPolygons({{Point2(2.4, -1), Point2(2.45, -1), Point2(2.45, 6), Point2(2.4, 6)}});
  const auto maps = highestNear(grid, {{&strip, 7}}, {0.6}, 1);
  const auto fine = highestNear(grid, {{&strip, 7}}, {0.6}, 0.1);  // cells of 0.1 mm: within 0.6 + 0.14
  for (int j = 0; j < grid.ny; ++j) {
    EXPECT_EQ(maps[0][grid.node(2, j)], 7);  // 0.4 mm from the strip
    EXPECT_EQ(maps[0][grid.node(0, j)], -std::numeric_limits<double>::infinity());  // 2.4 mm: past 0.6 + 1.41
    EXPECT_EQ(fine[0][grid.node(2, j)], 7);
    EXPECT_EQ(fine[0][grid.node(3, j)], 7);  // 0.55 mm
    EXPECT_EQ(fine[0][grid.node(1, j)], -std::numeric_limits<double>::infinity());  // 1.4 mm
  }
}

TEST(RegionRaster, BadArgumentsAreRefused) {
  const Region none;
  EXPECT_THROW(highestNear(NodeGrid{0, 0, 0, 3, 3}, {{&none, 0}}, {1}, 1), InputError);
  EXPECT_THROW(highestNear(NodeGrid{0, 0, 1, 3, 3}, {{&none, 0}}, {-1}, 1), InputError);
  EXPECT_THROW(highestNear(NodeGrid{0, 0, 1, 3, 3}, {{&none, 0}}, {1}, 0), InputError);
}
