// Reading a machine file (config/machines/*.yaml) into a Machine, with an InputError naming the file, the line and
// the key for anything wrong.
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <fstream>
#include <initializer_list>
#include <sstream>

#include "art2part/kinematics/machine.h"

namespace art2part {

namespace {

constexpr double kDegree = 3.14159265358979323846 / 180;

// Reads typed values out of YAML nodes; every failure names the source, line and key path.
class Reader {
 public:
  explicit Reader(std::string source) : source_(std::move(source)) {}

  [[noreturn]] void fail(const YAML::Node& near, const std::string& path, const std::string& what) const {
    std::string where = source_;
    if (near.IsDefined() && near.Mark().line >= 0) where += ":" + std::to_string(near.Mark().line + 1);
    throw InputError(where + ": " + path + ": " + what);
  }

  YAML::Node required(const YAML::Node& map, const std::string& key, const std::string& path) const {
    const YAML::Node node = map[key];
    if (!node.IsDefined() || node.IsNull()) fail(map, join(path, key), "missing key '" + key + "'");
    return node;
  }

  // Rejects keys the machine model does not know (a misspelt key would otherwise be silently ignored).
  void onlyKeys(const YAML::Node& map, const std::string& path, std::initializer_list<const char*> allowed,
                const std::string& context = "") const {
    for (const auto& entry : map) {
      const std::string key = entry.first.IsScalar() ? entry.first.Scalar() : "(not a plain key)";
      bool known = false;
      for (const char* name : allowed) known = known || key == name;
      if (!known) {
        std::string list;
        for (const char* name : allowed) list += std::string(list.empty() ? "" : ", ") + name;
        fail(entry.first, join(path, key), "unknown key '" + key + "'" + context + " (expected: " + list + ")");
      }
    }
  }

  void expectMap(const YAML::Node& node, const std::string& path) const {
    if (!node.IsMap()) fail(node, path.empty() ? "(top level)" : path, "expected a mapping of keys");
  }

  double number(const YAML::Node& node, const std::string& path) const {
    if (!node.IsScalar()) fail(node, path, "expected a number");
    double value = 0;
    try {
      value = node.as<double>();
    } catch (const YAML::Exception&) {
      fail(node, path, "expected a number, got '" + node.Scalar() + "'");
    }
    if (!std::isfinite(value)) fail(node, path, "expected a finite number, got '" + node.Scalar() + "'");
    return value;
  }

  double number(const YAML::Node& map, const std::string& key, const std::string& path) const {
    return number(required(map, key, path), join(path, key));
  }

  std::string text(const YAML::Node& map, const std::string& key, const std::string& path) const {
    const YAML::Node node = required(map, key, path);
    if (!node.IsScalar()) fail(node, join(path, key), "expected a string");
    return node.Scalar();
  }

  Vec3 vector3(const YAML::Node& map, const std::string& key, const std::string& path) const {
    const YAML::Node node = required(map, key, path);
    if (!node.IsSequence() || node.size() != 3) fail(node, join(path, key), "expected a list of 3 numbers");
    Vec3 v;
    for (int i = 0; i < 3; ++i) v[i] = number(node[i], join(path, key) + "[" + std::to_string(i) + "]");
    return v;
  }

  static std::string join(const std::string& path, const std::string& key) {
    return path.empty() ? key : path + "." + key;
  }

