// Titles and legends on pictures, so that a reader can tell what a colour means: a title band on top and a legend
// column on the right, text by FreeType in DejaVu Sans (Debian's fonts-dejavu-core). Without the font the swatches and
// scales are still drawn, the text left out.
#pragma once

#include <array>
#include <functional>
#include <string>
#include <vector>

#include "art2part/render/palette.h"
#include "art2part/render/picture.h"

namespace art2part {

// One colour of a legend and what it stands for ("setup 0: +z", "plane").
struct LegendEntry {
  Rgb colour;
  std::string label;
};

// A continuous colour scale: the ramp from `low` to `high` (in `unit`), with a caption.
struct ColourScale {
  std::string caption;                    // what is measured, e.g. "stock left above the part"
  std::string unit;                       // e.g. "mm"
  double low = 0, high = 1;
  std::function<Rgb(double)> colour;      // of a value in [low, high]
  std::vector<LegendEntry> extra;         // colours outside the ramp (e.g. "gouge" red), listed under it
};

// The picture with a title band above it and, right of it, the entries (a swatch and its label each).
Image withLegend(const Image& picture, const std::string& title, const std::vector<LegendEntry>& entries);

// The picture with a title band above it and, right of it, the scale (a vertical bar, its end values and unit).
Image withScale(const Image& picture, const std::string& title, const ColourScale& scale);

// The legend of triangleColoursByFace: one entry per surface type the part has (concave faces are drawn darker).
std::vector<LegendEntry> surfaceLegend(const Part& part);

// A direction as a reader names it: "+z" along an axis, else "(0.71, 0.00, 0.71)".
std::string directionLabel(const Vec3& d);

// Text drawn onto an image at (x, y) (top-left of the line), height `pixels`; the width drawn, in pixels. Returns 0
// and draws nothing when no font is found.
int drawText(Image& image, int x, int y, const std::string& text, int pixels, const std::array<unsigned char, 3>& colour);

}  // namespace art2part
