// Roughing over ROS: the checks and conversions of a plan_roughing goal, the result, and the rviz picture of a roughing
// plan. Thin functions of plain data, so they can be tested without a node.
#pragma once

#include <string>
#include <vector>

// The message is MachiningOperation: the core's struct art2part::RoughingOperation (roughing.h) keeps the short name.
#include <art2part/MachiningOperation.h>
#include <art2part/PlanRoughingAction.h>

#include <visualization_msgs/MarkerArray.h>

#include "art2part/geometry/part.h"
#include "art2part/roughing/roughing.h"
#include "art2part/setup/setup_plan.h"
#include "art2part/tooling/tool.h"
#include "art2part/visibility/analysis.h"

namespace art2part {

// ---- the goal ----------------------------------------------------------------------------------------------------

constexpr int kDefaultRoughingLevel = 3;

// Setup options of a goal: mode "" = 3axis, else 3axis | 5axis. Throws InputError naming the mode otherwise.
SetupOptions roughingSetupOptionsFrom(const PlanRoughingGoal& goal);

// Visibility options: level 0 = 3, else 1..7. Throws InputError for a level out of range.
VisibilityOptions roughingVisibilityOptionsFrom(const PlanRoughingGoal& goal);

// Roughing options in mm: allowance_m (0 = 0.3 mm), stepdown_m (0 = the tool's), tool, rest_pass. The tool must be
// a flat or bull end mill of `library` (read from `library_path`, named in the message). Throws InputError naming
// the field for a length outside its range (request_limits.h), an unknown tool, a tool that cannot rough.
RoughingOptions roughingOptionsFrom(const PlanRoughingGoal& goal, const ToolLibrary& library,
                                    const std::string& library_path);

// ---- the result --------------------------------------------------------------------------------------------------

// Operation `id` of a plan whose points start at `first_point` of the result's path arrays.
MachiningOperation toOperationMsg(const RoughingOperation& op, int id, int first_point);

// Operations, tips (metres) and moves of the result from a plan whose ops and setups are numbered already.
void fillResult(const RoughingPlan& plan, PlanRoughingResult& result);

// The plan's operations' paths, in order (what toolpaths.csv holds).
Toolpath wholeToolpath(const RoughingPlan& plan);

// The tools the operations use, in order of first use (what tools.json holds). Throws InputError for an id the
// library lacks.
std::vector<Tool> toolsUsed(const RoughingPlan& plan, const ToolLibrary& library);

// toolpaths.csv and tools.json in `folder` (created when missing). Throws InputError when it cannot be written.
void writeRoughingFiles(const RoughingPlan& plan, const ToolLibrary& library, const std::string& folder);

// ---- rviz --------------------------------------------------------------------------------------------------------

// DELETEALL first (the markers of an earlier plan go), then per operation i: ns "feed_<i>" (id 0), a LINE_LIST of its
// feed moves coloured by tool (one colour per tool id, in order of first use in the plan), and ns "rapid_<i>" (id 0),
// a thinner translucent grey LINE_LIST of its rapid moves (each left out when it has no segment); then per setup k
// that has operations, ns "slabs_<k>", one LINE_STRIP square per level (id = its rank from the top): the outline of
// the stock (the part's box + stock_margin) seen along the setup direction, at the level's height, yellow where the
// level is critical. Metres, in frame_id (the part frame); setup frame heights go through setups[k].frame.
visualization_msgs::MarkerArray roughingMarkers(const Part& part, const SetupPlan& setups, const RoughingPlan& plan,
                                                const RoughingOptions& options, const std::string& frame_id);

}  // namespace art2part
