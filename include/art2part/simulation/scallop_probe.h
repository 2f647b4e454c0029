// Scallop heights measured by simulation in small windows: a part-wide lattice is far too coarse to see a 0.01 mm cusp
// (a pitch d misses the apex by up to (s / 2R)(d / 2), s the stepover), so the height left is measured where it
// matters, on a fine local lattice.
//
// A window is a square of side 2 * half_width around a sample point p of a face, in a frame whose z is the face's
// normal at p. Rays along that normal at `pitch` across the square: on each, the part's surface height (the mesh,
// exactly) and the lowest point the tool's flutes reach over every pose of every feed move near the window (ray
// against each piece of the tool solid, tool_solid.h, poses along a move no farther apart than the pitch): the
// material left on the ray is the difference, when the tool passed over the ray at all. The window's scallop is the
// largest over its rays (rays no pose passed over are counted apart, as "not reached"). Pitch at most a twentieth of
// the stepover keeps the measure within 10 % of the true cusp.
#pragma once

#include <cstdint>
#include <vector>

#include "art2part/geometry/mesh.h"
#include "art2part/tooling/tool.h"
#include "art2part/tooling/toolpath.h"

namespace art2part {

struct ScallopProbeOptions {
  int windows = 400;          // sample points, spread over the faces' area at random (seeded)
  double half_width = 0.5;    // mm: half the window's side (at least the stepover, so a cusp lies inside)
  double pitch = 0.02;        // mm between rays (at most stepover / 20)
  double depth = 1.0;         // mm above and below the surface the rays look at
  std::uint32_t seed = 1;
  int threads = 0;
};

struct ScallopWindow {
  Vec3 point = Vec3::Zero();   // the sample, on the surface
  Vec3 normal = Vec3::UnitZ();
  int face = -1;
  double max_mm = 0;           // the largest material left on a reached ray
  double mean_mm = 0;          // over reached rays
  int rays = 0, reached = 0;   // rays, and rays some cutting pose passed over
  double deepest_cut_mm = 0;   // the tool below the surface (a gouge) on some ray, > 0 when it happened
};

struct ScallopReport {
  std::vector<ScallopWindow> windows;
  double seconds = 0;
  // Share of windows (with every ray reached) whose max_mm is at most `limit`.
  double shareWithin(double limit) const;
  // The q-quantile (0..1) of the windows' max_mm (reached windows only).
  double quantile(double q) const;
};

// Windows on the triangles whose face is in `faces` (ids into `triangle_face`'s faces). Throws InputError for a tool id
// the path uses that `tools` lacks, or an empty face set.
ScallopReport probeScallops(const Mesh& mesh, const std::vector<int>& triangle_face, const std::vector<int>& faces,
                            const Toolpath& path, const std::vector<Tool>& tools, const ScallopProbeOptions& options = {});

}  // namespace art2part
