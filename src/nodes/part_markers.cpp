#include "part_markers.h"

#include "art2part/render/palette.h"
#include "part_conversions.h"

namespace art2part {

namespace {

std_msgs::ColorRGBA colourOf(const Face& face) {
  const Rgb rgb = surfaceColour(face);
  std_msgs::ColorRGBA c;
  c.r = rgb[0];
  c.g = rgb[1];
  c.b = rgb[2];
  c.a = 1.0f;
  return c;
}

}  // namespace

visualization_msgs::Marker partMarker(const Part& part, const std::string& frame_id, const std::string& ns) {
  visualization_msgs::Marker m;
  m.header.frame_id = frame_id;
  m.ns = ns;
  m.id = 0;
  m.type = visualization_msgs::Marker::TRIANGLE_LIST;
  m.action = visualization_msgs::Marker::ADD;
  m.pose.orientation.w = 1.0;
  m.scale.x = m.scale.y = m.scale.z = 1.0;
  m.color.a = 1.0f;
  const Face other;
  for (int t = 0; t < part.mesh.triangleCount(); ++t) {
    const int f = t < static_cast<int>(part.triangle_face.size()) ? part.triangle_face[t] : -1;
    const std_msgs::ColorRGBA colour =
        colourOf(f >= 0 && f < static_cast<int>(part.faces.size()) ? part.faces[f] : other);
    for (int k = 0; k < 3; ++k) {
      m.points.push_back(toPointMsg(part.mesh.corner(t, k)));
      m.colors.push_back(colour);
    }
  }
  return m;
}

}  // namespace art2part
