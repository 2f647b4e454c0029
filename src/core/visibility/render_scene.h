// Private to render_visibility.cpp: what every view of the id renderer shares (the mesh relative to its bounding
// sphere, the resolution, whether back faces may be culled) and the camera of one view. Plain CPU work, no GL.
#pragma once

#include <vector>

#include "art2part/geometry/mesh.h"
#include "art2part/visibility/visibility.h"

namespace art2part::idrender {

// Everything the views share, computed once on the CPU and read by every worker.
struct Scene {
  std::vector<float> positions;  // xyz per vertex, relative to `centre`
  std::vector<unsigned> indices; // three per triangle, in triangle order: gl_PrimitiveID == triangle index
  std::vector<Vec3> normals;     // unit, for the exact n.d > 0 test in double
  std::vector<Vec3> corners;     // of the bounding box, relative to `centre`: where the part can appear in a view
  double radius = 1;             // bounding sphere about the box centre, slightly enlarged
  int resolution = 64;
  bool cull = false;             // back faces can be skipped: see backFacesNeverShow()
  bool outlines = true;          // RenderVisibilityOptions::outlines
};

// Throws std::invalid_argument when a triangle refers to a missing vertex.
Scene prepareScene(const Mesh& mesh, const RenderVisibilityOptions& options);

// One view: the matrix for the vertex shader and the pixel rectangle the part's box can cover.
struct View {
  float rows[9];  // right, up, back divided by the radius; back = d (towards the eye), right x up = back
  int x = 0, y = 0, width = 0, height = 0;
};

View makeView(const Vec3& d, const Scene& scene);

}  // namespace art2part::idrender
