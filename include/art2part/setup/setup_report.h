// Setup plans as JSON (the `setups` array of `art2part setups --json` and of plan.json) and as text.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "art2part/setup/setup_plan.h"

namespace art2part {

// {"mode", "max_tilt_deg", "setups": [{"id", "name", "direction": [x,y,z], "direction_index", "special",
//   "frame": {"origin", "x", "y", "z"}, "faces": [...], "triangles": [...], "triangle_count", "reachable_triangles",
//   "square_face_area_mm2"}], "unmachinable_triangles", "unmachinable_faces", "split_faces", "proven_minimal",
//   "bonus_proven_best", "greedy_setups", "cover": {...stats}, "seconds": {...}}
nlohmann::json setupPlanJson(const SetupPlan& plan, const DirectionSet& directions);

// A few lines a machinist can read: one per setup (direction, faces, triangles), then what is unmachinable.
std::string setupPlanText(const Part& part, const SetupPlan& plan, const DirectionSet& directions);

}  // namespace art2part
