// Setups for finishing, beyond the minimum cover. The cover (setup_plan.h) reaches every triangle from the fewest
// directions, counting a face parallel to a direction as reached from it (side visibility, 3.2.4); but a plane a
// flat end mill can reach only from its side 800 mm deep, or a bore whose axis is no setup direction, is then left to
// surface finishing or to nothing. Thesis 4.3.1 wants a plane face milled square or side milled parallel, the whole
// face from one direction. So, after the cover: the faces whose shape's own strategy (face milling along a plane's
// normal, peripheral milling along a cylinder's axis, side milling within the flutes) no cover setup offers, and
// which that direction sees whole, are gathered; the direction serving the most of their area is added as a setup
// while it serves at least `min_area_fraction` of the part's surface, at most `max_setups` times.
#pragma once

#include <vector>

#include "art2part/finishing/finishing.h"

namespace art2part {

struct FinishingSetupOptions {
  int max_setups = 2;               // setups added at most
  double min_area_fraction = 0.02;  // of the part's surface a setup must serve to be added
};

// The setups to add (for_finishing set, frames made as the cover's, finishing_faces the faces each serves), in order.
// `longest_flutes`: the longest flute length of the library's flat end mills (side milling deeper is no option).
std::vector<Setup> finishingSetups(const Part& part, const VisibilityResult& visibility, const SetupPlan& setups,
                                   double longest_flutes, const FinishingOptions& options,
                                   const FinishingSetupOptions& setup_options = {});

}  // namespace art2part
