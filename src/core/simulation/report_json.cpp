// The verification report as JSON (verify.h).
#include <cmath>
#include <nlohmann/json.hpp>

#include "art2part/simulation/verify.h"

namespace art2part {

namespace {

using nlohmann::json;

// Millimetres to the micrometre, so the report reads cleanly.
double mm(double v) { return std::round(v * 1e4) / 1e4; }
json point(const Vec3& p) { return json::array({mm(p.x()), mm(p.y()), mm(p.z())}); }
json box(const Box& b) { return {{"min", point(b.min)}, {"max", point(b.max)}}; }

json gougeJson(const GougeRecord& g) {
  return {{"point", g.point},       {"op", g.op},
          {"setup", g.setup},       {"tool", g.tool},
          {"depth_mm", mm(g.depth_mm)}, {"position", point(g.position)},
          {"tip", point(g.tip)}};
}

json collisionJson(const CollisionRecord& c) {
  return {{"point", c.point},       {"op", c.op},
          {"setup", c.setup},       {"tool", c.tool},
          {"kind", collisionKindName(c.kind)}, {"depth_mm", mm(c.depth_mm)},
          {"position", point(c.position)},     {"tip", point(c.tip)}};
}

json regionJson(const LeftoverRegion& r) {
  return {{"volume_mm3", mm(r.volume_mm3)},
          {"max_thickness_mm", mm(r.max_thickness_mm)},
          {"thickest_point", point(r.thickest_point)},
          {"box", box(r.box)}};
}

json faceJson(const FaceCusp& f) {
  return {{"face", f.face}, {"max_mm", mm(f.max_mm)}, {"mean_mm", mm(f.mean_mm)}, {"samples", f.samples}};
}

json faceCheckJson(const FaceVerification& f) {
  return {{"face", f.face},
          {"left_max_mm", mm(f.left_max_mm)},
          {"left_mean_mm", mm(f.left_mean_mm)},
          {"samples", f.samples},
          {"gouges", f.gouges},
          {"deepest_gouge_mm", mm(f.deepest_gouge_mm)},
          {"deepest_gouge_point", point(f.deepest_gouge_point)}};
}

template <class T, class F>
json list(const std::vector<T>& items, F each) {
  json out = json::array();
  for (const T& item : items) out.push_back(each(item));
  return out;
}

}  // namespace

std::string reportJson(const VerificationReport& r) {
  json j;
  j["passed"] = r.passed();
  j["gouges"] = r.gouges;
  j["worst_gouge_mm"] = mm(r.worst_gouge_mm);
  j["collisions"] = r.collisions;
  j["worst_collision_mm"] = mm(r.worst_collision_mm);
  j["leftover_volume_mm3"] = mm(r.leftover_volume_mm3);
  j["leftover_max_mm"] = mm(r.leftover_max_mm);
  j["gouge_list"] = list(r.gouge_list, gougeJson);
  j["collision_list"] = list(r.collision_list, collisionJson);
  j["leftover_regions"] = list(r.regions, regionJson);
  j["leftover_region_count"] = r.region_count;
  j["open_mesh_closed_edges"] = r.closed_open_mesh_edges;
  j["face_cusps"] = list(r.faces, faceJson);
  j["face_cusp_count"] = r.face_count;
  j["face_checks"] = list(r.face_checks, faceCheckJson);
  j["operations"] = json::array();
  for (const auto& [op, check] : r.by_op)
    j["operations"].push_back({{"op", op},
                               {"removed_mm3", mm(check.swept.removed_mm3)},
                               {"axial_depth_mm", mm(levelCutDepth(check.swept, kAxialDepthShare))},
                               {"deepest_level_cut_mm", mm(check.swept.deepest_level_cut_mm)},
                               {"deepest_level_cut_row", check.swept.deepest_level_cut_row},
                               {"gouges", check.gouges},
                               {"collisions", check.collisions},
                               {"rapid_collisions", check.rapid_collisions},
                               {"worst_collision_mm", mm(check.worst_collision_mm)}});
  j["tolerance_mm"] = r.tolerance_mm;
  j["resolution_mm"] = mm(r.resolution_mm);
  j["spacing_mm"] = point(r.spacing);
  j["dexels"] = r.dexels;
  j["moves"] = r.moves;
  j["poses"] = r.poses;
  j["seconds"] = std::round(r.seconds_total * 1000) / 1000;
  j["seconds_sweep"] = std::round(r.seconds_sweep * 1000) / 1000;
  j["moves_per_second"] = std::round(r.moves_per_second);
  j["resumed_at_row"] = r.resumed_at_row;
  j["stock"] = {{"box", box(r.stock_box)}, {"volume_mm3", mm(r.stock_volume_mm3)}};
  j["removed_volume_mm3"] = mm(r.removed_volume_mm3);
  j["remaining_volume_mm3"] = mm(r.remaining_volume_mm3);
  j["part_volume_mm3"] = mm(r.part_volume_mm3);
  return j.dump(2);
}

}  // namespace art2part
