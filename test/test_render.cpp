// Offscreen pictures (OSMesa): the silhouette has the part's shape, colours arrive, threads render alike.
#include <gtest/gtest.h>

#include <thread>

#include "art2part/render/picture.h"
#include "test_meshes.h"

using namespace art2part;

namespace {

struct Silhouette {
  int pixels = 0, width = 0, height = 0;
  double mean_red = 0, mean_green = 0, mean_blue = 0;
};

// Pixels that differ from the corner (background) pixel.
Silhouette silhouetteOf(const Image& image) {
  Silhouette s;
  const unsigned char* bg = image.rgb.data();
  int x0 = image.width, x1 = -1, y0 = image.height, y1 = -1;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      const unsigned char* p = &image.rgb[3 * (y * image.width + x)];
      if (p[0] == bg[0] && p[1] == bg[1] && p[2] == bg[2]) continue;
      ++s.pixels;
      s.mean_red += p[0];
      s.mean_green += p[1];
      s.mean_blue += p[2];
      x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
    }
  if (s.pixels) {
    s.width = x1 - x0 + 1, s.height = y1 - y0 + 1;
    s.mean_red /= s.pixels, s.mean_green /= s.pixels, s.mean_blue /= s.pixels;
  }
  return s;
}

PictureOptions topView() {
  PictureOptions o;
  o.width = 400;
  o.height = 300;
  o.samples = 1;
  o.view_direction = Vec3(0, 0, 1);
  return o;
}

}  // namespace

TEST(Picture, ABoxSeenFromAboveIsAFilledRectangleOfItsProportions) {
  const Mesh m = test::box(Vec3(0, 0, 0), Vec3(40, 20, 10));
  const Silhouette s = silhouetteOf(renderPicture(m, topView()));
  ASSERT_GT(s.pixels, 1000);
  EXPECT_NEAR(static_cast<double>(s.width) / s.height, 2.0, 0.03);
  EXPECT_NEAR(s.pixels, s.width * s.height, 0.01 * s.pixels) << "a rectangle has no holes";
  EXPECT_GT(s.width, 0.8 * 400) << "the part fills the frame";
}

TEST(Picture, TriangleColoursAreUsed) {
  const Mesh m = test::box(Vec3(0, 0, 0), Vec3(10, 10, 10));
  PictureOptions o = topView();
  o.triangle_colours.assign(m.triangles.size(), {230, 30, 30});
  const Silhouette s = silhouetteOf(renderPicture(m, o));
  EXPECT_GT(s.mean_red, 3 * s.mean_green);
  EXPECT_GT(s.mean_red, 3 * s.mean_blue);
}

TEST(Picture, TwoThreadsRenderTheSamePicture) {
  Mesh m = test::box(Vec3(0, 0, 0), Vec3(30, 20, 10));
  test::append(m, test::box(Vec3(5, 5, 10), Vec3(10, 10, 25)));
  PictureOptions o;
  o.width = 320;
  o.height = 240;
  Image a, b;
  std::thread ta([&] { a = renderPicture(m, o); });
  std::thread tb([&] { b = renderPicture(m, o); });
  ta.join();
  tb.join();
  EXPECT_EQ(a.rgb, b.rgb);
  EXPECT_GT(silhouetteOf(a).pixels, 1000);
}

TEST(Picture, PngIsWritten) {
  const std::string dir = test::tempDir();
  writePng(renderPicture(test::box(Vec3(0, 0, 0), Vec3(1, 1, 1)), topView()), dir + "/box.png");
  std::ifstream in(dir + "/box.png", std::ios::binary);
  char magic[4] = {0};
  in.read(magic, 4);
  EXPECT_EQ(std::string(magic + 1, 3), "PNG");
  EXPECT_THROW(writePng(Image{}, "/nonexistent-folder/x.png"), std::runtime_error);
}
