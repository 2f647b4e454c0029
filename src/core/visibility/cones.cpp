#include "art2part/visibility/cones.h"

#include <bitset>

namespace art2part {

Cone triangleCone(const VisibilityMap& map, int t) {
  const std::uint64_t* row = map.bits.row(t);
  return Cone(row, row + map.bits.wordsPerRow());
}

Cone commonCone(const VisibilityMap& map, const std::vector<int>& triangles) {
  Cone cone(map.bits.wordsPerRow(), ~std::uint64_t(0));
  if (triangles.empty()) return Cone(map.bits.wordsPerRow(), 0);
  for (int t : triangles) {
    const std::uint64_t* row = map.bits.row(t);
    for (std::size_t w = 0; w < cone.size(); ++w) cone[w] &= row[w];
  }
  return cone;
}

Cone unionCone(const VisibilityMap& map, const std::vector<int>& triangles) {
  Cone cone(map.bits.wordsPerRow(), 0);
  for (int t : triangles) {
    const std::uint64_t* row = map.bits.row(t);
    for (std::size_t w = 0; w < cone.size(); ++w) cone[w] |= row[w];
  }
  return cone;
}

int coneSize(const Cone& cone) {
  int n = 0;
  for (std::uint64_t w : cone) n += static_cast<int>(std::bitset<64>(w).count());
  return n;
}

bool coneHas(const Cone& cone, int d) { return (cone[d >> 6] >> (d & 63)) & 1u; }

double coneSolidAngle(const Cone& cone, const DirectionSet& directions) {
  std::vector<char> counted(directions.cells.size(), 0);
  double area = 0.0;
  for (int d = 0; d < directions.size(); ++d) {
    if (!coneHas(cone, d)) continue;
    const int c = directions.cell_of[d];
    if (counted[c]) continue;
    counted[c] = 1;
    area += directions.cell_area[c];
  }
  return area;
}

std::vector<double> coneSolidAngles(const VisibilityMap& map, const DirectionSet& directions) {
  std::vector<double> angles(map.triangles());
  for (int t = 0; t < map.triangles(); ++t) angles[t] = coneSolidAngle(triangleCone(map, t), directions);
  return angles;
}

std::vector<int> invisibleTriangles(const VisibilityMap& map) {
  std::vector<int> out;
  for (int t = 0; t < map.triangles(); ++t)
    if (map.bits.rowCount(t) == 0) out.push_back(t);
  return out;
}

std::vector<int> trianglesSeenPerDirection(const VisibilityMap& map) {
  std::vector<int> seen(map.directions(), 0);
  for (int t = 0; t < map.triangles(); ++t)
    for (int d = 0; d < map.directions(); ++d) seen[d] += map.bits.get(t, d);
  return seen;
}

}  // namespace art2part
