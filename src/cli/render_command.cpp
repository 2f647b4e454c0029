// art2part render PART --out FILE.png [--width W] [--height H] [--units U] [--tolerance MM] [--edges]
#include <filesystem>
#include <iostream>

#include "arguments.h"
#include "art2part/render/annotate.h"
#include "art2part/render/palette.h"
#include "art2part/render/picture.h"
#include "commands.h"

namespace art2part {

int runRender(const std::vector<std::string>& args) {
  const Arguments a(args, {"edges"}, {"out", "width", "height", "units", "tolerance"});
  const std::string path = a.requirePositional(1, "one part file: art2part render PART --out FILE.png");
  if (!a.has("out")) throw UsageError("render needs --out FILE.png");
  const Part part = loadPart(path, loadOptionsFrom(a));
  PictureOptions options;
  options.width = a.integer("width", options.width);
  options.height = a.integer("height", options.height);
  if (options.width < 16 || options.height < 16 || options.width > 8192 || options.height > 8192)
    throw UsageError("--width and --height must be between 16 and 8192");
  options.triangle_colours = triangleColoursByFace(part);
  options.draw_edges = a.flag("edges");
  const std::string name = std::filesystem::path(path).filename().string();
  const Image image = withLegend(renderPicture(part.mesh, options), name + ": faces by surface type", surfaceLegend(part));
  try {
    writePng(image, a.value("out"));
  } catch (const std::runtime_error& e) {
    throw InputError(e.what());  // a path the user gave us
  }
  std::cout << "wrote " << a.value("out") << " (" << options.width << "x" << options.height << ", "
            << part.mesh.triangleCount() << " triangles, faces coloured by surface type)\n";
  return 0;
}

}  // namespace art2part
