// art2part visibility PART --out DIR [--picture FILE.png] [--level L] [--sphere tetrahedron|icosahedron] [--backend ray|render] [--no-special] [--no-side]
//                         [--resolution PX] [--samples N] [--threads N] [--units U] [--tolerance MM]
#include <chrono>
#include <iomanip>
#include <filesystem>
#include <iostream>

#include "arguments.h"
#include "art2part/render/annotate.h"
#include "art2part/render/palette.h"
#include "art2part/render/picture.h"
#include "art2part/visibility/analysis.h"
#include "art2part/visibility/cones.h"
#include "commands.h"

namespace art2part {

VisibilityOptions visibilityOptionsFrom(const Arguments& a) {
  VisibilityOptions options;
  options.level = a.integer("level", options.level);
  const std::string sphere = a.value("sphere", "tetrahedron");
  if (sphere == "icosahedron" || sphere == "ico") options.base = SphereBase::Icosahedron;
  else if (sphere != "tetrahedron" && sphere != "tetra") throw UsageError("--sphere is tetrahedron or icosahedron");
  options.backend = parseVisibilityBackend(a.value("backend", visibilityBackendName(options.backend)));
  options.special_directions = !a.flag("no-special");
  options.side_correction = !a.flag("no-side");
  options.render.resolution = a.integer("resolution", 0);
  options.ray.samples_per_triangle = a.integer("samples", options.ray.samples_per_triangle);
  options.threads = a.integer("threads", 0);
  if (options.render.resolution < 0 || options.ray.samples_per_triangle < 1 || options.threads < 0)
    throw UsageError("--resolution, --samples and --threads must be positive");
  return options;
}

namespace {

// The part coloured by the solid angle of each triangle's cone: dark where hardly any direction reaches, yellow for a
// whole hemisphere, red where none does.
void writeConePicture(const Part& part, const VisibilityResult& r, const std::string& path) {
  constexpr double kTwoPi = 2.0 * 3.14159265358979323846;
  const std::vector<double> angles = coneSolidAngles(r.map, r.directions);
  PictureOptions picture;
  for (double a : angles) {
    const Rgb c = a <= 0.0 ? Rgb{0.9f, 0.1f, 0.1f} : rampColour(a / kTwoPi);
    picture.triangle_colours.push_back({static_cast<unsigned char>(255 * c[0]), static_cast<unsigned char>(255 * c[1]),
                                        static_cast<unsigned char>(255 * c[2])});
  }
  ColourScale scale;
  scale.caption = "solid angle of the cone";
  scale.unit = "sr";
  scale.low = 0;
  scale.high = kTwoPi;
  scale.colour = [](double v) { return rampColour(v / kTwoPi); };
  scale.extra = {{Rgb{0.9f, 0.1f, 0.1f}, "no direction reaches"}, {rampColour(1), "a whole hemisphere (2 pi sr)"}};
  const std::string title = std::filesystem::path(part.source).filename().string() +
                            ": from how many directions each triangle is visible";
  const Image image = withScale(renderPicture(part.mesh, picture), title, scale);
  try {
    writePng(image, path);
  } catch (const std::runtime_error& e) {
    throw InputError(e.what());  // a path the user gave us
  }
}

}  // namespace

int runVisibility(const std::vector<std::string>& args) {
  const Arguments a(args, {"no-special", "no-side"},
                    {"out", "picture", "level", "sphere", "backend", "resolution", "samples", "threads", "units", "tolerance"});
  const std::string path = a.requirePositional(1, "one part file: art2part visibility PART --out DIR");
  if (!a.has("out")) throw UsageError("visibility needs --out DIR");
  const VisibilityOptions options = visibilityOptionsFrom(a);
  const Part part = loadPart(path, loadOptionsFrom(a));
  const VisibilityResult r = analyseVisibility(part, options);
  writeVisibilityFiles(part, r, a.value("out"));
  if (a.has("picture")) writeConePicture(part, r, a.value("picture"));
  const double pairs = static_cast<double>(r.map.triangles()) * r.map.directions();
  std::cout << std::fixed << std::setprecision(3) << "triangles:   " << r.map.triangles() << "\n"
            << "directions:  " << r.map.directions() << " (level " << options.level << ", " << r.special_directions
            << " special)\n"
            << "backend:     " << visibilityBackendName(options.backend) << ", " << r.seconds_visibility << " s, "
            << std::setprecision(0) << pairs / std::max(r.seconds_visibility, 1e-9) << " pairs/s\n"
            << std::setprecision(3) << "side pairs:  " << r.side_pairs_added << " added by side correction ("
            << r.seconds_side << " s)\n"
            << "unseen:      " << r.unseen_triangles.size() << " triangles visible along no direction\n"
            << "wrote:       " << a.value("out") << "/{mesh.stl,directions.csv,visibility.bits}\n";
  return 0;
}

}  // namespace art2part
