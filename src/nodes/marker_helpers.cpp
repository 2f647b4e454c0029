#include "marker_helpers.h"

#include "part_conversions.h"

namespace art2part {

std_msgs::ColorRGBA toColour(const RgbColour& c, float alpha) {
  std_msgs::ColorRGBA out;
  out.r = c[0];
  out.g = c[1];
  out.b = c[2];
  out.a = alpha;
  return out;
}

geometry_msgs::Vector3 toVectorMsg(const Vec3& v) {
  geometry_msgs::Vector3 out;
  out.x = v.x();
  out.y = v.y();
  out.z = v.z();
  return out;
}

visualization_msgs::Marker baseMarker(const std::string& frame_id, const std::string& ns, int id, int type) {
  visualization_msgs::Marker m;
  m.header.frame_id = frame_id;
  m.ns = ns;
  m.id = id;
  m.type = type;
  m.action = visualization_msgs::Marker::ADD;
  m.pose.orientation.w = 1.0;
  m.scale.x = m.scale.y = m.scale.z = 1.0;
  m.color.a = 1.0f;
  return m;
}

visualization_msgs::Marker lineMarker(const std::string& frame_id, const std::string& ns, int id, int type,
                                      double width_mm) {
  visualization_msgs::Marker m = baseMarker(frame_id, ns, id, type);
  m.scale.x = width_mm * kMetresPerMm;  // line width
  m.scale.y = m.scale.z = 0.0;
  return m;
}

visualization_msgs::Marker deleteAllMarker(const std::string& frame_id) {
  visualization_msgs::Marker clear;
  clear.header.frame_id = frame_id;
  clear.action = visualization_msgs::Marker::DELETEALL;
  clear.pose.orientation.w = 1.0;
  return clear;
}

visualization_msgs::MarkerArray forPart(const std::string& part_id, visualization_msgs::MarkerArray markers) {
  visualization_msgs::MarkerArray out;
  const std::string frame_id = markers.markers.empty() ? std::string() : markers.markers.front().header.frame_id;
  out.markers.push_back(deleteAllMarker(frame_id));
  for (visualization_msgs::Marker& m : markers.markers) {
    if (m.action == visualization_msgs::Marker::DELETEALL) continue;
    m.ns = partNamespace(part_id, m.ns);
    out.markers.push_back(std::move(m));
  }
  return out;
}

std::string partNamespace(const std::string& part_id, const std::string& ns) {
  return part_id.empty() ? ns : part_id + "/" + ns;
}

std::string partIdOfFile(const std::string& path) {
  const std::string trimmed = path.substr(0, path.find_last_not_of('/') + 1);
  const std::string name = trimmed.substr(trimmed.find_last_of('/') + 1);
  const std::size_t dot = name.find_last_of('.');
  return dot == std::string::npos || dot == 0 ? name : name.substr(0, dot);
}

void appendMoves(visualization_msgs::Marker& lines, const Toolpath& path, std::size_t first, std::size_t last,
                 MoveKind kind) {
  for (std::size_t j = first + 1; j < last && j < path.size(); ++j) {
    if (path[j].move != kind || path[j].tool != path[j - 1].tool || path[j].setup != path[j - 1].setup) continue;
    lines.points.push_back(toPointMsg(path[j - 1].tip));
    lines.points.push_back(toPointMsg(path[j].tip));
  }
}

}  // namespace art2part
