// The crossings between the holes of a drilling or helix run kept low over what stands (issue 19, item 2): each at the
// lowest height at which the whole tool (flutes, shank, holder) may cross straight from over one R plane to over the
// next, by LinkClearance over the slabs of the stock along the run's axis. Sound when the slabs hold everything that
// may stand when the run is made: the stock roughing left, the part included (RoughingPlan::stock_left, or
// StockAfterRoughing's along a direction that is no setup's own); finishing before the run only takes stock away.
// Every zone of the tool keeps `margin` beside and over that stock (LinkClearance::Beside::WholeTool). Across open
// ground between holes on one face the tool stays at the R planes instead of climbing to the clearance level.
#pragma once

#include <vector>

#include "art2part/finishing/holes.h"
#include "art2part/roughing/roughing.h"
#include "art2part/setup/setup_plan.h"
#include "art2part/tooling/tool.h"

namespace art2part {

// Crossings for runs along `frame.z` (the holes' axis) over `slabs`, given in `frame` (top down).
HoleLink linkOverStock(const std::vector<SlabState>& slabs, const SetupFrame& frame, const Tool& tool, double margin);

}  // namespace art2part
