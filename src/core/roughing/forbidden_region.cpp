#include "art2part/roughing/forbidden_region.h"

#include <cmath>

namespace art2part {

std::vector<BodyZone> bodyZones(const Tool& tool) {
  std::vector<BodyZone> zones;
  // A shank no wider than the cutter follows where the flutes have cleared, in principle; it is checked all the same,
  // since the cleared area is known only to the accuracy of the offsets and of the passes.
  if (tool.stickout > tool.flute_length) zones.push_back({tool.flute_length, tool.stickout, tool.shank_diameter / 2});
  double from = tool.stickout;
  const std::size_t first_holder = zones.size();
  for (const HolderStep& step : tool.holder) {
    const double radius = step.diameter / 2;
    if (zones.size() > first_holder && std::abs(zones.back().radius - radius) < 10) {
      zones.back().to += step.length;
      zones.back().radius = std::max(zones.back().radius, radius);
    } else {
      zones.push_back({from, from + step.length, radius});
    }
    from += step.length;
  }
  return zones;
}

namespace {

// Shank and holder zones: 50 um of simplification and as much chord error, made up by 0.1 mm more radius, cut the
// vertices of a 30 mm offset about threefold.
constexpr double kBodyTolerance = 0.05;

void append(Region& to, const Region& from) { to.insert(to.end(), from.begin(), from.end()); }

}  // namespace

Region growForBody(const Region& region, double radius) {
  if (region.empty()) return {};
  return offsetRegion(simplifyRegion(region, kBodyTolerance), radius + 2 * kBodyTolerance, kBodyTolerance);
}

ForbiddenRegion::ForbiddenRegion(const ShadowStack& shadows, double cutter_radius, const std::vector<BodyZone>& zones,
                                 double holder_margin, bool stock_left)
    : shadows_(shadows) {
  if (cutter_radius >= 0) {
    Layer cutter;
    cutter.radius = cutter_radius;
    cutter.tolerance = kArcTolerance;
    layers_.push_back(cutter);
  }
  for (const BodyZone& zone : zones) {
    Layer layer;
    layer.from = zone.from;
    layer.radius = zone.radius + holder_margin;
    layer.counts_stock = stock_left;
    layer.tolerance = kBodyTolerance;
    layers_.push_back(layer);
  }
}

const Region& ForbiddenRegion::at(double z, const std::vector<StockLeft>& left_above) {
  while (slab_gains_.size() < left_above.size()) {
    Region gain = subtract(*left_above[slab_gains_.size()].remaining, slabs_counted_);
    if (!gain.empty()) slabs_counted_ = unite(slabs_counted_, gain);
    slab_gains_.push_back(dropThinPieces(gain, kThinGain));  // slivers: as the shadow's gains
  }
  std::vector<Region> fresh(layers_.size());  // per layer, disjoint pieces, listed
  for (std::size_t i = 0; i < layers_.size(); ++i) {
    Layer& layer = layers_[i];
    if (layer.counts_stock) {
      // Slabs whose top is above the zone's bottom.
      for (; layer.next_slab < left_above.size() && left_above[layer.next_slab].top > z + layer.from; ++layer.next_slab)
        append(fresh[i], slab_gains_[layer.next_slab]);
    } else {
      // The shadow's gains down to the zone's bottom.
      const int last = shadows_.indexAt(z + layer.from);
      for (; layer.next_gain <= last; ++layer.next_gain) append(fresh[i], shadows_.gain(layer.next_gain));
    }
  }
  // Pieces gained at neighbouring heights touch: merged first, their offsets would overlap and the union of
  // overlapping offsets is what costs. Then simplified and offset with chords as coarse as the layer allows, both
  // paid for by a larger radius (the region only grows: never a collision for an approximation), as are the slivers
  // the gains leave out. The layers with new pieces side by side (threads only when there are two or more).
  std::vector<int> grown_layers;
  for (std::size_t i = 0; i < layers_.size(); ++i)
    if (!fresh[i].empty()) grown_layers.push_back(static_cast<int>(i));
  parallelForRegions(static_cast<int>(grown_layers.size()), [&](int k) {
    const int i = grown_layers[k];
    const Layer& layer = layers_[i];
    fresh[i] = offsetRegion(simplifyRegion(unite(fresh[i], {}), layer.tolerance),
                            layer.radius + 2 * layer.tolerance + 2 * kThinGain, layer.tolerance);
  });
  Region added;  // offset pieces of every layer, united with the region once
  for (const Region& grown : fresh) append(added, grown);
  if (!added.empty()) forbidden_ = unite(forbidden_, added);
  return forbidden_;
}

}  // namespace art2part
