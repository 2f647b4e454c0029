// Stage records (stage_records.h): nlohmann::json's MessagePack of the core structs, field by field.
#include "art2part/plan/stage_records.h"

#include <nlohmann/json.hpp>

#include "art2part/geometry/adjacency.h"
#include "art2part/geometry/repair.h"

// Eigen vectors as [x, y, z] and Clipper's points as [X, Y]: the leaves every record is made of.
namespace nlohmann {
template <>
struct adl_serializer<art2part::Vec3> {
  static void to_json(json& j, const art2part::Vec3& v) { j = {v.x(), v.y(), v.z()}; }
  static void from_json(const json& j, art2part::Vec3& v) {
    v = art2part::Vec3(j.at(0).get<double>(), j.at(1).get<double>(), j.at(2).get<double>());
  }
};
template <>
struct adl_serializer<ClipperLib::IntPoint> {
  static void to_json(json& j, const ClipperLib::IntPoint& p) { j = {p.X, p.Y}; }
  static void from_json(const json& j, ClipperLib::IntPoint& p) {
    p.X = j.at(0).get<ClipperLib::cInt>();
    p.Y = j.at(1).get<ClipperLib::cInt>();
  }
};
}  // namespace nlohmann

namespace art2part {

using nlohmann::json;

// Every field of every struct a record holds (enums as their numbers). A field added to a struct and not here is not
// carried: test_stage_records compares a whole plan's files made from records with those made in one process.
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(Box, min, max)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(Mesh, vertices, triangles)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(Face, type, normal, offset, axis, point, radius, minor_radius, half_angle, concave,
                                   area, triangle_count)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(RepairReport, merged_vertices, dropped_degenerate, dropped_duplicate,
                                   split_neighbours, flipped, notes)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(SetupFrame, origin, x, y, z)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(Setup, direction, special, frame, faces, triangles, reachable_triangles,
                                   square_face_area, for_finishing, finishing_faces)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(CoverStats, elements, candidates, uncoverable, distinct_elements, empty_candidates,
                                   essential, dominated_candidates, dominated_elements, reduction_rounds,
                                   core_candidates, core_elements, bonus_core_candidates, bonus_core_elements,
                                   search_nodes, seconds_reduce, seconds_search)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(SetupPlan, mode, max_tilt_deg, setups, unmachinable_triangles, unmachinable_faces,
                                   split_faces, proven_minimal, bonus_proven_best, greedy_setups, cover, seconds_reach,
                                   seconds_cover, seconds_assign, cancelled)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(HolderStep, diameter, length)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(Tool, id, type, diameter, corner_radius, point_angle_deg, flute_length,
                                   shank_diameter, stickout, holder, flutes, spindle_rpm, feed_mm_min, plunge_mm_min,
                                   max_stepdown, max_stepover, max_engagement_deg, material)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(HoleSegment, kind, faces, from, to, diameter_from, diameter_to)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(Hole, axis, mouth, diameter, bore_start, depth, total_depth, bottom,
                                   point_angle_deg, counterbore_diameter, counterbore_depth, countersink_angle_deg,
                                   countersink_diameter, arc_deg, radial_deviation, segments, faces, bore_faces,
                                   signature, free_radius, clearance_step, free_beyond)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(HoleMachining, method, drill, spot, peck, tip_depth, spot_depth, reason)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(RoughingLevel, z, critical, cleared_mm2, remaining_mm2, rings)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(SlabState, z, top, remaining)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(FaceFinish, face, status, strategy, setup, direction, operations, tools, area_mm2,
                                   planned_mm2, radius_needed_mm, reason, simulated_left_mm, samples)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(GougeRecord, point, op, setup, tool, depth_mm, position, tip)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(CollisionRecord, point, op, setup, tool, kind, depth_mm, position, tip)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(LeftoverRegion, volume_mm3, max_thickness_mm, thickest_point, box)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(FaceCusp, face, max_mm, mean_mm, samples)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(FaceVerification, face, left_max_mm, left_mean_mm, samples, gouges,
                                   deepest_gouge_mm, deepest_gouge_point)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(OperationSweep, removed_mm3, deepest_level_cut_mm, deepest_level_cut_row,
                                   level_cut_by_height_mm3)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(OperationCheck, swept, gouges, collisions, rapid_collisions, worst_collision_mm)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(VerificationReport, gouges, worst_gouge_mm, gouge_list, collisions,
                                   worst_collision_mm, collision_list, leftover_volume_mm3, leftover_max_mm, regions,
                                   region_count, faces, face_count, face_checks, resolution_mm, tolerance_mm, spacing,
                                   dexels, moves, poses, seconds_sweep, seconds_total, moves_per_second, stock_box,
                                   stock_volume_mm3, removed_volume_mm3, remaining_volume_mm3, part_volume_mm3,
                                   by_op, closed_open_mesh_edges, resumed_at_row, cancelled)

// A toolpath point as an array (a plan has up to millions): [op, setup, tool, move, tip, axis].
void to_json(json& j, const CutterLocation& c) { j = {c.op, c.setup, c.tool, c.move, c.tip, c.axis}; }
void from_json(const json& j, CutterLocation& c) {
  c.op = j.at(0).get<int>();
  c.setup = j.at(1).get<int>();
  c.tool = j.at(2).get<std::string>();
  c.move = j.at(3).get<MoveKind>();
  c.tip = j.at(4).get<Vec3>();
  c.axis = j.at(5).get<Vec3>();
}

NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(RoughingOperation, setup, kind, tool, path, levels, feed_mm, rapid_mm, seconds, ramps,
                                   plunges, retracts, plan_seconds, direct_levels, planned_removal_mm3)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(DroppedOperation, setup, kind, tool, planned_removal_mm3, simulated, removed_mm3,
                                   seconds, reason)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(RoughingPlan, operations, stock_left, dropped, seconds, contours,
                                   closed_open_mesh_edges, region_failures, direct_levels, cancelled)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(RoughingStage, holes, hole_methods, roughing, seconds_holes)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(FinishingOperation, setup, kind, tool, direction, faces, path, feed_mm, rapid_mm,
                                   seconds, plan_seconds, note)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(ToolpathAndTools, path, tools)
// Verify options: all but stock_mesh (the caller's) and threads (the machine's own).
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(VerifyOptions, resolution, tolerance, stock_margin, step_fraction, cusp_step,
                                   max_listed, tool_chord_mm, face_allowance)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(FinishingPlan, operations, faces, holes, hole_methods, tool_changes_per_setup,
                                   tool_changes, seconds, plan_seconds, cancelled)

namespace {

RecordBytes pack(const char* kind, json data) {
  return json::to_msgpack(json{{"record", kind}, {"version", kRecordVersion}, {"data", std::move(data)}});
}

// The record's data, or InputError naming what was expected and what came.
json unpack(const char* kind, const RecordBytes& bytes) {
  const std::string what = std::string("a ") + kind + " record";
  if (bytes.empty()) throw InputError(what + " was expected: none given");
  json j;
  try {
    j = json::from_msgpack(bytes);
  } catch (const json::exception& e) {
    throw InputError(what + " was expected: " + std::to_string(bytes.size()) + " bytes that are not MessagePack (" +
                     e.what() + ")");
  }
  if (!j.is_object() || !j.contains("record") || !j["record"].is_string())
    throw InputError(what + " was expected: MessagePack without a record kind");
  if (j["record"] != kind) throw InputError(what + " was expected, not a " + j["record"].get<std::string>() + " record");
  if (j.value("version", 0) != kRecordVersion)
    throw InputError(what + " of version " + std::to_string(kRecordVersion) + " was expected, not version " +
                     j.value("version", json(0)).dump());
  if (!j.contains("data")) throw InputError(what + " without data");
  return std::move(j["data"]);
}

template <class T>
T read(const char* kind, const RecordBytes& bytes) {
  json data = unpack(kind, bytes);
  try {
    return data.get<T>();
  } catch (const json::exception& e) {
    throw InputError(std::string("a ") + kind + " record that does not hold one: " + e.what());
  }
}

}  // namespace

RecordBytes partRecord(const Part& part) {
  return pack("part", json{{"source", part.source},
                           {"mesh", part.mesh},
                           {"triangle_face", part.triangle_face},
                           {"faces", part.faces},
                           {"face_source", part.face_source},
                           {"repairs", part.repairs},
                           {"sharp_angle", part.adjacency.sharp_angle}});
}

Part partFromRecord(const RecordBytes& bytes) {
  const json data = unpack("part", bytes);
  Part part;
  try {
    part.source = data.at("source").get<std::string>();
    part.mesh = data.at("mesh").get<Mesh>();
    part.triangle_face = data.at("triangle_face").get<std::vector<int>>();
    part.faces = data.at("faces").get<std::vector<Face>>();
    part.face_source = data.at("face_source").get<FaceSource>();
    part.repairs = data.at("repairs").get<RepairReport>();
    const double sharp_angle = data.at("sharp_angle").get<double>();
    validateMesh(part.mesh, "part record '" + part.source + "'");
    if (part.triangle_face.size() != part.mesh.triangles.size())
      throw InputError("part record '" + part.source + "': " + std::to_string(part.triangle_face.size()) +
                       " face ids for " + std::to_string(part.mesh.triangles.size()) + " triangles");
    for (int f : part.triangle_face)
      if (f >= static_cast<int>(part.faces.size()))
        throw InputError("part record '" + part.source + "': face id " + std::to_string(f) + " out of range");
    part.adjacency = buildAdjacency(part.mesh, sharp_angle);
  } catch (const json::exception& e) {
    throw InputError(std::string("a part record that does not hold one: ") + e.what());
  }
  part.check = checkMesh(part.mesh);
  return part;
}

RecordBytes setupsRecord(const SetupPlan& plan) { return pack("setups", plan); }
SetupPlan setupsFromRecord(const RecordBytes& bytes) { return read<SetupPlan>("setups", bytes); }

RecordBytes roughingRecord(const RoughingStage& stage) { return pack("roughing", stage); }
RoughingStage roughingFromRecord(const RecordBytes& bytes) { return read<RoughingStage>("roughing", bytes); }

RecordBytes finishingRecord(const FinishingPlan& plan) { return pack("finishing", plan); }
FinishingPlan finishingFromRecord(const RecordBytes& bytes) { return read<FinishingPlan>("finishing", bytes); }

RecordBytes toolpathRecord(const Toolpath& path, const std::vector<Tool>& tools) {
  return pack("toolpath", ToolpathAndTools{path, tools});
}
ToolpathAndTools toolpathFromRecord(const RecordBytes& bytes) { return read<ToolpathAndTools>("toolpath", bytes); }

RecordBytes verifyOptionsRecord(const VerifyOptions& options) { return pack("verify options", options); }
VerifyOptions verifyOptionsFromRecord(const RecordBytes& bytes) { return read<VerifyOptions>("verify options", bytes); }

RecordBytes verificationRecord(const VerificationReport& report) { return pack("verification", report); }
VerificationReport verificationFromRecord(const RecordBytes& bytes) {
  return read<VerificationReport>("verification", bytes);
}

}  // namespace art2part
