// Fixtures per setup: candidate placements of the part on the table, each checked by posting the setup alone.
#include "art2part/post/fixture_placement.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>

#include "program_builder.h"

namespace art2part {

using post_detail::kDegree;

FixturePose Clamping::fixture() const {
  FixturePose pose;
  pose.rotation = rotation;
  pose.origin = table_point - rotation * anchor;
  return pose;
}

Clamping clampFacingUp(const Machine& machine, const SetupFrame& frame, const Box& stock) {
  Box in_frame;  // the stock's corners in the setup frame
  for (int corner = 0; corner < 8; ++corner) {
    const Vec3 p((corner & 1) ? stock.max.x() : stock.min.x(), (corner & 2) ? stock.max.y() : stock.min.y(),
                 (corner & 4) ? stock.max.z() : stock.min.z());
    const Vec3 d = p - frame.origin;
    in_frame.extend(Vec3(d.dot(frame.x), d.dot(frame.y), d.dot(frame.z)));
  }
  const Vec3 bottom(in_frame.center().x(), in_frame.center().y(), in_frame.min.z());
  Clamping clamping;
  clamping.rotation.row(0) = frame.x.transpose();
  clamping.rotation.row(1) = frame.y.transpose();
  clamping.rotation.row(2) = frame.z.transpose();
  clamping.anchor = frame.origin + bottom.x() * frame.x + bottom.y() * frame.y + bottom.z() * frame.z;
  clamping.table_point = machine.default_fixture.origin;
  return clamping;
}

bool FixturePlan::allReachable() const {
  for (const SetupPlacement& s : setups)
    if (!s.reachable) return false;
  return true;
}

std::map<int, FixturePose> FixturePlan::fixtures() const {
  std::map<int, FixturePose> fixtures;
  for (const SetupPlacement& s : setups) fixtures[s.setup] = s.fixture;
  return fixtures;
}

std::string FixturePlan::unreachableText() const {
  std::string list, reasons;
  int count = 0;
  for (const SetupPlacement& s : setups) {
    if (s.reachable) continue;
    list += (count++ ? ", " : "") + std::to_string(s.setup);
    reasons += "; setup " + std::to_string(s.setup) + ": " + s.reason;
  }
  if (count == 0) return "";
  return "machine " + machine + " cannot reach setup" + (count > 1 ? "s " : " ") + list + " in any placement tried" +
         reasons;
}

namespace {

// One placement to try.
struct Candidate {
  Vec3 table_point = Vec3::Zero();
  double yaw_deg = 0;
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Vec3 anchor = Vec3::Zero();

