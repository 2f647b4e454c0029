// Pieces every rviz picture of the nodes is made of (plain functions of plain data): colours, line markers, a
// toolpath's feeds and rapids as line lists.
#pragma once

#include <std_msgs/ColorRGBA.h>
#include <geometry_msgs/Vector3.h>
#include <visualization_msgs/Marker.h>
#include <visualization_msgs/MarkerArray.h>

#include <array>
#include <string>

#include "art2part/tooling/toolpath.h"

namespace art2part {

using RgbColour = std::array<float, 3>;

std_msgs::ColorRGBA toColour(const RgbColour& c, float alpha = 1.0f);
geometry_msgs::Vector3 toVectorMsg(const Vec3& v);

// An empty marker of `type` (LINE_LIST, LINE_STRIP, ...) in `frame_id`, lines `width_mm` wide (metres in the message).
// An ADD marker in frame_id: identity pose, unit scale, opaque (the caller sets points, colours and sizes).
visualization_msgs::Marker baseMarker(const std::string& frame_id, const std::string& ns, int id, int type);

visualization_msgs::Marker lineMarker(const std::string& frame_id, const std::string& ns, int id, int type,
                                      double width_mm);

// A marker that deletes every marker of the topic (the pictures of an earlier plan go).
visualization_msgs::Marker deleteAllMarker(const std::string& frame_id);

// The markers of part `part_id`: each namespace becomes "<part_id>/<ns>" and one DELETEALL goes first (any others are
// dropped), so two parts never mix on a topic and the pictures of the part planned before go.
visualization_msgs::MarkerArray forPart(const std::string& part_id, visualization_msgs::MarkerArray markers);

// The namespace of a marker of part `part_id` ("<part_id>/<ns>"; `ns` alone when the id is empty).
std::string partNamespace(const std::string& part_id, const std::string& ns);

// The id a part loaded from `path` gets by default: the file's (or folder's) name without folders and extension.
std::string partIdOfFile(const std::string& path);

// Appends the segments of `path` from point `first` to `last` (exclusive) whose move is `kind` to a LINE_LIST.
void appendMoves(visualization_msgs::Marker& lines, const Toolpath& path, std::size_t first, std::size_t last,
                 MoveKind kind);

}  // namespace art2part
