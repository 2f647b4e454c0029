// Titles and legends on pictures (annotate.h): FreeType renders the glyphs, blended onto the RGB image.
#include "art2part/render/annotate.h"

#include <ft2build.h>
#include FT_FREETYPE_H

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <mutex>

#include "art2part/geometry/part.h"

namespace art2part {

namespace {

using Bytes = std::array<unsigned char, 3>;

constexpr int kTitlePixels = 22;    // title text height
constexpr int kLabelPixels = 16;    // legend text height
constexpr int kMargin = 12;         // px around the title and the legend
constexpr int kSwatch = 16;         // px, a legend entry's colour square
constexpr int kLegendWidth = 300;   // px, the legend column
constexpr int kScaleHeight = 320;   // px, the colour bar's length
const Bytes kText = {30, 30, 30};
const Bytes kBackground = {250, 250, 250};

const char* const kFonts[] = {"/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf",
                              "/usr/share/fonts/TTF/DejaVuSans.ttf",
                              "/usr/share/fonts/dejavu/DejaVuSans.ttf"};

// One FreeType library and face for the process; FreeType faces are not thread-safe, so drawing takes the lock.
struct Font {
  FT_Library library = nullptr;
  FT_Face face = nullptr;
  std::mutex mutex;
  Font() {
    if (FT_Init_FreeType(&library) != 0) return;
    for (const char* path : kFonts)
      if (std::filesystem::exists(path) && FT_New_Face(library, path, 0, &face) == 0) return;
    face = nullptr;
  }
  ~Font() {
    if (face) FT_Done_Face(face);
    if (library) FT_Done_FreeType(library);
  }
};

Font& font() {
  static Font f;
  return f;
}

// Code points of a UTF-8 string (malformed bytes taken one by one).
std::vector<unsigned> codePoints(const std::string& text) {
  std::vector<unsigned> out;
  for (std::size_t i = 0; i < text.size();) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    int extra = c >= 0xF0 ? 3 : c >= 0xE0 ? 2 : c >= 0xC0 ? 1 : 0;
    unsigned cp = extra == 3 ? c & 0x07u : extra == 2 ? c & 0x0Fu : extra == 1 ? c & 0x1Fu : c;
    if (i + extra >= text.size() + (extra ? 0 : 1)) extra = 0, cp = c;
    for (int k = 1; k <= extra; ++k) cp = (cp << 6) | (static_cast<unsigned char>(text[i + k]) & 0x3Fu);
    out.push_back(cp);
    i += 1 + extra;
  }
  return out;
}

Bytes bytes(const Rgb& c) {
  auto b = [](float v) { return static_cast<unsigned char>(std::clamp(v, 0.0f, 1.0f) * 255.0f + 0.5f); };
  return {b(c[0]), b(c[1]), b(c[2])};
}

void fillRect(Image& image, int x0, int y0, int w, int h, const Bytes& colour) {
  for (int y = std::max(0, y0); y < std::min(image.height, y0 + h); ++y)
    for (int x = std::max(0, x0); x < std::min(image.width, x0 + w); ++x)
      std::copy(colour.begin(), colour.end(), image.rgb.begin() + 3 * (static_cast<std::size_t>(y) * image.width + x));
}

void frameRect(Image& image, int x0, int y0, int w, int h, const Bytes& colour) {
  fillRect(image, x0, y0, w, 1, colour);
  fillRect(image, x0, y0 + h - 1, w, 1, colour);
  fillRect(image, x0, y0, 1, h, colour);
  fillRect(image, x0 + w - 1, y0, 1, h, colour);
}

// The picture placed below a title band and left of a legend column, on the background.
Image canvas(const Image& picture, int legend_height, int& legend_x, int& top) {
  top = kTitlePixels + 2 * kMargin;
  Image out;
  out.width = picture.width + kLegendWidth;
  out.height = std::max(picture.height + top, legend_height + top + kMargin);
  out.rgb.assign(static_cast<std::size_t>(out.width) * out.height * 3, 0);
  fillRect(out, 0, 0, out.width, out.height, kBackground);
  for (int y = 0; y < picture.height; ++y)
    std::copy(picture.rgb.begin() + static_cast<std::size_t>(y) * picture.width * 3,
              picture.rgb.begin() + static_cast<std::size_t>(y + 1) * picture.width * 3,
              out.rgb.begin() + (static_cast<std::size_t>(y + top) * out.width) * 3);
  legend_x = picture.width + kMargin;
  return out;
}

std::string number(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", v);
  return text;
}

}  // namespace

