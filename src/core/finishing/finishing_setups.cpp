// Setups added for finishing (finishing_setups.h).
#include "art2part/finishing/finishing_setups.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "art2part/common/angles.h"
#include "art2part/finishing/admissible.h"
#include "art2part/finishing/face_assignment.h"

namespace art2part {

namespace {

constexpr double kSameDirection = 0.01 * kPi / 180;  // a sampled direction this close is the face's own

// Whether a face's shape asks for a strategy its assignment does not give it from a direction that sees it whole.
bool wantsItsOwnDirection(const Part& part, const FaceAssignment& a) {
  const SurfaceType type = part.faces[a.face].type;
  if (type != SurfaceType::Plane && type != SurfaceType::Cylinder) return false;
  for (const FinishingChoice& c : a.choices)
    if (c.whole && (c.kind == FinishingKind::FaceMill || c.kind == FinishingKind::SideMill ||
                    c.kind == FinishingKind::Contour || c.hole >= 0))
      return false;
  return true;
}

}  // namespace

std::vector<Setup> finishingSetups(const Part& part, const VisibilityResult& visibility, const SetupPlan& setups,
                                   double longest_flutes, const FinishingOptions& options,
                                   const FinishingSetupOptions& setup_options) {
  std::vector<Setup> added;
  if (setup_options.max_setups <= 0) return added;
  const DirectionSet& directions = visibility.directions;
  const std::vector<FaceAssignment> assignment =
      assignFaces(part, visibility, setups, {}, {}, longest_flutes, options);
  const std::vector<std::vector<int>> triangles = faceTriangles(part);
  const double tolerance = options.planar.square_angle_deg * kPi / 180;
  double total_area = 0;
  for (const Face& f : part.faces) total_area += f.area;
  // Per wanting face, the sampled directions that would give it its own strategy and see it whole.
  std::vector<std::pair<int, std::vector<int>>> wanting;
  for (const FaceAssignment& a : assignment) {
    if (!wantsItsOwnDirection(part, a)) continue;
    const std::vector<int>& tris = triangles[a.face];
    if (tris.empty()) continue;
    const Cone seen = commonCone(visibility.map, tris);
    std::vector<int> serving;
    for (const AdmissibleSet& set : admissibleSets(part, a.face, tris)) {
      if (set.kind == FinishingKind::Surface3Axis) continue;
      if (set.freedom == Freedom::Zero) {
        for (const Vec3& d : {set.axis, Vec3(-set.axis)}) {
          if (d.dot(set.axis) < 0 && !set.both_senses) continue;
          const int i = sampledDirection(directions, d, kSameDirection);
          if (i >= 0 && coneHas(seen, i)) serving.push_back(i);
        }
      } else {  // side milling: the directions in the plane that see it, within the flutes
        for (int i = 0; i < directions.size(); ++i)
          if (admits(set, directions.directions[i], tolerance) && coneHas(seen, i) &&
              extentAlong(part.mesh, tris, directions.directions[i]) <= longest_flutes)
            serving.push_back(i);
      }
    }
    if (!serving.empty()) wanting.push_back({a.face, serving});
  }
  std::vector<char> served(part.faces.size(), 0);
  for (int round = 0; round < setup_options.max_setups; ++round) {
    std::map<int, double> area;  // direction -> area of the unserved faces it serves
    for (const auto& [face, serving] : wanting)
      if (!served[face])
        for (int i : serving) area[i] += part.faces[face].area;
    if (area.empty()) break;
    const auto best = std::max_element(area.begin(), area.end(),
                                       [](const auto& x, const auto& y) { return x.second < y.second; });
    if (best->second < setup_options.min_area_fraction * total_area) break;
    Setup s;
    s.direction = best->first;
    s.special = best->first < static_cast<int>(directions.special.size()) && directions.special[best->first];
    s.frame = setupFrame(part, directions.directions[best->first]);
    s.for_finishing = true;
    for (const auto& [face, serving] : wanting)
      if (!served[face] && std::find(serving.begin(), serving.end(), best->first) != serving.end()) {
        s.finishing_faces.push_back(face);
        served[face] = 1;
      }
    std::sort(s.finishing_faces.begin(), s.finishing_faces.end());
    for (int t = 0; t < visibility.map.triangles(); ++t) s.reachable_triangles += visibility.map.bits.get(t, s.direction);
    added.push_back(std::move(s));
  }
  return added;
}

}  // namespace art2part
