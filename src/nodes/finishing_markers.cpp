#include "finishing_markers.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "art2part/common/request_limits.h"
#include "marker_helpers.h"
#include "part_conversions.h"

namespace art2part {

namespace {

// A length of the goal in metres as mm, within its range (request_limits.h); 0 gives `default_mm`.
double lengthMm(double metres, const RequestRange& range, double default_mm) {
  return checkedRequestValue(metres, range) > 0 ? metres / kMetresPerMm : default_mm;
}

RgbColour kindColour(const std::string& kind) {
  if (kind == "face_mill") return {0.20f, 0.45f, 0.90f};
  if (kind == "side_mill") return {0.25f, 0.75f, 0.30f};
  if (kind == "contour") return {0.15f, 0.70f, 0.70f};
  if (kind == "drill") return {0.90f, 0.15f, 0.15f};
  if (kind == "helix") return {0.95f, 0.55f, 0.10f};
  if (kind == "surface_3axis") return {0.60f, 0.35f, 0.85f};
  if (kind == "surface_5axis") return {0.90f, 0.30f, 0.75f};
  return {0.95f, 0.85f, 0.15f};  // rest
}

}  // namespace

PlanOptions finishingPlanOptionsFrom(const PlanFinishingGoal& goal) {
  if (!goal.mode.empty() && goal.mode != "3axis" && goal.mode != "5axis")
    throw InputError("unknown mode '" + goal.mode + "' (use 3axis or 5axis)");
  checkedRequestValue(goal.level, request_limits::kSphereLevel);
  PlanOptions options;
  options.setups.mode = parseMachineMode(goal.mode.empty() ? std::string("3axis") : goal.mode);
  options.roughing.five_axis.enabled = false;
  options.visibility.level = goal.level != 0 ? goal.level : kDefaultFinishingLevel;
  options.roughing.allowance = lengthMm(goal.allowance_m, request_limits::kAllowance, options.roughing.allowance);
  options.finishing.surface.scallop =
      lengthMm(goal.scallop_m, request_limits::kScallop, options.finishing.surface.scallop);
  options.verify = false;
  return options;
}

Toolpath finishingToolpath(const PlanResult& plan) {
  Toolpath path;
  for (const PlanOperation& op : plan.operations)
    if (op.finishing)
      path.insert(path.end(), plan.toolpath.begin() + op.first_point,
                  plan.toolpath.begin() + op.first_point + op.points);
  return path;
}

void fillFinishingResult(const Part& part, const PlanResult& plan, PlanFinishingResult& result) {
  result.operations.clear();
  result.tips.clear();
  result.axes.clear();
  result.moves.clear();
  result.faces.clear();
  result.setup_count = static_cast<uint32_t>(plan.setups.setups.size());
  result.finishing_setups = 0;
  for (const Setup& s : plan.setups.setups) result.finishing_setups += s.for_finishing ? 1 : 0;
  std::vector<int> index_of(plan.finishing.operations.size(), -1);  // finishing op -> result operation
  for (const PlanOperation& op : plan.operations) {
    if (!op.finishing) continue;
    const FinishingOperation& f = plan.finishing.operations.at(op.source);
    MachiningOperation m;
    m.id = static_cast<uint32_t>(result.operations.size());
    index_of[op.source] = static_cast<int>(m.id);
    m.setup = f.setup;
    m.kind = finishingKindName(f.kind);
    m.tool = f.tool;
    m.axis = toVectorMsg(f.direction);
    m.first_point = static_cast<uint32_t>(result.tips.size());
    m.points = static_cast<uint32_t>(op.points);
    m.cutting_length_m = f.feed_mm * kMetresPerMm;
    m.rapid_length_m = f.rapid_mm * kMetresPerMm;
    m.estimated_time_s = f.seconds;
    result.operations.push_back(m);
    for (std::size_t i = op.first_point; i < op.first_point + op.points; ++i) {
      const CutterLocation& c = plan.toolpath[i];
      result.tips.push_back(toPointMsg(c.tip));
      result.axes.push_back(toVectorMsg(c.axis));
      result.moves.push_back(c.move == MoveKind::Feed ? PlanFinishingResult::FEED : PlanFinishingResult::RAPID);
    }
  }
  for (const FaceFinish& f : plan.finishing.faces) {
    FaceFinishing m;
    m.face = f.face;
    m.type = surfaceTypeName(part.faces.at(f.face).type);
    m.status = faceStatusName(f.status);
    m.strategy = f.setup >= 0 ? finishingKindName(f.strategy) : "";
    m.setup = f.setup;
    m.direction = toVectorMsg(f.direction);
    m.tools = f.tools;
    for (int i : f.operations) m.operations.push_back(i < static_cast<int>(index_of.size()) ? index_of[i] : -1);
    m.area_m2 = f.area_mm2 * kMetresPerMm * kMetresPerMm;
    m.planned_m2 = f.planned_mm2 * kMetresPerMm * kMetresPerMm;
    m.reason = f.reason;
    result.faces.push_back(m);
  }
  result.tool_changes = static_cast<uint32_t>(plan.finishing.tool_changes);
  result.holes_drilled = 0;
  for (const HoleMachining& m : plan.finishing.hole_methods) result.holes_drilled += m.method == HoleMethod::Drill;
  result.estimated_time_s = plan.finishing.seconds;
}

visualization_msgs::MarkerArray finishingMarkers(const Part& part, const PlanResult& plan, const std::string& frame_id) {
  visualization_msgs::MarkerArray array;
  array.markers.push_back(deleteAllMarker(frame_id));
  const double diagonal = std::max(part.check.box.diagonal(), 1.0);
  const double feed_width = std::clamp(0.0015 * diagonal, 0.05, 1.0);  // mm
  for (const PlanOperation& op : plan.operations) {
    if (!op.finishing) continue;
    auto feed = lineMarker(frame_id, "finishing_" + op.kind, op.index, visualization_msgs::Marker::LINE_LIST, feed_width);
    feed.color = toColour(kindColour(op.kind));
    appendMoves(feed, plan.toolpath, op.first_point, op.first_point + op.points, MoveKind::Feed);
    auto rapid = lineMarker(frame_id, "finishing_rapids", op.index, visualization_msgs::Marker::LINE_LIST, 0.4 * feed_width);
    rapid.color = toColour({0.55f, 0.55f, 0.55f}, 0.6f);
    appendMoves(rapid, plan.toolpath, op.first_point, op.first_point + op.points, MoveKind::Rapid);
    for (auto* m : {&feed, &rapid})
      if (!m->points.empty()) array.markers.push_back(*m);
  }
  // The direction chosen for each face: an arrow from its centroid along the tool axis.
  const std::vector<std::vector<int>> triangles = faceTriangles(part);
  for (const FaceFinish& f : plan.finishing.faces) {
    if (f.setup < 0 || f.direction.squaredNorm() < 0.5 || triangles[f.face].empty()) continue;
    Vec3 centroid = Vec3::Zero();
    double area = 0;
    for (int t : triangles[f.face]) {
      const double a = triangleArea(part.mesh, t);
      centroid += a * triangleCentroid(part.mesh, t);
      area += a;
    }
    if (area <= 0) continue;
    centroid /= area;
    visualization_msgs::Marker arrow;
    arrow.header.frame_id = frame_id;
    arrow.ns = "face_directions";
    arrow.id = f.face;
    arrow.type = visualization_msgs::Marker::ARROW;
    arrow.action = visualization_msgs::Marker::ADD;
    arrow.pose.orientation.w = 1.0;
    const double length = diagonal / 20;
    arrow.points.push_back(toPointMsg(centroid));
    arrow.points.push_back(toPointMsg(centroid + length * f.direction.normalized()));
    arrow.scale.x = 0.04 * length * kMetresPerMm;  // shaft diameter
    arrow.scale.y = 0.10 * length * kMetresPerMm;  // head diameter
    arrow.scale.z = 0.20 * length * kMetresPerMm;  // head length
    arrow.color = toColour(f.status == FaceStatus::Finished ? kindColour(finishingKindName(f.strategy))
                                                             : RgbColour{0.9f, 0.1f, 0.1f});
    array.markers.push_back(arrow);
  }
  return array;
}

}  // namespace art2part
