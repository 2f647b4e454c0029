// Tools for the tests: end mills of the library's shapes, written out so a test does not depend on tools.yaml.
#pragma once

#include <string>

#include "art2part/tooling/tool.h"

namespace art2part::test {

// An end mill of `diameter` (a ball's corner radius its radius) with flutes 3 diameters long, a shank as wide, 5
// diameters out of a holder 4 diameters wide and 40 mm long.
inline Tool cutter(const std::string& id, ToolType type, double diameter, double corner = 0) {
  Tool t;
  t.id = id;
  t.type = type;
  t.diameter = diameter;
  t.corner_radius = type == ToolType::Ball ? diameter / 2 : corner;
  t.flute_length = 3 * diameter;
  t.shank_diameter = diameter;
  t.stickout = 5 * diameter;
  t.holder = {{4 * diameter, 40}};
  return t;
}

// A ball end mill in a slim shrink-fit holder (the library's ball6).
inline Tool ball6() {
  Tool t = cutter("ball6", ToolType::Ball, 6);
  t.flute_length = 12;
  t.stickout = 30;
  t.holder = {{23, 12}, {25, 13}, {27, 13}, {44, 42}};
  return t;
}

}  // namespace art2part::test
