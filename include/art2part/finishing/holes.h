// Holes (thesis 4.3.2, "the special case of drilled holes"): a hole is the ordered run of faces along one axis -
// cylinders, cones, flat bottoms, tori - from its mouth down. One whose diameter is a drill's (within a tolerance),
// whose bottom is through, flat or the cone of that drill's point, and which the drill reaches, is drilled: spot,
// then drill, pecking past a depth of a few diameters; its volume is kept out of roughing (holePlugs) so the drill
// meets solid stock. Other round holes an end mill fits get helical interpolation. Counterbores and countersinks are
// found along the axis. Holes with the same signature (diameter, depth, bottom) are one group: one tool load.
//
// Everything is in the part frame, mm.
#pragma once

#include <string>
#include <vector>

#include "art2part/geometry/part.h"
#include "art2part/tooling/tool.h"
#include "art2part/tooling/toolpath.h"

namespace art2part {

enum class HoleSegmentKind { Cylinder, Cone, Flat, Torus };
const char* holeSegmentKindName(HoleSegmentKind kind);  // cylinder | cone | flat | torus

// One face of a hole, as a stretch along its axis.
struct HoleSegment {
  HoleSegmentKind kind = HoleSegmentKind::Cylinder;
  int face = -1;
  double from = 0, to = 0;  // mm down the axis from the mouth, from <= to
  double diameter_from = 0, diameter_to = 0;  // at `from` and `to` (a flat: outer and inner diameter; a cone's apex: 0)
};

enum class HoleBottom {
  Through,  // open at its far end
  Flat,     // a plane square to the axis
  Cone,     // a cone closing the hole: a drill point
  Other,    // a sphere, a torus, a free-form end: no drill makes it
};
const char* holeBottomName(HoleBottom bottom);  // through | flat | cone | other

struct Hole {
  Vec3 axis = Vec3::UnitZ();   // unit, pointing out of the hole (the tool axis that makes it: tip towards spindle)
  Vec3 mouth = Vec3::Zero();   // on the axis, in the plane where the hole opens (its top)
  double diameter = 0;         // of the main bore: the deepest cylinder that reaches the bottom or the far end
  double depth = 0;            // mm from the mouth to the end of the main bore's full diameter (where a cone starts)
  double total_depth = 0;      // mm from the mouth to the deepest point (a cone's apex, the far end of a through hole)
  HoleBottom bottom = HoleBottom::Through;
  double point_angle_deg = 0;  // Cone bottom: the included angle (118 for a 59 deg half-angle)
  double counterbore_diameter = 0, counterbore_depth = 0;  // a wider cylinder at the mouth with a flat step; 0: none
  double countersink_angle_deg = 0, countersink_diameter = 0;  // a cone opening at the mouth; 0: none
  std::vector<HoleSegment> segments;  // mouth first
  std::vector<int> faces;             // every face of the hole (those of its segments)
  // Equal for holes one tool load makes: "d8.380 z25.000 cone118 cb0 cs0" (diameter and depths to 1 um).
  std::string signature;
};

struct HoleOptions {
  double diameter_tolerance = 0.02;       // mm: a drill matches a bore this close to its diameter
  double point_angle_tolerance_deg = 0.5; // a cone bottom matches a drill point this close to its angle
  double axis_tolerance_deg = 0.1;        // faces of one hole share their axis within this (and the axis line within 0.01 mm)
  double peck_ratio = 3.0;                // peck (G83) deeper than this many diameters; drill straight (G81) otherwise
  bool spot_drill = true;                 // centre each drilled hole with the library's spot drill first
  double retract_height = 2.0;            // mm above the mouth: the R plane of the drilling cycle
  double helix_pitch_ratio = 0.1;         // helical milling: mm of descent per turn, of the end mill's diameter
  double helix_tool_min = 0.5, helix_tool_max = 0.8;  // helical milling: end mill diameter, of the hole's
};

// How a hole gets made.
enum class HoleMethod {
  Drill,  // spot (optional), then the matching drill; pecked past peck_ratio diameters
  Helix,  // a flat end mill down a helix at the bore's radius, a full circle at the bottom (flat or through only)
  None,   // neither: left to the face-based finishing, reported with why
};
const char* holeMethodName(HoleMethod method);  // drill | helix | none

struct HoleMachining {
  HoleMethod method = HoleMethod::None;
  std::string drill;   // Drill: the drill's id; Helix: the end mill's id
  std::string spot;    // the spot drill's id, empty when none
  bool peck = false;   // Drill: deeper than peck_ratio diameters
  std::string reason;  // None: why (no drill within 0.02 mm of 8.38 mm, the cone is 120 deg, too deep for ..., ...)
};

// Every hole of the part: concave cylinders (holes, not bosses) grouped with the faces that continue them along the
// same axis line (cones, flat bottoms, tori, counterbores, countersinks), ordered from the mouth down. A cylinder
// split in two half faces (as STEP files often have) is one hole. Bosses and partial cylinders (an arc under 300 deg
// round their axis: fillets, slots' ends) are not holes.
std::vector<Hole> findHoles(const Part& part, const HoleOptions& options = {});

// The method for one hole with the library's tools (drills: type drill; helical milling: flat end mills). A drill
// must match the bore's diameter and the bottom (any point for a through hole, a point within the tolerance for a
// cone bottom, none for a flat one), and reach: flute length >= total depth, stickout beyond it by the holder's
// clearance over the part around the mouth.
HoleMachining chooseHoleMethod(const Hole& hole, const ToolLibrary& library, const HoleOptions& options = {});

// Closed solids filling each hole (the bore's cylinder from the mouth to its depth, the bottom cone or flat), in the
// part frame: added to the part for roughing, so roughing leaves the holes for the drill.
Mesh holePlugs(const std::vector<Hole>& holes, const std::vector<HoleMachining>& methods);

// The cutter locations of one group of holes (same signature and method) made with `tool` in setup `setup` whose
// direction is the holes' axis: in the order given (nearest neighbour from the first is the caller's choice), each a
// rapid to the R plane above its mouth, a feed straight down the axis to the depth (the drill's tip: depth + point
// length for a through hole, the cone's apex for a cone bottom), a rapid back to the R plane; between holes a rapid
// at the clearance height `clearance_above` mm over the highest mouth. The post turns each such run into G81 / G83.
// `spot`: a spot drill's run (down to the depth where its point makes a chamfer of the bore's diameter).
Toolpath drillingPath(const std::vector<Hole>& holes, const Tool& tool, bool spot, int setup,
                      double clearance_above, const HoleOptions& options = {});
// Helical milling of one hole with a flat end mill: down a helix at radius (bore - tool) / 2, then a full circle at the
// bottom, a circle back to the centre, up.
Toolpath helixPath(const Hole& hole, const Tool& tool, int setup, double clearance_above, const HoleOptions& options = {});

}  // namespace art2part
