// A shaded picture of a part, rendered offscreen (OSMesa) and written as PNG: the
// demo's images and, with per-triangle colours, verification colour maps.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "art2part/geometry/mesh.h"

namespace art2part {

class OffscreenContext;

struct PictureOptions {
  int width = 1024;
  int height = 768;
  // From the part towards the eye (need not be unit). +Z is drawn upwards unless
  // the view looks along Z, in which case +Y is.
  Vec3 view_direction = Vec3(-1, -2, 1.5);
  // Optional, one per triangle; empty = a neutral grey-blue for every triangle.
  std::vector<std::array<unsigned char, 3>> triangle_colours;
  // Thin dark lines along every triangle edge.
  bool draw_edges = false;
  // Multisample anti-aliasing samples (1 = off). Costs render time in software.
  int samples = 4;
};

struct Image {
  int width = 0;
  int height = 0;
  std::vector<unsigned char> rgb;  // row-major, top row first, 3 bytes per pixel
};

// Orthographic view that fits the whole part with a margin, flat shaded and lit
// from both sides (open meshes and inverted triangles still look solid), on a light
// background. Uses OffscreenContext::forThisThread() unless given a context (which
// it makes current). Throws std::invalid_argument for bad options and
// std::runtime_error for OpenGL failures.
Image renderPicture(const Mesh& mesh, const PictureOptions& options);
Image renderPicture(OffscreenContext& context, const Mesh& mesh, const PictureOptions& options);

// 8-bit RGB PNG. Throws std::runtime_error naming the path on failure.
void writePng(const Image& image, const std::string& path);

}  // namespace art2part
