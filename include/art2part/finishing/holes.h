// Holes (thesis 4.3.2, "the special case of drilled holes"): a hole is the ordered run of faces along one axis -
// cylinders, cones, flat bottoms, tori - from its mouth down. One whose diameter is a drill's (within a tolerance),
// whose bottom is through, flat or the cone of that drill's point, and which the drill reaches, is drilled: spot,
// then drill, pecking past a depth of a few diameters; its volume is kept out of roughing (holePlugs) so the drill
// meets solid stock. Other round holes an end mill fits get helical interpolation. Counterbores and countersinks are
// found along the axis. Holes with the same signature (diameter, depth, bottom) are one group: one tool load.
//
// Everything is in the part frame, mm. Depths are measured down the axis from the mouth.
//
// Recognition works on the faces and their triangles: B-rep faces (exact surfaces) or a mesh's segmented faces (fitted
// surfaces, looser tolerances). Extents along the axis come from the faces' triangles, so they are exact at the
// tessellation's vertices (B-rep: the faces' boundary edges are tessellated on the true edges).
// Reach is checked against the part itself, not assumed: findHoles measures, around each hole's axis, how far the
// part's material is from the axis in bands above the mouth (free_radius) and below the far end (free_beyond), and
// chooseHoleMethod keeps the whole tool (flutes, shank, holder) inside those bounds and inside the hole at full depth.
#pragma once

#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "art2part/geometry/part.h"
#include "art2part/tooling/tool.h"
#include "art2part/tooling/toolpath.h"

