// The shop's tool library (config/tools.yaml) and the tools.json file contract.
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>

#include "art2part/geometry/mesh.h"
#include "art2part/tooling/tool.h"
#include "library_yaml.h"

namespace art2part {

namespace tooling_detail {

double yamlNumber(const YAML::Node& entry, const std::string& key, const std::string& where) {
  const YAML::Node value = entry[key];
  if (!value) throw InputError(where + ": missing '" + key + "'");
  try {
    return value.as<double>();
  } catch (const YAML::Exception&) {
    throw InputError(where + ": '" + key + "' is not a number");
  }
}

double yamlNumberOr(const YAML::Node& entry, const std::string& key, double fallback, const std::string& where) {
  return entry[key] ? yamlNumber(entry, key, where) : fallback;
}

std::string yamlText(const YAML::Node& entry, const std::string& key, const std::string& where) {
  const YAML::Node value = entry[key];
  if (!value || !value.IsScalar()) throw InputError(where + ": missing or malformed '" + key + "'");
  return value.as<std::string>();
}

// Checks a tool and that its id is new; prefixes any error with where it came from (which names the tool already).
void addTool(std::vector<Tool>& tools, Tool tool, const std::string& where) {
  try {
    checkTool(tool);
  } catch (const InputError& error) {
    std::string what = error.what();
    const std::string named = "tool '" + tool.id + "': ";
    if (what.rfind(named, 0) == 0) what = what.substr(named.size());
    throw InputError(where + ": " + what);
  }
  for (const Tool& other : tools)
    if (other.id == tool.id) throw InputError(where + ": duplicate tool id '" + tool.id + "'");
  tools.push_back(std::move(tool));
}

}  // namespace tooling_detail

namespace {

using namespace tooling_detail;

int wholeFlutes(double flutes, const std::string& where) {
  if (!(flutes >= 1 && flutes <= 100 && flutes == std::floor(flutes)))
    throw InputError(where + ": 'flutes' must be a whole number from 1 to 100");
  return static_cast<int>(flutes);
}

// The optional cutting numbers of a tool entry, the same keys in tools.yaml and tools.json (flutes and material apart:
// a whole number and a text).
struct CuttingNumber {
  const char* key;      // the entry's key
  double Tool::*field;  // the tool's field it fills
};
const CuttingNumber kCuttingNumbers[] = {{"spindle_rpm", &Tool::spindle_rpm},   {"feed_mm_min", &Tool::feed_mm_min},
                                         {"plunge_mm_min", &Tool::plunge_mm_min}, {"max_stepdown", &Tool::max_stepdown},
                                         {"max_stepover", &Tool::max_stepover},
                                         {"max_engagement_deg", &Tool::max_engagement_deg}};

// ---- config/tools.yaml ----------------------------------------------------------------------------------------------

const std::set<std::string> kYamlKeys = {"id",           "type",          "diameter",     "corner_radius",
                                         "point_angle_deg", "flute_length", "shank_diameter", "stickout",
                                         "holder",       "flutes",        "spindle_rpm",  "feed_mm_min",
                                         "plunge_mm_min", "max_stepdown", "max_stepover", "max_engagement_deg",
                                         "material"};

std::vector<HolderStep> yamlSteps(const YAML::Node& list, const std::string& where) {
  if (!list.IsSequence()) throw InputError(where + ": a holder is a list of [diameter, length] steps");
  std::vector<HolderStep> steps;
  for (const YAML::Node& step : list) {
    if (!step.IsSequence() || step.size() != 2) throw InputError(where + ": a holder step is [diameter, length]");
    try {
      steps.push_back({step[0].as<double>(), step[1].as<double>()});
    } catch (const YAML::Exception&) {
      throw InputError(where + ": a holder step is [diameter, length] in mm");
    }
  }
  return steps;
}

HolderMap yamlHolders(const YAML::Node& root, const std::string& file) {
  HolderMap holders;
  const YAML::Node section = root["holders"];
  if (!section) return holders;
  if (!section.IsMap()) throw InputError(file + ": 'holders' must map names to [[diameter, length], ...]");
  for (const auto& named : section) {
    const std::string name = named.first.as<std::string>();
    holders[name] = yamlSteps(named.second, file + ": holder '" + name + "'");
  }
  return holders;
}

std::vector<HolderStep> yamlToolHolder(const YAML::Node& entry, const HolderMap& holders, const std::string& where) {
  const YAML::Node holder = entry["holder"];
  if (!holder) throw InputError(where + ": missing 'holder' (a name from 'holders' or [[diameter, length], ...])");
  if (!holder.IsScalar()) return yamlSteps(holder, where);
  const auto named = holders.find(holder.as<std::string>());
  if (named == holders.end()) throw InputError(where + ": unknown holder '" + holder.as<std::string>() + "'");
  return named->second;
}

void yamlCuttingData(const YAML::Node& entry, Tool& tool, const std::string& where) {
  tool.flutes = wholeFlutes(yamlNumberOr(entry, "flutes", tool.flutes, where), where);
  for (const CuttingNumber& number : kCuttingNumbers)
    tool.*number.field = yamlNumberOr(entry, number.key, tool.*number.field, where);
  if (entry["material"]) tool.material = yamlText(entry, "material", where);
}

Tool yamlTool(const YAML::Node& entry, const HolderMap& holders, const std::string& where) {
  if (!entry.IsMap()) throw InputError(where + ": a tool is a map of fields");
  for (const auto& field : entry)
    if (!kYamlKeys.count(field.first.as<std::string>()))
      throw InputError(where + ": unknown field '" + field.first.as<std::string>() + "'");
  Tool tool;
  tool.id = yamlText(entry, "id", where);
  tool.type = parseToolType(yamlText(entry, "type", where));
  tool.diameter = yamlNumber(entry, "diameter", where);
  // Only a bull's corner must be given: a ball's is its radius, a flat's and a drill's 0.
  const double corner = tool.type == ToolType::Ball ? 0.5 * tool.diameter : 0;
  tool.corner_radius = tool.type == ToolType::Bull ? yamlNumber(entry, "corner_radius", where)
                                                   : yamlNumberOr(entry, "corner_radius", corner, where);
  tool.point_angle_deg = yamlNumberOr(entry, "point_angle_deg", tool.point_angle_deg, where);
  tool.flute_length = yamlNumber(entry, "flute_length", where);
  tool.shank_diameter = yamlNumberOr(entry, "shank_diameter", tool.diameter, where);
  tool.stickout = yamlNumber(entry, "stickout", where);
  tool.holder = yamlToolHolder(entry, holders, where);
  yamlCuttingData(entry, tool, where);
  return tool;
}

std::string entryName(const YAML::Node& entry, size_t index) {
  std::string name = "entry " + std::to_string(index + 1);
  if (entry.IsMap() && entry["id"] && entry["id"].IsScalar()) name = "'" + entry["id"].as<std::string>() + "' (" + name + ")";
  return "tool " + name;
}

ToolLibrary yamlLibrary(const YAML::Node& root, const std::string& file) {
  if (!root.IsMap() || !root["tools"] || !root["tools"].IsSequence())
    throw InputError(file + ": expected a 'tools' list (and optionally named 'holders', 'drill_rules', 'drill_series')");
  for (const auto& section : root) {
    const std::string name = section.first.as<std::string>();
    if (name != "tools" && name != "holders" && name != "drill_rules" && name != "drill_series")
      throw InputError(file + ": unknown section '" + name + "' (tools, holders, drill_rules, drill_series)");
  }
  const HolderMap holders = yamlHolders(root, file);
  ToolLibrary library;
  const YAML::Node tools = root["tools"];
  for (size_t t = 0; t < tools.size(); ++t) {
    const std::string where = file + ": " + entryName(tools[t], t);
    Tool tool;
    try {
      tool = yamlTool(tools[t], holders, where);
    } catch (const YAML::Exception& error) {
      throw InputError(where + ": " + error.msg);
    } catch (const InputError& error) {
      const std::string what = error.what();
      throw InputError(what.rfind(where, 0) == 0 ? what : where + ": " + what);
    }
    addTool(library.tools, std::move(tool), where);
  }
  addDrillSeries(root, holders, file, library.tools);
  if (library.tools.empty()) throw InputError(file + ": no tools");
  return library;
}

// ---- tools.json -----------------------------------------------------------------------------------------------------

using Json = nlohmann::json;

Json toJson(const Tool& tool) {
  Json holder = Json::array();
  for (const HolderStep& step : tool.holder) holder.push_back({step.diameter, step.length});
  Json out = {{"id", tool.id},
              {"type", toolTypeName(tool.type)},
              {"diameter", tool.diameter},
              {"corner_radius", tool.corner_radius},
              {"flute_length", tool.flute_length},
              {"shank_diameter", tool.shank_diameter},
              {"stickout", tool.stickout},
              {"holder", holder},
              {"flutes", tool.flutes},
              {"material", tool.material}};
  for (const CuttingNumber& number : kCuttingNumbers) out[number.key] = tool.*number.field;
  if (tool.max_engagement_deg == 0) out.erase("max_engagement_deg");  // a conventional end mill, as files before it
  if (tool.type == ToolType::Drill) out["point_angle_deg"] = tool.point_angle_deg;
  return out;
}

double jsonNumber(const Json& entry, const char* key, const std::string& where) {
  const auto value = entry.find(key);
  if (value == entry.end()) throw InputError(where + ": missing '" + key + "'");
  if (!value->is_number()) throw InputError(where + ": '" + key + "' is not a number");
  return value->get<double>();
}

double jsonNumberOr(const Json& entry, const char* key, double fallback, const std::string& where) {
  return entry.contains(key) ? jsonNumber(entry, key, where) : fallback;
}

std::string jsonText(const Json& entry, const char* key, const std::string& where) {
  const auto value = entry.find(key);
  if (value == entry.end() || !value->is_string()) throw InputError(where + ": missing or malformed '" + key + "'");
  return value->get<std::string>();
}

std::vector<HolderStep> jsonHolder(const Json& entry, const std::string& where) {
  const auto holder = entry.find("holder");
  if (holder == entry.end() || !holder->is_array()) throw InputError(where + ": 'holder' must be [[diameter, length], ...]");
  std::vector<HolderStep> steps;
  for (const Json& step : *holder) {
    if (!step.is_array() || step.size() != 2 || !step[0].is_number() || !step[1].is_number())
      throw InputError(where + ": a holder step is [diameter, length] in mm");
    steps.push_back({step[0].get<double>(), step[1].get<double>()});
  }
  return steps;
}

void jsonCuttingData(const Json& entry, Tool& tool, const std::string& where) {
  tool.flutes = wholeFlutes(jsonNumberOr(entry, "flutes", tool.flutes, where), where);
  for (const CuttingNumber& number : kCuttingNumbers)
    tool.*number.field = jsonNumberOr(entry, number.key, tool.*number.field, where);
  if (entry.contains("material")) tool.material = jsonText(entry, "material", where);
}

Tool fromJson(const Json& entry, const std::string& where) {
  if (!entry.is_object()) throw InputError(where + ": a tool is an object");
  Tool tool;
  tool.id = jsonText(entry, "id", where);
  tool.type = parseToolType(jsonText(entry, "type", where));
  tool.diameter = jsonNumber(entry, "diameter", where);
  tool.corner_radius = jsonNumber(entry, "corner_radius", where);
  tool.point_angle_deg = jsonNumberOr(entry, "point_angle_deg", tool.point_angle_deg, where);
  tool.flute_length = jsonNumber(entry, "flute_length", where);
  tool.shank_diameter = jsonNumber(entry, "shank_diameter", where);
  tool.stickout = jsonNumber(entry, "stickout", where);
  tool.holder = jsonHolder(entry, where);
  jsonCuttingData(entry, tool, where);
  return tool;
}

}  // namespace

ToolLibrary loadToolLibrary(const std::string& yaml_path) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(yaml_path);
  } catch (const YAML::BadFile&) {
    throw InputError("'" + yaml_path + "': cannot open the tool library");
  } catch (const YAML::Exception& error) {
    throw InputError(yaml_path + ":" + std::to_string(error.mark.line + 1) + ": not valid YAML (" + error.msg + ")");
  }
  return yamlLibrary(root, yaml_path);
}

