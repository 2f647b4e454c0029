#include "art2part/render/palette.h"

namespace art2part {

Rgb surfaceColour(const Face& face) {
  Rgb c{0.85f, 0.78f, 0.60f};
  switch (face.type) {
    case SurfaceType::Plane: c = {0.55f, 0.62f, 0.75f}; break;
    case SurfaceType::Cylinder: c = {0.35f, 0.72f, 0.42f}; break;
    case SurfaceType::Cone: c = {0.95f, 0.60f, 0.25f}; break;
    case SurfaceType::Sphere:
    case SurfaceType::Torus: c = {0.65f, 0.45f, 0.80f}; break;
    case SurfaceType::Other: break;
  }
  if (face.concave)
    for (float& v : c) v *= 0.7f;
  return c;
}

std::vector<std::array<unsigned char, 3>> triangleColoursByFace(const Part& part) {
  std::vector<std::array<unsigned char, 3>> colours(part.mesh.triangles.size());
  const Face free_form;
  for (std::size_t t = 0; t < colours.size(); ++t) {
    const int f = t < part.triangle_face.size() ? part.triangle_face[t] : -1;
    const Rgb c = surfaceColour(f >= 0 && f < static_cast<int>(part.faces.size()) ? part.faces[f] : free_form);
    for (int k = 0; k < 3; ++k) colours[t][k] = static_cast<unsigned char>(c[k] * 255.0f + 0.5f);
  }
  return colours;
}

}  // namespace art2part
