// The drill series of config/tools.yaml: what a shop's drill cabinet holds (a metric series in 0.1 mm steps, tap and
// clearance sizes, inch fractions, letters and numbers), written as a rule per drill family and a list of sizes, and
// expanded here into one Tool per size.
//
//   drill_rules:
//     NAME:
//       material: hss                   point_angle_deg: 118          flutes: 2
//       lengths: [[largest diameter, flute length, overall length(, shank diameter)], ...]   (the first row that holds;
//                                        no shank column: the shank is the drill's diameter)
//       visible_shank: 5                 mm of shank between the flutes' end and the collet: stickout = flute + this
//       min_grip: 15                     mm of shank the collet must hold: overall - stickout at least this
//       holders: [[largest shank, holder name], ...]                                    (the first row that holds)
//       vc_m_min: 75                     cutting speed: rpm = 1000 vc / (pi D), at most max_rpm, rounded to 10 rpm
//       max_rpm: 24000
//       feed_per_rev: [per mm of D, least, most]   f = clamp(per_mm x D, least, most) mm/rev; feed = rpm x f, the
//                                        plunge feed the same (a drill only plunges), rounded to 1 mm/min
//       peck: 1.5                        max_stepdown, the peck depth of G83, = peck x D (rounded to 0.1 mm)
//   drill_series:
//     - {rule: NAME, prefix: hss, mm: {from: 3, to: 14, step: 0.1}}      id hss3, hss3.1, ... hss14
//     - {rule: NAME, prefix: hss, mm: [1.6, 2.05]}                        id hss1.6, hss2.05
//     - {rule: NAME, prefix: hss_, inch_fractions: {from: 4, to: 32, per_inch: 64}}   id hss_1_16in, hss_5_64in, ...
//     - {rule: NAME, prefix: hss_, inch: {H: 0.266, no7: 0.201}}         id hss_H, hss_no7 (sizes in inches)
#include <algorithm>
#include <cmath>
#include <numeric>
#include <set>

#include "art2part/common/angles.h"
#include "art2part/geometry/mesh.h"
#include "library_yaml.h"

