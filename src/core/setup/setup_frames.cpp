// The frame of a setup: z along the setup direction, x along the part's dominant straight feature across z (so the
// machine's axes run along the walls and holes of a prismatic part), origin on top of the part over its box centre.
#include <algorithm>
#include <cmath>

#include "art2part/common/angles.h"
#include "art2part/setup/setup_plan.h"
#include "art2part/sphere/special_directions.h"

namespace art2part {
namespace {

constexpr double kPerpendicularDeg = 2.0;  // a feature counts when it is within this of perpendicular to z
constexpr double kGroupDeg = 2.0;          // features this close (up to sign) are one direction

struct Feature {
  Vec3 direction;  // unit
  double weight;   // mm^2 for faces, mm for edges
};

// Plane normals and cylinder and cone axes, weighted by face area.
std::vector<Feature> faceFeatures(const Part& part) {
  std::vector<Feature> out;
  for (const Face& f : part.faces) {
    if (f.area <= 0.0) continue;
    if (f.type == SurfaceType::Plane && f.normal.norm() > 0.5) out.push_back({f.normal.normalized(), f.area});
    const bool axial = f.type == SurfaceType::Cylinder || f.type == SurfaceType::Cone;
    if (axial && f.axis.norm() > 0.5) out.push_back({f.axis.normalized(), f.area});
  }
  return out;
}

// Long straight sharp edges, weighted by length (the special directions' edge rule).
std::vector<Feature> edgeFeatures(const Part& part) {
  SpecialDirectionOptions options;
  options.plane_normals = false;
  options.cylinder_axes = false;
  std::vector<Feature> out;
  for (const SpecialDirection& s : specialDirections(part, options)) out.push_back({s.direction, s.weight});
  return out;
}

struct Group {
  Vec3 first;  // the heaviest member, projected across z
  Vec3 sum;    // weighted sum of the members, each turned to agree with `first`
  double weight;
};

// The heaviest group of features perpendicular to z, as a unit vector across z; zero when no feature is.
Vec3 dominantAcross(std::vector<Feature> features, const Vec3& z) {
  std::stable_sort(features.begin(), features.end(), [](const Feature& a, const Feature& b) {
    return a.weight > b.weight;
  });
  const double max_along = std::sin(kPerpendicularDeg * kPi / 180.0);
  const double min_cos = std::cos(kGroupDeg * kPi / 180.0);
  std::vector<Group> groups;
  for (const Feature& f : features) {
    if (std::abs(f.direction.dot(z)) > max_along) continue;
    const Vec3 p = (f.direction - f.direction.dot(z) * z).normalized();
    auto g = std::find_if(groups.begin(), groups.end(), [&](const Group& g) { return std::abs(g.first.dot(p)) >= min_cos; });
    if (g == groups.end()) {
      groups.push_back({p, f.weight * p, f.weight});
      continue;
    }
    g->sum += (g->first.dot(p) >= 0.0 ? 1.0 : -1.0) * f.weight * p;
    g->weight += f.weight;
  }
  const Group* best = nullptr;
  for (const Group& g : groups)
    if (!best || g.weight > best->weight) best = &g;
  return best ? Vec3(best->sum.normalized()) : Vec3(Vec3::Zero());
}

// The part-frame axis least aligned with z, across z: a frame for parts without straight features.
Vec3 fallbackAcross(const Vec3& z) {
  int axis = 0;
  for (int i = 1; i < 3; ++i)
    if (std::abs(z[i]) < std::abs(z[axis]) - 1e-12) axis = i;
  const Vec3 e = Vec3::Unit(axis);
  return (e - e.dot(z) * z).normalized();
}

// One of +-x, the same for both: the largest component positive (the first of equal ones).
Vec3 canonicalSign(const Vec3& x) {
  int axis = 0;
  for (int i = 1; i < 3; ++i)
    if (std::abs(x[i]) > std::abs(x[axis]) + 1e-9) axis = i;
  return x[axis] < 0.0 ? Vec3(-x) : x;
}

// Over the box centre, at the part's highest point along z.
Vec3 topOrigin(const Mesh& mesh, const Vec3& z) {
  if (mesh.vertices.empty()) return Vec3::Zero();
  double top = -std::numeric_limits<double>::infinity();
  for (const Vec3& v : mesh.vertices) top = std::max(top, v.dot(z));
  const Vec3 centre = boundingBox(mesh).center();
  return centre + (top - centre.dot(z)) * z;
}

}  // namespace

SetupFrame setupFrame(const Part& part, const Vec3& direction) {
  if (!direction.allFinite() || direction.norm() < 1e-12)
    throw InputError("a setup direction must be a finite non-zero vector");
  SetupFrame frame;
  frame.z = direction.normalized();
  Vec3 x = dominantAcross(faceFeatures(part), frame.z);
  if (x.isZero()) x = dominantAcross(edgeFeatures(part), frame.z);
  if (x.isZero()) x = fallbackAcross(frame.z);
  x = canonicalSign(x);
  frame.x = (x - x.dot(frame.z) * frame.z).normalized();
  frame.y = frame.z.cross(frame.x);
  frame.origin = topOrigin(part.mesh, frame.z);
  return frame;
}

}  // namespace art2part
