#include "art2part/visibility/analysis.h"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <system_error>

#include "art2part/geometry/mesh_io.h"
#include "art2part/visibility/cones.h"
#include "art2part/visibility/side_correction.h"

namespace art2part {

VisibilityBackend parseVisibilityBackend(const std::string& name) {
  if (name == "ray") return VisibilityBackend::Ray;
  if (name == "render") return VisibilityBackend::Render;
  throw InputError("unknown visibility backend '" + name + "' (use ray or render)");
}

const char* visibilityBackendName(VisibilityBackend backend) {
  return backend == VisibilityBackend::Ray ? "ray" : "render";
}

namespace {

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

VisibilityResult analyseVisibility(const Part& part, const VisibilityOptions& options, const ProgressSink& progress) {
  if (options.level < 0 || options.level > 7)
    throw InputError("sphere level " + std::to_string(options.level) + " is out of range 0..7");
  VisibilityResult result;
  auto start = std::chrono::steady_clock::now();
  result.directions = sampleSphere(options.level, options.base);
  if (options.special_directions) {
    const auto special = specialDirections(part, options.special);
    insertSpecialDirections(result.directions, special);
  }
  for (char s : result.directions.special) result.special_directions += s;
  result.seconds_directions = secondsSince(start);

  start = std::chrono::steady_clock::now();
  const std::string what = "visibility cones: " + std::to_string(part.mesh.triangleCount()) + " triangles along " +
                           std::to_string(result.directions.size()) + " directions";
  // The backends take a fraction callback and stop by throwing; the stop is turned into `cancelled` here.
  const Progress backend_progress = [&](double fraction) {
    if (reportProgress(progress, "visibility", fraction, what)) return true;
    result.cancelled = true;
    return false;
  };
  try {
    if (options.backend == VisibilityBackend::Ray) {
      RayVisibilityOptions ray = options.ray;
      if (ray.threads == 0) ray.threads = options.threads;
      result.map = rayVisibility(part.mesh, result.directions.directions, ray, backend_progress);
    } else {
      RenderVisibilityOptions render = options.render;
      if (render.threads == 0) render.threads = options.threads;
      result.map = renderVisibility(part.mesh, result.directions.directions, render, backend_progress);
    }
  } catch (const std::runtime_error&) {
    if (!result.cancelled) throw;
    return result;
  }
  result.seconds_visibility = secondsSince(start);

  start = std::chrono::steady_clock::now();
  if (options.side_correction) result.side_pairs_added = sideCorrection(result.map, part.mesh, result.directions);
  result.seconds_side = secondsSince(start);
  result.unseen_triangles = invisibleTriangles(result.map);
  return result;
}

void writeVisibilityFiles(const Part& part, const VisibilityResult& result, const std::string& folder) {
  std::error_code error;
  std::filesystem::create_directories(folder, error);
  if (error) throw InputError("cannot create the output folder '" + folder + "': " + error.message());
  writeBinaryStl(part.mesh, folder + "/mesh.stl", "art2part mesh analysed for visibility, mm");
  FILE* f = std::fopen((folder + "/directions.csv").c_str(), "w");
  if (!f) throw InputError("cannot write '" + folder + "/directions.csv'");
  for (const Vec3& d : result.directions.directions) std::fprintf(f, "%.17g,%.17g,%.17g\n", d.x(), d.y(), d.z());
  std::fclose(f);
  writeVisibilityBits(result.map, folder + "/visibility.bits");
}

}  // namespace art2part
