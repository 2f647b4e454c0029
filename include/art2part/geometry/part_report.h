// What a part is, for people (text) and programs (JSON): the `art2part info` output and the part section of plan.json.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "art2part/geometry/part.h"

namespace art2part {

nlohmann::json partReport(const Part& part);
std::string partReportText(const Part& part);

}  // namespace art2part
