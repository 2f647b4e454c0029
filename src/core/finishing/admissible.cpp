#include "art2part/finishing/admissible.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

namespace art2part {

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();
// Normals closer than this (radians) count as one for the 2-DOF test: the test then errs by at most this much.
constexpr double kNormalMerge = 0.008;

void addDistinct(std::map<std::array<long, 3>, Vec3>& cells, const Vec3& n) {
  if (n.squaredNorm() < 0.5) return;
  const std::array<long, 3> key{std::lround(n.x() / kNormalMerge), std::lround(n.y() / kNormalMerge),
                                std::lround(n.z() / kNormalMerge)};
  cells.emplace(key, n);
}

std::vector<Vec3> values(const std::map<std::array<long, 3>, Vec3>& cells) {
  std::vector<Vec3> out;
  out.reserve(cells.size());
  for (const auto& [key, n] : cells) out.push_back(n);
  return out;
}

std::vector<Vec3> distinctNormals(const Mesh& mesh, const std::vector<int>& triangles) {
  std::map<std::array<long, 3>, Vec3> cells;
  for (int t : triangles) addDistinct(cells, triangleNormal(mesh, t));
  return values(cells);
}

}  // namespace

bool admits(const AdmissibleSet& set, const Vec3& d, double tolerance) {
  switch (set.freedom) {
    case Freedom::Zero: {
      const double c = set.axis.dot(d);
      return c >= std::cos(tolerance) || (set.both_senses && -c >= std::cos(tolerance));
    }
    case Freedom::One:
      return std::abs(set.axis.dot(d)) <= std::sin(tolerance);
    case Freedom::Two:
      if (set.normals.empty()) return false;
      for (const Vec3& n : set.normals)
        if (n.dot(d) < -std::sin(tolerance + kNormalMerge)) return false;
      return true;
  }
  return false;
}

std::vector<AdmissibleSet> admissibleSets(const Part& part, int face, const std::vector<int>& triangles) {
  std::vector<AdmissibleSet> sets;
  const Face& f = part.faces.at(face);
  if (f.type == SurfaceType::Plane && f.normal.norm() > 0.5) {
    AdmissibleSet mill;
    mill.kind = FinishingKind::FaceMill;
    mill.freedom = Freedom::Zero;
    mill.axis = f.normal.normalized();
    sets.push_back(mill);
    AdmissibleSet side = mill;
    side.kind = FinishingKind::SideMill;
    side.freedom = Freedom::One;
    sets.push_back(side);
  }
  if (f.type == SurfaceType::Cylinder && f.axis.norm() > 0.5) {
    AdmissibleSet contour;
    contour.kind = FinishingKind::Contour;
    contour.freedom = Freedom::Zero;
    contour.axis = f.axis.normalized();
    contour.both_senses = true;
    sets.push_back(contour);
  }
  AdmissibleSet surface;
  surface.kind = FinishingKind::Surface3Axis;
  surface.freedom = Freedom::Two;
  surface.normals = distinctNormals(part.mesh, triangles);
  sets.push_back(surface);
  return sets;
}

Cone admissibleCone(const AdmissibleSet& set, const DirectionSet& directions, double tolerance) {
  Cone cone((directions.size() + 63) / 64, 0);
  for (int d = 0; d < directions.size(); ++d)
    if (admits(set, directions.directions[d], tolerance)) cone[d >> 6] |= std::uint64_t(1) << (d & 63);
  return cone;
}

Cone permissibleCone(const AdmissibleSet& set, const DirectionSet& directions, const Cone& accessible,
                     double tolerance) {
  Cone cone = admissibleCone(set, directions, tolerance);
  for (std::size_t w = 0; w < cone.size() && w < accessible.size(); ++w) cone[w] &= accessible[w];
  return cone;
}

