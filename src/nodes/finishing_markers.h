// Finishing over ROS: the checks of a plan_finishing goal, its result, and the rviz picture of the finishing paths (by
// operation kind) and of the tool direction chosen for each face. Thin functions of plain data, testable without a node.
#pragma once

#include <string>

#include <art2part/PlanFinishingAction.h>

#include <visualization_msgs/MarkerArray.h>

#include "art2part/plan/plan_part.h"

namespace art2part {

constexpr int kDefaultFinishingLevel = 3;

// The plan's options from a goal: mode ("" = 3axis), level (0 = 3, else 1..7), allowance_m (0 = 0.3 mm, at most
// 5 mm: a larger value is a unit slip), scallop_m (0 = 0.01 mm, at most 1 mm). Verification is left to the
// verification node. Throws InputError naming the field and its range.
PlanOptions finishingPlanOptionsFrom(const PlanFinishingGoal& goal);

// The finishing operations of the plan (roughing's are left out), their points, the faces and the figures.
void fillFinishingResult(const Part& part, const PlanResult& plan, PlanFinishingResult& result);

// The finishing operations' points in order (toolpaths.csv of the finishing alone), and the tools they use.
Toolpath finishingToolpath(const PlanResult& plan);

// DELETEALL first, then per finishing operation i: ns "finishing_<kind>" (id i) a LINE_LIST of its feed moves in the
// kind's colour (face_mill blue, side_mill green, contour teal, drill red, helix orange, surface_3axis purple,
// surface_5axis magenta, rest yellow), and ns "finishing_rapids" (id i) its rapids thin and grey; then per face finished
// along a direction, ns "face_directions" (id = face), an ARROW from the face's centroid along the tool axis, as long as
// a twentieth of the part's diagonal. Metres, in frame_id.
visualization_msgs::MarkerArray finishingMarkers(const Part& part, const PlanResult& plan, const std::string& frame_id);

}  // namespace art2part
