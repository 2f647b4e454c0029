// Visibility analysis (thesis 3.2): for every triangle, the directions of a DirectionSet along which it is visible.
// Two independent backends: OSMesa rendering of triangle ids (the thesis's graphics approach) and ray casting.
#pragma once

#include <functional>
#include <vector>

#include "art2part/geometry/mesh.h"
#include "art2part/visibility/visibility_map.h"

namespace art2part {

// Called now and then with the fraction done (0..1); return false to cancel (the backends then throw
// std::runtime_error("cancelled")).
using Progress = std::function<bool(double)>;

// Triangle t is visible along d when its outward normal n has n . d > 0 and some point of t has a clear straight
// line to infinity along +d (nothing of the part in front of it).

struct RenderVisibilityOptions {
  int resolution = 0;             // pixels per side of each view; 0 = chosen from pixels_per_triangle
  double pixels_per_triangle = 50; // the thesis's figure: the median triangle covers about this many pixels
  int max_resolution = 2048;
  int threads = 0;                // 0 = hardware threads; one OSMesa context per thread
};

// Orthographic views along each direction into an R32UI target (gl_PrimitiveID + 1), read back, every id seen
// marks its triangle visible. Front-facing triangles only count; every triangle occludes.
VisibilityMap renderVisibility(const Mesh& mesh, const std::vector<Vec3>& directions,
                               const RenderVisibilityOptions& options = {}, const Progress& progress = {});

struct RayVisibilityOptions {
  int samples_per_triangle = 4;   // the centroid and points towards each corner
  int threads = 0;
};

// Ray casting (Embree): rays from sample points of each front-facing triangle along d; visible when one escapes.
VisibilityMap rayVisibility(const Mesh& mesh, const std::vector<Vec3>& directions,
                            const RayVisibilityOptions& options = {}, const Progress& progress = {});

}  // namespace art2part