void writeToolsJson(const std::vector<Tool>& tools, const std::string& path) {
  Json list = Json::array();
  for (const Tool& tool : tools) list.push_back(toJson(tool));
  std::ofstream out(path);
  if (!out) throw InputError("'" + path + "': cannot open for writing");
  out << list.dump(2) << "\n";
  if (!out) throw InputError("'" + path + "': write failed");
}

std::vector<Tool> readToolsJson(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError("'" + path + "': cannot open tools.json");
  Json list;
  try {
    list = Json::parse(in);
  } catch (const Json::parse_error& error) {
    throw InputError(path + ": not valid JSON (" + std::string(error.what()) + ")");
  }
  if (!list.is_array()) throw InputError(path + ": expected a list of tools");
  std::vector<Tool> tools;
  for (size_t t = 0; t < list.size(); ++t) {
    std::string where = path + ": tool " + std::to_string(t + 1);
    if (list[t].is_object() && list[t].contains("id") && list[t]["id"].is_string())
      where = path + ": tool '" + list[t]["id"].get<std::string>() + "' (entry " + std::to_string(t + 1) + ")";
    Tool tool;
    try {
      tool = fromJson(list[t], where);
    } catch (const InputError& error) {
      const std::string what = error.what();
      throw InputError(what.rfind(where, 0) == 0 ? what : where + ": " + what);
    }
    addTool(tools, std::move(tool), where);
  }
  return tools;
}

}  // namespace art2part