int drawText(Image& image, int x, int y, const std::string& text, int pixels, const Bytes& colour) {
  Font& f = font();
  if (!f.face) return 0;
  std::lock_guard<std::mutex> lock(f.mutex);
  if (FT_Set_Pixel_Sizes(f.face, 0, static_cast<FT_UInt>(pixels)) != 0) return 0;
  const int baseline = y + static_cast<int>(f.face->size->metrics.ascender >> 6);
  int pen = x;
  for (unsigned cp : codePoints(text)) {
    if (FT_Load_Char(f.face, cp, FT_LOAD_RENDER) != 0) continue;
    const FT_GlyphSlot g = f.face->glyph;
    const FT_Bitmap& b = g->bitmap;
    for (unsigned row = 0; row < b.rows; ++row)
      for (unsigned col = 0; col < b.width; ++col) {
        const int px = pen + g->bitmap_left + static_cast<int>(col), py = baseline - g->bitmap_top + static_cast<int>(row);
        if (px < 0 || py < 0 || px >= image.width || py >= image.height) continue;
        const float a = b.buffer[row * b.pitch + col] / 255.0f;
        unsigned char* p = &image.rgb[(static_cast<std::size_t>(py) * image.width + px) * 3];
        for (int k = 0; k < 3; ++k) p[k] = static_cast<unsigned char>(p[k] * (1 - a) + colour[k] * a + 0.5f);
      }
    pen += static_cast<int>(g->advance.x >> 6);
  }
  return pen - x;
}

Image withLegend(const Image& picture, const std::string& title, const std::vector<LegendEntry>& entries) {
  const int row = kSwatch + 8;
  int x = 0, top = 0;
  Image out = canvas(picture, static_cast<int>(entries.size()) * row, x, top);
  drawText(out, kMargin, kMargin, title, kTitlePixels, kText);
  int y = top;
  for (const LegendEntry& e : entries) {
    fillRect(out, x, y, kSwatch, kSwatch, bytes(e.colour));
    frameRect(out, x, y, kSwatch, kSwatch, kText);
    drawText(out, x + kSwatch + 8, y - 1, e.label, kLabelPixels, kText);
    y += row;
  }
  return out;
}

Image withScale(const Image& picture, const std::string& title, const ColourScale& scale) {
  const int row = kSwatch + 8;
  const int bar = std::min(kScaleHeight, std::max(120, picture.height - 200));
  const int legend_height = 2 * row + bar + static_cast<int>(scale.extra.size()) * row + row;
  int x = 0, top = 0;
  Image out = canvas(picture, legend_height, x, top);
  drawText(out, kMargin, kMargin, title, kTitlePixels, kText);
  int y = top;
  drawText(out, x, y, scale.caption + (scale.unit.empty() ? "" : " (" + scale.unit + ")"), kLabelPixels, kText);
  y += row;
  const int bar_top = y + kLabelPixels / 2;
  for (int i = 0; i < bar; ++i) {  // high at the top
    const double v = scale.high - (scale.high - scale.low) * i / std::max(1, bar - 1);
    fillRect(out, x, bar_top + i, 2 * kSwatch, 1, bytes(scale.colour ? scale.colour(v) : Rgb{0.5f, 0.5f, 0.5f}));
  }
  frameRect(out, x, bar_top, 2 * kSwatch, bar, kText);
  drawText(out, x + 2 * kSwatch + 8, bar_top - kLabelPixels / 2, number(scale.high) + " " + scale.unit, kLabelPixels, kText);
  drawText(out, x + 2 * kSwatch + 8, bar_top + bar - kLabelPixels, number(scale.low) + " " + scale.unit, kLabelPixels,
           kText);
  y = bar_top + bar + row / 2;
  for (const LegendEntry& e : scale.extra) {
    fillRect(out, x, y, kSwatch, kSwatch, bytes(e.colour));
    frameRect(out, x, y, kSwatch, kSwatch, kText);
    drawText(out, x + kSwatch + 8, y - 1, e.label, kLabelPixels, kText);
    y += row;
  }
  return out;
}

std::vector<LegendEntry> surfaceLegend(const Part& part) {
  std::vector<LegendEntry> entries;
  auto add = [&](SurfaceType type, const std::string& label) {
    for (const Face& f : part.faces)
      if (f.type == type) {
        Face plain = f;
        plain.concave = false;
        entries.push_back({surfaceColour(plain), label});
        return;
      }
  };
  add(SurfaceType::Plane, "plane");
  add(SurfaceType::Cylinder, "cylinder");
  add(SurfaceType::Cone, "cone");
  add(SurfaceType::Sphere, "sphere or torus");
  if (entries.empty() || entries.back().label != "sphere or torus") add(SurfaceType::Torus, "sphere or torus");
  add(SurfaceType::Other, "free-form");
  if (std::any_of(part.faces.begin(), part.faces.end(), [](const Face& f) { return f.concave; }))
    entries.push_back({Rgb{0.4f, 0.4f, 0.4f}, "concave faces: darker"});
  return entries;
}

std::string directionLabel(const Vec3& d) {
  static const char* axes[] = {"x", "y", "z"};
  const Vec3 u = d.normalized();
  for (int k = 0; k < 3; ++k)
    if (std::abs(std::abs(u[k]) - 1) < 1e-6) return std::string(u[k] > 0 ? "+" : "-") + axes[k];
  char text[64];
  std::snprintf(text, sizeof text, "(%.2f, %.2f, %.2f)", u.x(), u.y(), u.z());
  return text;
}

}  // namespace art2part
