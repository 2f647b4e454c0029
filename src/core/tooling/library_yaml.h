// Internal to the tool library: the YAML field readers config/tools.yaml's tools and drill series share, and the
// expansion of the drill series (drill_series.cpp).
#pragma once

#include <yaml-cpp/yaml.h>

#include <map>
#include <string>
#include <vector>

#include "art2part/tooling/tool.h"

namespace art2part::tooling_detail {

using HolderMap = std::map<std::string, std::vector<HolderStep>>;

// Each throws InputError prefixed with `where` for a missing or malformed field.
double yamlNumber(const YAML::Node& entry, const std::string& key, const std::string& where);
double yamlNumberOr(const YAML::Node& entry, const std::string& key, double fallback, const std::string& where);
std::string yamlText(const YAML::Node& entry, const std::string& key, const std::string& where);

// Checks a tool and that its id is new, then appends it; errors are prefixed with `where`.
void addTool(std::vector<Tool>& tools, Tool tool, const std::string& where);

// The tools of the file's `drill_series` (with their `drill_rules`), appended to `tools` in the file's order. Throws
// InputError naming the file, the series (by its number and prefix) and the field.
void addDrillSeries(const YAML::Node& root, const HolderMap& holders, const std::string& file,
                    std::vector<Tool>& tools);

}  // namespace art2part::tooling_detail