 private:
  std::string source_;
};

MachineKind kindFromName(const Reader& reader, const YAML::Node& root) {
  const std::string name = reader.text(root, "kinematics", "");
  for (MachineKind kind :
       {MachineKind::Mill3Axis, MachineKind::TableTiltAC, MachineKind::TableTiltBC, MachineKind::HeadBC}) {
    if (name == kinematicsModuleName(kind)) return kind;
  }
  reader.fail(root["kinematics"], "kinematics",
              "unknown kinematics '" + name + "' (expected trivkins, xyzac-trt-kins, xyzbc-trt-kins or 5axiskins)");
}

// The joint letters each kind has, in LinuxCNC's joint order.
std::vector<std::string> jointLetters(MachineKind kind) {
  switch (kind) {
    case MachineKind::Mill3Axis: return {"X", "Y", "Z"};
    case MachineKind::TableTiltAC: return {"X", "Y", "Z", "A", "C"};
    case MachineKind::TableTiltBC:
    case MachineKind::HeadBC: return {"X", "Y", "Z", "B", "C"};
  }
  return {};
}

RotaryGeometry readGeometry(const Reader& reader, const YAML::Node& root, MachineKind kind) {
  RotaryGeometry geometry;
  const std::string context = " for " + kinematicsModuleName(kind);
  if (kind == MachineKind::Mill3Axis) {
    const YAML::Node node = root["geometry"];
    if (node.IsDefined() && !node.IsNull() && !(node.IsMap() && node.size() == 0)) {
      reader.fail(node, "geometry", "a trivkins machine has no rotary geometry; leave the key out");
    }
    return geometry;
  }
  const YAML::Node node = reader.required(root, "geometry", "");
  reader.expectMap(node, "geometry");
  if (kind == MachineKind::HeadBC) {
    reader.onlyKeys(node, "geometry", {"pivot-length"}, context);
    geometry.pivot_length = reader.number(node, "pivot-length", "geometry");
    return geometry;
  }
  if (kind == MachineKind::TableTiltAC) {
    reader.onlyKeys(node, "geometry", {"x-rot-point", "y-rot-point", "z-rot-point", "y-offset", "z-offset"}, context);
    geometry.offset = Vec3(0, reader.number(node, "y-offset", "geometry"), reader.number(node, "z-offset", "geometry"));
  } else {
    reader.onlyKeys(node, "geometry", {"x-rot-point", "y-rot-point", "z-rot-point", "x-offset", "z-offset"}, context);
    geometry.offset = Vec3(reader.number(node, "x-offset", "geometry"), 0, reader.number(node, "z-offset", "geometry"));
  }
  geometry.rot_point = Vec3(reader.number(node, "x-rot-point", "geometry"),
                            reader.number(node, "y-rot-point", "geometry"),
                            reader.number(node, "z-rot-point", "geometry"));
  return geometry;
}

Joint readJoint(const Reader& reader, const YAML::Node& node, const std::string& path, const std::string& letter) {
  reader.expectMap(node, path);
  reader.onlyKeys(node, path,
                  {"name", "description", "min", "max", "max_velocity", "max_acceleration", "rapid_velocity"});
  Joint joint;
  joint.name = reader.text(node, "name", path);
  if (joint.name != letter) {
    reader.fail(node["name"], path + ".name", "expected joint " + letter + " here, got '" + joint.name + "'");
  }
  if (node["description"].IsDefined()) joint.description = reader.text(node, "description", path);
  joint.rotary = letter == "A" || letter == "B" || letter == "C";
  const double unit = joint.rotary ? kDegree : 1.0;  // the file says deg, deg/s, deg/s^2 for rotary joints
  joint.min = reader.number(node, "min", path) * unit;
  joint.max = reader.number(node, "max", path) * unit;
  joint.max_velocity = reader.number(node, "max_velocity", path) * unit;
  joint.max_acceleration = reader.number(node, "max_acceleration", path) * unit;
  joint.rapid_velocity = node["rapid_velocity"].IsDefined() ? reader.number(node, "rapid_velocity", path) * unit
                                                            : joint.max_velocity;
  auto shown = [&](double v) {
    std::ostringstream out;
    out << v / unit;
    return out.str();
  };
  if (!(joint.min < joint.max)) {
    reader.fail(node["min"], path + ".min", "min " + shown(joint.min) + " is not below max " + shown(joint.max));
  }
  if (!(joint.max_velocity > 0)) reader.fail(node["max_velocity"], path + ".max_velocity", "must be positive");
  if (!(joint.max_acceleration > 0)) {
    reader.fail(node["max_acceleration"], path + ".max_acceleration", "must be positive");
  }
  if (!(joint.rapid_velocity > 0) || joint.rapid_velocity > joint.max_velocity) {
    reader.fail(node["rapid_velocity"], path + ".rapid_velocity",
                "must be positive and at most max_velocity " + shown(joint.max_velocity));
  }
  return joint;
}

std::vector<Joint> readJoints(const Reader& reader, const YAML::Node& root, MachineKind kind) {
  const YAML::Node node = reader.required(root, "joints", "");
  const std::vector<std::string> letters = jointLetters(kind);
  if (!node.IsSequence() || node.size() != letters.size()) {
    std::string list;
    for (const auto& letter : letters) list += letter;
    reader.fail(node, "joints",
                "expected a list of " + std::to_string(letters.size()) + " joints (" + list + ") for " +
                    kinematicsModuleName(kind));
  }
  std::vector<Joint> joints;
  for (std::size_t j = 0; j < letters.size(); ++j) {
    joints.push_back(readJoint(reader, node[j], "joints[" + std::to_string(j) + "]", letters[j]));
  }
  return joints;
}

FixturePose readFixturePose(const Reader& reader, const YAML::Node& node, const std::string& path) {
  reader.expectMap(node, path);
  reader.onlyKeys(node, path, {"origin", "rpy"});
  FixturePose pose;
  pose.origin = reader.vector3(node, "origin", path);
  pose.rotation = rotationFromRpy(reader.vector3(node, "rpy", path) * kDegree);
  return pose;
}

void readFixtures(const Reader& reader, const YAML::Node& root, Machine& machine) {
  const YAML::Node node = root["fixture"];
  if (!node.IsDefined() || node.IsNull()) return;  // the part frame is the table frame
  reader.expectMap(node, "fixture");
  reader.onlyKeys(node, "fixture", {"default", "setups"});
  if (node["default"].IsDefined()) machine.default_fixture = readFixturePose(reader, node["default"], "fixture.default");
  const YAML::Node setups = node["setups"];
  if (!setups.IsDefined() || setups.IsNull()) return;
  reader.expectMap(setups, "fixture.setups");
  for (const auto& entry : setups) {
    const std::string key = entry.first.IsScalar() ? entry.first.Scalar() : "(not a plain key)";
    const std::string path = "fixture.setups." + key;
    int setup = -1;
    try {
      std::size_t used = 0;
      setup = std::stoi(key, &used);
      if (used != key.size()) setup = -1;
    } catch (const std::exception&) {
      setup = -1;
    }
    if (setup < 0) reader.fail(entry.first, path, "expected a setup index (0, 1, ...) as the key");
    machine.setup_fixtures[setup] = readFixturePose(reader, entry.second, path);
  }
}

// Optional: seconds per tool change and per setup change (the defaults in machine.h when left out).
void readChangeTimes(const Reader& reader, const YAML::Node& root, Machine& machine) {
  for (auto [key, value] : {std::pair<const char*, double*>{"tool_change_s", &machine.tool_change_s},
                            std::pair<const char*, double*>{"setup_change_s", &machine.setup_change_s}}) {
    if (!root[key].IsDefined()) continue;
    *value = reader.number(root[key], key);
    if (*value < 0) reader.fail(root[key], key, "must not be negative (seconds)");
  }
}

}  // namespace

Machine parseMachine(const std::string& yaml_text, const std::string& source) {
  YAML::Node root;
  try {
    root = YAML::Load(yaml_text);
  } catch (const YAML::ParserException& error) {
    throw InputError(source + ":" + std::to_string(error.mark.line + 1) + ": not valid YAML: " + error.msg);
  }
  const Reader reader(source);
  reader.expectMap(root, "");
  reader.onlyKeys(root, "", {"name", "description", "kinematics", "geometry", "joints", "fixture", "tool_change_s",
                            "setup_change_s"});
  Machine machine;
  machine.source = source;
  machine.name = reader.text(root, "name", "");
  if (root["description"].IsDefined()) machine.description = reader.text(root, "description", "");
  machine.kind = kindFromName(reader, root);
  machine.geometry = readGeometry(reader, root, machine.kind);
  machine.joints = readJoints(reader, root, machine.kind);
  readFixtures(reader, root, machine);
  readChangeTimes(reader, root, machine);
  return machine;
}

Machine loadMachine(const std::string& yaml_path) {
  std::ifstream in(yaml_path);
  if (!in) throw InputError(yaml_path + ": cannot open the machine file");
  std::stringstream text;
  text << in.rdbuf();
  return parseMachine(text.str(), yaml_path);
}

}  // namespace art2part
