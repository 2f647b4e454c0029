// Verification over ROS: the checks of a verify_toolpaths request, the verification itself (the same steps as
// `art2part verify`, src/cli/verify_command.cpp), the response and the rviz picture of the remaining stock. Thin
// functions of plain data, so they can be tested without a node.
#pragma once

#include <string>

#include <art2part/VerifyToolpaths.h>
#include <visualization_msgs/MarkerArray.h>

#include "art2part/geometry/part.h"
#include "art2part/simulation/stock_mesh.h"
#include "art2part/simulation/verify.h"

namespace art2part {

// ---- the request -------------------------------------------------------------------------------------------------

// Options of a request: resolution (0 = automatic), tolerance (0 = 0.01 mm), stock_margin (0 = 2 mm). Throws
// InputError naming the field for a number outside its range (request_limits.h): NaN, negative, metres for mm.
VerifyOptions verifyOptionsFrom(const VerifyToolpathsRequest& request);

// The part file a request names: part_file, or folder/mesh.stl when it is empty.
std::string partFileOf(const VerifyToolpathsRequest& request);

// Everything a verification leaves: the part as loaded, the report, the simulation state (for the stock mesh).
struct FolderVerification {
  Part part;
  VerificationReport report;
  VerificationState state;
};

// Reads folder/toolpaths.csv, folder/tools.json and the part, and verifies, as `art2part verify` does. Throws
// InputError for an empty or missing folder, a malformed or missing file, an unknown tool, a part that cannot be
// loaded.
void verifyFolder(const VerifyToolpathsRequest& request, FolderVerification& out);

// The same for a request that hands the plan on (toolpath_record, options_record) on `part`, the part_server's.
// Throws InputError for a record that is not one, or an empty path.
void verifyHandedOn(const VerifyToolpathsRequest& request, const Part& part, FolderVerification& out);

// ---- the response ------------------------------------------------------------------------------------------------

// passed, the counts and figures and report_json (not success, message or seconds).
void fillResponse(const VerificationReport& report, VerifyToolpathsResponse& response);

// One line: passed/FAILED, gouges (worst), collisions, leftover, moves and resolution.
std::string summaryOf(const VerificationReport& report);

// ---- rviz --------------------------------------------------------------------------------------------------------

// The remaining stock mesh of a verification (stock_mesh.h), `max_cells` along the longest side of the stock box.
StockMesh remainingStock(const FolderVerification& verification, int max_cells = 150);

// DELETEALL first (the markers of an earlier verification go), then the remaining stock (ns "remaining_stock", id 0)
// as a TRIANGLE_LIST coloured per triangle by its deviation from the part (deviationColours: the ramp up to
// max(leftover_max_mm, 10 x tolerance), red for gouges), then the listed gouges (ns "gouges", id 0, red) and
// collisions (ns "collisions", id 0, orange) as SPHERE_LISTs at their deepest points, each only when there is one.
// Metres, in frame_id. Note that the DELETEALL marker's type field is 0 (= ARROW).
visualization_msgs::MarkerArray verificationMarkers(const StockMesh& stock, const VerificationReport& report,
                                                    const std::string& frame_id);

}  // namespace art2part
