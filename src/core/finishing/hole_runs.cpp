// Hole runs of the finishing stage (finishing_context.h): spot, drill and helix operations per setup.
#include <cmath>
#include <map>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "art2part/common/angles.h"
#include "art2part/geometry/travel_order.h"
#include "finishing_context.h"

namespace art2part::finishing_detail {

void makeHoles(const Context& c, const std::vector<FaceAssignment>& assignment, FinishingPlan& plan, Tally& tally,
               std::vector<std::vector<FinishingOperation>>& per_setup) {
  const Part& part = c.in.part;
  std::vector<Hole>& holes = plan.holes;
  std::vector<HoleMachining>& methods = plan.hole_methods;
  // Runs: (setup, axis, drill id) -> holes, and (setup, axis) -> holes to spot; an axis by its index in `axes` (a 5-axis
  // setup makes holes along several).
  std::map<std::tuple<int, int, std::string>, std::vector<int>> drilled;
  std::map<std::pair<int, int>, std::vector<int>> spotted;
  std::vector<Vec3> axes;
  auto axisIndex = [&](const Vec3& axis) {
    for (std::size_t i = 0; i < axes.size(); ++i)
      if (axes[i].dot(axis) > std::cos(c.options.holes.axis_tolerance_deg * kPi / 180)) return static_cast<int>(i);
    axes.push_back(axis);
    return static_cast<int>(axes.size()) - 1;
  };
  std::vector<char> turned(holes.size(), 0);
  std::vector<signed char> clear_over(holes.size(), -1);  // per hole, once known: 1 nothing over its mouth, 0 stock
  for (const FaceAssignment& a : assignment) {
    if (a.choices.empty() || a.choices.front().hole < 0) continue;
    const FinishingChoice& choice = a.choices.front();
    const int h = choice.hole;
    if (!turned[h] && choice.direction.dot(holes[h].axis) < 0) {
      turned[h] = 1;
      holes[h] = reversedHole(part, c.in.holes[h], c.options.holes);
      methods[h] = chooseHoleMethod(holes[h], c.in.library, c.options.holes);
    }
    const HoleMachining& m = methods[h];
    if (m.method == HoleMethod::None) continue;
    // Along a tilted direction roughing may have left stock over the mouth (its own setup direction cleared above it).
    auto blocked = [&](const std::string& id) {
      const Tool* tool = id.empty() ? nullptr : c.in.library.find(id);
      return tool && !c.after_roughing.clearOverHole(choice.setup, holes[h], *tool, c.options.tools.holder_margin);
    };
    if (clear_over[h] < 0)
      clear_over[h] = setupsOwnDirection(c.in.setups.setups[choice.setup], choice.direction) ||
                      !(blocked(m.drill) || (m.method == HoleMethod::Drill && blocked(m.spot)));
    if (!clear_over[h]) {
      for (int f : holes[h].bore_faces)
        tally.note(f, 0, 0.0, "roughing left stock over its mouth along its axis in setup " +
                                  std::to_string(choice.setup));
      continue;
    }
    const int axis = axisIndex(holes[h].axis);
    auto& list = drilled[{choice.setup, axis, m.method == HoleMethod::Drill ? m.drill : "helix:" + m.drill}];
    if (std::find(list.begin(), list.end(), h) == list.end()) list.push_back(h);
    if (m.method == HoleMethod::Drill && !m.spot.empty()) {
      auto& spots = spotted[{choice.setup, axis}];
      if (std::find(spots.begin(), spots.end(), h) == spots.end()) spots.push_back(h);
    }
  }
  // Each run's holes in the order that travels least between them (the face order crossed the part from hole to hole).
  auto inTravelOrder = [&](std::vector<int>& group) {
    std::vector<Vec3> mouths;
    for (int h : group) mouths.push_back(holes[h].mouth);
    std::vector<int> ordered;
    for (int k : travelOrder(mouths, holes[group.front()].axis)) ordered.push_back(group[k]);
    group = std::move(ordered);
  };
  for (auto& entry : spotted) inTravelOrder(entry.second);
  for (auto& entry : drilled) inTravelOrder(entry.second);
  // The rapids between holes at the setup's clearance plane: over the stock's top along the holes' axis.
  auto clearanceAbove = [&](const std::vector<int>& group) {
    const Vec3& d = holes[group.front()].axis;
    double top = -1e300, mouth = -1e300;
    for (const Vec3& v : c.stock.vertices) top = std::max(top, v.dot(d));
    for (int h : group) mouth = std::max(mouth, holes[h].mouth.dot(d));
    return std::max(c.options.holes.retract_height, top + c.options.clearance - mouth);
  };
  // Between the holes of a run, the lowest crossing the stock roughing left proves clear (hole_links.h).
  auto linkFor = [&](int setup, const std::vector<int>& group, const Tool& tool) {
    return linkOverStockLeft(c, setup, holes[group.front()].axis.normalized(), tool);
  };
  auto drillRun = [&](int setup, const std::vector<int>& group, const Tool& tool, bool spot) {
    std::vector<Hole> list;
    for (int h : group) list.push_back(holes[h]);
    FinishingOperation op;
    op.setup = setup;
    op.kind = FinishingKind::Drill;
    op.tool = tool.id;
    op.direction = list.front().axis;
    op.path =
        drillingPath(list, tool, spot, setup, clearanceAbove(group), c.options.holes, linkFor(setup, group, tool));
    for (int h : group) op.faces.insert(op.faces.end(), holes[h].bore_faces.begin(), holes[h].bore_faces.end());
    if (spot) op.note = "spot drilling";
    return op;
  };
  for (const auto& [key, group] : spotted)
    if (const Tool* spot = c.in.library.find(methods[group.front()].spot)) {
      const int setup = key.first;
      FinishingOperation op = drillRun(setup, group, *spot, true);
      if (!op.path.empty()) per_setup[setup].push_back(std::move(op));
    }
  for (const auto& [key, group] : drilled) {
    const auto& [setup, axis, id] = key;
    const bool helix = id.rfind("helix:", 0) == 0;
    const Tool* tool = c.in.library.find(helix ? id.substr(6) : id);
    if (!tool) continue;
    FinishingOperation op;
    if (helix) {
      op.setup = setup;
      op.kind = FinishingKind::Helix;
      op.tool = tool->id;
      op.direction = holes[group.front()].axis;
      std::vector<Hole> list;
      for (int h : group) {
        op.faces.insert(op.faces.end(), holes[h].bore_faces.begin(), holes[h].bore_faces.end());
        list.push_back(holes[h]);
      }
      op.path = helixPaths(list, *tool, setup, clearanceAbove(group), c.options.holes, linkFor(setup, group, *tool));
    } else {
      op = drillRun(setup, group, *tool, false);
    }
    if (op.path.empty()) continue;
    for (int h : group)
      for (int f : holes[h].bore_faces) tally.note(f, 0, 1.0, methods[h].reason);
    per_setup[setup].push_back(std::move(op));
  }
}

}  // namespace art2part::finishing_detail
