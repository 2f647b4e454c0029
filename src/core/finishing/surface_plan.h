// Internal to surface finishing: planning the passes of one direction (the CL map, its regions, the clearance maps,
// raster and waterline passes in cutting order), shared by the 3-axis and the 5-axis operation.
#pragma once

#include <memory>
#include <vector>

#include "art2part/setup/setup_plan.h"
#include "surface_passes.h"

namespace art2part::surface {

struct Plan {
  std::vector<Vec3> vertices;            // the part's, in the drop frame
  std::unique_ptr<DropCutter> cutter;    // the tool along the frame's z against the whole part
  std::unique_ptr<Context> ctx;          // null when no face triangle faces the direction
  Ordered ordered;
  std::vector<int> faces;                // sorted, unique
  std::vector<int> planned;              // the face triangles the planner believes cut (planned_area_mm2)
  double top = 0;                        // the part's highest z in the frame
  double clearance_z = 0;                // the retract height
  double short_link = 0;                 // mm
};

// Plans the passes of `faces` from `frame.z` (checks the tool, faces and options; fills the result's stepover, height
// step, radius, areas, counts and seconds_map). `body`: keep the shank and holder clear by the clearance maps (3-axis),
// of the part grown by the skin and of `stock_beyond` (what roughing left in `frame` beyond the skin, top down; may be
// empty);
// without it cut points are not checked for the body and no clearance maps are made (5-axis tilts instead).
Plan planPasses(const Part& part, const std::vector<int>& faces, const SetupFrame& frame, const Tool& tool,
                const SurfaceFinishingOptions& options, bool body, const std::vector<SlabState>& stock_beyond,
                SurfaceFinishingResult& result);

// Per face of the part, its B-rep radius of curvature where it may be concave (spheres, cylinders, cones, tori);
// infinity for planes, mesh regions and convex faces.
std::vector<double> faceConcaveRadii(const Part& part);
std::vector<int> checkedFaces(const Part& part, const std::vector<int>& faces);  // sorted, unique; throws InputError
void checkOptions(const SurfaceFinishingOptions& options);                       // throws InputError

}  // namespace art2part::surface
