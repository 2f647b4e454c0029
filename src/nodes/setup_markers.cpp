#include "setup_markers.h"

#include "art2part/render/palette.h"

#include "marker_helpers.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "art2part/common/request_limits.h"
#include "art2part/visibility/visibility_handoff.h"
#include "part_conversions.h"

namespace art2part {

namespace {

template <class Out, class In>
std::vector<Out> converted(const std::vector<In>& in) {
  return std::vector<Out>(in.begin(), in.end());
}

}  // namespace

// ---- the request -------------------------------------------------------------------------------------------------

SetupOptions setupOptionsFrom(const PlanSetupsRequest& request) {
  SetupOptions options;
  if (!request.mode.empty() && request.mode != "3axis" && request.mode != "5axis")
    throw InputError("unknown mode '" + request.mode + "' (use 3axis or 5axis)");
  options.mode = parseMachineMode(request.mode.empty() ? std::string("3axis") : request.mode);
  if (checkedRequestValue(request.max_tilt_deg, request_limits::kMaxTilt) > 0)
    options.max_tilt_deg = request.max_tilt_deg;
  if (checkedRequestValue(request.time_limit, request_limits::kSetupTimeLimit) > 0)
    options.time_limit_s = request.time_limit;
  return options;
}

VisibilityOptions visibilityOptionsFrom(const PlanSetupsRequest& request) {
  VisibilityOptions options;
  if (checkedRequestValue(request.level, request_limits::kSphereLevel) != 0) options.level = request.level;
  options.special_directions = !request.no_special_directions;
  return options;
}

bool carriesVisibility(const PlanSetupsRequest& request) {
  return !request.directions.empty() || !request.bits.empty() || !request.special.empty();
}

VisibilityResult visibilityFromRequest(const Part& part, const PlanSetupsRequest& request) {
  return visibilityFromMessage(part, request.directions, request.bits, request.special);
}

VisibilityResult visibilityFromMessage(const Part& part, const std::vector<geometry_msgs::Vector3>& given_directions,
                                       const std::vector<uint8_t>& bits, const std::vector<uint8_t>& special_flags) {
  std::vector<Vec3> directions;
  directions.reserve(given_directions.size());
  for (const geometry_msgs::Vector3& v : given_directions) directions.emplace_back(v.x, v.y, v.z);
  return visibilityFromBits(part, directions, bits, special_flags);
}

// ---- the response ------------------------------------------------------------------------------------------------

geometry_msgs::Pose toPoseMsg(const SetupFrame& frame) {
  geometry_msgs::Pose pose;
  pose.position = toPointMsg(frame.origin);
  Eigen::Matrix3d rotation;
  rotation.col(0) = frame.x;
  rotation.col(1) = frame.y;
  rotation.col(2) = frame.z;
  const Eigen::Quaterniond q = Eigen::Quaterniond(rotation).normalized();
  pose.orientation.x = q.x();
  pose.orientation.y = q.y();
  pose.orientation.z = q.z();
  pose.orientation.w = q.w();
  return pose;
}

MachiningSetup toMachiningSetup(const Setup& setup, int k, const DirectionSet& directions) {
  MachiningSetup out;
  out.id = k;
  const bool indexed = setup.direction >= 0 && setup.direction < directions.size();
  out.direction = toVectorMsg(indexed ? directions.directions[setup.direction] : setup.frame.z);
  out.direction_index = setup.direction;
  out.special = setup.special;
  out.frame = toPoseMsg(setup.frame);
  out.faces = converted<int32_t>(setup.faces);
  out.triangles = converted<int32_t>(setup.triangles);
  out.reachable_triangles = setup.reachable_triangles;
  out.square_face_area = setup.square_face_area;
  out.for_finishing = setup.for_finishing;
  out.finishing_faces = converted<int32_t>(setup.finishing_faces);
  return out;
}

void fillResponse(const SetupPlan& plan, const DirectionSet& directions, PlanSetupsResponse& response) {
  response.mode = machineModeName(plan.mode);
  response.setups.clear();
  for (int k = 0; k < static_cast<int>(plan.setups.size()); ++k)
    response.setups.push_back(toMachiningSetup(plan.setups[k], k, directions));
  response.unmachinable_triangles = converted<uint32_t>(plan.unmachinable_triangles);
  response.unmachinable_faces = converted<uint32_t>(plan.unmachinable_faces);
  response.split_faces = converted<uint32_t>(plan.split_faces);
  response.proven_minimal = plan.proven_minimal;
  response.greedy_setups = static_cast<uint32_t>(std::max(0, plan.greedy_setups));
  response.core_directions = static_cast<uint32_t>(std::max(0, plan.cover.core_candidates));
  response.core_triangles = static_cast<uint32_t>(std::max(0, plan.cover.core_elements));
}

// ---- tf2 ---------------------------------------------------------------------------------------------------------

std::string setupFrameName(int k) { return "setup_" + std::to_string(k); }

std::vector<geometry_msgs::TransformStamped> setupTransforms(const std::vector<MachiningSetup>& setups, int previous_count,
                                                             const std::string& parent,
                                                             const std::string& unused_parent, const ros::Time& stamp) {
  std::vector<geometry_msgs::TransformStamped> out;
  const int count = static_cast<int>(setups.size());
  for (int k = 0; k < std::max(count, previous_count); ++k) {
    geometry_msgs::TransformStamped t;
    t.header.stamp = stamp;
    t.child_frame_id = setupFrameName(k);
    if (k < count) {
      t.header.frame_id = parent;
      t.transform.translation.x = setups[k].frame.position.x;
      t.transform.translation.y = setups[k].frame.position.y;
      t.transform.translation.z = setups[k].frame.position.z;
      t.transform.rotation = setups[k].frame.orientation;
    } else {
      t.header.frame_id = unused_parent;
      t.transform.rotation.w = 1.0;
    }
    out.push_back(t);
  }
  return out;
}

// ---- rviz --------------------------------------------------------------------------------------------------------

visualization_msgs::MarkerArray setupMarkers(const Part& part, const SetupPlan& plan, const std::string& frame_id) {
  visualization_msgs::MarkerArray array;
  array.markers.push_back(deleteAllMarker(frame_id));

  const Box& box = part.check.box;
  const Vec3 centre = box.center();
  const double diagonal = std::max(box.diagonal(), 1e-9);
  for (int k = 0; k < static_cast<int>(plan.setups.size()); ++k) {
    const Vec3 z = plan.setups[k].frame.z.normalized();
    const RgbColour colour = setupColour(k);
    // From the centre to the box's face along z (its support distance), then a quarter diagonal beyond.
    const double length = 0.5 * z.cwiseAbs().dot(box.size()) + 0.25 * diagonal;

    auto arrow = baseMarker(frame_id, "setup_arrows", k, visualization_msgs::Marker::ARROW);
    arrow.points.push_back(toPointMsg(centre));
    arrow.points.push_back(toPointMsg(centre + length * z));
    arrow.scale.x = 0.012 * diagonal * kMetresPerMm;  // shaft diameter
    arrow.scale.y = 0.03 * diagonal * kMetresPerMm;   // head diameter
    arrow.scale.z = 0.06 * diagonal * kMetresPerMm;   // head length
    arrow.color = toColour(colour);
    array.markers.push_back(arrow);

    auto label = baseMarker(frame_id, "setup_labels", k, visualization_msgs::Marker::TEXT_VIEW_FACING);
    label.pose.position = toPointMsg(centre + (length + 0.06 * diagonal) * z);
    label.scale.x = label.scale.y = label.scale.z = 0.05 * diagonal * kMetresPerMm;  // text height
    label.color = toColour(colour);
    label.text = setupFrameName(k);
    array.markers.push_back(label);
  }

  const int T = part.mesh.triangleCount();
  std::vector<int> owner(T, -1);  // setup k, -2 unmachinable, -1 neither
  for (int k = 0; k < static_cast<int>(plan.setups.size()); ++k)
    for (int t : plan.setups[k].triangles)
      if (t >= 0 && t < T) owner[t] = k;
  for (int t : plan.unmachinable_triangles)
    if (t >= 0 && t < T) owner[t] = -2;
  auto surface = baseMarker(frame_id, "part_by_setup", 0, visualization_msgs::Marker::TRIANGLE_LIST);
  surface.points.reserve(3 * static_cast<std::size_t>(T));
  surface.colors.reserve(3 * static_cast<std::size_t>(T));
  for (int t = 0; t < T; ++t) {
    const RgbColour c = owner[t] >= 0 ? setupColour(owner[t]) : owner[t] == -2 ? unmachinableColour()
                                                                               : RgbColour{0.25f, 0.25f, 0.25f};
    for (int i = 0; i < 3; ++i) {
      surface.points.push_back(toPointMsg(part.mesh.corner(t, i)));
      surface.colors.push_back(toColour(c));
    }
  }
  array.markers.push_back(surface);
  return array;
}

}  // namespace art2part