  FixturePose fixture() const { return Clamping{rotation, anchor, table_point, false}.fixture(); }
};

// The setup's tool tips in the table frame under `candidate`: their middle in x and y.
Vec3 tipsMiddle(const Toolpath& path, int setup, const Candidate& candidate) {
  const FixturePose fixture = candidate.fixture();
  Box box;
  for (const CutterLocation& point : path)
    if (point.setup == setup) box.extend(fixture.pointToTable(point.tip));
  return box.center();
}

// The clamping turned by 0, 90, 180, 270 deg about the table's z, each on its table point and then with the setup's
// tips moved to the middle of the X and Y travel.
std::vector<Candidate> candidatesFor(const Machine& machine, const Toolpath& path, int setup,
                                     const Clamping& clamping) {
  std::vector<Candidate> candidates;
  const Candidate first{clamping.table_point, 0, clamping.rotation, clamping.anchor};
  candidates.push_back(first);
  if (clamping.fixed) return candidates;
  const Vec3 travel_middle(0.5 * (machine.joints[0].min + machine.joints[0].max),
                           0.5 * (machine.joints[1].min + machine.joints[1].max), 0);
  for (int quarter = 0; quarter < 4; ++quarter) {
    Candidate turned = first;
    turned.yaw_deg = 90.0 * quarter;
    turned.rotation = Eigen::AngleAxisd(turned.yaw_deg * kDegree, Vec3::UnitZ()).toRotationMatrix() * clamping.rotation;
    if (quarter > 0) candidates.push_back(turned);
    const Vec3 middle = tipsMiddle(path, setup, turned);
    const Vec3 shift(travel_middle.x() - middle.x(), travel_middle.y() - middle.y(), 0);
    if (shift.norm() > 1e-6) {
      turned.table_point += shift;
      candidates.push_back(turned);
    }
  }
  return candidates;
}

// The setup posted alone with `fixture`: empty when it fits the travel, else the post's reason.
std::optional<std::string> travelViolation(const Machine& machine, const Toolpath& path, const std::vector<Tool>& tools,
                                           int setup, const FixturePose& fixture, const PostOptions& options,
                                           JointPosition* first_joints) {
  PostOptions alone = options;
  alone.fixtures[setup] = fixture;
  alone.only_setup = setup;
  try {
    const MachineProgram program = buildMachineProgram(machine, path, tools, "placement", alone);
    for (const SetupProgram& s : program.setups)
      for (const ProgramStep& step : s.steps)
        if (step.at_row) {
          *first_joints = step.joints;
          return std::nullopt;
        }
    return std::nullopt;
  } catch (const InputError& e) {
    return std::string(e.what());
  }
}

}  // namespace

FixturePlan placeSetups(const Machine& machine, const Toolpath& path, const std::vector<Tool>& tools,
                        const std::map<int, Clamping>& clampings, const PostOptions& options) {
  {  // what the post refuses whatever the placement: checked once, posting no setup
    PostOptions none = options;
    none.only_setup = std::numeric_limits<int>::min();
    buildMachineProgram(machine, path, tools, "placement", none);
  }
  FixturePlan plan;
  plan.machine = machine.name;
  for (std::size_t row = 0; row < path.size(); ++row) {
    const int setup = path[row].setup;
    if (row > 0 && path[row - 1].setup == setup) continue;
    Clamping clamping;
    const auto given = clampings.find(setup);
    if (given != clampings.end() && !machine.setup_fixtures.count(setup)) {
      clamping = given->second;
    } else {  // the machine file's fixture, as it stands (its own for this setup wins over any clamping)
      clamping.rotation = fixtureForSetup(machine, setup).rotation;
      clamping.table_point = fixtureForSetup(machine, setup).origin;
      clamping.fixed = true;
    }
    SetupPlacement placement;
    placement.setup = setup;
    for (const Candidate& candidate : candidatesFor(machine, path, setup, clamping)) {
      ++placement.candidates_tried;
      JointPosition first;
      const std::optional<std::string> violation =
          travelViolation(machine, path, tools, setup, candidate.fixture(), options, &first);
      if (placement.candidates_tried == 1 || !violation) {
        placement.fixture = candidate.fixture();
        placement.anchor = candidate.anchor;
        placement.table_point = candidate.table_point;
        placement.yaw_deg = candidate.yaw_deg;
        placement.first_joints = first;
      }
      if (!violation) {
        placement.reachable = true;
        placement.reason.clear();
        break;
      }
      if (placement.candidates_tried == 1) placement.reason = *violation;
    }
    plan.setups.push_back(placement);
  }
  return plan;
}

std::string placementText(const Machine& machine, const SetupPlacement& p) {
  const std::string head = "setup " + std::to_string(p.setup) + " on " + machine.name + ": ";
  if (!p.reachable) return head + "unreachable: " + p.reason;
  char text[320];
  std::snprintf(text, sizeof text,
                "stock bottom middle at (%.1f, %.1f, %.1f) mm on the table, turned %g deg, first point at "
                "X %.3f Y %.3f Z %.3f mm", p.table_point.x(), p.table_point.y(), p.table_point.z(), p.yaw_deg,
                p.first_joints.linear.x(), p.first_joints.linear.y(), p.first_joints.linear.z());
  std::string line = head + text;
  if (machine.fiveAxis()) {
    std::snprintf(text, sizeof text, " %s %.3f C %.3f deg", machine.tiltJoint().name.c_str(),
                  p.first_joints.tilt / kDegree, p.first_joints.rotary / kDegree);
    line += text;
  }
  return line + " (" + std::to_string(p.candidates_tried) + " placement" + (p.candidates_tried > 1 ? "s" : "") +
         " tried)";
}

// ---- plan.json -----------------------------------------------------------------------------------------------------

namespace {

nlohmann::json vectorJson(const Vec3& v) { return nlohmann::json::array({v.x(), v.y(), v.z()}); }

const nlohmann::json& member(const nlohmann::json& j, const char* key, const std::string& where) {
  if (!j.is_object() || !j.contains(key)) throw InputError("plan.json: " + where + " has no '" + key + "'");
  return j.at(key);
}

Vec3 vectorFrom(const nlohmann::json& j, const char* key, const std::string& where) {
  const nlohmann::json& v = member(j, key, where);
  if (!v.is_array() || v.size() != 3 || !v[0].is_number() || !v[1].is_number() || !v[2].is_number())
    throw InputError("plan.json: " + where + "." + key + " is not three numbers");
  const Vec3 value(v[0].get<double>(), v[1].get<double>(), v[2].get<double>());
  if (!value.allFinite()) throw InputError("plan.json: " + where + "." + key + " is not finite");
  return value;
}

Eigen::Matrix3d rotationFrom(const nlohmann::json& j, const std::string& where) {
  const nlohmann::json& rows = member(j, "rotation", where);
  if (!rows.is_array() || rows.size() != 3) throw InputError("plan.json: " + where + ".rotation is not 3 rows");
  Eigen::Matrix3d r;
  for (int i = 0; i < 3; ++i) {
    const nlohmann::json wrapper = {{"row", rows[i]}};
    r.row(i) = vectorFrom(wrapper, "row", where + ".rotation[" + std::to_string(i) + "]").transpose();
  }
  if (!(r.transpose() * r).isApprox(Eigen::Matrix3d::Identity(), 1e-6) || r.determinant() < 0)
    throw InputError("plan.json: " + where + ".rotation is not a rotation");
  return r;
}

SetupFrame frameFrom(const nlohmann::json& setup, const std::string& where) {
  const nlohmann::json& f = member(setup, "frame", where);
  SetupFrame frame;
  frame.origin = vectorFrom(f, "origin", where + ".frame");
  frame.x = vectorFrom(f, "x", where + ".frame");
  frame.y = vectorFrom(f, "y", where + ".frame");
  frame.z = vectorFrom(f, "z", where + ".frame");
  return frame;
}

}  // namespace

nlohmann::json fixtureJson(const std::string& machine, const SetupPlacement& p) {
  char note[200];
  std::snprintf(note, sizeof note, "the stock's bottom middle at (%.1f, %.1f, %.1f) mm on the table of %s, turned %g deg",
                p.table_point.x(), p.table_point.y(), p.table_point.z(), machine.c_str(), p.yaw_deg);
  nlohmann::json rotation = nlohmann::json::array();
  for (int i = 0; i < 3; ++i) rotation.push_back(vectorJson(p.fixture.rotation.row(i).transpose()));
  return {{"machine", machine},
          {"reachable", p.reachable},
          {"reason", p.reason},
          {"note", p.reachable ? std::string(note) : machine + " cannot reach this setup: " + p.reason},
          {"origin_mm", vectorJson(p.fixture.origin)},
          {"rotation", rotation},
          {"rpy_deg", vectorJson(rpyFromRotation(p.fixture.rotation) / kDegree)},
          {"anchor_mm", vectorJson(p.anchor)},
          {"table_point_mm", vectorJson(p.table_point)},
          {"yaw_deg", p.yaw_deg},
          {"first_joints", {p.first_joints.linear.x(), p.first_joints.linear.y(), p.first_joints.linear.z(),
                            p.first_joints.tilt / kDegree, p.first_joints.rotary / kDegree}},
          {"candidates_tried", p.candidates_tried}};
}

void recordFixtures(nlohmann::json& plan_json, const FixturePlan& plan) {
  if (!plan_json.contains("setups") || !plan_json["setups"].is_array()) return;
  nlohmann::json& setups = plan_json["setups"];
  for (const SetupPlacement& p : plan.setups)
    if (p.setup >= 0 && p.setup < static_cast<int>(setups.size()))
      setups[p.setup]["fixture"] = fixtureJson(plan.machine, p);
}

FixturePose recordedFixture(const nlohmann::json& plan_json, int setup, const std::string& machine) {
  const nlohmann::json& setups = member(plan_json, "setups", "plan.json");
  const int count = setups.is_array() ? static_cast<int>(setups.size()) : 0;
  if (setup < 0 || setup >= count)
    throw InputError("plan.json has no setup " + std::to_string(setup) + " (it has " + std::to_string(count) + ")");
  const std::string where = "setups[" + std::to_string(setup) + "].fixture";
  if (!setups[setup].is_object() || !setups[setup].contains("fixture"))
    throw InputError("plan.json: setup " + std::to_string(setup) + " has no fixture (the plan was not posted)");
  const nlohmann::json& f = setups[setup]["fixture"];
  const nlohmann::json& name = member(f, "machine", where);
  if (!name.is_string() || name.get<std::string>() != machine)
    throw InputError("plan.json: " + where + " is for machine " + name.dump() + ", not " + machine);
  FixturePose fixture;
  fixture.rotation = rotationFrom(f, where);
  fixture.origin = vectorFrom(f, "origin_mm", where);
  return fixture;
}

std::map<int, Clamping> clampingsFromPlanJson(const nlohmann::json& plan_json, const Machine& machine,
                                              double stock_margin) {
  std::map<int, Clamping> clampings;
  if (!plan_json.is_object() || !plan_json.contains("setups") || !plan_json["setups"].is_array()) return clampings;
  const nlohmann::json& setups = plan_json["setups"];
  std::optional<Box> stock;
  for (std::size_t k = 0; k < setups.size(); ++k) {
    const std::string where = "setups[" + std::to_string(k) + "]";
    const SetupFrame frame = frameFrom(setups[k], where);
    if (setups[k].contains("fixture")) {
      const nlohmann::json& f = setups[k]["fixture"];
      const std::string at = where + ".fixture";
      Clamping clamping;
      clamping.anchor = vectorFrom(f, "anchor_mm", at);
      const nlohmann::json& name = member(f, "machine", at);
      if (name.is_string() && name.get<std::string>() == machine.name) {  // as recorded, then the search from it
        clamping.rotation = rotationFrom(f, at);
        clamping.table_point = vectorFrom(f, "table_point_mm", at);
      } else {  // recorded for another machine: facing up on this one's table point
        clamping.rotation = clampFacingUp(machine, frame, Box{clamping.anchor, clamping.anchor}).rotation;
        clamping.table_point = machine.default_fixture.origin;
      }
      clampings[static_cast<int>(k)] = clamping;
      continue;
    }
    if (!stock) {
      const nlohmann::json& box = member(member(plan_json, "part", "plan.json"), "bounding_box", "part");
      stock = Box{vectorFrom(box, "min", "part.bounding_box") - Vec3::Constant(stock_margin),
                  vectorFrom(box, "max", "part.bounding_box") + Vec3::Constant(stock_margin)};
    }
    clampings[static_cast<int>(k)] = clampFacingUp(machine, frame, *stock);
  }
  return clampings;
}

std::map<int, Clamping> clampingsFromPlanFolder(const std::string& dir, const Machine& machine) {
  const std::filesystem::path file = std::filesystem::path(dir) / "plan.json";
  if (!std::filesystem::is_regular_file(file)) return {};
  std::ifstream in(file);
  nlohmann::json plan;
  try {
    in >> plan;
  } catch (const nlohmann::json::exception& e) {
    throw InputError(file.string() + ": not valid JSON: " + e.what());
  }
  return clampingsFromPlanJson(plan, machine);
}

}  // namespace art2part
