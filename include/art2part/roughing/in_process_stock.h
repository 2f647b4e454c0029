// The stock between setups: what the operations so far left (the machined result of one setup is the raw stock of
// the next). A dexel model of the simulation (simulation/stock.h) on a coarse lattice, swept by each setup's
// operations as they are planned; a later setup asks it for the material in each of its slabs, projected along its
// direction. Without it every setup would start from the whole block: cutting air where an earlier setup cleared,
// and keeping shanks and holders clear of stock that is long gone.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <utility>
#include <vector>

#include "art2part/geometry/part.h"
#include "art2part/roughing/region.h"
#include "art2part/setup/setup_plan.h"
#include "art2part/simulation/stock.h"
#include "art2part/simulation/tool_solid.h"
#include "art2part/tooling/tool.h"
#include "art2part/tooling/toolpath.h"

namespace art2part {

class MeshDexels;
class PartDistance;

class InProcessStock {
 public:
  // The block of `stock` (a closed mesh in the part frame) around `solid`, on a lattice of about `rays` z-rays, its
  // cells no coarser than `coarsest` mm unless that needs more than `max_rays` z-rays, and never finer than 0.5 mm.
  // Throws InputError when a count is under 1 or `coarsest` not positive.
  InProcessStock(const Part& solid, const Mesh& stock, long rays = 20000, double coarsest = 1.5,
                 long max_rays = 400000);
  ~InProcessStock();
  InProcessStock(const InProcessStock&) = delete;
  InProcessStock& operator=(const InProcessStock&) = delete;

  // Takes away what `path` cuts (every kind of move; `tools` by id), each tool eroded by half a cell's diagonal: a
  // film up to that thick stays on what it cut, and nothing a ray passes by is taken.
  void remove(const Toolpath& path, const std::vector<Tool>& tools);

  // The material between heights lo and hi of `frame` (its z) for each slab, projected on the frame's x-y plane and
  // grown by a cell (remove keeps every point of material within half a cell's diagonal of a ray's material, and its
  // projection is rasterised): a superset of the material there, part included.
  std::vector<Region> slabs(const SetupFrame& frame, const std::vector<std::pair<double, double>>& slabs) const;

  // What of the stock in each slab the model proves is there: the points of its rays in the slab with material a
  // cell every way along the three axes and no part within kPartClearanceCells along any (provenOnRay), projected and
  // grown back by two cells (the proof stops a cell inside the material; a raster cell stands for a point in it).
  // Free of the film the model keeps on faces cut square to an axis or at an angle in a coordinate plane, and of the
  // part with the allowance and film over its faces finished by earlier setups, which slabs() holds and a setup
  // cutting by it would trace as stock, round the part at every level: cut only this, keep holders, links and
  // descents clear of slabs(). Stock thinner than two cells along an axis, or within a cell of the part unless thicker
  // stock beyond it is proven, is not proven: a setup's levels near the part nest (roughing.cpp, nestCentres).
  // The tests across each ray, and each projection asked, are kept until the next remove(): ask from one thread at a
  // time.
  std::vector<Region> provenSlabs(const SetupFrame& frame, const std::vector<std::pair<double, double>>& slabs) const;

  // Where the faces the operations so far cut lie in each slab (within doubt() of it along the frame's z), projected
  // and grown by doubt(): the raw stock's faces and the part's are not in it.
  std::vector<Region> cutSlabs(const SetupFrame& frame, const std::vector<std::pair<double, double>>& slabs) const;

  // mm: proven stock within this of the part's skin (the part with the allowance) and of a cut face may be no stock:
  // the film remove leaves on what it cut (half a cell's diagonal) and the proof's growth back (two cells).
  double doubt() const;
  double cell() const;      // the lattice's largest spacing, mm
  double volume() const;    // mm^3 of material left, part included

 private:
  enum class Projection { All, Proven, Cuts };
  std::vector<Region> project(const SetupFrame& frame, const std::vector<std::pair<double, double>>& slabs,
                              Projection what) const;  // walk(), or what it gave for the same question
  std::vector<Region> walk(const SetupFrame& frame, const std::vector<std::pair<double, double>>& slabs,
                           Projection what) const;
  // Stock at `p` (in `span` of ray (iu, iv) of family `axis`): stockAlong holds for the three families. The other two
  // families' tests depend only on the lattice cell p lies in along the ray, so they are asked once per cell
  // (across_) until the model changes.
  bool provenOnRay(int axis, int iu, int iv, const Span& span, const Vec3& p) const;
  // One family's test: on its ray nearest p one span holds [p - cell, p + cell], and no part lies within
  // kPartClearanceCells of p along it.
  bool stockAlong(int axis, const Vec3& p) const;
  bool partNear(int axis, int ray, double t) const;  // part within kPartClearanceCells of t along the ray

  static constexpr double kPartClearanceCells = 1;  // partNear

  Stock stock_;
  Stock raw_;  // the stock before any operation: its faces are exact, no film on them
  std::unique_ptr<MeshDexels> part_;
  std::unique_ptr<PartDistance> distance_;
  std::map<std::string, ToolSolid> solids_;
  // Per family, 2 bits per lattice cell along each ray (each ray whole 64-bit words, so the threads projecting their
  // rows never share a word): 0 not asked, 1 the other families prove stock there, 2 they do not. remove() clears it.
  mutable std::array<std::vector<std::uint64_t>, 3> across_;
  // The projections asked since the last remove(): a setup's passes share their levels (main and reach, the rest
  // passes among them), so each set is walked once.
  struct Asked {
    Projection what;
    SetupFrame frame;
    std::vector<std::pair<double, double>> slabs;
    std::vector<Region> regions;
  };
  mutable std::vector<Asked> asked_;
};

}  // namespace art2part
