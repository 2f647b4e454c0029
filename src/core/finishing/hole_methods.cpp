// How a hole gets made (holes.h): the drill that matches its bore and bottom and reaches it, else a flat end mill on a
// helix, else nothing with the reason; the depths each tool's tip goes to; the reach of a whole tool (flutes, shank,
// holder) checked against the hole below the mouth and the part's material above it.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "hole_internal.h"

namespace art2part {

using namespace hole_detail;

const char* holeMethodName(HoleMethod method) {
  switch (method) {
    case HoleMethod::Drill: return "drill";
    case HoleMethod::Helix: return "helix";
    case HoleMethod::None: return "none";
  }
  return "none";
}

namespace {

constexpr double kSizeSlack = 1e-9;      // mm: sizes compared within a tolerance get this much more (rounding)
constexpr double kBelowMouthStep = 0.05; // mm: the tool is checked inside the hole's counterbore at this pitch

std::string format(const char* pattern, double a, double b = 0, double c = 0) {
  char text[160];
  std::snprintf(text, sizeof text, pattern, a, b, c);
  return text;
}

std::string mm(double value) { return format("%.2f", value); }

// Where the outline of a tool changes piece: the tip's profile, the flutes' and the shank's tops, the holder's steps.
std::vector<double> outlineBreaks(const Tool& tool) {
  std::vector<double> breaks = {0, tool.flute_length, tool.stickout};
  if (tool.type == ToolType::Drill) breaks.push_back(pointLength(tool));
  if (tool.type == ToolType::Ball || tool.type == ToolType::Bull) breaks.push_back(tool.corner_radius);
  double h = tool.stickout;
  for (const HolderStep& step : tool.holder) breaks.push_back(h += step.length);
  std::sort(breaks.begin(), breaks.end());
  return breaks;
}

// The widest the tool gets between heights h0 < h1 (its outline is monotone between breaks).
double widestOver(const Tool& tool, const std::vector<double>& breaks, double h0, double h1) {
  double widest = std::max(toolRadiusAt(tool, h0), toolRadiusAt(tool, h1));
  for (double b : breaks)
    if (b > h0 && b < h1)
      widest = std::max({widest, toolRadiusAt(tool, b - 1e-9), toolRadiusAt(tool, b), toolRadiusAt(tool, b + 1e-9)});
  return widest;
}

const char* zoneName(ToolZone zone) {
  switch (zone) {
    case ToolZone::Flutes: return "flutes";
    case ToolZone::Shank: return "shank";
    case ToolZone::Holder: return "holder";
    case ToolZone::Above: return "spindle";
  }
  return "tool";
}

// Empty when `tool`, its tip `tip_depth` below the mouth and its axis on the hole's axis (or `offset` from it, swept
// round: helical milling), fits: its flutes span the cut in the bore, below the mouth it stays inside the hole, above
// it clear of the part's material. Otherwise why.
std::string reachProblem(const Hole& hole, const Tool& tool, double tip_depth, double offset, const HoleOptions& o) {
  const double cut = tip_depth - hole.bore_start;
  if (cut > tool.flute_length + kSizeSlack)
    return mm(tip_depth) + " mm deep: " + tool.id + "'s flutes reach " + mm(tool.flute_length + hole.bore_start) + " mm";
  const std::vector<double> breaks = outlineBreaks(tool);
  const double length = toolLength(tool), flute_slack = 0.5 * o.diameter_tolerance + kSizeSlack;
  // Below the mouth, above the bore: inside the counterbore or countersink.
  std::vector<double> depths;
  for (double d = 0; d < hole.bore_start; d += kBelowMouthStep) depths.push_back(d);
  for (double b : breaks)
    for (double e : {-1e-6, 1e-6})
      if (tip_depth - b - e > 0 && tip_depth - b - e < hole.bore_start) depths.push_back(tip_depth - b - e);
  for (double d : depths) {
    const double h = tip_depth - d;
    const ToolZone zone = toolZoneAt(tool, h);
    const double envelope = offset + toolRadiusAt(tool, h), room = holeRadiusAt(hole, d);
    const bool fits = zone == ToolZone::Flutes ? envelope <= room + flute_slack : envelope + o.holder_margin <= room;
    if (!fits)
      return tool.id + "'s " + zoneName(zone) + " (" + mm(2 * envelope) + " mm) does not fit the " + mm(2 * room) +
             " mm of the hole " + mm(d) + " mm below the mouth";
  }
  // Above the mouth: the part's material band by band, each band split where the tool's zone changes.
  for (size_t k = 0; k < hole.free_radius.size(); ++k) {
    const double band_lo = tip_depth + k * hole.clearance_step, band_hi = band_lo + hole.clearance_step;
    if (band_lo >= length) break;
    if (!std::isfinite(hole.free_radius[k])) continue;
    std::vector<double> cuts = {band_lo, std::min(band_hi, length)};
    for (double b : {tool.flute_length, tool.stickout})
      if (b > cuts.front() && b < cuts.back()) cuts.insert(cuts.end() - 1, b);
    for (size_t p = 0; p + 1 < cuts.size(); ++p) {
      const ToolZone zone = toolZoneAt(tool, 0.5 * (cuts[p] + cuts[p + 1]));
      const double envelope = offset + widestOver(tool, breaks, cuts[p], cuts[p + 1]);
      const double free = hole.free_radius[k];
      const bool fits = zone == ToolZone::Flutes ? envelope <= free + flute_slack : envelope + o.holder_margin <= free;
      if (!fits)
        return tool.id + "'s " + zoneName(zone) + " (" + mm(2 * envelope) + " mm) meets the part " +
               mm(k * hole.clearance_step) + ".." + mm((k + 1) * hole.clearance_step) + " mm above the mouth, " +
               mm(free) + " mm from the axis";
    }
  }
  return "";
}

bool isSpot(const Tool& tool, const HoleOptions& o) {
  return tool.type == ToolType::Drill && std::abs(tool.point_angle_deg - kSpotPointAngleDeg) <= o.point_angle_tolerance_deg;
}

// A narrower stretch above the bore (an undercut seen from the mouth): nothing of the bore's size passes it.
std::string undercut(const Hole& hole, const HoleOptions& o) {
  for (const HoleSegment& s : hole.segments) {
    if (s.from >= hole.bore_start - kSizeSlack) break;
    for (double d : {s.from, 0.5 * (s.from + s.to), std::min(s.to, hole.bore_start)})
      if (d < hole.bore_start && holeRadiusAt(hole, d) < 0.5 * hole.diameter - o.axis_line_tolerance)
        return "a narrower stretch (" + mm(2 * holeRadiusAt(hole, d)) + " mm) " + mm(d) +
               " mm below the mouth, above the " + mm(hole.diameter) + " mm bore";
  }
  return "";
}

// A breakthrough the through hole's surroundings allow the tool (a drill's point length, 0 for an end mill).
std::string breakthroughProblem(const Hole& hole, double needed, const HoleOptions& o, const std::string& who) {
  if (hole.bottom != HoleBottom::Through || hole.free_beyond - o.holder_margin >= needed) return "";
  return "material " + mm(hole.free_beyond) + " mm beyond the far end: " + who + " needs " + mm(needed + o.holder_margin) +
         " mm to break through";
}

struct Choice {
  const Tool* tool = nullptr;
  double tip = 0;
  std::string reason;  // why none, when tool is null
};

Choice chooseDrill(const Hole& hole, const ToolLibrary& library, const HoleOptions& o) {
  Choice choice;
  const std::string size = mm(hole.diameter) + " mm";
  const double tolerance =
      o.diameter_tolerance + 2 * std::min(hole.radial_deviation, o.measurement_credit) + kSizeSlack;
  std::vector<const Tool*> near;
  for (const Tool& tool : library.tools)
    if (tool.type == ToolType::Drill && !isSpot(tool, o) && std::abs(tool.diameter - hole.diameter) <= tolerance)
      near.push_back(&tool);
  if (near.empty()) {
    choice.reason = "no drill within " + format("%g", o.diameter_tolerance) + " mm of " + size;
    return choice;
  }
  if (hole.bottom == HoleBottom::Other) {
    choice.reason = "the " + size + " bore ends in a rounded or free-form bottom: no drill makes it";
    return choice;
  }
  std::vector<const Tool*> pointed;
  std::string points;
  for (const Tool* tool : near) {
    points += (points.empty() ? "" : ", ") + format("%g", tool->point_angle_deg);
    if (hole.bottom != HoleBottom::Cone ||
        std::abs(tool->point_angle_deg - hole.point_angle_deg) <= o.point_angle_tolerance_deg + kSizeSlack)
      pointed.push_back(tool);
  }
  if (pointed.empty()) {
    choice.reason = "cone bottom " + format("%.1f", hole.point_angle_deg) + " deg: no " + size +
                    " drill point matches (" + points + " deg)";
    return choice;
  }
  const Tool* longest = nullptr;
  for (const Tool* tool : pointed) {
    const double tip = drillDepth(hole, *tool, o);
    std::string problem = breakthroughProblem(hole, pointLength(*tool), o, tool->id + "'s point");
    if (problem.empty()) problem = reachProblem(hole, *tool, tip, 0, o);
    if (!problem.empty()) {
      if (!longest || tool->flute_length > longest->flute_length) longest = tool;
      if (choice.reason.empty()) choice.reason = problem;
      continue;
    }
    // The closest diameter, then the closest point, then the shortest flutes (the stiffest), then the id.
    const auto key = [&](const Tool* t) {
      return std::make_tuple(std::abs(t->diameter - hole.diameter),
                             hole.bottom == HoleBottom::Cone ? std::abs(t->point_angle_deg - hole.point_angle_deg) : 0.0,
                             t->flute_length, t->id);
    };
    if (!choice.tool || key(tool) < key(choice.tool)) {
      choice.tool = tool;
      choice.tip = tip;
    }
  }
  if (choice.tool) {
    choice.reason.clear();
  } else if (longest && drillDepth(hole, *longest, o) - hole.bore_start > longest->flute_length) {
    choice.reason = mm(drillDepth(hole, *longest, o)) + " mm deep: longest " + size + " drill (" + longest->id +
                    ") reaches " + mm(longest->flute_length + hole.bore_start) + " mm";
  }
  return choice;
}

Choice chooseHelixMill(const Hole& hole, const ToolLibrary& library, const HoleOptions& o) {
  Choice choice;
  const double lo = o.helix_tool_min * hole.diameter, hi = o.helix_tool_max * hole.diameter;
  const std::string range = "no flat end mill of " + mm(lo) + ".." + mm(hi) + " mm";
  if (hole.bottom != HoleBottom::Flat && hole.bottom != HoleBottom::Through) {
    choice.reason = std::string("helix: a ") + (hole.bottom == HoleBottom::Cone ? "cone" : "rounded or free-form") +
                    " bottom needs a flat floor";
    return choice;
  }
  const double tip = helixDepth(hole, o);
  const std::string beyond = breakthroughProblem(hole, 0, o, "an end mill");
  if (!beyond.empty()) {
    choice.reason = "helix: " + beyond;
    return choice;
  }
  for (const Tool& tool : library.tools) {
    if (tool.type != ToolType::Flat || tool.max_engagement_deg > 0 || tool.diameter < lo - kSizeSlack ||
        tool.diameter > hi + kSizeSlack)
      continue;
    const std::string problem = reachProblem(hole, tool, tip, 0.5 * (hole.diameter - tool.diameter), o);
    if (!problem.empty()) {
      if (choice.reason.empty() || choice.reason == range) choice.reason = "helix: " + problem;
      continue;
    }
    if (!choice.tool || tool.diameter > choice.tool->diameter) choice.tool = &tool;  // the largest: fewest turns
  }
  if (choice.tool) {
    choice.tip = tip;
    choice.reason.clear();
  } else if (choice.reason.empty()) {
    choice.reason = "helix: " + range;
  }
  return choice;
}

}  // namespace

double drillDepth(const Hole& hole, const Tool& drill, const HoleOptions& options) {
  switch (hole.bottom) {
    case HoleBottom::Cone: return std::min(hole.total_depth, hole.depth + pointLength(drill));
    case HoleBottom::Through:
      return hole.total_depth +
             std::clamp(hole.free_beyond - options.holder_margin, 0.0, pointLength(drill) + options.breakthrough);
    default: return hole.depth;
  }
}

double helixDepth(const Hole& hole, const HoleOptions& options) {
  if (hole.bottom != HoleBottom::Through) return hole.depth;
  return hole.total_depth + std::clamp(hole.free_beyond - options.holder_margin, 0.0, options.breakthrough);
}

double spotDepth(const Hole& hole, const Tool& spot, const HoleOptions& options) {
  const double chamfer = std::clamp(hole.diameter - options.spot_undersize, 0.0, spot.diameter);
  return std::min(hole.total_depth, hole.bore_start + 0.5 * chamfer / std::tan(0.5 * spot.point_angle_deg * kDegree));
}

HoleMachining chooseHoleMethod(const Hole& hole, const ToolLibrary& library, const HoleOptions& options) {
  HoleMachining m;
  const std::string blocked = undercut(hole, options);
  if (!blocked.empty()) {
    m.reason = blocked;
    return m;
  }
  const Choice drill = chooseDrill(hole, library, options);
  // A flat floor: an end mill makes it exactly; a drill only down to the floor, leaving the ring its point misses.
  const bool helix_first = hole.bottom == HoleBottom::Flat || !drill.tool;
  const Choice helix = helix_first ? chooseHelixMill(hole, library, options) : Choice{};
  if (helix.tool && (hole.bottom == HoleBottom::Flat || !drill.tool)) {
    m.method = HoleMethod::Helix;
    m.drill = helix.tool->id;
    m.tip_depth = helix.tip;
    return m;
  }
  if (!drill.tool) {
    m.reason = drill.reason + (helix.reason.empty() ? "" : "; " + helix.reason);
    return m;
  }
  m.method = HoleMethod::Drill;
  m.drill = drill.tool->id;
  m.tip_depth = drill.tip;
  m.peck = m.tip_depth + options.retract_height > options.peck_ratio * drill.tool->diameter;
  if (hole.bottom == HoleBottom::Flat)
    m.reason = "flat bottom drilled to the floor: the point leaves a ring up to " + mm(pointLength(*drill.tool)) +
               " mm high at the wall (" + helix.reason + ")";
  if (options.spot_drill) {
    const Tool* best = nullptr;
    for (const Tool& spot : library.tools) {
      if (!isSpot(spot, options)) continue;
      const double depth = spotDepth(hole, spot, options);
      if (!reachProblem(hole, spot, depth, 0, options).empty()) continue;
      if (!best || spot.diameter > best->diameter) best = &spot;
    }
    if (best) {
      m.spot = best->id;
      m.spot_depth = spotDepth(hole, *best, options);
    }
  }
  return m;
}

}  // namespace art2part
