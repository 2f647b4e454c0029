#include "art2part/common/request_limits.h"

#include <cstring>
#include <sstream>

#include "art2part/geometry/mesh.h"

namespace art2part {

namespace {

std::string number(double value) {
  std::ostringstream text;  // as %g: 5, 0.0003, 1e-05, nan, inf
  text << value;
  return text.str();
}

std::string withUnit(double value, const RequestRange& range) {
  return number(value) + (std::strlen(range.unit) > 0 ? std::string(" ") + range.unit : std::string());
}

// What a caller who slipped a unit needs to hear.
std::string unitHint(const RequestRange& range) {
  if (std::strcmp(range.unit, "m") == 0) return " (ROS lengths are metres: 0.5 mm is 0.0005)";
  if (std::strcmp(range.unit, "mm") == 0) return " (this service's sizes are mm, as the plan folder's files)";
  if (std::strcmp(range.unit, "deg") == 0) return " (degrees, not radians)";
  return "";
}

}  // namespace

std::string rangeViolation(double value, const RequestRange& range) {
  if (value == 0 || (value >= range.smallest && value <= range.largest)) return "";  // NaN fails both
  return std::string(range.field) + " " + number(value) + " is out of range: " + number(range.smallest) + ".." +
         withUnit(range.largest, range) + ", or 0 for " + range.zero_means + unitHint(range);
}

double checkedRequestValue(double value, const RequestRange& range) {
  const std::string reason = rangeViolation(value, range);
  if (!reason.empty()) throw InputError(reason);
  return value;
}

}  // namespace art2part