namespace art2part::tooling_detail {

namespace {

constexpr double kMmPerInch = 25.4;
// A size belongs to a length row when it is at most the row's diameter plus this (sizes are given to 0.001 mm).
constexpr double kSizeSlack = 1e-6;
// Sizes of a from/to/step range are rounded to a micrometre, so 3 + 11 x 0.1 is 4.1 and not 4.1000000000000005.
constexpr double kSizeRounding = 1000;
constexpr int kMaxSeriesSizes = 2000;  // a range with more sizes is a typing error (a step in metres)

const std::set<std::string> kRuleKeys = {"material", "point_angle_deg", "flutes",   "lengths", "visible_shank",
                                         "min_grip", "holders",         "vc_m_min", "max_rpm", "feed_per_rev",
                                         "peck"};
const std::set<std::string> kSeriesKeys = {"rule", "prefix", "mm", "inch_fractions", "inch"};

struct LengthRow {
  double largest_diameter = 0, flute = 0, overall = 0, shank = 0;  // shank 0: the drill's diameter
};

struct DrillRule {
  std::string name, material;
  double point_angle_deg = 118;
  int flutes = 2;
  std::vector<LengthRow> lengths;
  double visible_shank = 0, min_grip = 0;
  std::vector<std::pair<double, std::string>> holders;  // largest shank, holder name
  double vc_m_min = 0, max_rpm = 0;
  double feed_per_mm = 0, feed_least = 0, feed_most = 0;  // mm/rev
  double peck = 0;
};

struct DrillSize {
  std::string name;  // the id's tail: "8.4", "1_16in", "H"
  double diameter = 0;  // mm
};

void requireKeys(const YAML::Node& entry, const std::set<std::string>& keys, const std::string& where) {
  if (!entry.IsMap()) throw InputError(where + ": expected a map of fields");
  for (const auto& field : entry)
    if (!keys.count(field.first.as<std::string>()))
      throw InputError(where + ": unknown field '" + field.first.as<std::string>() + "'");
}

std::vector<double> numberRow(const YAML::Node& row, const std::string& where) {
  if (!row.IsSequence()) throw InputError(where + ": expected a list of numbers");
  std::vector<double> values;
  try {
    for (const YAML::Node& value : row) values.push_back(value.as<double>());
  } catch (const YAML::Exception&) {
    throw InputError(where + ": expected a list of numbers");
  }
  return values;
}

double positive(double value, const std::string& what, const std::string& where) {
  if (!(value > 0) || !std::isfinite(value)) throw InputError(where + ": '" + what + "' must be a positive number");
  return value;
}

std::vector<LengthRow> lengthRows(const YAML::Node& entry, const std::string& where) {
  const YAML::Node list = entry["lengths"];
  if (!list || !list.IsSequence() || list.size() == 0)
    throw InputError(where + ": 'lengths' must list [largest diameter, flute length, overall length(, shank)] rows");
  std::vector<LengthRow> rows;
  for (const YAML::Node& node : list) {
    const std::vector<double> v = numberRow(node, where + ": 'lengths'");
    if (v.size() != 3 && v.size() != 4)
      throw InputError(where + ": a 'lengths' row is [largest diameter, flute length, overall length(, shank)]");
    for (double value : v) positive(value, "lengths", where);
    LengthRow row{v[0], v[1], v[2], v.size() == 4 ? v[3] : 0.0};
    if (row.overall <= row.flute) throw InputError(where + ": a 'lengths' row's overall length is not above its flute");
    if (!rows.empty() && row.largest_diameter <= rows.back().largest_diameter)
      throw InputError(where + ": 'lengths' rows must grow in diameter");
    rows.push_back(row);
  }
  return rows;
}

std::vector<std::pair<double, std::string>> holderRows(const YAML::Node& entry, const HolderMap& holders,
                                                       const std::string& where) {
  const YAML::Node list = entry["holders"];
  if (!list || !list.IsSequence() || list.size() == 0)
    throw InputError(where + ": 'holders' must list [largest shank, holder name] rows");
  std::vector<std::pair<double, std::string>> rows;
  for (const YAML::Node& row : list) {
    if (!row.IsSequence() || row.size() != 2 || !row[1].IsScalar())
      throw InputError(where + ": a 'holders' row is [largest shank, holder name]");
    double shank = 0;
    try {
      shank = row[0].as<double>();
    } catch (const YAML::Exception&) {
      throw InputError(where + ": a 'holders' row is [largest shank, holder name]");
    }
    const std::string name = row[1].as<std::string>();
    if (!holders.count(name)) throw InputError(where + ": unknown holder '" + name + "'");
    rows.emplace_back(positive(shank, "holders", where), name);
  }
  return rows;
}

DrillRule drillRule(const std::string& name, const YAML::Node& entry, const HolderMap& holders,
                    const std::string& file) {
  const std::string where = file + ": drill rule '" + name + "'";
  requireKeys(entry, kRuleKeys, where);
  DrillRule rule;
  rule.name = name;
  rule.material = yamlText(entry, "material", where);
  rule.point_angle_deg = yamlNumber(entry, "point_angle_deg", where);
  const double flutes = yamlNumberOr(entry, "flutes", 2, where);
  if (!(flutes >= 1 && flutes <= 100 && flutes == std::floor(flutes)))
    throw InputError(where + ": 'flutes' must be a whole number from 1 to 100");
  rule.flutes = static_cast<int>(flutes);
  rule.lengths = lengthRows(entry, where);
  rule.visible_shank = yamlNumber(entry, "visible_shank", where);
  if (rule.visible_shank < 0) throw InputError(where + ": 'visible_shank' must not be negative");
  rule.min_grip = positive(yamlNumber(entry, "min_grip", where), "min_grip", where);
  rule.holders = holderRows(entry, holders, where);
  rule.vc_m_min = positive(yamlNumber(entry, "vc_m_min", where), "vc_m_min", where);
  rule.max_rpm = positive(yamlNumber(entry, "max_rpm", where), "max_rpm", where);
  const YAML::Node feed = entry["feed_per_rev"];
  if (!feed) throw InputError(where + ": missing 'feed_per_rev' ([per mm of diameter, least, most] mm/rev)");
  const std::vector<double> f = numberRow(feed, where + ": 'feed_per_rev'");
  if (f.size() != 3) throw InputError(where + ": 'feed_per_rev' is [per mm of diameter, least, most] mm/rev");
  for (double value : f) positive(value, "feed_per_rev", where);
  if (f[1] > f[2]) throw InputError(where + ": 'feed_per_rev' has its least above its most");
  rule.feed_per_mm = f[0];
  rule.feed_least = f[1];
  rule.feed_most = f[2];
  rule.peck = positive(yamlNumber(entry, "peck", where), "peck", where);
  return rule;
}

std::map<std::string, DrillRule> drillRules(const YAML::Node& root, const HolderMap& holders,
                                            const std::string& file) {
  std::map<std::string, DrillRule> rules;
  const YAML::Node section = root["drill_rules"];
  if (!section) return rules;
  if (!section.IsMap()) throw InputError(file + ": 'drill_rules' must map names to rules");
  for (const auto& named : section) {
    const std::string name = named.first.as<std::string>();
    rules[name] = drillRule(name, named.second, holders, file);
  }
  return rules;
}

// "8.4", "3", "2.05": the shortest decimal form of a size given to a micrometre.
std::string sizeName(double mm) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3f", mm);
  std::string name = text;
  while (name.back() == '0') name.pop_back();
  if (name.back() == '.') name.pop_back();
  return name;
}

std::vector<DrillSize> metricSizes(const YAML::Node& node, const std::string& where) {
  std::vector<DrillSize> sizes;
  if (node.IsSequence()) {
    for (double mm : numberRow(node, where + ": 'mm'")) {
      positive(mm, "mm", where);
      sizes.push_back({sizeName(mm), std::round(mm * kSizeRounding) / kSizeRounding});
    }
    return sizes;
  }
  if (!node.IsMap()) throw InputError(where + ": 'mm' is a list of sizes or {from, to, step}");
  requireKeys(node, {"from", "to", "step"}, where + ": 'mm'");
  const double from = positive(yamlNumber(node, "from", where), "from", where);
  const double to = positive(yamlNumber(node, "to", where), "to", where);
  const double step = positive(yamlNumber(node, "step", where), "step", where);
  if (to < from) throw InputError(where + ": 'mm' has 'to' below 'from'");
  const double count = std::floor((to - from) / step + 1e-6);
  if (count >= kMaxSeriesSizes) throw InputError(where + ": 'mm' makes more than 2000 sizes");
  for (int k = 0; k <= static_cast<int>(count); ++k) {
    const double mm = std::round((from + k * step) * kSizeRounding) / kSizeRounding;
    sizes.push_back({sizeName(mm), mm});
  }
  return sizes;
}

// 4/64 .. 32/64 in, each named by its reduced fraction: "1_16in", "5_64in", "1_2in".
std::vector<DrillSize> inchFractions(const YAML::Node& node, const std::string& where) {
  requireKeys(node, {"from", "to", "per_inch"}, where + ": 'inch_fractions'");
  const double from = yamlNumber(node, "from", where), to = yamlNumber(node, "to", where);
  const double per_inch = yamlNumber(node, "per_inch", where);
  for (double value : {from, to, per_inch})
    if (!(value >= 1 && value == std::floor(value) && value <= 4096))
      throw InputError(where + ": 'inch_fractions' takes whole numbers from 1 to 4096");
  if (to < from) throw InputError(where + ": 'inch_fractions' has 'to' below 'from'");
  std::vector<DrillSize> sizes;
  for (int n = static_cast<int>(from); n <= static_cast<int>(to); ++n) {
    const int d = static_cast<int>(per_inch), g = std::gcd(n, d);
    const std::string name = d / g == 1 ? std::to_string(n / g) + "in"
                                        : std::to_string(n / g) + "_" + std::to_string(d / g) + "in";
    sizes.push_back({name, kMmPerInch * n / per_inch});
  }
  return sizes;
}

std::vector<DrillSize> namedInchSizes(const YAML::Node& node, const std::string& where) {
  if (!node.IsMap()) throw InputError(where + ": 'inch' maps size names to diameters in inches");
  std::vector<DrillSize> sizes;
  for (const auto& named : node) {
    const std::string name = named.first.as<std::string>();
    double inches = 0;
    try {
      inches = named.second.as<double>();
    } catch (const YAML::Exception&) {
      throw InputError(where + ": inch size '" + name + "' is not a number");
    }
    sizes.push_back({name, kMmPerInch * positive(inches, "inch size " + name, where)});
  }
  return sizes;
}

const LengthRow& lengthsFor(const DrillRule& rule, double diameter, const std::string& where) {
  for (const LengthRow& row : rule.lengths)
    if (diameter <= row.largest_diameter + kSizeSlack) return row;
  throw InputError(where + ": size " + sizeName(diameter) + " mm is beyond rule '" + rule.name + "' lengths (up to " +
                   sizeName(rule.lengths.back().largest_diameter) + " mm)");
}

std::vector<HolderStep> holderFor(const DrillRule& rule, const HolderMap& holders, double shank,
                                  const std::string& where) {
  for (const auto& [largest, name] : rule.holders)
    if (shank <= largest + kSizeSlack) return holders.at(name);
  throw InputError(where + ": no holder of rule '" + rule.name + "' takes a " + sizeName(shank) + " mm shank");
}

Tool drillOf(const DrillRule& rule, const HolderMap& holders, const std::string& prefix, const DrillSize& size,
             const std::string& where) {
  const LengthRow& lengths = lengthsFor(rule, size.diameter, where);
  Tool tool;
  tool.id = prefix + size.name;
  tool.type = ToolType::Drill;
  tool.diameter = size.diameter;
  tool.corner_radius = 0;
  tool.point_angle_deg = rule.point_angle_deg;
  tool.flute_length = lengths.flute;
  tool.shank_diameter = lengths.shank > 0 ? lengths.shank : size.diameter;
  tool.stickout = lengths.flute + rule.visible_shank;
  if (lengths.overall - tool.stickout < rule.min_grip)
    throw InputError(where + ": drill '" + tool.id + "' leaves " + sizeName(lengths.overall - tool.stickout) +
                     " mm of shank in the collet, under min_grip");
  tool.holder = holderFor(rule, holders, tool.shank_diameter, where);
  tool.flutes = rule.flutes;
  tool.spindle_rpm = std::min(rule.max_rpm, std::round(1000 * rule.vc_m_min / (kPi * size.diameter) / 10) * 10);
  const double feed_per_rev = std::clamp(rule.feed_per_mm * size.diameter, rule.feed_least, rule.feed_most);
  tool.feed_mm_min = std::max(1.0, std::round(tool.spindle_rpm * feed_per_rev));
  tool.plunge_mm_min = tool.feed_mm_min;
  tool.max_stepdown = std::round(rule.peck * size.diameter * 10) / 10;
  tool.max_stepover = 0;
  tool.material = rule.material;
  return tool;
}

}  // namespace

