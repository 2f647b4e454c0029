// Numbers as text for people and for text file formats (URDF, YAML, notes): the shortest form of the given
// significant digits, as an ostream prints it ("12.5", "1e-06").
#pragma once

#include <string>

namespace art2part {

// value with at most `significant_digits` significant digits.
std::string numberText(double value, int significant_digits);

}  // namespace art2part
