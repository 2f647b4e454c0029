// The stock roughing left, along any direction of a setup (stock_after_roughing.h).
#include "art2part/finishing/stock_after_roughing.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace art2part {

namespace {

constexpr double kSlabCells = 2;  // slabs this many of the model's cells thick
constexpr double kBodyStepMm = 1;  // clearOverHole: the body's outline sampled this often along the axis

}  // namespace

StockAfterRoughing::StockAfterRoughing(const Part& part, const Mesh& stock, const RoughingPlan& roughing,
                                       const ToolLibrary& library, const RoughingOptions::RawStock& model)
    : part_(part), stock_(stock), roughing_(roughing), library_(library), options_(model) {}

const InProcessStock& StockAfterRoughing::model(int setup) {
  std::unique_ptr<InProcessStock>& slot = models_[setup];
  if (!slot) {
    slot = std::make_unique<InProcessStock>(part_, stock_, options_.in_process_rays, options_.in_process_cell,
                                            options_.in_process_max_rays);
    removeOperations(*slot, roughing_.operations, library_, std::numeric_limits<int>::min(), setup);
    film_ = slot->doubt();
  }
  return *slot;
}

std::vector<SlabState> StockAfterRoughing::slabs(int setup, const SetupFrame& frame) {
  std::lock_guard<std::mutex> lock(mutex_);
  const InProcessStock& stock = model(setup);
  double top = -1e300, bottom = 1e300;
  for (const Vec3& v : stock_.vertices) {
    const double z = (v - frame.origin).dot(frame.z);
    top = std::max(top, z);
    bottom = std::min(bottom, z);
  }
  if (!(top > bottom)) return {};
  const int n = std::max(1, static_cast<int>(std::ceil((top - bottom) / (kSlabCells * stock.cell()))));
  std::vector<std::pair<double, double>> extents;
  for (int i = 0; i < n; ++i)
    extents.emplace_back(top - (top - bottom) * (i + 1) / n, top - (top - bottom) * i / n);
  std::vector<Region> regions = project(setup, frame, extents);
  std::vector<SlabState> out;
  for (int i = 0; i < n; ++i) out.push_back({extents[i].first, extents[i].second, std::move(regions[i])});
  return out;
}

std::vector<Region> StockAfterRoughing::slabs(int setup, const SetupFrame& frame,
                                              const std::vector<std::pair<double, double>>& extents) {
  std::lock_guard<std::mutex> lock(mutex_);
  return project(setup, frame, extents);
}

std::vector<Region> StockAfterRoughing::project(int setup, const SetupFrame& frame,
                                                const std::vector<std::pair<double, double>>& extents) {
  return model(setup).slabs(frame, extents);
}

bool StockAfterRoughing::clearOverHole(int setup, const Hole& hole, const Tool& tool, double margin) {
  std::lock_guard<std::mutex> lock(mutex_);
  const InProcessStock& stock = model(setup);
  const SetupFrame frame = setupFrame(part_, hole.axis);
  const Vec3 mouth_in_frame = hole.mouth - frame.origin;
  const Point2 axis(mouth_in_frame.dot(frame.x), mouth_in_frame.dot(frame.y));
  const double mouth = mouth_in_frame.dot(frame.z), lowest_tip = mouth - hole.total_depth;
  double top = mouth;
  for (const Vec3& v : stock_.vertices) top = std::max(top, (v - frame.origin).dot(frame.z));
  const double from = mouth + film_;
  if (top <= from) return true;
  const int n = std::max(1, static_cast<int>(std::ceil((top - from) / (kSlabCells * stock.cell()))));
  std::vector<std::pair<double, double>> extents;
  for (int i = 0; i < n; ++i) extents.emplace_back(from + (top - from) * i / n, from + (top - from) * (i + 1) / n);
  const std::vector<Region> regions = project(setup, frame, extents);
  for (int i = 0; i < n; ++i) {
    // The widest the body is over the slab, the tip anywhere from above it down to the hole's deepest point.
    const double reach = extents[i].second - lowest_tip;
    double radius = 0;
    for (double h = 0;; h += kBodyStepMm) {
      radius = std::max(radius, toolRadiusAt(tool, std::min(h, reach)));
      if (h >= reach) break;
    }
    if (radius > 0 && regionDistance(regions[i], axis) < radius + margin) return false;
  }
  return true;
}

}  // namespace art2part
