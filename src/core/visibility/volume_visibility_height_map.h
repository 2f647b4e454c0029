// Internal to volume visibility: the CPU shadow map of the part along one direction.
#pragma once

#include <vector>

#include "art2part/geometry/mesh.h"

namespace art2part::volume {

// An orthographic grid of pixels perpendicular to d over the projection of a box. Pixel (i, j) covers
// [i, i+1) x [j, j+1) in pixel coordinates ((p . e1 - u0) / pixel, (p . e2 - v0) / pixel).
struct HeightMap {
  Vec3 d, e1, e2;
  double u0 = 0, v0 = 0, inv_pixel = 1;
  int w = 0, h = 0;
  std::vector<float> height;  // largest p . d of the part over the pixel; -inf where the part is absent

  // Sets up the frame and clears the buffer (reusing its storage) for a view of `box` along unit d.
  void reset(const Vec3& d, const Box& box, double pixel);
  // Raises every pixel the triangle touches to the largest height it can reach inside that pixel.
  void rasterise(const Vec3& a, const Vec3& b, const Vec3& c);
  void rasteriseMesh(const Mesh& mesh);
};

}  // namespace art2part::volume