namespace art2part {

enum class HoleSegmentKind { Cylinder, Cone, Flat, Torus, Sphere };
const char* holeSegmentKindName(HoleSegmentKind kind);  // cylinder | cone | flat | torus | sphere

// A stretch of a hole along its axis: one surface, made of one or more faces (a cylinder split in two halves, as
// STEP files often have, is one segment of two faces).
struct HoleSegment {
  HoleSegmentKind kind = HoleSegmentKind::Cylinder;
  std::vector<int> faces;   // the part's faces on this surface, ascending
  double from = 0, to = 0;  // mm down the axis from the mouth, from <= to (a flat: from == to)
  double diameter_from = 0, diameter_to = 0;  // at `from` and `to` (a flat: outer and inner diameter, inner 0 when it
                                              // closes the hole; a cone's apex: 0)
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
  Vec3 mouth = Vec3::Zero();   // on the axis, in the plane where the hole opens (its top: the highest rim point)
  double diameter = 0;         // of the main bore: the deepest cylinder that reaches the bottom or the far end
  double bore_start = 0;       // mm from the mouth to where the main bore begins (under a counterbore or countersink)
  double depth = 0;            // mm from the mouth to the end of the main bore's full diameter (where a cone starts)
  double total_depth = 0;      // mm from the mouth to the deepest point (a cone's apex, the far end of a through hole)
  HoleBottom bottom = HoleBottom::Through;
  double point_angle_deg = 0;  // Cone bottom: the included angle (118 for a 59 deg half-angle)
  double counterbore_diameter = 0, counterbore_depth = 0;  // a wider cylinder at the mouth with a flat step; 0: none
  double countersink_angle_deg = 0, countersink_diameter = 0;  // a cone opening at the mouth; 0: none
  double arc_deg = 360;        // how far round the axis the main bore's faces reach (at least HoleOptions::min_arc_deg)
  double radial_deviation = 0; // mm, the largest distance of the main bore's vertices from its cylinder: how well the
                               // diameter is known (B-rep: ~0; a float STL's segmented face: ~1e-5; a loose fit: more)
  std::vector<HoleSegment> segments;  // mouth first (by `from`, then `to`)
  std::vector<int> faces;             // every face of the hole (those of its segments), ascending
  std::vector<int> bore_faces;        // the faces a drill or end mill of the bore's diameter makes: the main bore from
                                      // bore_start down and the bottom (not counterbores nor countersinks)
  // Equal for holes one tool load makes: "d8.380 z25.000 cone118 cb0 cs0" (diameter and depths to 1 um; a
  // counterbore "cb14.000x8.000", diameter x depth; a countersink "cs90x12.000", angle x diameter).
  std::string signature;
  // The part around the axis. free_radius[k]: the least distance from the axis of the part's material between
  // k * clearance_step and (k + 1) * clearance_step above the mouth (infinity: none within clearance_radius). The
  // hole's own faces lie below the mouth and so never count.
  std::vector<double> free_radius;
  double clearance_step = 1.0;  // mm, the bands of free_radius
  // Through holes: how far below the far end the axis's neighbourhood of the bore's radius is free of material, mm,
  // to band resolution and never overstated (infinity: nothing within clearance_height). 0 for a blind hole.
  double free_beyond = 0;
};

struct HoleOptions {
  double diameter_tolerance = 0.02;       // mm: a drill matches a bore this close to its diameter...
  double measurement_credit = 0.005;      // ...plus twice its radial_deviation up to this (a mesh's vertices are floats:
                                          // 8.38 mm from an STL must match 8.4 as from the STEP)
  double point_angle_tolerance_deg = 0.5; // a cone bottom matches a drill point this close to its angle
  double axis_tolerance_deg = 0.1;        // faces of one hole share their axis within this...
  double axis_line_tolerance = 0.01;      // ...and their axis line within this many mm (radii equal within it too)
  // Segmented mesh faces are fitted, not exact: their axes within max(axis_tolerance_deg, this)...
  double segmented_axis_tolerance_deg = 1.0;
  double segmented_line_ratio = 0.02;     // ...and lines and radii within max(axis_line_tolerance, this x radius)
  double min_arc_deg = 300;               // a cylinder reaching less far round its axis is not a hole (fillet, slot end)
  double peck_ratio = 3.0;                // peck (G83) deeper than this many diameters; drill straight (G81) otherwise
  bool spot_drill = true;                 // centre each drilled hole with the library's spot drill first
  double spot_undersize = 0.5;            // mm: the spot's chamfer is the bore's diameter less this (at most the spot's)
  double retract_height = 2.0;            // mm above the mouth: the R plane of the drilling cycle
  double breakthrough = 1.0;              // mm a drill's full diameter (an end mill's bottom) goes past a through
                                          // hole's far end, when free_beyond allows
  double holder_margin = 0.5;             // mm between shank or holder and the part (and flutes and the part above
                                          // the mouth)
  double helix_pitch_ratio = 0.1;         // helical milling: mm of descent per turn, of the end mill's diameter
  double helix_tool_min = 0.5, helix_tool_max = 0.8;  // helical milling: end mill diameter, of the hole's
  double helix_chord = 0.002;             // mm: the helix's chords lie inside its circle by at most this
  double clearance_step = 1.0;            // mm: the bands of Hole::free_radius (and of free_beyond)
  double clearance_height = 250.0;        // mm above the mouth (and below a through hole's far end) that is measured
  double clearance_radius = 40.0;         // mm from the axis: material farther counts as none (wider than any holder:
                                          // the library's widest is 63 mm)
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
  bool peck = false;   // Drill: its feed from the R plane (tip_depth + retract_height) is longer than peck_ratio x D
  double tip_depth = 0;   // mm below the mouth the tool's tip reaches (Drill: its point; Helix: its bottom)
  double spot_depth = 0;  // mm below the mouth the spot drill's tip reaches
  // None: why, with diameter and depth ("no drill within 0.02 mm of 8.38 mm", "cone bottom 120 deg: no drill point
  // matches", "27 mm deep: longest 8.4 mm drill reaches 20 mm", ...). Drill or Helix: what the method leaves
  // (a flat bottom drilled to the floor leaves the ring its point does not reach), or empty.
  std::string reason;
};

// Every hole of the part: concave cylinders (holes, not bosses) grouped with the faces that continue them along the
// same axis line (cones, flat bottoms, tori, spheres, counterbores, countersinks), ordered from the mouth down. A
// cylinder split in two half faces (as STEP files often have) is one hole. Bosses and partial cylinders (an arc under
// min_arc_deg round their axis: fillets, slots' ends) are not holes. A plane belongs to a hole when it is square to the
// axis and lies within a coaxial cylinder of the hole on the side its normal points to (a flat bottom, a counterbore's
// step), never the face the hole opens in. The bottom is the face the axis pierces; with none the hole is through, its
// mouth the end with the counterbore or countersink, else the end facing +z (then +x, +y), unless material lies right
// past its far end within the bore (free_beyond 0): then its bottom is Other. Never throws on a part's
// data (faces without triangles, degenerate axes are skipped). Cost: O(holes x triangles) for the clearance bands.
std::vector<Hole> findHoles(const Part& part, const HoleOptions& options = {});

// A through hole seen from its other end (a setup that reaches only that end): axis and mouth there, segments, bore,
// counterbore and countersink, free_radius and free_beyond measured again (a hole counterbored at its first mouth
// then has the counterbore as its deepest cylinder: no drill passes the bore before it). Throws InputError for a hole
// that is not through or whose faces are not the part's.
Hole reversedHole(const Part& part, const Hole& hole, const HoleOptions& options = {});

// The method for one hole with the library's tools (drills: type drill with a point other than a spot drill's 90 deg;
// helical milling: flat end mills). A drill must match the bore's diameter and the bottom (any point for a through
// hole, a point within the tolerance for a cone bottom; a flat bottom is helix-milled when an end mill can, else drilled
// to the floor with the ring its point leaves named in `reason`), and reach: flute length >= the cut below bore_start,
// and at full depth the tool (shank and holder with holder_margin) inside the hole below the mouth and clear of the
// part's material above it (Hole::free_radius); a through hole's breakthrough must fit in free_beyond. Among drills
// that can, the closest diameter, then the closest point, then the shortest flutes. Spot: the library's 90 deg drill.
HoleMachining chooseHoleMethod(const Hole& hole, const ToolLibrary& library, const HoleOptions& options = {});

// Closed, outward-oriented solids filling the main bore of each hole whose method is Drill or Helix (from bore_start to
// the depth, then the bottom cone or flat; a through hole to its far end), in the part frame: added to the part for
// roughing, so roughing leaves the holes for the drill. The bore is a prism INSCRIBED in its circle (vertices on it,
// chords inside by at most 0.01 mm): roughing may take the slivers between, which the drill takes anyway.
// Throws InputError when methods and holes differ in number.
Mesh holePlugs(const std::vector<Hole>& holes, const std::vector<HoleMachining>& methods);

// The height, along a run's axis as Vec3::dot(axis) measures it, at which the tool may cross straight from over the
// R plane point `from` to over `to`: in [lowest, level], `level` where nothing lower is proven clear. The run's
// drill goes up its hole's axis to that height, across, and down the next one's: the columns over the R planes up to
// the clearance level are the holes' own to keep clear (chooseHoleMethod, StockAfterRoughing::clearOverHole).
using HoleLink = std::function<double(const Vec3& from, const Vec3& to, double lowest, double level)>;
// Every crossing at the clearance level.
double linkAtClearanceLevel(const Vec3& from, const Vec3& to, double lowest, double level);

// The cutter locations of one group of holes (same method and tool) made with `tool` in setup `setup` whose direction
// is the holes' axis: in the order given (travelOrder's is the caller's choice), for each a rapid down to the R plane
// (retract_height over its mouth; under a counterbore or countersink, down to retract_height over the bore's start
// where `link` proves the whole tool may stand there: the drill is not fed through the counterbore's air), a feed
// straight down the axis to the depth, a rapid back to the R plane. The run
// starts and ends at the clearance level (`clearance_above` mm over the highest mouth along the axis, raised over the
// part's material measured round the holes, free_radius, + holder_margin: the caller passes enough to clear the part
// beyond clearance_radius, e.g. the setup's stock top + its clearance - the highest mouth); between holes the tool goes
// up to the height `link` gives, across and down (by default at the clearance level). The depth: the drill's tip as
// chooseHoleMethod puts it (tip_depth: the cone's apex or the shoulder at the bore's end, whichever is shallower, for a
// cone bottom; the floor for a flat one; the far end + point length + breakthrough, within free_beyond less
// holder_margin, for a through hole); `spot`: spotDepth. The post turns each hole into G81 / G83 (G98 back to the
// height the tool came down from when it leaves at that height, else G99). Throws InputError when the holes' axes
// differ by more than axis_tolerance_deg, or `tool` is not a drill.
Toolpath drillingPath(const std::vector<Hole>& holes, const Tool& tool, bool spot, int setup, double clearance_above,
                      const HoleOptions& options = {}, const HoleLink& link = linkAtClearanceLevel);
// Helical milling of one hole with a flat end mill: from the clearance height (as drillingPath's) down to the R plane
// over the centre, out to radius (bore - tool) / 2, down a helix of helix_pitch_ratio x D per turn to the floor (a
// through hole: the far end + breakthrough, within free_beyond less holder_margin), a full circle there, back to the
// centre, up. Chords inside the circle by at most helix_chord. Throws InputError for a tool that is not a flat end
// mill narrower than the bore.
Toolpath helixPath(const Hole& hole, const Tool& tool, int setup, double clearance_above, const HoleOptions& options = {});
// Helical milling of `holes` (one axis) one after the other, from and back to drillingPath's one clearance level over
// them all, crossing between holes as drillingPath does: level at the height `link` gives, never slanted from a high
// mouth's level down to a low one's through what stands between. Throws as drillingPath and helixPath do.
Toolpath helixPaths(const std::vector<Hole>& holes, const Tool& tool, int setup, double clearance_above,
                    const HoleOptions& options = {}, const HoleLink& link = linkAtClearanceLevel);

// Depths below the mouth that the tools' tips reach (what drillingPath and helixPath cut to, and chooseHoleMethod
// checks). A drill: a cone bottom's apex or, when shallower, the depth that puts the drill's shoulder at the bore's end
// (a point up to the tolerance off the cone's angle then leaves a sliver and never cuts the cone); a flat bottom's
// floor; a through hole's far end + the point's length + breakthrough, cut short at free_beyond - holder_margin.
double drillDepth(const Hole& hole, const Tool& drill, const HoleOptions& options = {});
// A flat end mill: the floor; a through hole's far end + breakthrough, within free_beyond - holder_margin.
double helixDepth(const Hole& hole, const HoleOptions& options = {});
// A spot drill: its cone makes a chamfer of the bore's diameter less spot_undersize (at most the spot's diameter) at
// bore_start, never deeper than the hole's total depth.
double spotDepth(const Hole& hole, const Tool& spot, const HoleOptions& options = {});

}  // namespace art2part
