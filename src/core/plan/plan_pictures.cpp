// The plan folder's pictures (plan_pictures.h).
#include "art2part/plan/plan_pictures.h"

#include <algorithm>
#include <stdexcept>

#include "art2part/geometry/mesh.h"  // InputError
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

}  // namespace

void writeSetupPicture(const Part& part, const SetupPlan& plan, const std::string& path) {
  PictureOptions picture;
  picture.triangle_colours.assign(part.mesh.triangleCount(), {220, 220, 220});
  for (int k = 0; k < static_cast<int>(plan.setups.size()); ++k)
    for (int t : plan.setups[k].triangles) picture.triangle_colours[t] = bytes(setupColour(k));
  for (int t : plan.unmachinable_triangles) picture.triangle_colours[t] = bytes(unmachinableColour());
  const Image image = renderPicture(part.mesh, picture);
  try {
    writePng(image, path);
  } catch (const std::runtime_error& e) {
    throw InputError(e.what());  // a path the caller gave
  }
}

void writeRemainingPicture(const Part& part, const PlanResult& plan, const std::string& path) {
  if (!plan.verified) throw InputError("no picture of what is left: the plan was not simulated");
  const PartDistance distance(part.mesh);
  const StockMesh stock = remainingStockMesh(plan.simulation.stock, plan.simulation.part, distance);
  const VerificationReport& report = plan.verification;
  writeDeviationPicture(stock, std::max(report.leftover_max_mm, 10.0 * report.tolerance_mm), report.tolerance_mm, path);
}

}  // namespace art2part
