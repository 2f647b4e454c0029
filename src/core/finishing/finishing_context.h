// What the finishing stage's pieces share while planning (finishing.cpp, hole_runs.cpp): the context of a plan, the
// planner's tally of its faces, and the stock roughing left along a direction.
#pragma once

#include <algorithm>
#include <string>
#include <vector>

#include "art2part/finishing/face_assignment.h"
#include "art2part/finishing/finishing.h"
#include "art2part/finishing/stock_after_roughing.h"

namespace art2part::finishing_detail {

class StockBeyondCache;  // finishing.cpp: the stock beyond the skins, per setup and direction

// What the planner believes of each face: the best share of it reached by any choice tried, which choice, and why
// not all of it.
struct Tally {
  std::vector<double> share;
  std::vector<int> choice;  // index into the face's choices that reached the best share (-1: none yet)
  std::vector<std::string> shortfall;
  void note(int face, int choice_index, double reached_share, const std::string& why) {
    if (reached_share > share[face] + 1e-12 || this->choice[face] < 0) {
      share[face] = std::max(share[face], reached_share);
      this->choice[face] = choice_index;
      shortfall[face] = why;
    }
  }
};

// The context every group of a plan shares.
struct Context {
  const FinishingInput& in;
  const FinishingOptions& options;
  const Part& solid;
  const Mesh& stock;
  const std::vector<const Tool*>& flats;
  const std::vector<const Tool*>& balls;
  const std::vector<std::vector<int>>& triangles;
  StockAfterRoughing& after_roughing;  // the stock along directions that are no setup's own
  StockBeyondCache& stock_beyond;
};

// The frame of a direction within a setup: the setup's own when it is the setup's direction.
SetupFrame frameFor(const Part& part, const Setup& setup, const Vec3& d);

// `d` is the setup's own direction (to within a microradian).
bool setupsOwnDirection(const Setup& setup, const Vec3& d);

// What roughing left in the frame of `direction` in a setup: the setup's slabs when the direction is the setup's own,
// else the in-process model's along it (a 5-axis plan's tilted directions).
std::vector<SlabState> stockLeftAlong(const Context& c, int setup_index, const Vec3& direction);

// The lowest crossings along `axis` in a setup over what roughing left there (linkOverStock over stockLeftAlong, the
// holder margin kept): a drilling run's between holes, one tool's between its operations.
HoleLink linkOverStockLeft(const Context& c, int setup_index, const Vec3& axis, const Tool& tool);

// Holes (hole_runs.cpp): a spot and a drill run per setup and drill (one signature's tool load), a helix per hole,
// added to `per_setup`; the holes' bore faces noted in `tally`. A through hole reached from its far end is made from
// there (reversedHole), its method chosen again for that end (plan.holes and plan.hole_methods as made).
void makeHoles(const Context& c, const std::vector<FaceAssignment>& assignment, FinishingPlan& plan, Tally& tally,
               std::vector<std::vector<FinishingOperation>>& per_setup);

}  // namespace art2part::finishing_detail
