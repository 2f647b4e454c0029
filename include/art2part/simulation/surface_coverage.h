// Which part of the part's surface the cutting moves bring within a tolerance: the area figure of finishing.
//
// The surface is sampled (points spread over every triangle at about `sample_spacing`, each standing for its share
// of the triangle's area); a sample is covered when some pose of a feed move puts the flutes of the tool within
// `tolerance` of it: the distance from the point to the tool's cutting solid (the solid of revolution of its flutes,
// tool_solid.h), in the tool's frame the distance from (h, rho) to the outline, least over the poses. Poses are taken
// along every feed move at most `pose_step` apart, so the distance is over-estimated by at most pose_step^2 / 8 r (a
// flat's rim, a ball's sphere of radius r): 0.0004 mm at 0.1 mm on a 3 mm ball. A scallop between passes counts as
// what it is: a sample at the bottom of a cusp valley is covered, one on a ridge higher than the tolerance is not.
// Rapids never cover. Samples inside the tool (gouged) count as covered here; gouges are the verification's to find.
#pragma once

#include <vector>

#include "art2part/geometry/face.h"
#include "art2part/geometry/mesh.h"
#include "art2part/tooling/tool.h"
#include "art2part/tooling/toolpath.h"

namespace art2part {

struct CoverageOptions {
  double tolerance = 0.05;      // mm: covered when a cutting pose comes this close
  double sample_spacing = 0;    // mm between samples; 0 = automatic (about 400k samples over the area, 0.2..2 mm)
  double pose_step = 0.1;       // mm between poses along a feed move
  int threads = 0;              // 0 = the hardware's
};

struct FaceCoverage {
  int face = -1;
  SurfaceType type = SurfaceType::Other;
  double area_mm2 = 0, covered_mm2 = 0;
  int samples = 0, covered_samples = 0;
};

struct TypeCoverage {
  SurfaceType type = SurfaceType::Other;
  double area_mm2 = 0, covered_mm2 = 0;
};

struct CoverageReport {
  double area_mm2 = 0, covered_mm2 = 0;  // the whole surface
  std::vector<FaceCoverage> faces;       // by face id (one per face of `faces`)
  std::vector<TypeCoverage> types;       // by surface type, types present only
  long samples = 0;
  long long pose_queries = 0;
  double sample_spacing_mm = 0, seconds = 0;
  double share() const { return area_mm2 > 0 ? covered_mm2 / area_mm2 : 0; }
};

// `triangle_face` and `faces` as in Part (faces may be empty: everything is face -1, type Other). Throws InputError for
// a tool id the path uses that `tools` lacks.
CoverageReport surfaceCoverage(const Mesh& mesh, const std::vector<int>& triangle_face, const std::vector<Face>& faces,
                               const Toolpath& path, const std::vector<Tool>& tools, const CoverageOptions& options = {});

}  // namespace art2part
