#include "art2part/roughing/roughing.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "art2part/common/angles.h"
#include "art2part/roughing/engagement_clearing.h"
#include "art2part/roughing/forbidden_region.h"
#include "art2part/roughing/in_process_stock.h"
#include "art2part/roughing/operation_moves.h"
#include "art2part/roughing/shadow.h"

namespace art2part {

namespace {

// Tuning of the levels and the regions; each value decides what the plans look like.
constexpr double kStepdownOfDiameter = 0.5;   // a tool without max_stepdown steps down half its diameter
constexpr double kMergedLevelMm = 0.02;       // a fixed height this close below the previous one merges with it
constexpr double kRestSkinMm = 0.05;          // a rest pass keeps this beyond the allowance: never grazes the skin
// The tool centre may go this far beyond the stock it is to clear (grown by its radius), so the edges of the
// stock are cut through; a rest pass's target is its predecessor's leftovers, so it stays closer.
constexpr double kCentreBeyondStockMm = 1.0;
constexpr double kRestCentreBeyondStockMm = 0.5;
constexpr double kRestTargetOpeningMm = 0.02;  // a rest target thinner than twice this is no target (opened away)
constexpr double kRestTargetSliverMm2 = 0.01;  // and a piece of it smaller than this
constexpr double kCentreSliverMm2 = 0.001;     // centre regions smaller than this are dropped
constexpr double kAirGapMm = 0.1;              // centres farther than radius + this from the stock cut air
constexpr double kClearedInsetMm = 0.05;       // the cleared area: centres grown by the radius less this
// A slab thinner than the tool's max_stepdown is cleared with the step-over (zig-zag) or the radial engagement
// (engagement clearing) grown in proportion: the same ae x ap as the library's cutting data (a shop faces a thin
// layer with a wide cutter path), up to this share of the diameter.
constexpr double kThinSlabStepoverRatio = 0.75;
// nestCentres: a later setup's level takes in the centres below within this many in-process cells of its forbidden
// region (the remnant within a cell of the part that the proof leaves, its film and the proof's own cell).
constexpr double kNestBandCells = 3;

// The pieces of a centre region whose sweep (each grown by `reach`) takes at least `least_mm2` of `target`.
Region piecesReaching(const Region& centre, const Region& target, double reach, double least_mm2) {
  Region kept;
  for (const RegionPiece& piece : regionPieces(centre))
    if (regionArea(intersect(offsetRegion(piece.rings, reach), target)) >= least_mm2)
      kept.insert(kept.end(), piece.rings.begin(), piece.rings.end());
  return kept;
}

// One level of an operation once its centre region is known: what the moves and the slabs left are drawn from.
struct LevelDraft {
  Region stock;      // all the stock that may be in the slab (the model's film included)
  Region proven;     // what of it the operation is to remove
  Region forbidden;  // where no centre may go: the part, and shank and holder against the stock left above
  ClearingLevel clear;
  Region cleared;    // what its centres clear: clear.centre grown by the radius less kClearedInsetMm
  Region doubtful;   // proven stock left out of the target as what may be the earlier setups' film round the skin
};

// The centres within `reach` (a target grown by the radius and how far beyond it centres may go), out of
// `forbidden`. A check on the grown region: no centre may lie in the shadow itself. Where one does (the grown region
// lost a piece of the shadow: seen on CTC-02, setup 2.8 deg off z, tips 27 mm deep in the part), the level takes the
// shadow grown directly (counted in `direct_levels`).
Region centresReaching(const Region& reach, const Region& forbidden, const Region& shadow, double r, double allowance,
                       int& direct_levels) {
  if (regionEmpty(reach)) return {};
  Region centre = dropSlivers(subtract(reach, forbidden), kCentreSliverMm2);
  if (!regionEmpty(centre) && !regionEmpty(intersect(centre, shadow))) {
    ++direct_levels;
    centre = dropSlivers(subtract(centre, offsetRegion(shadow, r + allowance)), kCentreSliverMm2);
  }
  return centre;
}

// The centres that clear `target` at level z: within the radius and `beyond` of it, out of `forbidden`.
Region levelCentres(const Region& target, const Region& forbidden, const Region& shadow, double r, double beyond,
                    double allowance, int& direct_levels) {
  if (regionEmpty(target)) return {};
  return centresReaching(offsetRegion(target, r + beyond), forbidden, shadow, r, allowance, direct_levels);
}

// What one level of an operation is to remove, and the stock round it.
struct LevelTarget {
  Region stock;     // all the stock that may be in the slab
  Region proven;    // what of it the model proves (the stock itself without a model)
  Region doubtful;  // proven stock that may be the earlier setups' film round the skin (LevelDraft::doubtful)
  Region target;    // what the operation is to remove
  Region reach;     // where centres may go for it: the target grown by the radius and the centres' reach beyond it
};
constexpr std::size_t kTargetBlock = 8;  // levels whose targets are worked out side by side

// Bottom up, each level of an operation over an in-process stock takes in what keeps the column over every cut of
// the levels below clear, never into the forbidden region nor the part's shadow:
// - the stock in doubt it left out (LevelDraft::doubtful) that the discs of the levels below reach: their flutes
//   would take it from under, deeper than the step-down;
// - with `band` > 0 (a main pass, which targets the stock the model proves and so leaves near the part, within a
//   cell of it with the allowance and the film, a remnant that a level above does not take and a level below, its
//   own stock proven beside it, sweeps under), the centres of the levels below that lie within `band` of its
//   forbidden region (where that remnant is) and whose disc would meet stock in its slab.
// The columns stay unproven elsewhere (film on faces cut far from the part): such levels prove their links and
// descents by the stock model (ClearingLevel::column_clear and descents_clear false).
void nestCentres(std::vector<LevelDraft>& drafts, const ShadowStack& shadows, double r, double beyond,
                 double allowance, double band, RoughingOperation& op) {
  Region below, reach;  // the centres of the levels below, and their discs
  for (auto it = drafts.rbegin(); it != drafts.rend(); ++it) {
    ClearingLevel& clear = it->clear;
    const Region& shadow = shadows.at(clear.z);
    Region add;
    if (!regionEmpty(reach) && !regionEmpty(it->doubtful)) {
      const Region reached = intersect(it->doubtful, reach);
      add = levelCentres(reached, it->forbidden, shadow, r, beyond, allowance, op.direct_levels);
    }
    if (band > 0 && !regionEmpty(below)) {
      Region nested = intersect(below, offsetRegion(it->stock, r + kAirGapMm));
      if (!regionEmpty(nested))
        nested = subtract(intersect(nested, offsetRegion(it->forbidden, band)), it->forbidden);
      if (!regionEmpty(nested) && !regionEmpty(intersect(nested, shadow))) {
        ++op.direct_levels;
        nested = subtract(nested, offsetRegion(shadow, r + allowance));
      }
      add = unite(add, nested);
    }
    if (!regionEmpty(add)) {
      clear.centre = dropSlivers(unite(clear.centre, add), kCentreSliverMm2);
      it->cleared = offsetRegion(clear.centre, r - kClearedInsetMm);
    }
    if (regionEmpty(clear.centre)) continue;
    below = unite(below, clear.centre);
    reach = unite(reach, offsetRegion(clear.centre, r));
  }
}

// The step-over for a slab `thickness` deep, given the operation's `stepover` at the tool's max_stepdown: wider in
// proportion for a thinner slab, up to kThinSlabStepoverRatio diameters (never narrower than `stepover`).
double slabStepover(const Tool& tool, double stepover, double thickness) {
  if (!(tool.max_stepdown > 0) || !(thickness > 0) || thickness >= tool.max_stepdown) return stepover;
  return std::max(stepover, std::min(stepover * tool.max_stepdown / thickness, kThinSlabStepoverRatio * tool.diameter));
}

// The engagement limit for a slab `thickness` deep: the radial engagement of the tool's max_engagement_deg on a
// straight wall, grown as slabStepover grows a step-over.
double slabEngagement(const Tool& tool, double thickness) {
  const double r = tool.diameter / 2, ae = engagementStepover(r, 0, tool.max_engagement_deg);
  const double grown = std::min(slabStepover(tool, ae, thickness), 2 * r);
  return std::acos(1 - grown / r) * 180 / kPi;
}

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// The part and its stock in one setup's frame.
struct SetupGeometry {
  std::vector<Vec3> part;   // part vertices in the frame
  Mesh stock;               // stock mesh, vertices in the frame
  double stock_top = 0, stock_bottom = 0;
};

SetupGeometry setupGeometry(const Part& part, const Setup& setup, const RoughingOptions& options) {
  SetupGeometry g;
  g.part = toFrame(part.mesh.vertices, setup.frame);
  g.stock = roughingStock(part, options);
  g.stock.vertices = toFrame(g.stock.vertices, setup.frame);
  g.stock_top = -1e300;
  g.stock_bottom = 1e300;
  for (const Vec3& p : g.stock.vertices) {
    g.stock_top = std::max(g.stock_top, p.z());
    g.stock_bottom = std::min(g.stock_bottom, p.z());
  }
  return g;
}

double stepdownFor(const Tool& tool, const RoughingOptions& options, bool rest) {
  double step = options.levels.stepdown > 0 ? options.levels.stepdown
                                            : (tool.max_stepdown > 0 ? tool.max_stepdown
                                                                     : kStepdownOfDiameter * tool.diameter);
  if (rest && options.rest.stepdown > 0) step = std::min(step, options.rest.stepdown);
  return std::min(step, tool.flute_length);
}

// mm between the levels of an operation: a step-up pass takes Clearing::step_up_share of its cutter's step-down.
double levelStep(const Tool& tool, const RoughingOptions& options, const RoughingStart& start) {
  if (start.step_up) return options.clearing.step_up_share * stepdownFor(tool, options, false);
  return stepdownFor(tool, options, !start.previous.empty() && !start.reach);
}

// The stock a previous operation left in the slab [z, top] (its slabs contain ours: our levels include theirs).
const Region* beforeRemaining(const std::vector<SlabState>& before, double z, double top) {
  for (const SlabState& s : before)
    if (z >= s.z - 1e-9 && top <= s.top + 1e-9) return &s.remaining;
  return nullptr;
}

// What an operation's levels start from: the setup's block, what earlier setups left of it (their model's projections
// per level: empty without one) and what the pass before left (a rest pass).
struct LevelSources {
  const SetupGeometry& g;
  const InProcessStock* in_process;
  const std::vector<SlabState>* before;
  const std::vector<Region>& in_process_slabs;   // all that may be there
  const std::vector<Region>& in_process_proven;  // what the model proves is there: to be cut
  const std::vector<Region>& in_process_cuts;    // near the faces earlier setups cut: proven stock there may be film
  double reach;  // how far centres may go from the target: the radius and kCentreBeyondStockMm (or the rest's)
};

// The slab [z, top] of level `index`: its stock and what the operation is to remove of it; `skin` is the part with
// the allowance at z (unused by a first main pass).
LevelTarget levelTarget(const LevelSources& from, std::size_t index, double z, double top, const Region& skin) {
  LevelTarget t;
  t.stock = stockSlabRegion(from.g.stock.vertices, from.g.stock.triangles, z, top);
  if (from.in_process) t.stock = intersect(t.stock, from.in_process_slabs[index]);
  if (from.before) {
    const Region* left = beforeRemaining(*from.before, z, top);
    t.stock = left ? intersect(t.stock, *left) : Region{};
  }
  // What this operation is to remove: all the stock (that earlier setups' model proves there, less what lies within
  // its doubt of both the skin and a face they cut: the stairs and film they left round the part, which a pass would
  // trace at every level for next to nothing), or for a rest pass what of it lies beyond the allowance. Shanks,
  // holders and links keep clear of all of `stock`.
  t.proven = from.in_process ? intersect(t.stock, from.in_process_proven[index]) : t.stock;
  if (from.in_process && !regionEmpty(from.in_process_cuts[index])) {
    t.doubtful =
        intersect(t.proven, intersect(offsetRegion(skin, from.in_process->doubt()), from.in_process_cuts[index]));
    if (from.before) t.doubtful = subtract(t.doubtful, skin);
  }
  t.target = subtract(t.proven, t.doubtful);
  if (from.before) {
    const Region beyond_skin = subtract(t.target, skin);
    t.target = dropSlivers(offsetRegion(offsetRegion(beyond_skin, -kRestTargetOpeningMm), kRestTargetOpeningMm),
                           kRestTargetSliverMm2);
  }
  t.reach = regionEmpty(t.target) ? Region{} : offsetRegion(t.target, from.reach);
  return t;
}

void appendMoves(const std::vector<ClearingPoint>& moves, const SetupFrame& frame, const Tool& tool, int setup_index,
                 RoughingOperation& op) {
  for (const ClearingPoint& m : moves) {
    CutterLocation cl;
    cl.setup = setup_index;
    cl.tool = tool.id;
    cl.move = m.move == ClearingMove::Rapid ? MoveKind::Rapid : MoveKind::Feed;
    cl.tip = fromFrame(m.tip, frame);
    cl.axis = frame.z;
    if (!op.path.empty() && op.path.back().move == cl.move && (op.path.back().tip - cl.tip).norm() < 1e-9) continue;
    op.path.push_back(cl);
  }
}

void countEntries(const ClearingStats& stats, RoughingOperation& op) {
  op.plunges += stats.plunges_into_stock;
  op.ramps += stats.ramps;
  op.retracts += stats.retracts;
}

void estimateTime(const Tool& tool, const RoughingOptions& options, RoughingOperation& op) {
  op.feed_mm = toolpathLength(op.path, MoveKind::Feed);
  op.rapid_mm = toolpathLength(op.path, MoveKind::Rapid);
  op.seconds = 60.0 * (op.feed_mm / std::max(1.0, tool.feed_mm_min) + op.rapid_mm / std::max(1.0, options.rapid_mm_min));
}

}  // namespace

double roughingStepover(const Tool& tool, const RoughingOptions& options) {
  const double step = options.clearing.stepover > 0 ? options.clearing.stepover
                                                    : (tool.max_stepover > 0 ? tool.max_stepover
                                                                             : kRoughingStepoverRatio * tool.diameter);
  return std::min(step, kMostStepoverRatio * tool.diameter);
}

Mesh roughingStock(const Part& part, const RoughingOptions& options) {
  if (options.stock.mesh) return *options.stock.mesh;
  Box box = boundingBox(part.mesh);
  box.min -= Vec3::Constant(options.stock.margin);
  box.max += Vec3::Constant(options.stock.margin);
  return boxMesh(box);
}

std::vector<RoughingLevel> roughingLevels(const Part& part, const std::vector<Vec3>& frame_vertices,
                                          double stock_top, double stock_bottom, double stepdown,
                                          const RoughingOptions& options) {
  std::vector<RoughingLevel> critical;
  if (options.levels.critical_heights) {
    const double cos_limit = std::cos(options.levels.critical_angle_deg * kPi / 180);
    std::vector<char> seen(part.faces.size(), 0);
    for (int t = 0; t < part.mesh.triangleCount(); ++t) {
      const int f = t < static_cast<int>(part.triangle_face.size()) ? part.triangle_face[t] : -1;
      if (f < 0 || f >= static_cast<int>(part.faces.size()) || seen[f] || part.faces[f].type != SurfaceType::Plane)
        continue;
      seen[f] = 1;
      const Triangle& tri = part.mesh.triangles[t];
      const Vec3 &a = frame_vertices[tri[0]], &b = frame_vertices[tri[1]], &c = frame_vertices[tri[2]];
      const Vec3 n = (b - a).cross(c - a).normalized();
      if (n.z() < cos_limit) continue;  // not facing up, square to the direction
      const double z = (a.z() + b.z() + c.z()) / 3 + options.allowance;
      if (z < stock_top - 1e-6 && z > stock_bottom + 1e-6) critical.push_back({z, true});
    }
  }
  std::sort(critical.begin(), critical.end(), [](const RoughingLevel& p, const RoughingLevel& q) { return p.z > q.z; });
  // Regular levels between consecutive fixed heights (stock top, critical heights, stock bottom), evenly spaced at
  // most `stepdown` apart.
  std::vector<RoughingLevel> fixed = critical;
  fixed.push_back({stock_bottom, false});
  std::vector<RoughingLevel> levels;
  double top = stock_top;
  for (const RoughingLevel& f : fixed) {
    if (top - f.z < kMergedLevelMm) {  // a critical height a hair below the previous one: merged
      if (f.critical && !levels.empty()) levels.back().critical = true;
      continue;
    }
    const int n = std::max(1, static_cast<int>(std::ceil((top - f.z) / stepdown - 1e-9)));
    for (int i = 1; i < n; ++i) levels.push_back({top - (top - f.z) * i / n, false});
    levels.push_back(f);
    top = f.z;
  }
  return levels;
}

RoughingPass roughSetup(const Part& part, const Setup& setup, int setup_index, const Tool& tool,
                        const RoughingOptions& options, const RoughingStart& start_from, const ProgressSink& progress) {
  const auto start = std::chrono::steady_clock::now();
  RoughingPass pass;
  RoughingOperation& op = pass.operation;
  const std::vector<SlabState>* before = start_from.previous.empty() ? nullptr : &start_from.previous;
  const InProcessStock* in_process = start_from.earlier;
  op.setup = setup_index;
  op.tool = tool.id;
  // A high-efficiency cutter clears front by front under its engagement limit, in the main pass and its step-up pass;
  // rest passes take conventional tools.
  const bool by_engagement = tool.max_engagement_deg > 0 && (!before || start_from.step_up);
  op.kind = start_from.reach ? "reach roughing"
            : !by_engagement ? (before ? "rest roughing" : "roughing")
                             : (before ? "adaptive rest roughing" : "adaptive roughing");
  const SetupGeometry g = setupGeometry(part, setup, options);
  std::vector<RoughingLevel> levels =
      roughingLevels(part, g.part, g.stock_top, g.stock_bottom, levelStep(tool, options, start_from), options);
  if (before) {  // our slabs must each lie in one of the previous operation's slabs
    for (const SlabState& s : *before)
      if (std::none_of(levels.begin(), levels.end(), [&](const RoughingLevel& l) { return std::abs(l.z - s.z) < 1e-9; }))
        levels.push_back({s.z, false});
    std::sort(levels.begin(), levels.end(), [](const RoughingLevel& p, const RoughingLevel& q) { return p.z > q.z; });
  }
  const double r = tool.diameter / 2;
  const double allowance = options.allowance + (before ? kRestSkinMm : 0.0);
  const std::vector<BodyZone> zones = bodyZones(tool);
  ClearingOptions clearing;
  clearing.stepover = roughingStepover(tool, options);
  clearing.tool_radius = r;
  clearing.ramp_angle_deg = options.clearing.ramp_angle_deg;
  clearing.clearance_z = g.stock_top + options.clearing.clearance;
  clearing.stay_down = options.clearing.stay_down;
  clearing.feed_mm_min = tool.feed_mm_min;
  clearing.rapid_mm_min = options.rapid_mm_min;
  OperationLevels planned;  // the levels' regions: the moves are written once all are known

  // Shadows at the levels only: the body zones keep clear of the stock left above, which holds the part's sections,
  // so no zone bottom needs a shadow of its own.
  std::vector<double> heights;
  for (const RoughingLevel& l : levels) heights.push_back(l.z);
  const ShadowStack shadows = start_from.shadows ? start_from.shadows->stack(heights)
                                                 : ShadowStack(g.part, part.mesh.triangles, heights);
  ForbiddenRegion forbidden_region(shadows, r + allowance, zones, options.clearing.holder_margin, true);
  ForbiddenRegion part_with_allowance(shadows, allowance, {}, 0, false);  // a rest pass's target: the stock beyond it
  std::vector<SlabState> slabs;
  std::vector<LevelDraft> drafts;
  drafts.reserve(levels.size());
  std::vector<Region> drafts_left;  // the stock each level leaves by its draft's centre
  drafts_left.reserve(levels.size());  // left_above points into it
  std::vector<StockLeft> left_above;
  std::vector<Region> in_process_slabs;  // what earlier setups left in each slab: all that may be there
  std::vector<Region> in_process_proven;  // what the model proves is there: to be cut
  std::vector<Region> in_process_cuts;    // near the faces earlier setups cut: proven stock there may be film
  if (in_process) {
    std::vector<std::pair<double, double>> extents;
    double above = g.stock_top;
    for (const RoughingLevel& level : levels) extents.emplace_back(level.z, above), above = level.z;
    in_process_slabs = in_process->slabs(setup.frame, extents);
    in_process_proven = in_process->provenSlabs(setup.frame, extents);
    in_process_cuts = in_process->cutSlabs(setup.frame, extents);
  }
  const double beyond = before ? kRestCentreBeyondStockMm : kCentreBeyondStockMm;  // centres beyond the target
  double top = g.stock_top;
  const std::string what = op.kind + ", " + tool.id + ", level ";
  // What each level is to remove (LevelTarget), worked out kTargetBlock levels at a time side by side; then level
  // after level its centres against the forbidden region, which grows with the stock each level leaves.
  std::vector<LevelTarget> targets(levels.size());
  const LevelSources sources{g, in_process, before, in_process_slabs, in_process_proven, in_process_cuts, r + beyond};
  for (RoughingLevel& level : levels) {
    const std::size_t index = &level - levels.data();
    if (!reportProgress(progress, "roughing", static_cast<double>(index) / levels.size(),
                        what + std::to_string(index + 1) + " of " + std::to_string(levels.size()),
                        static_cast<long>(index))) {
      pass.cancelled = true;
      levels.resize(index);
      break;
    }
    if (index % kTargetBlock == 0) {
      const std::size_t block = std::min(kTargetBlock, levels.size() - index);
      std::vector<Region> skins(block);  // the part with the allowance: a first main pass has no use for it
      if (in_process || before)
        for (std::size_t j = 0; j < block; ++j) skins[j] = part_with_allowance.at(levels[index + j].z, {});
      parallelForRegions(static_cast<int>(block), [&](int j) {
        const std::size_t k = index + j;
        targets[k] = levelTarget(sources, k, levels[k].z, k == 0 ? g.stock_top : levels[k - 1].z, skins[j]);
      });
    }
    const double z = level.z;
    LevelTarget& target = targets[index];
    // The cutter against the part, shank and holder against the part and the stock left above; every level above's
    // region is in it (the column over every cutting point is clear).
    const Region& forbidden = forbidden_region.at(z, left_above);

    ClearingLevel clear;
    clear.z = z;
    clear.top = top;
    clear.column_clear = before == nullptr && in_process == nullptr;
    clear.descents_clear = in_process == nullptr;
    if (!by_engagement) clear.stepover = slabStepover(tool, clearing.stepover, top - z);
    else clear.engagement_deg = slabEngagement(tool, top - z);
    clear.centre = centresReaching(target.reach, forbidden, shadows.at(z), r, allowance, op.direct_levels);
    // Only pieces whose sweep meets stock to remove: a rest pass's, or the stock a later setup's model proves.
    const double least_mm2 = before ? options.rest.least_target_mm2 : in_process ? options.stock.least_proven_mm2 : 0;
    if (least_mm2 > 0) clear.centre = piecesReaching(clear.centre, target.target, r - kClearedInsetMm, least_mm2);
    // The levels below see the stock this one leaves (conservative: nesting only adds to its centre).
    Region cleared = offsetRegion(clear.centre, r - kClearedInsetMm);
    drafts_left.push_back(subtract(target.stock, cleared));
    left_above.push_back({top, &drafts_left.back()});
    drafts.push_back({std::move(target.stock), std::move(target.proven), forbidden, std::move(clear),
                      std::move(cleared), std::move(target.doubtful)});
    top = z;
  }
  if (in_process)
    nestCentres(drafts, shadows, r, beyond, allowance, before ? 0.0 : kNestBandCells * in_process->cell(), op);
  // Each level's slabs and sweeps from its draft, the levels side by side (their region work is independent).
  const std::size_t n = drafts.size();
  slabs.resize(n);
  planned.slabs.resize(n);
  planned.swept.resize(n);
  std::vector<double> removal(n, 0.0);
  parallelForRegions(static_cast<int>(n), [&](int index) {
    LevelDraft& draft = drafts[index];
    RoughingLevel& level = levels[index];
    ClearingLevel& clear = draft.clear;
    const Region& stock = draft.stock;
    const double z = clear.z, top = clear.top;
    clear.stock_reach = offsetRegion(stock, r + kAirGapMm);
    clear.air = subtract(clear.centre, clear.stock_reach);

    const Region& cleared = draft.cleared;
    SlabState slab{z, top, subtract(stock, cleared)};
    level.cleared_mm2 = regionArea(intersect(stock, cleared));
    // What the tool can take: its whole disc round every centre point, over the slab (links, ramps and feeds stay in
    // the centre region at or above the level).
    Region swept = regionEmpty(clear.centre) ? Region{} : offsetRegion(clear.centre, r);
    // The links' proofs (link_clearance.h): engagement fronts may stop short of their centre region by
    // kEngagementReachShortfallMm, which the slabs (the rest passes' stock) do not record, the band being no rest
    // pass's to clear. So in a setup roughed by engagement the proofs' slabs keep that band: round this pass's own
    // discs when it is by engagement, round the stock the passes before it left when it follows one.
    if (by_engagement || (before && options.clearing.strategy == RoughingOptions::Clearing::Strategy::Engagement)) {
      const Region link_stock = before ? offsetRegion(stock, kEngagementReachShortfallMm) : stock;
      Region reached = !by_engagement || regionEmpty(clear.centre)
                           ? swept
                           : offsetRegion(clear.centre, r - kEngagementReachShortfallMm);
      planned.slabs[index] = {z, top, subtract(link_stock, reached)};
      planned.swept[index] = std::move(reached);
    } else {
      planned.slabs[index] = slab;
      planned.swept[index] = swept;
    }
    removal[index] = regionArea(intersect(draft.proven, swept)) * (top - z);  // not the model's film
    level.remaining_mm2 = regionArea(slab.remaining);
    level.rings = static_cast<int>(clear.centre.size());
    slabs[index] = std::move(slab);
  });
  bool centres = false;
  for (std::size_t index = 0; index < n; ++index) {
    op.planned_removal_mm3 += removal[index];
    centres = centres || !regionEmpty(drafts[index].clear.centre);
    planned.levels.push_back(std::move(drafts[index].clear));
  }
  if (centres && op.planned_removal_mm3 < start_from.least_removal_mm3) {
    pass.under_least_removal = true;
    op.levels = std::move(levels);
    op.plan_seconds = secondsSince(start);
    return pass;
  }
  OperationMovesOptions moves_options;
  moves_options.clearing = clearing;
  moves_options.holder_margin = options.clearing.holder_margin;
  moves_options.by_engagement = by_engagement;
  moves_options.engagement.tool_radius = r;
  moves_options.engagement.max_engagement_deg = tool.max_engagement_deg;
  moves_options.engagement.corner_radius = options.clearing.corner_radius_ratio * r;
  ClearingStats stats;
  appendMoves(operationMoves(planned, tool, moves_options, stats), setup.frame, tool, setup_index, op);
  countEntries(stats, op);
  op.levels = std::move(levels);
  estimateTime(tool, options, op);
  pass.left = std::move(slabs);
  op.plan_seconds = secondsSince(start);
  return pass;
}

}  // namespace art2part
