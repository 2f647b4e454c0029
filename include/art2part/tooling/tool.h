// Cutting tools with their real shapes (thesis future work: tool selection, holder interference): flat, ball and bull
// end mills and drills, each with flutes, a shank and a holder made of (diameter, length) steps. A tool is a solid of
// revolution around its axis; `toolRadiusAt` gives its outline, which the simulation sweeps and the planners keep clear.
#pragma once

#include <string>
#include <vector>

#include "art2part/geometry/mesh.h"

namespace art2part {

enum class ToolType { Flat, Ball, Bull, Drill };
ToolType parseToolType(const std::string& text);  // flat | ball | bull | drill; throws InputError
const char* toolTypeName(ToolType type);

struct HolderStep {
  double diameter = 0;  // mm
  double length = 0;    // mm, upwards from the previous step (the first from the holder's face)
};

struct Tool {
  std::string id;               // as in toolpaths.csv's tool column and tools.json
  ToolType type = ToolType::Flat;
  double diameter = 0;          // mm, cutting diameter
  double corner_radius = 0;     // mm: ball = diameter / 2, bull in (0, diameter / 2), flat and drill 0
  double point_angle_deg = 118; // drills only: the included angle of the point
  double flute_length = 0;      // mm, from the tip: the cutting part
  double shank_diameter = 0;    // mm, above the flutes up to the holder
  double stickout = 0;          // mm, tip to the holder's face (>= flute_length)
  std::vector<HolderStep> holder;  // upwards from the holder's face
  // Cutting data a planner uses (the simulation does not need them).
  int flutes = 2;
  double spindle_rpm = 10000;
  double feed_mm_min = 1000;    // cutting feed
  double plunge_mm_min = 300;   // feed along the axis into material
  double max_stepdown = 0;      // mm, 0 = diameter / 2
  double max_stepover = 0;      // mm, 0 = 0.4 * diameter
  // A high-efficiency roughing cutter (chip breakers, cutting data for light radial cuts at full depth): the most of
  // its circumference that may be in material, degrees; 0 = a conventional end mill (full-width cuts at
  // max_stepdown). A tool with a limit is used only by constant-engagement clearing (engagement_clearing.h), which
  // keeps to it; its max_stepdown and feed are for that, its max_stepover the band it takes on a straight cut.
  double max_engagement_deg = 0;
  std::string material = "carbide";
};

// Radius of the whole tool body (flutes, shank, holder) at height h above the tip along its axis; 0 below the tip,
// the tip's profile (ball, torus corner, drill point) near it, 0 above the top of the holder.
double toolRadiusAt(const Tool& tool, double h);
double toolLength(const Tool& tool);       // tip to the top of the holder
double holderTopRadius(const Tool& tool);  // the widest the holder gets
// The tool's library removal rate, mm^3/min: max_stepdown x max_stepover x feed (0 step-down = diameter / 2, 0
// step-over = 0.4 diameter, as Tool says).
double libraryRemovalRate(const Tool& tool);
// Which part of the tool lies at height h: the flutes cut, the shank and holder must never touch material.
enum class ToolZone { Flutes, Shank, Holder, Above };
ToolZone toolZoneAt(const Tool& tool, double h);

// Throws InputError naming the tool and the field for a tool that cannot exist (negative sizes, a corner radius above
// the radius, stickout shorter than the flutes, a holder narrower than the shank at its face, ...).
void checkTool(const Tool& tool);

// A tool placed in space: tip (mm) and unit axis from the tip towards the spindle; in the part frame unless named
// otherwise (the kinematics and the simulation share it).
struct ToolPose {
  Vec3 tip = Vec3::Zero();
  Vec3 axis = Vec3::UnitZ();
};

struct ToolLibrary {
  std::vector<Tool> tools;
  const Tool* find(const std::string& id) const;  // nullptr when absent
};

// config/tools.yaml: the shop's tools and holders. Throws InputError naming the file and the entry.
ToolLibrary loadToolLibrary(const std::string& yaml_path);
// tools.json of the file contracts: a list of {id, type, diameter, corner_radius, flute_length, shank_diameter,
// stickout, holder: [[diameter, length], ...]} (mm), plus point_angle_deg for drills and the cutting data.
void writeToolsJson(const std::vector<Tool>& tools, const std::string& path);
std::vector<Tool> readToolsJson(const std::string& path);  // throws InputError

}  // namespace art2part