void addDrillSeries(const YAML::Node& root, const HolderMap& holders, const std::string& file,
                    std::vector<Tool>& tools) {
  const std::map<std::string, DrillRule> rules = drillRules(root, holders, file);
  const YAML::Node series = root["drill_series"];
  if (!series) return;
  if (!series.IsSequence()) throw InputError(file + ": 'drill_series' must be a list");
  for (std::size_t s = 0; s < series.size(); ++s) {
    const YAML::Node& entry = series[s];
    std::string where = file + ": drill series " + std::to_string(s + 1);
    requireKeys(entry, kSeriesKeys, where);
    const std::string prefix = yamlText(entry, "prefix", where);
    where += " ('" + prefix + "')";
    const auto rule = rules.find(yamlText(entry, "rule", where));
    if (rule == rules.end()) throw InputError(where + ": unknown rule '" + entry["rule"].as<std::string>() + "'");
    const int kinds = (entry["mm"] ? 1 : 0) + (entry["inch_fractions"] ? 1 : 0) + (entry["inch"] ? 1 : 0);
    if (kinds != 1) throw InputError(where + ": give exactly one of 'mm', 'inch_fractions' and 'inch'");
    const std::vector<DrillSize> sizes = entry["mm"]               ? metricSizes(entry["mm"], where)
                                         : entry["inch_fractions"] ? inchFractions(entry["inch_fractions"], where)
                                                                   : namedInchSizes(entry["inch"], where);
    for (const DrillSize& size : sizes)
      addTool(tools, drillOf(rule->second, holders, prefix, size, where), where + ": drill '" + prefix + size.name + "'");
  }
}

}  // namespace art2part::tooling_detail
