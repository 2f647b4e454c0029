// Which part of the part's surface the cutting moves bring within a tolerance: the area figure of finishing
// (issue 17, "Figures to reach").
//
// The surface is sampled: every triangle is split by longest-edge bisection until each piece has an area of at most
// sample_spacing^2 and no edge longer than 4 * sample_spacing (slivers are cut along their length, so a long thin
// triangle still gets samples all along it); a sample sits at each piece's centroid and stands for that piece's area.
// Deterministic: the same mesh gives the same samples. A sample is covered when some pose of a feed move puts the
// flutes of the tool within `tolerance` of it: the exact distance from the point to the tool's cutting solid (the
// union of the ToolPieces of zone Flutes, tool_solid.h), which for a solid of revolution is, in the tool's frame, the
// planar distance from (h, rho) (height above the tip, distance from the axis) to each piece's outline (a trapezoid
// for a frustum, a disc cut by two chords for a sphere zone), least over the pieces and the poses. Poses are taken
// along every feed move at most `pose_step` apart (the tip's travel plus the turn of the axis times the flutes'
// height), both ends included, so the distance is over-estimated by at most pose_step^2 / 8 r (a flat's rim, a
// ball's sphere of radius r): 0.0004 mm at 0.1 mm on a 3 mm ball.
// A scallop between passes counts as what it is: a sample at the bottom of a cusp valley is covered, one under a ridge
// is covered when the tool came within the tolerance of it. For a ball of radius R at stepover s on a plane that
// distance is sqrt(R^2 + s^2/4) - R, a little under the ridge's height R - sqrt(R^2 - s^2/4) (1.4 % under at
// R = 3, s = 1): the coverage reads the distance, scallop_probe.h reads the height.
// Rapids never cover. Samples inside the tool (gouged) count as covered here; gouges are the verification's to find.
//
// Speed: samples sit in a uniform grid of cells; the feed moves are cut into chunks of about a flute radius of travel;
// for each chunk only the cells inside its swept box (grown by the tolerance) are visited, and per sample only the
// poses whose bounding cylinder (radius of the flutes plus the tolerance) holds it are measured (an interval of poses
// per straight move, solved from a quadratic). A covered sample leaves its cell's list. Threads own interleaved slabs
// of cells, each going over every chunk, so no sample is touched by two threads and the result does not depend on the
// thread count.
#pragma once

#include <vector>

#include "art2part/geometry/face.h"
#include "art2part/geometry/mesh.h"
#include "art2part/tooling/tool.h"
#include "art2part/tooling/toolpath.h"

namespace art2part {

struct CoverageOptions {
  double tolerance = 0.05;      // mm: covered when a cutting pose comes this close
  // mm (pieces of at most spacing^2); 0 = automatic: sqrt(area / 400k) kept within 0.2..2 mm, so at least 400k
  // samples below the caps; small triangles and slivers add more (CTC-02's 122k-triangle mesh: 2.5 M at 2 mm).
  double sample_spacing = 0;
  double pose_step = 0.1;       // mm between poses along a feed move
  int threads = 0;              // 0 = the hardware's
};

struct FaceCoverage {
  int face = -1;
  SurfaceType type = SurfaceType::Other;
  double area_mm2 = 0, covered_mm2 = 0;  // of the samples' pieces (= the face's triangles' area)
  int samples = 0, covered_samples = 0;
  double share() const { return area_mm2 > 0 ? covered_mm2 / area_mm2 : 0; }
};

struct TypeCoverage {
  SurfaceType type = SurfaceType::Other;  // triangles of no face (face -1) count as Other
  double area_mm2 = 0, covered_mm2 = 0;
  double share() const { return area_mm2 > 0 ? covered_mm2 / area_mm2 : 0; }
};

struct CoverageReport {
  double area_mm2 = 0, covered_mm2 = 0;  // the whole surface
  std::vector<FaceCoverage> faces;       // by face id (one per face of `faces`)
  std::vector<TypeCoverage> types;       // by surface type (enum order), types present only
  long samples = 0;
  long long poses = 0;                   // poses along the feed moves (each move's ends included)
  long long pose_queries = 0;            // exact sample-to-pose distances measured
  double sample_spacing_mm = 0, seconds = 0;
  double share() const { return area_mm2 > 0 ? covered_mm2 / area_mm2 : 0; }
};

// `triangle_face` and `faces` as in Part (both may be empty: everything is face -1, type Other; a triangle beyond
// triangle_face's end is face -1). Throws InputError for a tool id the path uses that `tools` lacks (naming the row),
// a tool that cannot exist, a face id beyond `faces`, a negative tolerance or a pose step or spacing that is not
// positive (spacing 0 = automatic).
CoverageReport surfaceCoverage(const Mesh& mesh, const std::vector<int>& triangle_face, const std::vector<Face>& faces,
                               const Toolpath& path, const std::vector<Tool>& tools, const CoverageOptions& options = {});

}  // namespace art2part
