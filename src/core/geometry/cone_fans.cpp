// Seeds for pass 2 of face segmentation: cones tessellated as a fan of strips round their apex (a drill point, the
// tip of a countersink that reaches its axis). Three neighbouring strips of such a fan fit a cylinder nearly as well
// as a cone, so the generic seeds cut the fan into pieces; the whole fan, fitted at once, leaves no doubt.
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "segmentation_internal.h"

namespace art2part {
namespace segmentation {

namespace {

constexpr int kMinFanPatches = 6;                         // strips round an apex before it counts as a fan
constexpr double kMaxConeHalfAngle = 80.0 * kPi / 180.0;  // flatter cones cannot be told from planes

// Patches with a corner at each vertex.
std::vector<std::vector<int>> patchesAtVertices(const Mesh& mesh, const std::vector<PlanarPatch>& patches) {
  std::vector<std::vector<int>> at(mesh.vertices.size());
  for (int p = 0; p < static_cast<int>(patches.size()); ++p)
    if (!patches[p].degenerate())
      for (int v : patches[p].vertices) at[v].push_back(p);
  return at;
}

// The cone whose tangent planes are the patches' planes. Every tangent plane of a cone passes through its apex, so
// the apex is the point nearest to all the planes (least squares); every normal makes one angle with the axis, so
// the axis is the direction along which the normals vary least. False when the planes do not make a cone.
bool coneFromPlanes(const std::vector<PlanarPatch>& patches, const std::vector<int>& fan, ConeSurface& cone,
                    bool& concave) {
  Eigen::Matrix3d planes = Eigen::Matrix3d::Zero(), spread = Eigen::Matrix3d::Zero();
  Vec3 rhs = Vec3::Zero(), mean_normal = Vec3::Zero(), middle = Vec3::Zero();
  double weight = 0.0;
  for (int p : fan) {
    const PlanarPatch& patch = patches[p];
    planes += patch.area * patch.normal * patch.normal.transpose();
    rhs += patch.area * patch.normal * patch.offset;
    mean_normal += patch.area * patch.normal;
    middle += patch.area * patch.centroid();
    weight += patch.area;
  }
  if (!(weight > 0.0)) return false;
  mean_normal /= weight;
  middle /= weight;
  for (int p : fan) {
    const Vec3 d = patches[p].normal - mean_normal;
    spread += patches[p].area * d * d.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> plane_spectrum(planes), normal_spectrum(spread);
  // Normals all in one plane or along one line: the planes meet in a line (a cylinder, a fold), not a point.
  if (plane_spectrum.eigenvalues()(0) <= 1e-6 * plane_spectrum.eigenvalues()(2)) return false;
  if (normal_spectrum.eigenvalues()(1) <= 1e-6 * weight) return false;
  cone.apex = planes.ldlt().solve(rhs);
  Vec3 axis = normal_spectrum.eigenvectors().col(0).normalized();
  if (axis.dot(middle - cone.apex) < 0.0) axis = -axis;  // from the apex into the cone
  cone.axis = axis;
  const double along = axis.dot(mean_normal);  // sin(half angle): + inside a hole, - on a point
  concave = along > 0.0;
  cone.half_angle = std::asin(std::min(1.0, std::abs(along)));
  return cone.apex.allFinite() && cone.half_angle > 0.0;
}

// Whether the patch is a strip of the cone: its normal at the cone's angle to the axis, its corners on the cone.
bool stripOf(const Mesh& mesh, const PlanarPatch& patch, const ConeSurface& cone, bool concave, const Tolerances& tol) {
  const double expected = (concave ? 1.0 : -1.0) * std::sin(cone.half_angle);
  if (std::abs(patch.normal.dot(cone.axis) - expected) > std::sin(tol.angle + patch.normal_slack)) return false;
  for (int v : patch.vertices)
    if (distanceToCone(cone, mesh.vertices[v]) > tol.distance) return false;
  return true;
}

// The fan round vertex v as a cone, or nothing.
bool fanAt(const Mesh& mesh, const std::vector<PlanarPatch>& patches, const Tolerances& tol, int v,
           const std::vector<int>& fan, RuledRegion& region) {
  ConeSurface cone;
  bool concave = false;
  if (!coneFromPlanes(patches, fan, cone, concave)) return false;
  if (cone.half_angle < tol.angle || cone.half_angle > kMaxConeHalfAngle) return false;
  if ((cone.apex - mesh.vertices[v]).norm() > tol.distance) return false;  // the fan's vertex is its apex
  for (int p : fan)
    if (!stripOf(mesh, patches[p], cone, concave, tol)) return false;
  region = RuledRegion();
  region.patches = fan;
  region.surface.is_cone = true;
  region.surface.cone = cone;
  region.concave = concave;
  return true;
}

}  // namespace

std::vector<RuledRegion> findConeFans(const Mesh& mesh, const std::vector<PlanarPatch>& patches,
                                      const Tolerances& tol) {
  const std::vector<std::vector<int>> at = patchesAtVertices(mesh, patches);
  std::vector<char> taken(patches.size(), 0);
  std::vector<RuledRegion> fans;
  for (int v = 0; v < static_cast<int>(at.size()); ++v) {
    if (static_cast<int>(at[v].size()) < kMinFanPatches) continue;
    bool free = true;
    for (int p : at[v]) free = free && !taken[p];
    RuledRegion region;
    if (!free || !fanAt(mesh, patches, tol, v, at[v], region)) continue;
    for (int p : at[v]) taken[p] = 1;
    fans.push_back(std::move(region));
  }
  return fans;
}

}  // namespace segmentation
}  // namespace art2part
