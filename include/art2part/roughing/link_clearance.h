// Stay-down links over the in-process stock (issue 19, item 2): the lowest height at which the whole tool, flutes,
// shank and holder, may cross a straight segment in a setup frame, proven from the stock left in the slabs an
// operation has finished. Why from the stock and not from the centre regions alone: a rest pass's regions are narrow
// bands round its targets and a link between two of them rarely stays inside any, while the slabs' stock says where
// the tool may pass over cleared pockets, over the part's own air and outside the block.
// Sound because a slab's `remaining` holds everything that may be in it when the link is made (the part's section
// included; the caller adds the stock still to be cut there, or gives only slabs it has finished) and holds only less
// as the operation goes on; a segment is clear of a slab when every body zone overlapping the slab's heights, or
// coming within the margin over its top, keeps its radius plus the margin from every point of `remaining`. Heights
// start at the caller's lowest, at or above the top of the slab it cuts. Every zone keeps the margin over the stock's
// top; beside it, in roughing (Beside::BodyOnly), the flutes and a shank no wider than them keep none, and `remaining`
// loses the whole disc the cutter swept round every centre point (the slab's own record keeps a band kClearedInsetMm
// wide of it): otherwise no link could pass where the tool has just cut beside a wall, a tool radius from the stock
// left on the wall. Stock that leaves out a band round the part (finishing's stock beyond the skin) needs the margin
// beside the flutes too, the margin covering the band (Beside::WholeTool).
#pragma once

#include <vector>

#include "art2part/roughing/region.h"
#include "art2part/roughing/roughing.h"
#include "art2part/tooling/tool.h"

namespace art2part {

class LinkClearance {
 public:
  // Which zones of the tool keep the margin beside the stock (every zone keeps it over a slab's top).
  enum class Beside {
    BodyOnly,   // the zones wider than the cutter: the slabs' stock lost what the cutter swept (roughing)
    WholeTool,  // the flutes too: the margin covers a band the slabs leave out (finishing's skin)
  };
  // `margin`: mm kept between the tool and the stock (the holder margin of roughing; finishing: its allowance and a
  // clearance).
  LinkClearance(const Tool& tool, double margin, Beside beside = Beside::BodyOnly);

  // A slab (its stock, part section included) and what the operation swept there, if anything: the centre region
  // grown by the tool radius (every point within the radius of it is swept: clearing_paths.h).
  void addSlab(const SlabState& slab, const Region& swept);
  // The slab added `index`-th, as it stands now: its stock may only have shrunk (pieces of it cut since).
  void replaceSlab(std::size_t index, const SlabState& slab, const Region& swept);

  // The lowest height in [lowest, ceiling) at which the tool tip may go straight from `a` to `b` with every body zone
  // clear of every finished slab, or `ceiling` when none is: each slab within a zone's reach of the segment lifts the
  // lowest such zone, and with it every zone above, `margin` over the slab's top.
  double lowestClear(const Point2& a, const Point2& b, double lowest, double ceiling) const;

 private:
  struct Zone {
    double from = 0, to = 0, radius = 0;  // above the tip, mm; radius with the margin the zone keeps
  };
  struct Edge {
    Point2 a, b;
  };
  struct Slab {
    double z = 0, top = 0;
    Point2 lo, hi;  // box of its remaining stock
    Region remaining;
    std::vector<Edge> edges;
  };
  static Slab slabOf(const SlabState& slab, const Region& swept);
  bool clearAt(const Point2& a, const Point2& b, double height) const;
  // The distance from the segment to the slab's stock (0 where it enters it); farther than `beyond`: any larger value.
  static double distanceTo(const Slab& slab, const Point2& a, const Point2& b, double beyond);

  double margin_ = 0;  // kept over a slab's top by every zone, beside it as `Beside` says
  double widest_ = 0;  // the widest zone's radius, margin included
  std::vector<Zone> zones_;
  std::vector<Slab> slabs_;
};

}  // namespace art2part
