#include "art2part/common/number_text.h"

#include <sstream>

namespace art2part {

std::string numberText(double value, int significant_digits) {
  std::ostringstream out;
  out.precision(significant_digits);
  out << value;
  return out.str();
}

}  // namespace art2part
