// plan.json (plan_json.h).
#include "art2part/plan/plan_json.h"

#include <cstdio>

#include <cmath>

#include "art2part/plan/plan_figures.h"
#include "art2part/setup/setup_report.h"

namespace art2part {

namespace {

nlohmann::json vec(const Vec3& v) { return nlohmann::json::array({v.x(), v.y(), v.z()}); }

nlohmann::json partJson(const Part& part) {
  const Box box = boundingBox(part.mesh);
  return {{"source", part.source},
          {"triangles", part.mesh.triangleCount()},
          {"faces", part.faces.size()},
          {"bounding_box", {{"min", vec(box.min)}, {"max", vec(box.max)}}}};
}

nlohmann::json cycleTimeJson(const CycleTime& t) {
  return {{"total_s", t.total_s()},         {"cutting_s", t.cutting_s},        {"rapid_s", t.rapid_s},
          {"tool_change_s", t.tool_change_s}, {"setup_change_s", t.setup_change_s}, {"cutting_mm", t.cutting_mm},
          {"rapid_mm", t.rapid_mm},          {"tool_changes", t.tool_changes},  {"setup_changes", t.setup_changes}};
}

// The operation's machine time, and when simulated what it removed against its bound.
void addFigures(nlohmann::json& j, const OperationFigures& f) {
  j["time_s"] = f.time.total_s();
  j["time"] = cycleTimeJson(f.time);
  if (!f.simulated) return;
  j["removed_mm3"] = f.removed_mm3;
  j["axial_depth_mm"] = f.axial_depth_mm;
  j["deepest_level_cut_mm"] = f.deepest_level_cut_mm;
  j["gouges"] = f.gouges;
  j["collisions"] = f.collisions;
  if (f.collisions > 0) {
    j["rapid_collisions"] = f.rapid_collisions;
    j["worst_collision_mm"] = f.worst_collision_mm;
  }
  j["material_mm3_per_min"] = f.mm3_per_min;
  j["bound_s"] = f.bound_s;
  j["bound_ratio"] = f.bound_ratio > 0 ? nlohmann::json(f.bound_ratio) : nlohmann::json(nullptr);
  if (f.useless) {
    j["useless"] = true;
    j["useless_reason"] = f.useless_reason;
  }
}

nlohmann::json machiningTimeJson(const PlanFigures& figures) {
  nlohmann::json j = cycleTimeJson(figures.time.total);
  j["machine"] = figures.machine;
  j["roughing_s"] = figures.roughing.total_s();
  j["finishing_s"] = figures.finishing.total_s();
  j["roughing_removed_mm3"] = figures.roughing_removed_mm3;
  j["roughing_bound_s"] = figures.roughing_bound_s;
  j["roughing_bound_ratio"] = figures.roughing_bound_s > 0
                                  ? nlohmann::json(figures.roughing.total_s() / figures.roughing_bound_s)
                                  : nlohmann::json(nullptr);
  return j;
}

nlohmann::json operationJson(const PlanResult& plan, const PlanOperation& op) {
  nlohmann::json j = {{"index", op.index}, {"setup", op.setup}, {"kind", op.kind}, {"tool", op.tool},
                      {"points", op.points}, {"stage", op.finishing ? "finishing" : "roughing"}};
  if (!op.finishing) {
    const RoughingOperation& r = plan.roughing.operations.at(op.source);
    int critical = 0;
    for (const RoughingLevel& l : r.levels) critical += l.critical ? 1 : 0;
    j.update({{"length_mm", r.feed_mm}, {"rapid_mm", r.rapid_mm}, {"levels", r.levels.size()},
              {"critical_levels", critical}, {"ramps", r.ramps}, {"plunges", r.plunges}, {"retracts", r.retracts},
              {"plan_seconds", r.plan_seconds}, {"direct_shadow_levels", r.direct_levels},
              {"planned_removal_mm3", r.planned_removal_mm3}});
  } else {
    const FinishingOperation& f = plan.finishing.operations.at(op.source);
    j.update({{"length_mm", f.feed_mm}, {"rapid_mm", f.rapid_mm}, {"faces", f.faces},
              {"direction", vec(f.direction)}, {"plan_seconds", f.plan_seconds}});
    if (!f.note.empty()) j["note"] = f.note;
  }
  return j;
}

}  // namespace

nlohmann::json holeJson(const Hole& hole, const HoleMachining& method) {
  nlohmann::json segments = nlohmann::json::array();
  for (const HoleSegment& s : hole.segments)
    segments.push_back({{"kind", holeSegmentKindName(s.kind)}, {"faces", s.faces}, {"from", s.from}, {"to", s.to},
                        {"diameter_from", s.diameter_from}, {"diameter_to", s.diameter_to}});
  return {{"axis", vec(hole.axis)},
          {"mouth", vec(hole.mouth)},
          {"diameter", hole.diameter},
          {"depth", hole.depth},
          {"total_depth", hole.total_depth},
          {"bottom", holeBottomName(hole.bottom)},
          {"point_angle_deg", hole.point_angle_deg},
          {"counterbore", {{"diameter", hole.counterbore_diameter}, {"depth", hole.counterbore_depth}}},
          {"countersink", {{"angle_deg", hole.countersink_angle_deg}, {"diameter", hole.countersink_diameter}}},
          {"signature", hole.signature},
          {"faces", hole.faces},
          {"tip_depth", method.tip_depth},
          {"segments", segments},
          {"method", holeMethodName(method.method)},
          {"tool", method.drill},
          {"spot", method.spot},
          {"peck", method.peck},
          {"reason", method.reason}};
}

nlohmann::json faceFinishJson(const Part& part, const FaceFinish& face) {
  nlohmann::json j = {{"face", face.face},
                      {"type", surfaceTypeName(part.faces.at(face.face).type)},
                      {"area_mm2", face.area_mm2},
                      {"status", faceStatusName(face.status)},
                      {"operations", face.operations},
                      {"tools", face.tools},
                      {"planned_mm2", face.planned_mm2}};
  if (face.setup >= 0) {
    j["strategy"] = finishingKindName(face.strategy);
    j["setup"] = face.setup;
    j["direction"] = vec(face.direction);
  }
  if (face.radius_needed_mm >= 0) j["radius_needed_mm"] = face.radius_needed_mm;
  if (face.samples > 0) j["simulated_left_mm"] = face.simulated_left_mm;
  if (!face.reason.empty()) j["reason"] = face.reason;
  return j;
}

// "passed" says nothing gouges or collides; this says whether the part came out: what stock is left beyond the
// tolerance, how much and how thick, so a passed plan never reads as a finished part.
std::string whatIsLeft(const VerificationReport& report) {
  char text[200];
  if (report.leftover_volume_mm3 <= 0) {
    std::snprintf(text, sizeof text, "finished: no stock left beyond %.3g mm of the part", report.tolerance_mm);
  } else {
    std::snprintf(text, sizeof text, "not finished: %.0f mm3 of stock left beyond %.3g mm of the part, up to %.2f mm thick",
                  report.leftover_volume_mm3, report.tolerance_mm, report.leftover_max_mm);
  }
  return text;
}

nlohmann::json verificationJson(const VerificationReport& report) {
  return {{"gouges", report.gouges},
          {"what_is_left", whatIsLeft(report)},
          {"finished", report.leftover_volume_mm3 <= 0},
          {"collisions", report.collisions},
          {"passed", report.passed()},
          {"worst_gouge_mm", report.worst_gouge_mm},
          {"worst_collision_mm", report.worst_collision_mm},
          {"stock_volume_mm3", report.stock_volume_mm3},
          {"part_volume_mm3", report.part_volume_mm3},
          {"removed_volume_mm3", report.removed_volume_mm3},
          {"remaining_volume_mm3", report.remaining_volume_mm3},
          {"leftover_volume_mm3", report.leftover_volume_mm3},
          {"leftover_max_mm", report.leftover_max_mm},
          {"resolution_mm", report.resolution_mm},
          {"open_mesh_closed_edges", report.closed_open_mesh_edges},
          {"seconds", report.seconds_total}};
}

nlohmann::json planJson(const Part& part, const PlanResult& plan, const Machine& machine) {
  const PlanFigures figures = planFigures(plan, machine);
  nlohmann::json j = setupPlanJson(plan.setups, plan.visibility.directions);
  for (std::size_t k = 0; k < j["setups"].size(); ++k) {
    const auto time = figures.time.by_setup.find(static_cast<int>(k));
    j["setups"][k]["time"] = cycleTimeJson(time == figures.time.by_setup.end() ? CycleTime{} : time->second);
  }
  j["setup_seconds"] = j["seconds"];
  j.erase("seconds");
  j["part"] = partJson(part);
  nlohmann::json directions = nlohmann::json::array();
  for (const Vec3& d : plan.visibility.directions.directions) directions.push_back(vec(d));
  j["directions"] = directions;
  j["operations"] = nlohmann::json::array();
  for (std::size_t i = 0; i < plan.operations.size(); ++i) {
    nlohmann::json op = operationJson(plan, plan.operations[i]);
    addFigures(op, figures.operations[i]);
    j["operations"].push_back(op);
  }
  // Operations planned and left out because they would remove, or in the simulation removed, almost nothing.
  j["dropped_operations"] = nlohmann::json::array();
  for (const DroppedOperation& d : plan.roughing.dropped) {
    nlohmann::json op = {{"setup", d.setup}, {"kind", d.kind}, {"tool", d.tool},
                         {"planned_removal_mm3", d.planned_removal_mm3}, {"plan_seconds", d.plan_seconds},
                         {"reason", d.reason}};
    if (d.simulated) {
      op["removed_mm3"] = d.removed_mm3;
      op["seconds"] = d.seconds;
    }
    j["dropped_operations"].push_back(op);
  }
  if (plan.useless.found > 0) {
    j["useless_roughing"] = {
        {"found", plan.useless.found}, {"dropped", plan.useless.dropped}, {"kept", plan.useless.kept}};
    if (!plan.useless.kept_why.empty()) j["useless_roughing"]["kept_why"] = plan.useless.kept_why;
  }
  j["roughing_region_failures"] = plan.roughing.region_failures;
  j["roughing_direct_shadow_levels"] = plan.roughing.direct_levels;

  nlohmann::json faces = nlohmann::json::array();
  std::map<std::string, int> by_status;
  for (const FaceFinish& f : plan.finishing.faces) {
    nlohmann::json face = faceFinishJson(part, f);
    // The simulation's word on the face (roughing and finishing together): material left above it, deepest gouge.
    if (plan.verified && f.face < static_cast<int>(plan.verification.face_checks.size())) {
      const FaceVerification& check = plan.verification.face_checks[f.face];
      face["simulated"] = {{"left_max_mm", check.left_max_mm},
                           {"left_mean_mm", check.left_mean_mm},
                           {"samples", check.samples},
                           {"gouges", check.gouges},
                           {"deepest_gouge_mm", check.deepest_gouge_mm}};
    }
    faces.push_back(face);
    ++by_status[faceStatusName(f.status)];
  }
  j["faces"] = faces;
  nlohmann::json holes = nlohmann::json::array();
  for (std::size_t h = 0; h < plan.holes.size(); ++h)
    holes.push_back(holeJson(plan.holes[h], h < plan.hole_methods.size() ? plan.hole_methods[h] : HoleMachining{}));
  j["holes"] = holes;
  j["finishing"] = {{"faces_by_status", by_status},
                    {"tool_changes_per_setup", plan.finishing.tool_changes_per_setup},
                    {"tool_changes", plan.finishing.tool_changes},
                    {"plan_seconds", plan.finishing.plan_seconds},
                    {"cancelled", plan.finishing.cancelled}};
  j["machining_time"] = machiningTimeJson(figures);
  j["verification"] = plan.verified ? verificationJson(plan.verification) : nlohmann::json(nullptr);
  nlohmann::json timings = nlohmann::json::object();
  for (const auto& [stage, seconds] : plan.timings) timings[stage] = seconds;
  j["timings"] = timings;
  j["cancelled"] = plan.cancelled;
  return j;
}

}  // namespace art2part
