// After pass 2 of face segmentation: cylinders that are pieces of an extruded free-form profile. A tessellation cuts
// an extruded spline into strips just like a cylinder, and over a few strips the spline fits a circle within the
// tolerance, so pass 2 finds a chain of short cylinders of changing radius. Such a piece runs on into further curved
// strips of the same extrusion on both of its sides, strips that are not on its circle; a cylinder face of a B-rep
// ends at a sharp edge, at a plane, or on one side at most at another curved face.
#include <algorithm>
#include <cmath>

#include "segmentation_internal.h"

namespace art2part {
namespace segmentation {

namespace {

const double kAlongRuling = std::sqrt(0.5);  // an edge at less than 45 degrees to the ruling runs along it
constexpr double kExactFit = 0.01;      // of the fine tolerance: a region fitting this closely is a true circle
constexpr double kSimilarRadius = 0.1;  // relative difference of two cylinders' radii (and axes, rad) still alike

// Whether two cylinders are near one circle: pieces of one cylinder whose fits, each over a few strips with
// corners off by the B-rep's edge tolerance, stayed too far apart to be merged.
bool similarCircle(const RuledRegion& a, const RuledRegion& b) {
  if (a.surface.is_cone || b.surface.is_cone) return false;
  const CylinderSurface &p = a.surface.cylinder, &q = b.surface.cylinder;
  const Vec3 d = q.point - p.point;
  const double scale = kSimilarRadius * std::max(p.radius, q.radius);
  return std::abs(p.axis.dot(q.axis)) >= std::cos(kSimilarRadius) && std::abs(p.radius - q.radius) <= scale &&
         (d - p.axis * p.axis.dot(d)).norm() <= scale;
}

// Whether patch s, across a side of the region, continues the extrusion with a curve other than the region's: a
// small strip (or one of another region) square to the axis, not on the region's circle.
bool curvedContinuation(const RegionContext& c, const std::vector<RuledRegion>& regions, const RuledRegion& region,
                        int s) {
  const PlanarPatch& patch = c.patches[s];
  if (patch.degenerate()) return false;
  const int other = c.region_of[s];
  if (other < 0 && patch.size() >= c.tol.min_plane_triangles) return false;  // a plane
  const Vec3& axis = region.surface.axis();
  if (std::abs(patch.normal.dot(axis)) > std::sin(c.tol.angle + patch.normal_slack)) return false;
  if (other >= 0) return !similarCircle(regions[other], region);
  for (int v : patch.vertices)
    if (region.surface.distance(c.mesh.vertices[v]) > region.tolerance) return true;
  // Corners on the circle but turned from it: the strip of a neighbouring curve, which the circle still holds over
  // so short a piece.
  const Vec3 outward = (region.concave ? -1.0 : 1.0) * region.surface.normal(patch.centroid());
  return std::acos(std::min(1.0, patch.normal.dot(outward))) > c.tol.angle + patch.normal_slack;
}

double worstResidual(const RegionContext& c, const RuledRegion& region) {
  double worst = 0.0;
  for (int p : region.patches)
    for (int v : c.patches[p].vertices) worst = std::max(worst, region.surface.distance(c.mesh.vertices[v]));
  return worst;
}

// Whether the region runs on into other curved strips on both of its sides (around the axis).
bool continuesOnBothSides(const RegionContext& c, const std::vector<RuledRegion>& regions, int id) {
  const RuledRegion& region = regions[id];
  const Vec3& axis = region.surface.axis();
  Vec3 middle = Vec3::Zero();
  double area = 0.0;
  for (int p : region.patches) {
    middle += c.patches[p].moment;
    area += c.patches[p].area;
  }
  if (!(area > 0.0)) return false;
  const Vec3 reference = region.surface.radial(middle / area), side = axis.cross(reference);
  bool low = false, high = false;
  for (int p : region.patches)
    for (int li : c.graph.links_of[p]) {
      const PatchLink& link = c.graph.links[li];
      const int s = link.other(p);
      if (c.region_of[s] == id || link.max_bend > c.tol.max_bend) continue;
      const std::pair<int, int>& e = link.edges.front();
      const Vec3 d = c.mesh.vertices[e.second] - c.mesh.vertices[e.first];
      if (std::abs(d.dot(axis)) < kAlongRuling * d.norm()) continue;  // an end, not a side
      if (!curvedContinuation(c, regions, region, s)) continue;
      const double azimuth = region.surface.radial(c.mesh.vertices[e.first]).dot(side);
      (azimuth < 0.0 ? low : high) = true;
    }
  return low && high;
}

}  // namespace

std::vector<char> releaseProfilePieces(const RegionContext& c, std::vector<RuledRegion>& regions,
                                       std::vector<int>& ruled_of) {
  std::vector<char> release(regions.size(), 0);
  for (int r = 0; r < static_cast<int>(regions.size()); ++r) {
    const RuledRegion& region = regions[r];
    if (region.surface.is_cone) continue;
    // A cylinder of a CAD tessellation fits its strips to rounding; a piece of a spline only within the tolerance.
    release[r] = worstResidual(c, region) > kExactFit * c.tol.fine_distance && continuesOnBothSides(c, regions, r);
  }
  std::vector<char> freed(ruled_of.size(), 0);
  for (int r = 0; r < static_cast<int>(regions.size()); ++r) {
    if (!release[r]) continue;
    for (int p : regions[r].patches) {
      ruled_of[p] = -1;
      freed[p] = 1;
    }
    regions[r].patches.clear();
  }
  return freed;
}

}  // namespace segmentation
}  // namespace art2part
