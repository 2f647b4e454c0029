// 5-axis voxel roughing (thesis 4.1.3-4.1.5): where a setup's 3-axis roughing left stock that a tilted tool reaches
// (under overhangs, beside steep walls), clear it with the tool axis chosen per voxel.
//  - Voxels: the material each slab still holds after the 3-axis operations (their SlabStates, minus the part's
//    section in the slab grown by the allowance), sampled on rows a step-over apart, a point every half step-over,
//    the tool tip at the slab's bottom.
//  - Orienting the tool in a voxel (4.1.3.1): the voxel's visibility cone (point_cones.h), thinned on the
//    triangulated sphere restricted to the machine's reach around the setup direction (cone_thinning.h): the access
//    direction.
//  - Profiling (4.1.3.2): the tool, shank and holder posed there and tested against the part with FCL, tilted away by
//    the zones that collide, else the voxel is dead (tool_profiling.h). The tool's shank and holder must also stay
//    out of stock left in the slabs above (the holder-interference check of the thesis's future work).
//  - The tool's section in the slab plane is an ellipse, r / cos(theta) along the tilt: a voxel whose ellipse (grown
//    by the allowance) meets the part's section is refused before profiling (the non-linear offset of 4.1.5).
//  - Voxel-to-voxel transitions (4.1.4): neighbours on a row are joined when their cones share more than a threshold
//    solid angle and the tool posed half-way (axes interpolated) is clear; dead voxels and discontinuities end a pass.
//  - Paths (4.1.5): zig-zag passes along the rows with the axis per point; each pass is entered along its first
//    axis from the clearance plane, from a voxel in air when the pass has one at either end (else a plunge, counted),
//    and left along its last axis; between passes the tool moves over the clearance plane.
#pragma once

#include <vector>

#include "art2part/roughing/roughing.h"

namespace art2part {

struct VoxelRoughingStats {
  int voxels = 0;        // sampled points of material left by the 3-axis operations
  int live = 0;          // of those, reached by the chosen tool at some posture
  int dead = 0;          // no posture: no direction in reach, profiling failed, or the holder meets stock above
  int broken_transitions = 0;  // neighbours both live but not joined (cones apart, or the tool collides half-way)
  int passes = 0;
  double mean_tilt_deg = 0, max_tilt_deg = 0;  // of the live voxels' axes from the setup direction
  double seconds = 0;
};

// One operation over what `left` (the SlabStates of the setup's last 3-axis operation) still holds; `tools` the
// candidates, largest first (the largest that reaches at least options.clearing.tool_area_fraction of what the smallest
// does
// is used). An operation with an empty path when nothing is reachable.
RoughingOperation voxelRoughSetup(const Part& part, const Setup& setup, int setup_index,
                                  const std::vector<const Tool*>& tools, const RoughingOptions& options,
                                  const std::vector<SlabState>& left, VoxelRoughingStats* stats = nullptr);

}  // namespace art2part
