// Pass 2 of face segmentation, the test that drops a ruled region: bands of a torus or a sphere look like short
// cylinders and cones, told apart by how they end.
#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>

#include "segmentation_internal.h"

namespace art2part {
namespace segmentation {

namespace {

const double kAlongRuling = std::sqrt(0.5);  // an edge at less than 45 degrees to the ruling runs along it

Vec3 edgeVector(const Mesh& mesh, const std::pair<int, int>& e) {
  return mesh.vertices[e.second] - mesh.vertices[e.first];
}

// How the region ends, at its low and at its high end along the axis: the length of its end edges (across the
// rulings, to patches outside it), of those bending gently into small unfitted patches, and the corners of those.
struct RegionEnd {
  double all = 0.0, gentle = 0.0;
  std::vector<Vec3> gentle_corners;
};

std::array<RegionEnd, 2> regionEnds(const RegionContext& c, const RuledRegion& region, int id) {
  const Vec3& axis = region.surface.axis();
  double middle = 0.0;
  int count = 0;
  for (int p : region.patches)
    for (int v : c.patches[p].vertices) {
      middle += axis.dot(c.mesh.vertices[v]);
      ++count;
    }
  middle /= std::max(1, count);
  std::array<RegionEnd, 2> ends;
  for (int m : region.patches)
    for (int li : c.graph.links_of[m]) {
      const PatchLink& link = c.graph.links[li];
      const int s = link.other(m);
      if (c.region_of[s] == id) continue;
      const bool gentle = link.max_bend <= c.tol.max_bend && c.patches[s].size() < c.tol.min_plane_triangles;
      for (const auto& e : link.edges) {
        const Vec3 d = edgeVector(c.mesh, e), start = c.mesh.vertices[e.first];
        const double length = d.norm();
        if (std::abs(d.dot(region.surface.ruling(start))) > kAlongRuling * length) continue;  // a side
        RegionEnd& end = ends[axis.dot(start + 0.5 * d) > middle ? 1 : 0];
        end.all += length;
        if (!gentle) continue;
        end.gentle += length;
        end.gentle_corners.push_back(start);
        end.gentle_corners.push_back(start + d);
      }
    }
  return ends;
}

// Whether the corners of an end lie on a plane that leans from the plane square to the axis. Corners on a line
// (or too few) span no plane and do not lean.
bool leans(const std::vector<Vec3>& corners, const Vec3& axis, const Tolerances& tol) {
  if (corners.size() < 3) return false;
  Vec3 mean = Vec3::Zero();
  for (const Vec3& c : corners) mean += c / static_cast<double>(corners.size());
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const Vec3& c : corners) scatter += (c - mean) * (c - mean).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> spectrum(scatter);
  if (spectrum.eigenvalues()(1) <= 1e-6 * spectrum.eigenvalues()(2)) return false;
  // A band of a surface of revolution leans by half the bend between bands; two fillets mitred at a corner lean
  // by half the corner's angle, often more.
  const double tilt = std::acos(std::min(1.0, std::abs(spectrum.eigenvectors().col(0).dot(axis))));
  return tilt > tol.angle && tilt < 0.5 * tol.max_bend;
}

// A doubly curved surface of revolution (torus, sphere) tessellated in a grid falls apart into bands that bend
// gently into each other at both ends. A band between two meridians looks like a short cylinder that ends on
// meridian planes leaning from the plane square to its axis by half the band's angle, one each way; a cylinder
// running into corner blends ends on circles square to its axis (with perhaps a few facets of the blend that
// joined it), and one meeting another fillet leans at one end at most. A band between two parallels is a true
// cone frustum, told apart only by running into unfitted facets at both ends.
}  // namespace

bool bandOfRevolution(const RegionContext& c, const RuledRegion& region, int id) {
  for (const RegionEnd& end : regionEnds(c, region, id)) {
    const bool band_end = region.surface.is_cone ? end.gentle > 0.5 * end.all
                                                 : leans(end.gentle_corners, region.surface.axis(), c.tol);
    if (!band_end) return false;
  }
  return true;
}


}  // namespace segmentation
}  // namespace art2part
