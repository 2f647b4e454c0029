#include "visibility_markers.h"

#include "marker_helpers.h"

#include <algorithm>

#include "art2part/render/palette.h"
#include "part_conversions.h"

namespace art2part {

namespace {

constexpr double kFourPi = 4.0 * 3.14159265358979323846;


visualization_msgs::Marker directionSphere(const Part& part, const VisibilityResult& r, const std::string& frame) {
  const Box& box = part.check.box;
  const double radius = 0.25 * box.diagonal();
  const Vec3 centre = box.max + Vec3(radius * 1.3, 0, 0) - Vec3(0, 0.5 * box.size().y(), 0.5 * box.size().z());
  auto m = baseMarker(frame, "direction_sphere", 0, visualization_msgs::Marker::SPHERE_LIST);
  m.scale.x = m.scale.y = m.scale.z = 0.06 * radius * kMetresPerMm;
  const std::vector<int> seen = trianglesSeenPerDirection(r.map);
  const int most = std::max(1, *std::max_element(seen.begin(), seen.end()));
  for (int d = 0; d < r.directions.size(); ++d) {
    m.points.push_back(toPointMsg(centre + radius * r.directions.directions[d]));
    m.colors.push_back(r.directions.special[d] ? toColour({1.0f, 0.2f, 0.2f})
                                               : toColour(rampColour(static_cast<double>(seen[d]) / most)));
  }
  return m;
}

visualization_msgs::Marker partByConeSize(const Part& part, const VisibilityResult& r, const std::string& frame) {
  auto m = baseMarker(frame, "part_by_cone", 0, visualization_msgs::Marker::TRIANGLE_LIST);
  const std::vector<double> angles = coneSolidAngles(r.map, r.directions);
  for (int t = 0; t < part.mesh.triangleCount(); ++t) {
    // A cone of a whole hemisphere (2 pi) is as open as a face gets.
    const Rgb c = angles[t] <= 0.0 ? Rgb{0.9f, 0.1f, 0.1f} : rampColour(angles[t] / (0.5 * kFourPi));
    for (int k = 0; k < 3; ++k) {
      m.points.push_back(toPointMsg(part.mesh.corner(t, k)));
      m.colors.push_back(toColour(c));
    }
  }
  return m;
}

}  // namespace

visualization_msgs::MarkerArray visibilityMarkers(const Part& part, const VisibilityResult& result,
                                                  const std::string& frame_id) {
  visualization_msgs::MarkerArray array;
  array.markers.push_back(directionSphere(part, result, frame_id));
  array.markers.push_back(partByConeSize(part, result, frame_id));
  return array;
}

visualization_msgs::Marker coneMarker(const Part& part, const VisibilityResult& result, const Cone& cone,
                                      const Vec3& apex_mm, const std::string& frame_id) {
  auto m = baseMarker(frame_id, "cone", 0, visualization_msgs::Marker::LINE_LIST);
  m.scale.x = 0.002 * part.check.box.diagonal() * kMetresPerMm;
  const double length = 0.2 * part.check.box.diagonal();
  m.color = toColour({1.0f, 0.55f, 0.0f});
  for (int d = 0; d < result.directions.size(); ++d) {
    if (!coneHas(cone, d)) continue;
    m.points.push_back(toPointMsg(apex_mm));
    m.points.push_back(toPointMsg(apex_mm + length * result.directions.directions[d]));
  }
  return m;
}

}  // namespace art2part
