// The circle's constant, one definition for the whole code base (it was repeated in 22 files).
#pragma once

namespace art2part {

inline constexpr double kPi = 3.14159265358979323846;

}  // namespace art2part
