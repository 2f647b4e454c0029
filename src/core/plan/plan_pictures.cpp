// The plan folder's pictures (plan_pictures.h).
#include "art2part/plan/plan_pictures.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include "art2part/geometry/mesh.h"  // InputError
#include "art2part/render/annotate.h"
#include "art2part/render/palette.h"
#include "art2part/render/picture.h"
#include "art2part/simulation/part_distance.h"
#include "art2part/simulation/stock_mesh.h"

namespace art2part {

namespace {

std::array<unsigned char, 3> bytes(const Rgb& c) {
  auto byte = [](float v) { return static_cast<unsigned char>(std::clamp(v, 0.0f, 1.0f) * 255.0f + 0.5f); };
  return {byte(c[0]), byte(c[1]), byte(c[2])};
}

std::string partLabel(const Part& part) {
  const std::string name = std::filesystem::path(part.source).filename().string();
  return name.empty() ? "part" : name;
}

}  // namespace

void writeSetupPicture(const Part& part, const SetupPlan& plan, const std::string& path) {
  PictureOptions picture;
  picture.triangle_colours.assign(part.mesh.triangleCount(), {220, 220, 220});
  for (int k = 0; k < static_cast<int>(plan.setups.size()); ++k)
    for (int t : plan.setups[k].triangles) picture.triangle_colours[t] = bytes(setupColour(k));
  for (int t : plan.unmachinable_triangles) picture.triangle_colours[t] = bytes(unmachinableColour());
  std::vector<LegendEntry> legend;
  for (int k = 0; k < static_cast<int>(plan.setups.size()); ++k) {
    const Setup& setup = plan.setups[k];
    legend.push_back({setupColour(k), "setup " + std::to_string(k) + ": " + directionLabel(setup.frame.z) +
                                          (setup.for_finishing ? " (for finishing)" : "")});
  }
  if (!plan.unmachinable_triangles.empty()) legend.push_back({unmachinableColour(), "no setup reaches"});
  const std::string title = partLabel(part) + ": " + std::to_string(plan.setups.size()) + " setups, by the setup that machines each triangle";
  const Image image = withLegend(renderPicture(part.mesh, picture), title, legend);
  try {
    writePng(image, path);
  } catch (const std::runtime_error& e) {
    throw InputError(e.what());  // a path the caller gave
  }
}

void writeRemainingPicture(const Part& part, const PlanResult& plan, const std::string& path) {
  if (!plan.verified) throw InputError("no picture of what is left: the plan was not simulated");
  writeRemainingPicture(part, plan.verification, plan.simulation, path);
}

void writeRemainingPicture(const Part& part, const VerificationReport& report, const VerificationState& simulation,
                           const std::string& path) {
  const PartDistance distance(part.mesh);
  const StockMesh stock = remainingStockMesh(simulation.stock, simulation.part, distance);
  char title[200];
  std::snprintf(title, sizeof title, "%s: stock left by the plan, %.0f mm3 beyond %.3g mm", partLabel(part).c_str(),
                report.leftover_volume_mm3, report.tolerance_mm);
  writeDeviationPicture(stock, std::max(report.leftover_max_mm, 10.0 * report.tolerance_mm), report.tolerance_mm, path,
                        title);
}

}  // namespace art2part
