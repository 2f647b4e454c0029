// rviz markers of a visibility analysis.
#pragma once

#include <visualization_msgs/MarkerArray.h>

#include "art2part/geometry/part.h"
#include "art2part/visibility/analysis.h"
#include "art2part/visibility/cones.h"

namespace art2part {

// The Gaussian sphere beside the part: one dot per direction, coloured by the share of triangles it sees (special
// directions larger), and the part coloured by the solid angle of each triangle's cone (dark: hardly reachable,
// yellow: open; red: seen from nowhere).
visualization_msgs::MarkerArray visibilityMarkers(const Part& part, const VisibilityResult& result,
                                                  const std::string& frame_id);

// A cone drawn as lines from a point of the part along each direction of the cone.
visualization_msgs::Marker coneMarker(const Part& part, const VisibilityResult& result, const Cone& cone,
                                      const Vec3& apex_mm, const std::string& frame_id);

}  // namespace art2part
