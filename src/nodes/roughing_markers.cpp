#include "roughing_markers.h"

#include "art2part/plan/plan_folder.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <system_error>
#include <utility>

#include "art2part/common/request_limits.h"
#include "art2part/roughing/shadow.h"
#include "marker_helpers.h"
#include "part_conversions.h"
#include "setup_markers.h"

namespace art2part {

namespace {

// A length of the goal in metres as mm, within its range (request_limits.h); 0 gives `default_mm`.
double lengthMm(double metres, const RequestRange& range, double default_mm) {
  return checkedRequestValue(metres, range) > 0 ? metres / kMetresPerMm : default_mm;
}

// The levels of the operations of setup k, highest first, duplicates (main and rest operations share heights) merged;
// critical when any operation says so.
std::vector<std::pair<double, bool>> setupLevels(const RoughingPlan& plan, int k) {
  std::vector<std::pair<double, bool>> levels;
  for (const RoughingOperation& op : plan.operations)
    if (op.setup == k)
      for (const RoughingLevel& l : op.levels) levels.emplace_back(l.z, l.critical);
  std::sort(levels.begin(), levels.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  std::vector<std::pair<double, bool>> merged;
  for (const auto& l : levels) {
    if (!merged.empty() && std::abs(merged.back().first - l.first) < 1e-6) merged.back().second |= l.second;
    else merged.push_back(l);
  }
  return merged;
}

}  // namespace

// ---- the goal ----------------------------------------------------------------------------------------------------

SetupOptions roughingSetupOptionsFrom(const PlanRoughingGoal& goal) {
  if (!goal.mode.empty() && goal.mode != "3axis" && goal.mode != "5axis")
    throw InputError("unknown mode '" + goal.mode + "' (use 3axis or 5axis)");
  SetupOptions options;
  options.mode = parseMachineMode(goal.mode.empty() ? std::string("3axis") : goal.mode);
  return options;
}

VisibilityOptions roughingVisibilityOptionsFrom(const PlanRoughingGoal& goal) {
  checkedRequestValue(goal.level, request_limits::kSphereLevel);
  VisibilityOptions options;
  options.level = goal.level != 0 ? goal.level : kDefaultRoughingLevel;
  return options;
}

RoughingOptions roughingOptionsFrom(const PlanRoughingGoal& goal, const ToolLibrary& library,
                                    const std::string& library_path) {
  RoughingOptions options;
  options.allowance = lengthMm(goal.allowance_m, request_limits::kAllowance, options.allowance);
  options.levels.stepdown = lengthMm(goal.stepdown_m, request_limits::kStepdown, 0.0);
  options.rest.enabled = goal.rest_pass;
  options.five_axis.enabled = goal.five_axis;
  if (!goal.tool.empty()) {
    const Tool* tool = library.find(goal.tool);
    if (!tool) throw InputError("no tool '" + goal.tool + "' in " + library_path);
    if (tool->type != ToolType::Flat && tool->type != ToolType::Bull)
      throw InputError("tool '" + goal.tool + "' is a " + toolTypeName(tool->type) +
                       ", roughing needs a flat or bull end mill");
    options.clearing.tool = goal.tool;
  }
  return options;
}

// ---- the result --------------------------------------------------------------------------------------------------

MachiningOperation toOperationMsg(const RoughingOperation& op, int id, int first_point) {
  MachiningOperation out;
  out.id = static_cast<uint32_t>(id);
  out.setup = op.setup;
  out.kind = op.kind;
  out.tool = op.tool;
  if (!op.path.empty()) out.axis = toVectorMsg(op.path.front().axis.normalized());
  out.first_point = static_cast<uint32_t>(first_point);
  out.points = static_cast<uint32_t>(op.path.size());
  out.cutting_length_m = op.feed_mm * kMetresPerMm;
  out.rapid_length_m = op.rapid_mm * kMetresPerMm;
  out.estimated_time_s = op.seconds;
  out.levels = static_cast<uint32_t>(op.levels.size());
  out.critical_levels = static_cast<uint32_t>(
      std::count_if(op.levels.begin(), op.levels.end(), [](const RoughingLevel& l) { return l.critical; }));
  out.ramps = static_cast<uint32_t>(std::max(0, op.ramps));
  out.plunges = static_cast<uint32_t>(std::max(0, op.plunges));
  out.retracts = static_cast<uint32_t>(std::max(0, op.retracts));
  return out;
}

void fillResult(const RoughingPlan& plan, PlanRoughingResult& result) {
  result.operations.clear();
  result.tips.clear();
  result.moves.clear();
  std::size_t points = 0;
  for (const RoughingOperation& op : plan.operations) points += op.path.size();
  result.tips.reserve(points);
  result.moves.reserve(points);
  int first = 0;
  for (int i = 0; i < static_cast<int>(plan.operations.size()); ++i) {
    const RoughingOperation& op = plan.operations[i];
    result.operations.push_back(toOperationMsg(op, i, first));
    for (const CutterLocation& c : op.path) {
      result.tips.push_back(toPointMsg(c.tip));
      result.moves.push_back(c.move == MoveKind::Feed ? PlanRoughingResult::FEED : PlanRoughingResult::RAPID);
    }
    first += static_cast<int>(op.path.size());
  }
}

Toolpath wholeToolpath(const RoughingPlan& plan) {
  Toolpath path;
  for (const RoughingOperation& op : plan.operations) path.insert(path.end(), op.path.begin(), op.path.end());
  return path;
}

std::vector<Tool> toolsUsed(const RoughingPlan& plan, const ToolLibrary& library) {
  std::vector<Tool> tools;
  for (const RoughingOperation& op : plan.operations) {
    if (std::any_of(tools.begin(), tools.end(), [&](const Tool& t) { return t.id == op.tool; })) continue;
    const Tool* tool = library.find(op.tool);
    if (!tool) throw InputError("operation uses tool '" + op.tool + "', which the tool library lacks");
    tools.push_back(*tool);
  }
  return tools;
}

void writeRoughingFiles(const RoughingPlan& plan, const ToolLibrary& library, const std::string& folder) {
  writeToolpathFiles(folder, wholeToolpath(plan), toolsUsed(plan, library));
}

// ---- rviz --------------------------------------------------------------------------------------------------------

visualization_msgs::MarkerArray roughingMarkers(const Part& part, const SetupPlan& setups, const RoughingPlan& plan,
                                                const RoughingOptions& options, const std::string& frame_id) {
  visualization_msgs::MarkerArray array;
  array.markers.push_back(deleteAllMarker(frame_id));

  const double diagonal = std::max(part.check.box.diagonal(), 1.0);
  const double feed_width = std::clamp(0.0015 * diagonal, 0.05, 1.0);  // mm
  const double rapid_width = 0.4 * feed_width;

  std::vector<std::string> tool_order;  // one colour per tool id, in order of first use
  for (int i = 0; i < static_cast<int>(plan.operations.size()); ++i) {
    const RoughingOperation& op = plan.operations[i];
    auto known = std::find(tool_order.begin(), tool_order.end(), op.tool);
    const int tool_index = static_cast<int>(known - tool_order.begin());
    if (known == tool_order.end()) tool_order.push_back(op.tool);

    auto feed = lineMarker(frame_id, "feed_" + std::to_string(i), 0, visualization_msgs::Marker::LINE_LIST, feed_width);
    feed.color = toColour(setupColour(tool_index));
    auto rapid =
        lineMarker(frame_id, "rapid_" + std::to_string(i), 0, visualization_msgs::Marker::LINE_LIST, rapid_width);
    rapid.color = toColour({0.55f, 0.55f, 0.55f}, 0.6f);
    for (std::size_t j = 1; j < op.path.size(); ++j) {
      auto& line = op.path[j].move == MoveKind::Feed ? feed : rapid;
      line.points.push_back(toPointMsg(op.path[j - 1].tip));
      line.points.push_back(toPointMsg(op.path[j].tip));
    }
    if (!feed.points.empty()) array.markers.push_back(std::move(feed));
    if (!rapid.points.empty()) array.markers.push_back(std::move(rapid));
  }

  // The stock's outline along each setup direction, at each level of the setup.
  const Mesh stock = roughingStock(part, options);
  for (int k = 0; k < static_cast<int>(setups.setups.size()); ++k) {
    const std::vector<std::pair<double, bool>> levels = setupLevels(plan, k);
    if (levels.empty()) continue;
    const SetupFrame& frame = setups.setups[k].frame;
    double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
    for (const Vec3& p : toFrame(stock.vertices, frame)) {
      x0 = std::min(x0, p.x());
      y0 = std::min(y0, p.y());
      x1 = std::max(x1, p.x());
      y1 = std::max(y1, p.y());
    }
    if (x0 > x1 || y0 > y1) continue;
    const RgbColour colour = setupColour(k);
    for (int l = 0; l < static_cast<int>(levels.size()); ++l) {
      const auto& [z, critical] = levels[l];
      auto square = lineMarker(frame_id, "slabs_" + std::to_string(k), l, visualization_msgs::Marker::LINE_STRIP,
                               rapid_width);
      square.color = critical ? toColour({1.0f, 0.85f, 0.1f}, 0.8f) : toColour(colour, 0.45f);
      for (const Vec3& corner : {Vec3(x0, y0, z), Vec3(x1, y0, z), Vec3(x1, y1, z), Vec3(x0, y1, z), Vec3(x0, y0, z)})
        square.points.push_back(toPointMsg(fromFrame(corner, frame)));
      array.markers.push_back(std::move(square));
    }
  }
  return array;
}

}  // namespace art2part
