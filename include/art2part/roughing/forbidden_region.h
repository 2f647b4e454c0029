// Where a 3-axis roughing tool's centre may not go at a level (thesis 5.1 step 7, with the holder interference of its
// future work): within the cutter's radius plus the allowance of the part's shadow at the level, and within each
// body zone's radius (shank, holder steps) plus the holder margin of the part's shadow at the zone's bottom and of
// the stock left in every slab reaching above that bottom. Each of those sets only grows as the levels go down, and
// the Minkowski sum distributes over union, so the region is grown level by level: only what is new at a level (the
// shadow's gain, the part of a slab's leftover stock not already counted) is offset and added. Offsetting the whole
// shadow at every level, as one would first write it, costs the outline's full complexity per level and was most of
// roughing's time on fine meshes.
#pragma once

#include <vector>

#include "art2part/roughing/region.h"
#include "art2part/roughing/shadow.h"
#include "art2part/tooling/tool.h"

namespace art2part {

// A part of the tool body above the flutes that is wider than the cutter: from..to above the tip, its radius.
struct BodyZone {
  double from = 0, to = 0, radius = 0;
};

// The body above the flutes: the shank, then the holder steps (those within 10 mm of radius of each other merged, as
// wide as the wider: one offset instead of one per step, at the price of a few mm of reach under it).
std::vector<BodyZone> bodyZones(const Tool& tool);

// The region grown by at least `radius` for keeping a shank or holder clear: simplified and offset with coarse chords
// (50 um each, paid for by 0.1 mm more radius), several times faster than an exact offset by a large radius.
Region growForBody(const Region& region, double radius);

// Stock left in a slab [z, top] by the levels above (part section included).
struct StockLeft {
  double top = 0;
  const Region* remaining = nullptr;
};

class ForbiddenRegion {
 public:
  // `shadows` must hold every level's height (a zone's bottom takes the shadow at the stored height at or below it:
  // conservative); it must outlive this. With `stock_left`, body zones keep clear of the stock left above, which holds
  // the part's sections (a level never clears its own shadow), and so of the part; without, of the part alone (a
  // quick comparison of tools, with no levels done). A negative cutter_radius leaves the cutter out (its caller
  // offsets the shadow itself).
  ForbiddenRegion(const ShadowStack& shadows, double cutter_radius, const std::vector<BodyZone>& zones,
                  double holder_margin, bool stock_left);
  // The region at level z. Levels come highest first; `left_above` lists the slabs of the levels already done,
  // highest first, and only grows between calls (empty without `stock_left`).
  const Region& at(double z, const std::vector<StockLeft>& left_above);

 private:
  struct Layer {
    double from = 0, radius = 0;
    double tolerance = 0;       // of simplification and of arcs, each added to the radius
    bool counts_stock = false;  // against the stock left, not the shadow
    int next_gain = 0;          // the first shadow gain not yet added
    std::size_t next_slab = 0;  // the first slab gain not yet added
  };
  const ShadowStack& shadows_;
  std::vector<Layer> layers_;
  // Each slab's leftover less that of the slabs above (on a vertical wall the part section and the skin repeat from
  // slab to slab, and nothing is new), shared by the zones, which reach each slab at different levels.
  std::vector<Region> slab_gains_;
  Region slabs_counted_;
  Region forbidden_;
};

}  // namespace art2part
