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

Rgb setupColour(int k) {
  static const Rgb palette[] = {{0.25f, 0.45f, 0.85f}, {0.30f, 0.70f, 0.35f}, {0.95f, 0.78f, 0.20f},
                                {0.60f, 0.40f, 0.80f}, {0.20f, 0.75f, 0.80f}, {0.95f, 0.55f, 0.15f},
                                {0.55f, 0.35f, 0.20f}, {0.90f, 0.50f, 0.75f}, {0.55f, 0.60f, 0.30f},
                                {0.50f, 0.50f, 0.50f}};
  const int n = sizeof palette / sizeof palette[0];
  const int i = k < 0 ? 0 : k;
  const float shade = 1.0f / static_cast<float>(1 + i / n);
  const Rgb& c = palette[i % n];
  return {c[0] * shade, c[1] * shade, c[2] * shade};
}

Rgb unmachinableColour() { return {0.90f, 0.10f, 0.10f}; }

Rgb rampColour(double value) {
  // Stops of a viridis-like ramp; linear in between.
  static const Rgb stops[5] = {
      {0.267f, 0.005f, 0.329f}, {0.231f, 0.322f, 0.545f}, {0.129f, 0.569f, 0.549f}, {0.369f, 0.788f, 0.384f},
      {0.993f, 0.906f, 0.144f}};
  const double v = value < 0.0 ? 0.0 : (value > 1.0 ? 1.0 : value);
  const double x = v * 4.0;
  const int i = x >= 4.0 ? 3 : static_cast<int>(x);
  const float f = static_cast<float>(x - i);
  Rgb c;
  for (int k = 0; k < 3; ++k) c[k] = stops[i][k] + f * (stops[i + 1][k] - stops[i][k]);
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
