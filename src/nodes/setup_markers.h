// Setup planning over ROS: the checks and conversions of a plan_setups request, the response, the tf2 frames
// setup_<k> and the rviz picture of a plan. Thin functions of plain data, so they can be tested without a node.
#pragma once

#include "art2part/render/palette.h"  // setupColour: one palette for pictures and rviz

#include <memory>
#include <string>
#include <vector>

// The message is MachiningSetup: the core's struct art2part::Setup (setup_plan.h) keeps the short name.
#include <art2part/MachiningSetup.h>
#include <art2part/PlanSetups.h>

#include <geometry_msgs/TransformStamped.h>
#include <visualization_msgs/MarkerArray.h>

#include <array>

#include "art2part/geometry/part.h"
#include "art2part/setup/setup_plan.h"
#include "art2part/visibility/analysis.h"

namespace art2part {

// ---- the request -------------------------------------------------------------------------------------------------

// Planner options of a request: mode ("" = 3axis), max_tilt_deg (0 = 110), time_limit (0 = 5 s). Throws InputError
// naming the field for an unknown mode, a tilt or time limit outside its range (request_limits.h).
SetupOptions setupOptionsFrom(const PlanSetupsRequest& request);

// Visibility options for the analysis done here: level 0 = 4, else 1..7; special directions unless
// no_special_directions. Throws InputError for a level out of range.
VisibilityOptions visibilityOptionsFrom(const PlanSetupsRequest& request);

// True when the request carries a visibility result (directions or bits given).
bool carriesVisibility(const PlanSetupsRequest& request);

// The visibility result of an analyse_visibility action carried by a request, rebuilt for the planner on this part:
// directions (unit, checked), special flags (given, or found by matching the part's special directions), the map
// from bits (per triangle ceil(D/8) bytes, bit d least significant first; padding ignored), unseen triangles. The
// DirectionSet's sphere (level, cells, cell areas, neighbours, cell_of) is rebuilt too when the directions are those
// of sampleSphere(L) with special directions inserted (what analyseVisibility makes); otherwise it stays empty
// (directions and special only). Throws InputError for bits without directions, bits of the wrong size, a direction
// that is not a unit vector, special flags of the wrong size.
VisibilityResult visibilityFromRequest(const Part& part, const PlanSetupsRequest& request);
// The same from the three fields of any message that carries an analyse_visibility result (visibilityFromBits, the
// core's decoding of the contract's layout).
VisibilityResult visibilityFromMessage(const Part& part, const std::vector<geometry_msgs::Vector3>& directions,
                                       const std::vector<uint8_t>& bits, const std::vector<uint8_t>& special);

// ---- the response ------------------------------------------------------------------------------------------------

// A setup frame as a pose in the part frame: position in metres, orientation the rotation whose columns are x, y, z.
geometry_msgs::Pose toPoseMsg(const SetupFrame& frame);

// Setup k of a plan made on `directions`.
MachiningSetup toMachiningSetup(const Setup& setup, int k, const DirectionSet& directions);

// Everything of the response but success, message and seconds.
void fillResponse(const SetupPlan& plan, const DirectionSet& directions, PlanSetupsResponse& response);

// ---- tf2 ---------------------------------------------------------------------------------------------------------

// The frame name of setup k: "setup_<k>".
std::string setupFrameName(int k);

// Static transforms parent -> setup_<k> for each setup, then setup_<k> for k = setups.size() .. previous_count - 1
// (frames of an earlier, bigger plan) re-parented to unused_parent with an identity pose: a static transform cannot
// be withdrawn, and listeners keep the old ones, so a stale setup_<k> is cut off from the part's tree instead
// (looking it up from `parent` fails) rather than left where an old plan put it.
std::vector<geometry_msgs::TransformStamped> setupTransforms(const std::vector<MachiningSetup>& setups, int previous_count,
                                                             const std::string& parent,
                                                             const std::string& unused_parent, const ros::Time& stamp);

// ---- rviz --------------------------------------------------------------------------------------------------------

using RgbColour = std::array<float, 3>;



// DELETEALL first (the markers of an earlier plan go), then per setup an ARROW (ns "setup_arrows", id k) from the
// centre of the part's box along its direction to a quarter box diagonal beyond the box, and a TEXT_VIEW_FACING
// "setup_<k>" (ns "setup_labels", id k) past its tip, in the setup's colour; then the part (ns "part_by_setup", id 0)
// as a TRIANGLE_LIST coloured per triangle by the setup that machines it, red where unmachinable, dark grey where in
// neither (should not happen). Metres, in frame_id. Note that the DELETEALL marker's type field is 0 (= ARROW).
visualization_msgs::MarkerArray setupMarkers(const Part& part, const SetupPlan& plan, const std::string& frame_id);

}  // namespace art2part
