// Tool outlines (solids of revolution around the tool axis) and the checks that a tool can exist.
#include "art2part/tooling/tool.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "art2part/common/angles.h"
#include "art2part/geometry/mesh.h"

namespace art2part {

ToolType parseToolType(const std::string& text) {
  for (ToolType type : {ToolType::Flat, ToolType::Ball, ToolType::Bull, ToolType::Drill})
    if (text == toolTypeName(type)) return type;
  throw InputError("unknown tool type '" + text + "' (expected flat, ball, bull or drill)");
}

const char* toolTypeName(ToolType type) {
  switch (type) {
    case ToolType::Flat: return "flat";
    case ToolType::Ball: return "ball";
    case ToolType::Bull: return "bull";
    case ToolType::Drill: return "drill";
  }
  return "flat";
}

namespace {

// Height of the tip's profile: above it the flutes have the full cutting radius.
double tipHeight(const Tool& tool) {
  const double r = 0.5 * tool.diameter;
  switch (tool.type) {
    case ToolType::Flat: return 0;
    case ToolType::Ball: return r;
    case ToolType::Bull: return tool.corner_radius;
    case ToolType::Drill: return r / std::tan(0.5 * tool.point_angle_deg * kPi / 180);
  }
  return 0;
}

// Radius of the cutting part at height h in [0, flute_length].
double fluteRadiusAt(const Tool& tool, double h) {
  const double r = 0.5 * tool.diameter;
  if (h >= tipHeight(tool)) return r;
  switch (tool.type) {
    case ToolType::Flat: return r;
    case ToolType::Ball: return std::sqrt(std::max(0.0, r * r - (r - h) * (r - h)));
    case ToolType::Bull: {
      const double rc = tool.corner_radius;
      return (r - rc) + std::sqrt(std::max(0.0, rc * rc - (rc - h) * (rc - h)));
    }
    case ToolType::Drill: return h * std::tan(0.5 * tool.point_angle_deg * kPi / 180);
  }
  return r;
}

double holderLength(const Tool& tool) {
  double length = 0;
  for (const HolderStep& step : tool.holder) length += step.length;
  return length;
}

}  // namespace

double toolRadiusAt(const Tool& tool, double h) {
  if (!(h >= 0)) return 0;
  if (h <= tool.flute_length) return fluteRadiusAt(tool, h);
  if (h <= tool.stickout) return 0.5 * tool.shank_diameter;
  double top = tool.stickout;
  for (const HolderStep& step : tool.holder) {
    top += step.length;
    if (h <= top) return 0.5 * step.diameter;
  }
  return 0;
}

double toolLength(const Tool& tool) { return tool.stickout + holderLength(tool); }

double libraryRemovalRate(const Tool& tool) {
  const double stepdown = tool.max_stepdown > 0 ? tool.max_stepdown : tool.diameter / 2;
  const double stepover = tool.max_stepover > 0 ? tool.max_stepover : 0.4 * tool.diameter;
  return stepdown * stepover * tool.feed_mm_min;
}

double holderTopRadius(const Tool& tool) {
  double widest = 0;
  for (const HolderStep& step : tool.holder) widest = std::max(widest, 0.5 * step.diameter);
  return tool.holder.empty() ? 0.5 * tool.shank_diameter : widest;
}

ToolZone toolZoneAt(const Tool& tool, double h) {
  if (h <= tool.flute_length) return ToolZone::Flutes;
  if (h <= tool.stickout) return ToolZone::Shank;
  if (h <= toolLength(tool)) return ToolZone::Holder;
  return ToolZone::Above;
}

// ---- checks ---------------------------------------------------------------------------------------------------------

namespace {

[[noreturn]] void fail(const Tool& tool, const std::string& field, const std::string& what, double value) {
  std::ostringstream out;
  out << "tool '" << tool.id << "': " << field << " " << what << " (got " << value << ")";
  throw InputError(out.str());
}

std::string shortNumber(double value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

void requirePositive(const Tool& tool, const std::string& field, double value) {
  if (!std::isfinite(value) || value <= 0) fail(tool, field, "must be a positive number of mm", value);
}

void requireNonNegative(const Tool& tool, const std::string& field, double value) {
  if (!std::isfinite(value) || value < 0) fail(tool, field, "must be zero or positive", value);
}

void checkId(const Tool& tool) {
  if (tool.id.empty()) throw InputError("tool with an empty id");
  if (tool.id.find_first_of(",\"\r\n\t ") != std::string::npos)
    throw InputError("tool '" + tool.id + "': id must not contain commas, quotes or white space (it is a CSV field)");
}

void checkCorner(const Tool& tool) {
  const double r = 0.5 * tool.diameter, rc = tool.corner_radius;
  requireNonNegative(tool, "corner_radius", rc);
  switch (tool.type) {
    case ToolType::Flat:
    case ToolType::Drill:
      if (rc != 0) fail(tool, "corner_radius", "must be 0 for a " + std::string(toolTypeName(tool.type)), rc);
      break;
    case ToolType::Ball:
      if (std::abs(rc - r) > 1e-9 * std::max(1.0, r)) fail(tool, "corner_radius", "must be diameter / 2 for a ball", rc);
      break;
    case ToolType::Bull:
      if (rc <= 0 || rc >= r) fail(tool, "corner_radius", "must lie strictly between 0 and diameter / 2", rc);
      break;
  }
  if (tool.type == ToolType::Drill &&
      !(std::isfinite(tool.point_angle_deg) && tool.point_angle_deg > 0 && tool.point_angle_deg < 180))
    fail(tool, "point_angle_deg", "must lie strictly between 0 and 180", tool.point_angle_deg);
}

void checkLengths(const Tool& tool) {
  requirePositive(tool, "flute_length", tool.flute_length);
  if (tool.flute_length < tipHeight(tool) - 1e-9)
    fail(tool, "flute_length", "is shorter than the tip's profile (" + shortNumber(tipHeight(tool)) + " mm)",
         tool.flute_length);
  requirePositive(tool, "shank_diameter", tool.shank_diameter);
  requirePositive(tool, "stickout", tool.stickout);
  if (tool.stickout < tool.flute_length) fail(tool, "stickout", "is shorter than flute_length", tool.stickout);
}

void checkHolder(const Tool& tool) {
  for (size_t s = 0; s < tool.holder.size(); ++s) {
    const std::string field = "holder step " + std::to_string(s + 1);
    requirePositive(tool, field + " diameter", tool.holder[s].diameter);
    requirePositive(tool, field + " length", tool.holder[s].length);
  }
  if (!tool.holder.empty() && tool.holder.front().diameter < tool.shank_diameter)
    fail(tool, "holder step 1 diameter", "is narrower than the shank it clamps", tool.holder.front().diameter);
}

void checkCuttingData(const Tool& tool) {
  if (tool.flutes < 1) fail(tool, "flutes", "must be at least 1", tool.flutes);
  requirePositive(tool, "spindle_rpm", tool.spindle_rpm);
  requirePositive(tool, "feed_mm_min", tool.feed_mm_min);
  requirePositive(tool, "plunge_mm_min", tool.plunge_mm_min);
  requireNonNegative(tool, "max_stepdown", tool.max_stepdown);
  requireNonNegative(tool, "max_stepover", tool.max_stepover);
  if (tool.max_stepover > tool.diameter) fail(tool, "max_stepover", "exceeds the diameter", tool.max_stepover);
  if (!(tool.max_engagement_deg >= 0 && tool.max_engagement_deg <= 180))
    fail(tool, "max_engagement_deg", "must be from 0 (no limit) to 180", tool.max_engagement_deg);
  if (tool.max_engagement_deg > 0 && tool.type != ToolType::Flat && tool.type != ToolType::Bull)
    fail(tool, "max_engagement_deg", "is for flat and bull end mills", tool.max_engagement_deg);
}

}  // namespace

void checkTool(const Tool& tool) {
  checkId(tool);
  requirePositive(tool, "diameter", tool.diameter);
  checkCorner(tool);
  checkLengths(tool);
  checkHolder(tool);
  checkCuttingData(tool);
}

const Tool* ToolLibrary::find(const std::string& id) const {
  for (const Tool& tool : tools)
    if (tool.id == id) return &tool;
  return nullptr;
}

}  // namespace art2part
