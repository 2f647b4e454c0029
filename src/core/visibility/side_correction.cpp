#include "art2part/visibility/side_correction.h"

#include <algorithm>
#include <cmath>

namespace art2part {

std::vector<double> cellRadii(const DirectionSet& directions) {
  std::vector<double> radius(directions.size(), 0.0);
  for (int d = 0; d < directions.size(); ++d) {
    const auto& cell = directions.cells[directions.cell_of[d]];
    for (int corner : cell) {
      const double c = std::clamp(directions.directions[d].dot(directions.corners[corner]), -1.0, 1.0);
      radius[d] = std::max(radius[d], std::acos(c));
    }
  }
  return radius;
}

long long sideCorrection(VisibilityMap& map, const Mesh& mesh, const DirectionSet& directions) {
  const int D = directions.size();
  const std::vector<double> radius = cellRadii(directions);
  std::vector<double> max_cos(D);
  std::vector<std::vector<int>> neighbours(D);
  for (int d = 0; d < D; ++d) {
    max_cos[d] = std::sin(radius[d]);
    neighbours[d] = directions.neighbours(d);
  }
  const BitMatrix direct = map.bits;  // the neighbours' direct visibility, before any correction
  long long added = 0;
  for (int t = 0; t < mesh.triangleCount(); ++t) {
    const Vec3 n = triangleNormal(mesh, t);
    if (n.isZero()) continue;
    for (int o = 0; o < D; ++o) {
      if (direct.get(t, o) || std::abs(n.dot(directions.directions[o])) > max_cos[o]) continue;
      for (int other : neighbours[o])
        if (direct.get(t, other)) {
          map.bits.set(t, o);
          ++added;
          break;
        }
    }
  }
  return added;
}

}  // namespace art2part