std::vector<EdgeCondition> edgeConditions(const Part& part, int face, const std::vector<int>& triangles) {
  std::map<int, EdgeCondition> by_neighbour;
  std::map<int, std::pair<std::map<std::array<long, 3>, Vec3>, std::map<std::array<long, 3>, Vec3>>> normals;
  for (int t : triangles) {
    for (int e = 0; e < 3; ++e) {
      const int u = part.adjacency.neighbour[t][e];
      const int g = u >= 0 && u < static_cast<int>(part.triangle_face.size()) ? part.triangle_face[u] : -1;
      if (u >= 0 && g == face) continue;
      EdgeCondition& edge = by_neighbour[g];
      edge.neighbour = g;
      const double length = (part.mesh.corner(t, (e + 1) % 3) - part.mesh.corner(t, e)).norm();
      edge.length_mm += length;
      addDistinct(normals[g].first, triangleNormal(part.mesh, t));
      if (u >= 0) addDistinct(normals[g].second, triangleNormal(part.mesh, u));
      const EdgeClass k = part.adjacency.klass[t][e];
      // The edge's class is its sharpest stretch: concave over convex over smooth.
      if (k == EdgeClass::Concave || (k == EdgeClass::Convex && edge.klass != EdgeClass::Concave) ||
          (edge.klass == EdgeClass::Smooth && k != EdgeClass::Smooth))
        edge.klass = k;
    }
  }
  std::vector<EdgeCondition> out;
  for (auto& [g, edge] : by_neighbour) {
    edge.normals = values(normals[g].first);
    edge.neighbour_normals = values(normals[g].second);
    out.push_back(edge);
  }
  std::sort(out.begin(), out.end(), [](const EdgeCondition& a, const EdgeCondition& b) { return a.length_mm > b.length_mm; });
  return out;
}

bool flatMillMakesEdge(const EdgeCondition& edge, const Vec3& d, double tolerance) {
  if (edge.klass != EdgeClass::Concave) return true;
  const double s = std::sin(tolerance + kNormalMerge);
  auto tangent = [&](const std::vector<Vec3>& normals) {
    return !normals.empty() &&
           std::all_of(normals.begin(), normals.end(), [&](const Vec3& n) { return std::abs(n.dot(d)) <= s; });
  };
  return tangent(edge.normals) || tangent(edge.neighbour_normals);
}

double concaveRadius(const Part& part, int face, const std::vector<int>& triangles) {
  const Face& f = part.faces.at(face);
  switch (f.type) {
    case SurfaceType::Plane:
      return kInfinity;
    case SurfaceType::Cylinder:
    case SurfaceType::Sphere:
      return f.concave ? f.radius : kInfinity;
    case SurfaceType::Torus:
      return f.concave ? std::min(f.minor_radius, f.radius > 0 ? f.radius : kInfinity) : kInfinity;
    case SurfaceType::Cone:
      return kInfinity;  // a straight line along the surface: a concave cone is made by any tool along its rulings
    case SurfaceType::Other:
      break;
  }
  // Mesh estimate: across each edge inside the face that bends concave, the radius of the circle through the two
  // triangles' centroids tangent to both: distance between centroids / the angle between the normals.
  double least = kInfinity;
  for (int t : triangles) {
    for (int e = 0; e < 3; ++e) {
      const int u = part.adjacency.neighbour[t][e];
      if (u < 0 || u < t || part.triangle_face[u] != face) continue;
      const double angle = part.adjacency.dihedral[t][e];
      if (angle >= -1e-6) continue;  // convex or flat
      const double gap = (triangleCentroid(part.mesh, t) - triangleCentroid(part.mesh, u)).norm();
      least = std::min(least, gap / -angle);
    }
  }
  return least;
}

int sampledDirection(const DirectionSet& directions, const Vec3& d, double tolerance) {
  int best = -1;
  double best_dot = std::cos(tolerance);
  for (int i = 0; i < directions.size(); ++i) {
    const double c = directions.directions[i].dot(d);
    if (c >= best_dot) best_dot = c, best = i;
  }
  return best;
}

double extentAlong(const Mesh& mesh, const std::vector<int>& triangles, const Vec3& d) {
  double lo = 1e300, hi = -1e300;
  for (int t : triangles)
    for (int c = 0; c < 3; ++c) {
      const double z = mesh.corner(t, c).dot(d);
      lo = std::min(lo, z);
      hi = std::max(hi, z);
    }
  return triangles.empty() ? 0.0 : hi - lo;
}

}  // namespace art2part
