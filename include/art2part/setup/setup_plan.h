// Setup planning (thesis 3.3): from the visibility cones of a part to the fewest orientations (setups) from which the
// whole part can be machined, biased towards directions parallel or perpendicular to its flat faces, each with a
// frame and the faces and triangles it machines; plus what no setup reaches.
#pragma once

#include <string>
#include <vector>

#include "art2part/common/progress.h"
#include "art2part/geometry/part.h"
#include "art2part/setup/minimum_cover.h"
#include "art2part/visibility/analysis.h"

namespace art2part {

enum class MachineMode { ThreeAxis, FiveAxis };
MachineMode parseMachineMode(const std::string& text);  // "3axis" | "5axis"; throws InputError
const char* machineModeName(MachineMode mode);           // "3axis" | "5axis"

struct SetupOptions {
  MachineMode mode = MachineMode::ThreeAxis;
  // 5-axis: the tool may tilt up to this angle from the setup direction (a trunnion's +-110 deg A with unlimited C
  // reaches a cap of half-angle 110 deg around the table normal). Ignored in 3-axis mode.
  double max_tilt_deg = 110.0;
  bool parallel_perpendicular = true;  // the PP bias of 3.3.2 (multi-valued matrix)
  double pp_angle_deg = 10.0;          // "square": within this of the face normal, or within this of the face plane
  double time_limit_s = 5.0;           // for the exact search on the cyclic core
};

struct SetupFrame {
  Vec3 origin = Vec3::Zero();  // part frame, mm: on the top of the part (highest point along z), over its box centre
  Vec3 x = Vec3::UnitX(), y = Vec3::UnitY(), z = Vec3::UnitZ();  // right-handed, orthonormal; z = setup direction
};

struct Setup {
  int direction = -1;        // index into the DirectionSet the plan was made on
  bool special = false;      // a special direction of the part (face normal, cylinder axis, edge)
  SetupFrame frame;
  std::vector<int> faces;      // faces machined entirely from this setup (every face appears in at most one setup)
  std::vector<int> triangles;  // triangles machined from this setup (each machinable triangle in exactly one setup)
  int reachable_triangles = 0; // triangles this setup could reach (more than it is assigned)
  double square_face_area = 0; // mm^2 of flat faces it sees whole and square (the PP "2" entries it earns)
  // A setup added beyond the minimum cover so that faces get the finish their shape asks for (finishing_setups.h):
  // its faces and triangles stay with the cover's setups (empty here); it finishes these faces.
  bool for_finishing = false;
  std::vector<int> finishing_faces;
};

struct SetupPlan {
  MachineMode mode = MachineMode::ThreeAxis;
  double max_tilt_deg = 0;
  std::vector<Setup> setups;             // most assigned area first; frame names setup_0, setup_1, ... Setups added for
                                         // finishing come last (Setup::for_finishing)
  std::vector<int> unmachinable_triangles;  // reached by no direction
  std::vector<int> unmachinable_faces;      // faces with at least one unmachinable triangle
  std::vector<int> split_faces;             // faces no single chosen setup reaches whole: their triangles are shared out
  bool proven_minimal = false;
  bool bonus_proven_best = false;
  int greedy_setups = 0;                 // what greedy set cover needs on the same matrix, for comparison
  CoverStats cover;
  double seconds_reach = 0, seconds_cover = 0, seconds_assign = 0;
  bool cancelled = false;  // the progress sink asked to stop: no setups (the cover was not finished)
};

// What each setup can reach: a triangle x direction matrix like the visibility map. 3-axis: the visibility map
// itself. 5-axis: triangle t is reachable from setup direction s when some direction of t's cone lies within
// max_tilt_deg of s.
BitMatrix reachMatrix(const VisibilityResult& visibility, const SetupOptions& options);

// The multi-valued matrix of 3.3.2 as a cover problem: coverers = the reach matrix; one bonus item per plane face
// that some direction sees whole and square (angle to the face normal below pp_angle_deg or above 90 - pp_angle_deg),
// earned by exactly those directions, weighted by the face's area.
CoverProblem setupCoverProblem(const Part& part, const VisibilityResult& visibility, const BitMatrix& reach,
                               const SetupOptions& options);

// The frame of a setup along direction z: x along the part's dominant straight feature perpendicular to z (plane
// face normals, cylinder axes and long straight edges, weighted by area or length), origin on top of the part.
SetupFrame setupFrame(const Part& part, const Vec3& z);

// The whole stage: reach, minimum cover, frames, face and triangle assignment. Throws InputError when the visibility
// result does not belong to the part (triangle counts differ) or options are out of range. Reports to `progress`
// (stage "setups") before each step and at least every kSetupReportSeconds during the cover search, the fraction the
// share of its time limit spent; when it asks to stop, returns within a second with no setups and `cancelled` set.
constexpr double kSetupReportSeconds = 0.25;
SetupPlan planSetups(const Part& part, const VisibilityResult& visibility, const SetupOptions& options = {},
                     const ProgressSink& progress = {});

}  // namespace art2part
