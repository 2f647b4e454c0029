// art2part plan PART --out DIR [--mode 3axis|5axis] [--tilt DEG] [--level L] [--time-limit S] [--no-pp] plus the
// visibility options: the pipeline without ROS. So far: visibility and setups. Writes DIR/plan.json, DIR/setups.png
// and the visibility contract files (mesh.stl, directions.csv, visibility.bits).
#include <chrono>
#include <fstream>
#include <iostream>

#include "arguments.h"
#include "art2part/render/palette.h"
#include "art2part/render/picture.h"
#include "art2part/setup/setup_report.h"
#include "art2part/visibility/analysis.h"
#include "commands.h"

namespace art2part {
namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

nlohmann::json vectorJson(const Vec3& v) { return nlohmann::json::array({v.x(), v.y(), v.z()}); }

nlohmann::json partJson(const Part& part) {
  const Box box = boundingBox(part.mesh);
  return {{"source", part.source},
          {"triangles", part.mesh.triangleCount()},
          {"faces", part.faces.size()},
          {"bounding_box", {{"min", vectorJson(box.min)}, {"max", vectorJson(box.max)}}}};
}

nlohmann::json directionsJson(const DirectionSet& directions) {
  nlohmann::json out = nlohmann::json::array();
  for (const Vec3& d : directions.directions) out.push_back(vectorJson(d));
  return out;
}

// The plan so far: later stages fill operations and verification.
nlohmann::json planJson(const Part& part, const VisibilityResult& visibility, const SetupPlan& plan,
                        const nlohmann::json& timings) {
  nlohmann::json j = setupPlanJson(plan, visibility.directions);
  j["setup_seconds"] = j["seconds"];
  j.erase("seconds");
  j["part"] = partJson(part);
  j["directions"] = directionsJson(visibility.directions);
  j["operations"] = nlohmann::json::array();
  j["verification"] = nullptr;
  j["timings"] = timings;
  return j;
}

void writeJson(const nlohmann::json& j, const std::string& path) {
  std::ofstream out(path);
  if (!out) throw InputError("cannot write '" + path + "'");
  out << j.dump() << "\n";
  if (!out) throw InputError("cannot write '" + path + "'");
}

// Setup colours, far from the red of what no setup reaches; after ten they repeat darker.
std::array<unsigned char, 3> setupColour(int k) {
  static const Rgb palette[] = {{0.25f, 0.45f, 0.85f}, {0.30f, 0.70f, 0.35f}, {0.95f, 0.78f, 0.20f},
                                {0.60f, 0.40f, 0.80f}, {0.20f, 0.75f, 0.80f}, {0.95f, 0.55f, 0.15f},
                                {0.55f, 0.35f, 0.20f}, {0.90f, 0.50f, 0.75f}, {0.55f, 0.60f, 0.30f},
                                {0.50f, 0.50f, 0.50f}};
  const int n = sizeof palette / sizeof palette[0];
  const float shade = 1.0f / static_cast<float>(1 + k / n);
  const Rgb& c = palette[k % n];
  return {static_cast<unsigned char>(255 * c[0] * shade), static_cast<unsigned char>(255 * c[1] * shade),
          static_cast<unsigned char>(255 * c[2] * shade)};
}

// The part coloured by the setup that machines each triangle, unmachinable triangles red.
void writeSetupPicture(const Part& part, const SetupPlan& plan, const std::string& path) {
  PictureOptions picture;
  picture.triangle_colours.assign(part.mesh.triangleCount(), {220, 220, 220});
  for (int k = 0; k < static_cast<int>(plan.setups.size()); ++k)
    for (int t : plan.setups[k].triangles) picture.triangle_colours[t] = setupColour(k);
  for (int t : plan.unmachinable_triangles) picture.triangle_colours[t] = {230, 25, 25};
  const Image image = renderPicture(part.mesh, picture);
  try {
    writePng(image, path);
  } catch (const std::runtime_error& e) {
    throw InputError(e.what());  // a path the user gave us
  }
}

}  // namespace

int runPlan(const std::vector<std::string>& args) {
  std::set<std::string> options = setupValueOptions();
  options.insert("out");
  const Arguments a(args, setupFlags(), options);
  const std::string path = a.requirePositional(1, "one part file: art2part plan PART --out DIR");
  if (!a.has("out")) throw UsageError("plan needs --out DIR");
  const std::string out = a.value("out");
  const SetupOptions setup_options = setupOptionsFrom(a);
  const VisibilityOptions visibility_options = visibilityOptionsFrom(a);
  nlohmann::json timings;
  const auto all = Clock::now();

  auto start = Clock::now();
  const Part part = loadPart(path, loadOptionsFrom(a));
  timings["load"] = secondsSince(start);
  start = Clock::now();
  const VisibilityResult visibility = analyseVisibility(part, visibility_options);
  timings["visibility"] = secondsSince(start);
  start = Clock::now();
  const SetupPlan plan = planSetups(part, visibility, setup_options);
  timings["setups"] = secondsSince(start);

  start = Clock::now();
  writeVisibilityFiles(part, visibility, out);
  writeSetupPicture(part, plan, out + "/setups.png");
  timings["write"] = secondsSince(start);
  timings["total"] = secondsSince(all);
  writeJson(planJson(part, visibility, plan, timings), out + "/plan.json");

  std::cout << "part:         " << path << " (" << part.mesh.triangleCount() << " triangles, "
            << visibility.directions.size() << " directions)\n"
            << setupPlanText(part, plan, visibility.directions) << "wrote:        " << out
            << "/{plan.json,setups.png,mesh.stl,directions.csv,visibility.bits}\n";
  return 0;
}

}  // namespace art2part
