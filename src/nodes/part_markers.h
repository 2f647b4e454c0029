// rviz markers of a part.
#pragma once

#include <visualization_msgs/Marker.h>

#include "art2part/geometry/part.h"

namespace art2part {

// The part as a TRIANGLE_LIST in metres, each triangle coloured by its face's surface type (plane grey-blue,
// cylinder green, cone orange, sphere/torus purple, free-form sand); concave faces darker.
visualization_msgs::Marker partMarker(const Part& part, const std::string& frame_id, const std::string& ns);

}  // namespace art2part
