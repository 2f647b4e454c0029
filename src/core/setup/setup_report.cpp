#include "art2part/setup/setup_report.h"

#include <cstdio>
#include <numeric>

namespace art2part {
namespace {

nlohmann::json vectorJson(const Vec3& v) { return nlohmann::json::array({v.x(), v.y(), v.z()}); }

nlohmann::json frameJson(const SetupFrame& f) {
  return {{"origin", vectorJson(f.origin)}, {"x", vectorJson(f.x)}, {"y", vectorJson(f.y)}, {"z", vectorJson(f.z)}};
}

std::string setupName(int id) { return "setup_" + std::to_string(id); }

nlohmann::json setupJson(const Setup& s, int id, const DirectionSet& directions) {
  return {{"id", id},
          {"name", setupName(id)},
          {"direction", vectorJson(directions.directions.at(s.direction))},
          {"direction_index", s.direction},
          {"special", s.special},
          {"frame", frameJson(s.frame)},
          {"faces", s.faces},
          {"triangles", s.triangles},
          {"triangle_count", s.triangles.size()},
          {"reachable_triangles", s.reachable_triangles},
          {"square_face_area_mm2", s.square_face_area},
          {"for_finishing", s.for_finishing},
          {"finishing_faces", s.finishing_faces}};
}

nlohmann::json coverStatsJson(const CoverStats& c) {
  return {{"elements", c.elements},
          {"candidates", c.candidates},
          {"uncoverable", c.uncoverable},
          {"distinct_elements", c.distinct_elements},
          {"empty_candidates", c.empty_candidates},
          {"essential", c.essential},
          {"dominated_candidates", c.dominated_candidates},
          {"dominated_elements", c.dominated_elements},
          {"reduction_rounds", c.reduction_rounds},
          {"core_candidates", c.core_candidates},
          {"core_elements", c.core_elements},
          {"search_nodes", c.search_nodes},
          {"seconds_reduce", c.seconds_reduce},
          {"seconds_search", c.seconds_search}};
}

std::string format(const char* pattern, double a, double b = 0, double c = 0) {
  char buffer[160];
  std::snprintf(buffer, sizeof buffer, pattern, a, b, c);
  return buffer;
}

std::string setupLine(const Part& part, const Setup& s, int id, const DirectionSet& directions) {
  const Vec3& d = directions.directions.at(s.direction);
  double area = 0.0;
  for (int t : s.triangles) area += triangleArea(part.mesh, t);
  std::string line = setupName(id) + ": direction " + format("(%.3f, %.3f, %.3f)", d.x(), d.y(), d.z()) +
                     (s.special ? " special" : " sampled") + ", x " +
                     format("(%.3f, %.3f, %.3f)", s.frame.x.x(), s.frame.x.y(), s.frame.x.z()) + "; " +
                     std::to_string(s.faces.size()) + " whole faces, " + std::to_string(s.triangles.size()) +
                     " triangles" + format(" (%.0f mm2)", area) + ", reaches " +
                     std::to_string(s.reachable_triangles) + format(", square faces %.0f mm2", s.square_face_area);
  if (s.for_finishing)
    line = setupName(id) + ": direction " + format("(%.3f, %.3f, %.3f)", d.x(), d.y(), d.z()) +
           ", added for finishing " + std::to_string(s.finishing_faces.size()) + " faces no setup of the cover finishes";
  return line + "\n";
}

}  // namespace

nlohmann::json setupPlanJson(const SetupPlan& plan, const DirectionSet& directions) {
  nlohmann::json setups = nlohmann::json::array();
  for (int i = 0; i < static_cast<int>(plan.setups.size()); ++i)
    setups.push_back(setupJson(plan.setups[i], i, directions));
  return {{"mode", machineModeName(plan.mode)},
          {"max_tilt_deg", plan.max_tilt_deg},
          {"setups", setups},
          {"unmachinable_triangles", plan.unmachinable_triangles},
          {"unmachinable_faces", plan.unmachinable_faces},
          {"split_faces", plan.split_faces},
          {"proven_minimal", plan.proven_minimal},
          {"bonus_proven_best", plan.bonus_proven_best},
          {"greedy_setups", plan.greedy_setups},
          {"cover", coverStatsJson(plan.cover)},
          {"seconds", {{"reach", plan.seconds_reach}, {"cover", plan.seconds_cover}, {"assign", plan.seconds_assign}}}};
}

std::string setupPlanText(const Part& part, const SetupPlan& plan, const DirectionSet& directions) {
  std::string text = "mode:         " + std::string(machineModeName(plan.mode));
  if (plan.mode == MachineMode::FiveAxis) text += format(", tilt up to %.0f deg", plan.max_tilt_deg);
  int added = 0;
  for (const Setup& s : plan.setups) added += s.for_finishing ? 1 : 0;
  text += "\nsetups:       " + std::to_string(plan.setups.size() - added) +
          (plan.proven_minimal ? " (proven minimal" : " (best found in the time limit") + ", greedy cover needs " +
          std::to_string(plan.greedy_setups) + ")" +
          (added > 0 ? " + " + std::to_string(added) + " added for finishing" : std::string()) + "\n";
  for (int i = 0; i < static_cast<int>(plan.setups.size()); ++i)
    text += "  " + setupLine(part, plan.setups[i], i, directions);
  text += "unmachinable: " + std::to_string(plan.unmachinable_triangles.size()) + " triangles in " +
          std::to_string(plan.unmachinable_faces.size()) + " faces\n";
  text += "split faces:  " + std::to_string(plan.split_faces.size()) + " (no one setup reaches them whole)\n";
  text += "cover:        core " + std::to_string(plan.cover.core_candidates) + " directions x " +
          std::to_string(plan.cover.core_elements) + " triangle classes, " + std::to_string(plan.cover.search_nodes) +
          " search nodes\n";
  text += format("seconds:      reach %.3f, cover %.3f, assign %.3f\n", plan.seconds_reach, plan.seconds_cover,
                 plan.seconds_assign);
  return text;
}

}  // namespace art2part
