// Where each setup's part sits on a machine: a fixture per setup that the machine's travel allows, found by trying
// placements of the part on the table and keeping the first whose whole program stays inside every joint's travel
// (X Y Z and the rotaries, with each tool's full length: stickout and holder). The CLI's `plan` and `post` and the
// controller bridge all place setups with placeSetups, so a plan folder runs where it was posted.
//
// A setup is clamped facing up: its frame's z (the setup direction) along the table's z, the middle of the stock's
// bottom (in the setup frame) on the machine's table point (the default fixture's origin: the platter's top at the C
// axis on a trunnion). The candidates, in order: that clamping turned about the table's z by 0, 90, 180 and 270 deg,
// each first on the table point and then shifted so that the setup's tool tips sit in the middle of the X and Y travel.
// The travel check is the post itself (buildMachineProgram on the setup's points alone): every move, approach and
// retract, the 3+2 rotary branch (post/three_plus_two.cpp keeps the one that fits) or the 5-axis joint path.
// A setup the clampings do not name, or one the machine file gives a fixture of its own (fixture.setups), keeps the
// machine file's fixture: checked, never moved.
#pragma once

#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "art2part/kinematics/machine.h"
#include "art2part/post/machine_program.h"
#include "art2part/setup/setup_plan.h"
#include "art2part/tooling/tool.h"
#include "art2part/tooling/toolpath.h"

namespace art2part {

// How a setup's part goes on the table before the search turns or shifts it.
struct Clamping {
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();  // part frame -> table frame
  Vec3 anchor = Vec3::Zero();       // the part-frame point that sits on table_point (mm): the stock's bottom middle
  Vec3 table_point = Vec3::Zero();  // where the anchor goes, table frame (mm)
  bool fixed = false;               // only this pose is tried (the machine file's fixture)

  FixturePose fixture() const;      // origin = table_point - rotation * anchor
};

// The clamping of a setup with `frame`, its stock a box in the part frame: facing up on the machine's table point.
Clamping clampFacingUp(const Machine& machine, const SetupFrame& frame, const Box& stock);

// What the search found for one setup.
struct SetupPlacement {
  int setup = 0;              // toolpaths.csv's setup index
  bool reachable = false;     // some candidate keeps the setup's whole program inside the travel
  FixturePose fixture;        // the candidate kept (when not reachable: the first candidate tried)
  Vec3 anchor = Vec3::Zero(); // the part-frame point on the table (the stock's bottom middle)
  Vec3 table_point = Vec3::Zero();  // where the anchor sits, table frame
  double yaw_deg = 0;         // the turn about the table's z from the clamping
  JointPosition first_joints; // reachable: the joints at the setup's first toolpath point (3+2: the rotaries kept)
  int candidates_tried = 0;
  std::string reason;         // not reachable: why (the first candidate's travel violation)
};

struct FixturePlan {
  std::string machine;                  // Machine::name
  std::vector<SetupPlacement> setups;   // in the toolpath's order

  bool allReachable() const;
  std::map<int, FixturePose> fixtures() const;  // the fixtures found, by setup: PostOptions::fixtures
  // "" when every setup is reachable, else one line: "machine M cannot reach setups 1, 3: setup 1: ...; setup 3: ...".
  std::string unreachableText() const;
};

// Places every setup of `path`: the first candidate of each setup's clamping whose program (posted alone with
// `options`, its fixtures replaced) stays inside the travel. `tools` is tools.json. Throws InputError only for input
// the post refuses whatever the placement (a tool missing from tools.json, an empty path, bad options).
FixturePlan placeSetups(const Machine& machine, const Toolpath& path, const std::vector<Tool>& tools,
                        const std::map<int, Clamping>& clampings, const PostOptions& options = {});

// One line for a person: "setup 1 on vmc_3axis: stock bottom middle at (0, 0, 0) mm on the table, turned 90 deg,
// first point at X 12.000 Y -3.000 Z 240.000 mm (1 candidate tried)", or "setup 1 on M: unreachable: why".
std::string placementText(const Machine& machine, const SetupPlacement& placement);

// ---- plan.json ----
// One setup's placement as plan.json records it under setups[k].fixture: machine, reachable, reason, note (for a
// person: where the stock sits, or why the machine cannot reach the setup), origin_mm and
// rotation (the part frame in the table frame: p_table = rotation * p_part + origin_mm; rotation row-major), rpy_deg
// (the same rotation as roll, pitch, yaw about fixed x, y, z), anchor_mm, table_point_mm, yaw_deg, first_joints (mm,
// deg), candidates_tried.
nlohmann::json fixtureJson(const std::string& machine, const SetupPlacement& placement);
// Adds each placement to plan.json's setups[setup].fixture (setups the array lacks are skipped).
void recordFixtures(nlohmann::json& plan_json, const FixturePlan& plan);

// The fixture plan.json records for one setup (setups[setup].fixture: origin_mm and rotation), for a machine named
// `machine`: where the part sat on that machine's table when the plan was posted. Throws InputError for a setup the
// plan lacks, a setup without a fixture, a fixture recorded for another machine, or a malformed one.
FixturePose recordedFixture(const nlohmann::json& plan_json, int setup, const std::string& machine);

// The clampings a plan folder's plan.json gives for `machine`, by setup index: a fixture recorded for a machine of the
// same name is tried first exactly as recorded (so the bridge runs the plan where `plan` posted it), then the search
// goes on from it; otherwise each setup is clamped facing up from its recorded frame and anchor (or, in a plan.json
// without fixtures, the part's bounding box grown by stock_margin mm). Empty when plan.json has no setups. Throws
// InputError naming the key for a malformed entry.
std::map<int, Clamping> clampingsFromPlanJson(const nlohmann::json& plan_json, const Machine& machine,
                                              double stock_margin = 2.0);
// The same from DIR/plan.json; empty when the folder has none (a hand-made toolpath: the machine file's fixtures).
// Throws InputError when plan.json is there but not valid JSON.
std::map<int, Clamping> clampingsFromPlanFolder(const std::string& dir, const Machine& machine);

}  // namespace art2part
