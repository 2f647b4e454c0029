// The ranges of every number a ROS request or goal carries, in one place. ROS fields are metres, seconds and radians
// (REP 103) unless the interface says mm or deg; a range catches NaN, infinity and negatives, and also the unit slips a
// caller makes (5 m of step-down, 0.3 "m" of allowance meant as mm, a verification resolution given in metres). In
// every field here 0 keeps the default the interface documents, so 0 is always accepted; any other value must lie in
// [smallest, largest].
#pragma once

#include <string>

namespace art2part {

// What one request field accepts besides 0.
struct RequestRange {
  const char* field;       // the field as the .srv or .action names it
  double smallest;         // smallest accepted value other than 0
  double largest;          // largest accepted value
  const char* unit;        // "m", "mm", "s", "deg", "pixels", "points/s", "" for a count
  const char* zero_means;  // what 0 gives, as the interface documents it
};

namespace request_limits {

// part_server load_part: STEP tessellation; below 1 um the mesh explodes, above 5 mm it is no longer the part.
inline constexpr RequestRange kChordalTolerance{"chordal_tolerance", 1e-6, 0.005, "m", "automatic"};
// The sphere subdivision level of every visibility analysis (4 * 4^level directions), analyseVisibility's own range.
inline constexpr RequestRange kSphereLevel{"level", 1, 7, "", "the node's default"};
// analyse_visibility's render backend: pixels per side of a view (8192^2 ids are 256 MB).
inline constexpr RequestRange kRenderResolution{"resolution", 16, 8192, "pixels", "from the triangle size"};
// plan_setups: tool tilt from the setup direction in 5-axis (below 5 deg it is radians typed as degrees), and the
// exact search's time budget.
inline constexpr RequestRange kMaxTilt{"max_tilt_deg", 5, 180, "deg", "110"};
inline constexpr RequestRange kSetupTimeLimit{"time_limit", 0.01, 600, "s", "5 s"};
// plan_roughing and plan_finishing: what roughing leaves for finishing, and the step between roughing levels.
inline constexpr RequestRange kAllowance{"allowance_m", 1e-5, 0.005, "m", "0.0003 m"};
inline constexpr RequestRange kStepdown{"stepdown_m", 1e-4, 0.05, "m", "each tool's max_stepdown"};
// plan_finishing: cusp height left on free-form faces.
inline constexpr RequestRange kScallop{"scallop_m", 1e-6, 0.001, "m", "0.00001 m"};
// verify_toolpaths (sizes in mm, as the plan folder's files): lattice spacing, depth that counts, stock margin.
inline constexpr RequestRange kVerifyResolution{"resolution", 0.01, 10, "mm", "automatic"};
inline constexpr RequestRange kVerifyTolerance{"tolerance", 1e-4, 1, "mm", "0.01 mm"};
inline constexpr RequestRange kStockMargin{"stock_margin", 0.01, 100, "mm", "2 mm"};
// run_program: trajectory points per second.
inline constexpr RequestRange kTrajectoryRate{"rate", 1, 1000, "points/s", "the node's ~rate"};
// follow_joint_trajectory: per joint, m for slides and rad for rotary joints (above 1 it is mm or deg).
inline constexpr RequestRange kPathTolerance{"path_tolerance", 1e-9, 1, "m or rad", "not checked"};
inline constexpr RequestRange kGoalTolerance{"goal_tolerance", 1e-9, 1, "m or rad", "not checked"};

}  // namespace request_limits

// The reason `value` is refused, or "" when it is 0 or within the range. The reason names the field, the value, the
// range with its unit and what 0 gives; for lengths it adds which unit the interface uses.
std::string rangeViolation(double value, const RequestRange& range);

// `value` when rangeViolation finds nothing; otherwise throws InputError with the reason.
double checkedRequestValue(double value, const RequestRange& range);

}  // namespace art2part
