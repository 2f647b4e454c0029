// Scallop heights measured by simulation in small windows (issue 17, "Figures to reach"): a part-wide lattice is far
// too coarse to see a 0.01 mm cusp (a pitch d misses the apex by up to (s / 2R)(d / 2), s the stepover), so the height
// left is measured where it matters, on a fine local lattice.
//
// A window is a square of side 2 * half_width around a sample point p of a face, in a frame whose z is the normal of
// p's triangle (outward), its x turned about z by a random angle (a ridge along a row of rays would hide its apex
// between two rows: up to (s / 2R)(pitch / 2), a tenth of the cusp at pitch s / 20; at an angle some ray of the
// window's many rows comes much closer). Rays along that normal at `pitch` across the square, each looking `depth` above and below
// p's tangent plane. On each ray:
//  - the part's surface: the first crossing of a triangle coming down the ray from `depth` above (any triangle of the
//    mesh near the window, exact), when that triangle faces up the ray; a ray that crosses nothing within the depth
//    (beyond a convex edge) or first meets a triangle facing down (it starts inside material: a wall beside the
//    window) is not counted;
//  - the tool: the lowest point of the flutes on the ray over every pose of every feed move near the window
//    (rayPieceSpan of tool_solid.h against each ToolPiece of zone Flutes, the poses transformed into the window's
//    frame), poses taken along each move so that no flute point moves more than `pitch` between two (the tip's travel
//    plus the axis' turn times the flutes' height);
//  - the material left is the tool's lowest point minus the surface, when the tool came within the depth of the
//    surface at all ("reached"); a tool below the surface is a gouge (deepest_cut_mm).
// The window's scallop is the largest material left over its reached rays; the ray that reads it is nearest a ridge's
// apex line, so lattices 4 and 16 times finer around it (9 x 9 rays, a pitch and then a quarter pitch to each side)
// find the apex (the window's max only; rays, reached and the mean stay the lattice's).
// Speed: moves are found through their swept boxes (blocks of 64 consecutive moves first), nearest the window first;
// only the stretch of a move whose tip comes within the flutes' reach of the window is posed; a piece whose lowest
// point over the window (a sphere's exactly, a frustum's box) lies above every ray's lowest so far is skipped (rays
// start at the depth above the surface), so once the nearest passes are in, the farther poses cost one bound each. Windows are spread over the faces' area at random from `seed` and measured in parallel, each by
// one thread, so the result does not depend on the thread count.
// Error: a ray a distance e beside a ridge's apex reads it (s / 2R) e lower (R the ball's radius, s the stepover); the
// turned lattice brings e well under pitch / 2 (a tenth of the cusp at pitch s / 20 in the worst case); poses a pitch
// apart leave a cusp of pitch^2 / 8R along the feed (1.7e-5 mm at 0.02 mm on a 3 mm ball).
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
  double pitch = 0.02;        // mm between rays (at most stepover / 20) and the most a flute point moves between poses
  double depth = 1.0;         // mm above and below the surface the rays look at
  std::uint32_t seed = 1;
  int threads = 0;            // 0 = the hardware's
};

struct ScallopWindow {
  Vec3 point = Vec3::Zero();   // the sample, on the surface
  Vec3 normal = Vec3::UnitZ();
  double turn = 0;             // rad: the lattice's rows turned about the normal (drawn at random with the point)
  int face = -1;
  double max_mm = 0;           // the largest material left on a reached ray (0 when none is reached)
  double mean_mm = 0;          // over reached rays
  int rays = 0, reached = 0;   // rays that cross the surface, and those some cutting pose came within the depth of
  double deepest_cut_mm = 0;   // the tool below the surface (a gouge) on some ray, > 0 when it happened
  bool fullyReached() const { return rays > 0 && reached == rays; }
};

struct ScallopReport {
  std::vector<ScallopWindow> windows;  // in the order drawn
  long long ray_piece_tests = 0;       // rays met against a posed piece
  double seconds = 0;
  // Share of the fully reached windows whose max_mm is at most `limit` (0 when there are none).
  double shareWithin(double limit) const;
  // The q-quantile (0..1) of the fully reached windows' max_mm (nearest rank; 0 when there are none).
  double quantile(double q) const;
  int fullyReachedCount() const;
};

// Windows on the triangles whose face is in `faces` (ids into `triangle_face`'s faces). Throws InputError for a tool id
// the path uses that `tools` lacks, an empty face set or one whose triangles have no area, a triangle_face that does
// not match the mesh, or options that are not positive (windows, half_width, pitch, depth).
ScallopReport probeScallops(const Mesh& mesh, const std::vector<int>& triangle_face, const std::vector<int>& faces,
                            const Toolpath& path, const std::vector<Tool>& tools, const ScallopProbeOptions& options = {});

}  // namespace art2part
