// Tool choice for roughing (thesis future work: tool selection) and the stage over every setup.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>
#include <utility>

#include "art2part/geometry/solid_closure.h"
#include "art2part/roughing/forbidden_region.h"
#include "art2part/roughing/in_process_stock.h"
#include "art2part/roughing/roughing.h"
#include "art2part/roughing/shadow.h"
#include "art2part/roughing/voxel_roughing.h"

namespace art2part {

std::vector<const Tool*> roughingTools(const ToolLibrary& library) {
  std::vector<const Tool*> tools;
  // Rigid tools only: a long-series end mill (flutes beyond kRoughingFluteRatio diameters) deflects under full-width
  // cuts; it is a finishing tool for deep walls.
  for (const Tool& t : library.tools)
    if ((t.type == ToolType::Flat || t.type == ToolType::Bull) && t.flute_length <= kRoughingFluteRatio * t.diameter)
      tools.push_back(&t);
  std::stable_sort(tools.begin(), tools.end(), [](const Tool* a, const Tool* b) {
    if (a->diameter != b->diameter) return a->diameter > b->diameter;
    return a->type == ToolType::Flat && b->type != ToolType::Flat;  // a flat mill clears closer to a floor
  });
  return tools;
}

namespace {

// A reach pass planned to remove stock at under `share` of its tool's library rate, or empty (kept).
std::string slowReach(const RoughingOperation& op, const Tool& tool, double share) {
  const double rate = op.seconds > 0 ? op.planned_removal_mm3 / (op.seconds / 60) : 0.0;
  if (rate >= share * libraryRemovalRate(tool)) return {};
  char line[200];
  std::snprintf(line, sizeof line,
                "planned to remove %.1f mm3 in %.0f s: %.1f mm3/min, under %.3g %% of %s's library rate (%.0f mm3/min)",
                op.planned_removal_mm3, op.seconds, rate, 100 * share, tool.id.c_str(), libraryRemovalRate(tool));
  return line;
}

DroppedOperation droppedPass(const RoughingOperation& op, double share, double planned_total) {
  char line[200];
  std::snprintf(line, sizeof line, "planned to remove %.1f mm3, under %.2g %% of the %.0f mm3 planned before it",
                op.planned_removal_mm3, 100 * share, planned_total);
  return droppedOperation(op, line);
}

// The tool choice measures each candidate on kChoiceLevels levels evenly down the stock, against shadows at levels
// kChoiceShadowSpacingMm apart above the lowest (for shanks and holders): the levels of a rest pass at its default
// step-down, whose shadows it shares. The centre may go kChoiceCentreBeyondMm beyond the stock, as in roughSetup.
constexpr int kChoiceLevels = 8;
constexpr double kChoiceShadowSpacingMm = 2;
constexpr double kChoiceCentreBeyondMm = 1.0;

// Area a tool would sweep over a few levels of a setup, counting only the part (not stock left above) against its
// shank and holder: a quick measure to compare tools.
double sweptArea(const Tool& tool, const std::vector<double>& zs, const ShadowStack& shadows,
                 const std::vector<Region>& stocks, const RoughingOptions& options) {
  const double r = tool.diameter / 2;
  ForbiddenRegion forbidden(shadows, r + options.allowance, bodyZones(tool), options.clearing.holder_margin, false);
  double area = 0;
  for (std::size_t i = 0; i < zs.size(); ++i) {
    const Region centre = subtract(offsetRegion(stocks[i], r + kChoiceCentreBeyondMm), forbidden.at(zs[i], {}));
    area += regionArea(intersect(stocks[i], offsetRegion(centre, r)));
  }
  return area;
}

}  // namespace

DroppedOperation droppedOperation(const RoughingOperation& op, std::string reason) {
  DroppedOperation dropped;
  dropped.setup = op.setup;
  dropped.kind = op.kind;
  dropped.tool = op.tool;
  dropped.planned_removal_mm3 = op.planned_removal_mm3;
  dropped.plan_seconds = op.plan_seconds;
  dropped.reason = std::move(reason);
  return dropped;
}

const Tool* chooseRoughingTool(const Part& part, const Setup& setup, const std::vector<const Tool*>& candidates,
                               const RoughingOptions& options) {
  SetupShadows shadows(toFrame(part.mesh.vertices, setup.frame), part.mesh.triangles);
  return chooseRoughingTool(part, setup, candidates, options, nullptr, shadows);
}

const Tool* chooseRoughingTool(const Part& part, const Setup& setup, const std::vector<const Tool*>& candidates,
                               const RoughingOptions& options, const InProcessStock* in_process,
                               SetupShadows& setup_shadows) {
  if (candidates.empty()) return nullptr;
  const std::vector<Vec3> vertices = toFrame(part.mesh.vertices, setup.frame);
  Mesh stock = roughingStock(part, options);
  stock.vertices = toFrame(stock.vertices, setup.frame);
  double top = -1e300, bottom = 1e300;
  for (const Vec3& p : stock.vertices) {
    top = std::max(top, p.z());
    bottom = std::min(bottom, p.z());
  }
  // Eight levels evenly down the stock, and where they see nothing for any tool (a setup from the side of a long
  // part: the first is already deeper than any tool reaches), eight evenly down the first of them.
  constexpr int n = kChoiceLevels;
  for (const double depth : {top - bottom, (top - bottom) / (n + 0.5)}) {
    std::vector<double> zs, heights;
    std::vector<Region> stocks;
    double above = top;
    std::vector<std::pair<double, double>> extents;
    for (int i = 1; i <= n; ++i) {
      const double z = top - depth * i / (n + 0.5);
      zs.push_back(z);
      stocks.push_back(stockSlabRegion(stock.vertices, stock.triangles, z, above));
      extents.emplace_back(z, above);
      above = z;
    }
    if (in_process) {
      const std::vector<Region> left = in_process->provenSlabs(setup.frame, extents);  // what a tool would cut
      for (int i = 0; i < n; ++i) stocks[i] = intersect(stocks[i], left[i]);
    }
    // Shadows at the levels and above them at the rest passes' levels (for the shanks and holders).
    for (const RoughingLevel& l : roughingLevels(part, vertices, top, bottom, kChoiceShadowSpacingMm, options))
      if (l.z >= zs.back()) heights.push_back(l.z);
    heights.insert(heights.end(), zs.begin(), zs.end());
    const ShadowStack shadows = setup_shadows.stack(heights);
    // The reference is what the smallest tool sweeps (a smaller tool reaches at least as far, up to its shorter
    // reach); then the largest that sweeps the fraction of it. Two or three evaluations on most parts: the reference
    // and the largest side by side.
    std::vector<double> area(candidates.size(), -1);
    const std::size_t first[] = {candidates.size() - 1, 0};
    parallelForRegions(candidates.size() > 1 ? 2 : 1, [&](int j) {
      area[first[j]] = sweptArea(*candidates[first[j]], zs, shadows, stocks, options);
    });
    const double best = area.back();
    if (best <= 0) continue;
    for (std::size_t i = 0; i < candidates.size(); ++i) {
      if (area[i] < 0) area[i] = sweptArea(*candidates[i], zs, shadows, stocks, options);
      if (area[i] >= options.clearing.tool_area_fraction * best) return candidates[i];
    }
    return candidates.back();
  }
  return nullptr;
}

namespace {

// A flat mill of the rest tool's size class after `main`: at most kRestToolRatio of its diameter, at least
// kSmallestRoughingTool.
bool restSized(const Tool& t, const Tool& main) {
  return t.type == ToolType::Flat && t.diameter <= kRestToolRatio * main.diameter + 1e-9 &&
         t.diameter >= kSmallestRoughingTool - 1e-9;
}

// The rest tool: the largest flat mill of the rest size class.
const Tool* restTool(const std::vector<const Tool*>& candidates, const Tool& main) {
  for (const Tool* t : candidates)
    if (restSized(*t, main)) return t;
  return nullptr;
}

// The reach tool after `main`: the library's flat mill of its diameter with the longest flutes beyond its own
// (nullptr: none). Long-series tools are no main or rest tools (roughingTools); their library cutting data (a
// lighter stepover and feed) is what a reach pass takes.
const Tool* reachTool(const ToolLibrary& library, const Tool& main) {
  const Tool* best = nullptr;
  for (const Tool& t : library.tools)
    if (t.type == ToolType::Flat && std::abs(t.diameter - main.diameter) < 1e-9 &&
        t.flute_length > main.flute_length + 1e-9 && (!best || t.flute_length > best->flute_length))
      best = &t;
  return best;
}

// How deep the setup's stock goes below its top along its direction (stock top to the part's lowest point).
double setupDepth(const Part& part, const Setup& setup, const RoughingOptions& options) {
  double top = -1e300, bottom = 1e300;
  for (const Vec3& p : toFrame(roughingStock(part, options).vertices, setup.frame)) top = std::max(top, p.z());
  for (const Vec3& p : toFrame(part.mesh.vertices, setup.frame)) bottom = std::min(bottom, p.z());
  return top - bottom;
}

// A setup cancelled part way is dropped whole: the in-process stock and finishing count on whole setups.
void dropSetup(RoughingPlan& plan, int k) {
  plan.operations.erase(std::remove_if(plan.operations.begin(), plan.operations.end(),
                                       [k](const RoughingOperation& op) { return op.setup == k; }),
                        plan.operations.end());
  plan.dropped.erase(std::remove_if(plan.dropped.begin(), plan.dropped.end(),
                                    [k](const DroppedOperation& op) { return op.setup == k; }),
                     plan.dropped.end());
}

bool cuts(const RoughingOperation& op) {
  return std::any_of(op.path.begin(), op.path.end(), [](const CutterLocation& c) { return c.move == MoveKind::Feed; });
}

}  // namespace

RoughingPlan planRoughing(const Part& given, const SetupPlan& setups, const ToolLibrary& library,
                          const RoughingOptions& options, const ProgressSink& progress) {
  const auto start = std::chrono::steady_clock::now();
  RoughingPlan plan;
  // An open mesh is roughed as the solid it closes (solid_closure.h), which the simulation checks against too:
  // otherwise every setup from its open side would clear up to the surface's back.
  const RegionFailureTally failures;
  SolidClosure closure;
  const Part part = machiningSolid(given, &closure);
  plan.closed_open_mesh_edges = closure.boundary_edges;
  const std::vector<const Tool*> candidates = roughingTools(library);
  const Tool* forced = nullptr;
  if (!options.clearing.tool.empty()) {
    forced = library.find(options.clearing.tool);
    if (!forced) throw InputError("roughing: no tool '" + options.clearing.tool + "' in the tool library");
    if (forced->type != ToolType::Flat && forced->type != ToolType::Bull)
      throw InputError("roughing: tool '" + options.clearing.tool + "' is a " + toolTypeName(forced->type) +
                       ", roughing needs a flat or bull end mill");
  }
  // Conventional end mills for zig-zag main passes, rest and 5-axis passes; the high-efficiency cutters for
  // engagement clearing's main passes.
  std::vector<const Tool*> conventional, engagement;
  for (const Tool* t : candidates) (t->max_engagement_deg > 0 ? engagement : conventional).push_back(t);
  const std::vector<const Tool*>& main_tools =
      options.clearing.strategy == RoughingOptions::Clearing::Strategy::Engagement && !engagement.empty() ? engagement
                                                                                                         : conventional;
  if (!forced && main_tools.empty()) throw InputError("roughing: the tool library has no flat or bull end mill");
  std::unique_ptr<InProcessStock> in_process;
  if (options.stock.in_process && setups.setups.size() > 1)
    in_process = std::make_unique<InProcessStock>(part, roughingStock(part, options), options.stock.in_process_rays,
                                                  options.stock.in_process_cell, options.stock.in_process_max_rays);
  plan.stock_left.resize(setups.setups.size());
  const int n = static_cast<int>(setups.setups.size());
  long levels_done = 0;
  double planned_total = 0;  // mm3 the operations kept so far are planned to remove
  for (int k = 0; k < n && !plan.cancelled; ++k) {
    // Each operation's reports as a share of all the setups, levels counted on: setup k spans [k/n, (k+1)/n], shared
    // out among the operations it may have (the main one, the rest passes), operation j taking the j-th part.
    const int slots = 3 + (options.rest.enabled ? std::max(0, options.rest.passes) : 0);  // main, step-up, reach, rest
    int slot = 0;
    const ProgressSink within = [&](const ProgressReport& p) {
      const double share = (slot + std::clamp(p.fraction, 0.0, 1.0)) / slots;
      return reportProgress(progress, "roughing", (k + share) / n,
                            "setup " + std::to_string(k + 1) + " of " + std::to_string(n) + ": " + p.message,
                            levels_done + p.done);
    };
    if (!reportProgress(progress, "roughing", static_cast<double>(k) / n,
                        "setup " + std::to_string(k + 1) + " of " + std::to_string(n) + ": choosing the tool",
                        levels_done)) {
      plan.cancelled = true;
      break;
    }
    // What the earlier setups cut is gone from the stock this one starts from.
    if (in_process && k > 0) removeOperations(*in_process, plan.operations, library, k - 1, k - 1);
    const Setup& setup = setups.setups[k];
    const InProcessStock* stock = k > 0 ? in_process.get() : nullptr;  // the first setup starts from the block
    SetupShadows shadows(toFrame(part.mesh.vertices, setup.frame), part.mesh.triangles);
    const Tool* tool = forced ? forced : chooseRoughingTool(part, setup, main_tools, options, stock, shadows);
    if (!tool) continue;
    RoughingStart from;
    from.earlier = stock;
    from.shadows = &shadows;
    RoughingPass main = roughSetup(part, setup, k, *tool, options, from, within);
    levels_done += static_cast<long>(main.operation.levels.size());
    if (main.cancelled) {
      plan.cancelled = true;
      break;
    }
    std::vector<SlabState> left = std::move(main.left);
    if (!cuts(main.operation)) continue;
    planned_total += main.operation.planned_removal_mm3;
    plan.operations.push_back(std::move(main.operation));
    // A step-up pass after a main pass by engagement (the same cutter), then rest passes, each with a tool at most
    // half the size of the one before, over what the one before left.
    const bool step_up = tool->max_engagement_deg > 0 && options.clearing.step_up_share > 0;
    const Tool* previous = tool;
    const Tool* reach = options.rest.enabled && options.rest.reach ? reachTool(library, *tool) : nullptr;
    if (reach && setupDepth(part, setup, options) <= tool->flute_length) reach = nullptr;
    const int first = step_up ? -2 : -1;  // -2: the step-up pass, -1: the reach pass
    for (int pass = first; pass < (options.rest.enabled ? options.rest.passes : 0); ++pass) {
      if (pass == -1 && !reach) continue;
      const Tool* rest = pass == -2 ? tool : pass == -1 ? reach : restTool(conventional, *previous);
      if (!rest) break;
      slot = pass + 3;
      RoughingStart after;
      after.previous = left;
      after.earlier = stock;
      after.shadows = &shadows;
      after.step_up = pass == -2;
      after.reach = pass == -1;
      after.least_removal_mm3 = options.rest.least_removal_share * planned_total;
      RoughingPass op = roughSetup(part, setup, k, *rest, options, after, within);
      levels_done += static_cast<long>(op.operation.levels.size());
      if (op.cancelled) {
        plan.cancelled = true;
        break;
      }
      if (pass >= 0) previous = rest;  // the rest tools halve from the main tool, not from the reach tool
      if (op.under_least_removal) {
        plan.dropped.push_back(droppedPass(op.operation, options.rest.least_removal_share, planned_total));
        continue;  // the next rest tool starts from what this one started from
      }
      if (!cuts(op.operation)) {
        left = std::move(op.left);
        continue;
      }
      if (pass == -1) {
        const std::string slow = slowReach(op.operation, *rest, options.rest.least_reach_rate_share);
        if (!slow.empty()) {
          plan.dropped.push_back(droppedOperation(op.operation, slow));
          continue;
        }
      }
      planned_total += op.operation.planned_removal_mm3;
      plan.operations.push_back(std::move(op.operation));
      left = std::move(op.left);
    }
    if (plan.cancelled) {
      dropSetup(plan, k);
      break;
    }
    plan.stock_left[k] = left;
    // 5-axis voxel roughing over what the 3-axis operations left, with a flat mill of the rest tool's size class
    // (at most half the main tool: what the main tool could not reach upright, it rarely reaches leaning over).
    if (options.five_axis.enabled) {
      std::vector<const Tool*> tilted;
      for (const Tool* t : conventional)
        if (restSized(*t, *tool)) tilted.push_back(t);
      RoughingOperation op = voxelRoughSetup(part, setup, k, tilted, options, left);
      if (cuts(op)) plan.operations.push_back(std::move(op));
    }
  }
  for (int i = 0; i < static_cast<int>(plan.operations.size()); ++i) {
    for (CutterLocation& c : plan.operations[i].path) c.op = i;
    for (const RoughingLevel& l : plan.operations[i].levels) plan.contours += l.rings;
    plan.direct_levels += plan.operations[i].direct_levels;
  }
  plan.region_failures = failures.count();
  plan.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!plan.cancelled) reportProgress(progress, "roughing", 1.0, "roughing done", levels_done);
  return plan;
}

void removeOperations(InProcessStock& stock, const std::vector<RoughingOperation>& operations,
                      const ToolLibrary& library, int first, int last) {
  Toolpath cut;
  std::vector<Tool> tools;
  for (const RoughingOperation& op : operations)
    if (op.setup >= first && op.setup <= last) {
      cut.insert(cut.end(), op.path.begin(), op.path.end());
      if (const Tool* t = library.find(op.tool)) tools.push_back(*t);
    }
  stock.remove(cut, tools);
}

}  // namespace art2part
