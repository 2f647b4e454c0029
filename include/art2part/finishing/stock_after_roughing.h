// What roughing left, as finishing sees it along any direction of a setup. Roughing records the stock its last pass
// left in each setup's own frame (RoughingPlan::stock_left); a 5-axis plan also finishes faces along their own
// directions within a setup's tilt, where no such record exists, and no record is not no stock: a tool kept clear of
// nothing runs its holder and rapids into what roughing never reached. This answers from the in-process model
// instead (in_process_stock.h): the block less every roughing operation of the setup and of the setups before it,
// projected along the direction. Its slabs hold a superset of the material there (the model's film on cut faces
// included, up to film() thick), so a tool kept clear of them is clear of the stock; finishing passes run before later
// setups' roughing, and earlier setups' finishing is not taken away (it only makes the stock smaller).
#pragma once

#include <map>
#include <memory>
#include <mutex>
#include <utility>
#include <vector>

#include "art2part/finishing/holes.h"
#include "art2part/geometry/mesh.h"
#include "art2part/geometry/part.h"
#include "art2part/roughing/in_process_stock.h"
#include "art2part/roughing/roughing.h"
#include "art2part/setup/setup_plan.h"
#include "art2part/tooling/tool.h"

namespace art2part {

class StockAfterRoughing {
 public:
  // `part`, `stock` (the block, part frame), `roughing` and `library` must outlive this. Nothing is computed until
  // asked. Threads may ask side by side: one answer is worked out at a time.
  StockAfterRoughing(const Part& part, const Mesh& stock, const RoughingPlan& roughing, const ToolLibrary& library,
                     const RoughingOptions::RawStock& model = {});

  // The stock left once setup `setup`'s roughing is done, in `frame`: slabs top down, about twice the model's cell
  // thick, from the stock's top to its bottom along frame.z (SlabState::remaining: the material's projection, the
  // part included, as RoughingPlan::stock_left holds it). The model keeps what it projected: finishing's later rounds
  // ask again at no cost.
  std::vector<SlabState> slabs(int setup, const SetupFrame& frame);
  // The same between the heights of `extents` (lo, hi along frame.z).
  std::vector<Region> slabs(int setup, const SetupFrame& frame, const std::vector<std::pair<double, double>>& extents);

  // Whether `tool` can make `hole` along its axis in setup `setup` with its body kept `margin` clear of the stock left
  // over the mouth: from the clearance plane down to the hole's deepest point, every zone of the body (the cutter
  // as it descends to the mouth included) against the slabs from film() above the mouth up (below that the model's
  // film on the face round the mouth would block every drill; the hole's own clearance from the part is the hole
  // method's check, holes.h).
  bool clearOverHole(int setup, const Hole& hole, const Tool& tool, double margin);

  // mm: the slabs may hold a film this thick on faces roughing cut (InProcessStock::doubt(): the model's film and its
  // projection's growth); 0 before any model is built.
  double film() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return film_;
  }

 private:
  const InProcessStock& model(int setup);
  std::vector<Region> project(int setup, const SetupFrame& frame,
                              const std::vector<std::pair<double, double>>& extents);

  const Part& part_;
  const Mesh& stock_;
  const RoughingPlan& roughing_;
  const ToolLibrary& library_;
  RoughingOptions::RawStock options_;
  std::map<int, std::unique_ptr<InProcessStock>> models_;  // per setup, built when first asked
  double film_ = 0;
  mutable std::mutex mutex_;  // over the models and their projections' caches
};

}  // namespace art2part
