// Colours shared by pictures and rviz markers, so a face looks the same everywhere.
#pragma once

#include <array>
#include <vector>

#include "art2part/geometry/part.h"

namespace art2part {

using Rgb = std::array<float, 3>;  // 0..1

// By surface type: plane grey-blue, cylinder green, cone orange, sphere/torus purple, free-form sand;
// concave faces (holes, pockets) darker.
Rgb surfaceColour(const Face& face);

// A perceptually ordered ramp for a value in 0..1 (dark blue, teal, green, yellow), clamped outside.
Rgb rampColour(double value);

// Setup k's colour (pictures and rviz alike), far from the red of what no setup reaches; after ten they repeat darker.
Rgb setupColour(int k);

// What no setup reaches.
Rgb unmachinableColour();

// One 8-bit colour per triangle of the part, by its face.
std::vector<std::array<unsigned char, 3>> triangleColoursByFace(const Part& part);

}  // namespace art2part
