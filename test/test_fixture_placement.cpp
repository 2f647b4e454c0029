// Fixtures per setup (fixture_placement.h): a synthetic three-setup plan of a 100 x 60 x 40 mm block (top, bottom and
// side raster passes with a 100 mm tool assembly) and a tilted 5-axis pass are placed on the 3-axis VMC and on the
// default 5-axis trunnion; every move of the program posted with those fixtures lies inside the travel, and every
// toolpath point comes back through forward kinematics. A machine that cannot reach a setup says which and why;
// plan.json's record brings back the same placement.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "art2part/kinematics/inverse_kinematics.h"
#include "art2part/kinematics/machine_urdf.h"
#include "art2part/post/fixture_placement.h"
#include "art2part/post/machine_program.h"

using namespace art2part;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180;

Machine machineNamed(const std::string& name) {
  return loadMachine(std::string(ART2PART_SOURCE_DIR) + "/config/machines/" + name + ".yaml");
}

Tool flat10() {
  Tool tool;
  tool.id = "flat10";
  tool.diameter = 10;
  tool.flute_length = 25;
  tool.shank_diameter = 10;
  tool.stickout = 40;
  tool.holder = {{32, 60}};  // 100 mm from the tip to the top of the holder
  tool.feed_mm_min = 1200;
  tool.plunge_mm_min = 300;
  return tool;
}

const Box kStock{Vec3(-52, -32, -2), Vec3(52, 32, 42)};  // the block's box + 2 mm

SetupFrame frameOf(const Vec3& x, const Vec3& y, const Vec3& z, const Vec3& origin) {
  SetupFrame f;
  f.x = x;
  f.y = y;
  f.z = z;
  f.origin = origin;
  return f;
}

// Top (+z), bottom (-z) and the +x side of the block.
std::vector<SetupFrame> blockFrames() {
  return {frameOf(Vec3::UnitX(), Vec3::UnitY(), Vec3::UnitZ(), Vec3(0, 0, 40)),
          frameOf(Vec3::UnitX(), -Vec3::UnitY(), -Vec3::UnitZ(), Vec3(0, 0, 0)),
          frameOf(Vec3::UnitY(), Vec3::UnitZ(), Vec3::UnitX(), Vec3(50, 0, 20))};
}

// A raster over the face at the frame's origin, 5 mm into the stock, across the whole stock as seen along z.
void addRaster(Toolpath& path, int setup, const SetupFrame& f) {
  Box seen;  // the stock in the setup frame
  for (int c = 0; c < 8; ++c) {
    const Vec3 p((c & 1) ? kStock.max.x() : kStock.min.x(), (c & 2) ? kStock.max.y() : kStock.min.y(),
                 (c & 4) ? kStock.max.z() : kStock.min.z());
    seen.extend(Vec3((p - f.origin).dot(f.x), (p - f.origin).dot(f.y), (p - f.origin).dot(f.z)));
  }
  auto at = [&](double u, double v, double w) { return Vec3(f.origin + u * f.x + v * f.y + w * f.z); };
  auto add = [&](MoveKind move, const Vec3& tip) {
    CutterLocation p;
    p.op = setup;
    p.setup = setup;
    p.tool = "flat10";
    p.move = move;
    p.tip = tip;
    p.axis = f.z;
    path.push_back(p);
  };
  add(MoveKind::Rapid, at(seen.min.x(), seen.min.y(), 10));
  bool forward = true;
  for (double v = seen.min.y(); v <= seen.max.y() + 1e-9; v += 8, forward = !forward) {
    add(MoveKind::Feed, at(forward ? seen.min.x() : seen.max.x(), v, -5));
    add(MoveKind::Feed, at(forward ? seen.max.x() : seen.min.x(), v, -5));
  }
  add(MoveKind::Rapid, path.back().tip + 10 * f.z);
}

Toolpath blockPath() {
  Toolpath path;
  const std::vector<SetupFrame> frames = blockFrames();
  for (int k = 0; k < static_cast<int>(frames.size()); ++k) addRaster(path, k, frames[k]);
  return path;
}

std::map<int, Clamping> clampingsFor(const Machine& machine) {
  std::map<int, Clamping> clampings;
  const std::vector<SetupFrame> frames = blockFrames();
  for (int k = 0; k < static_cast<int>(frames.size()); ++k) clampings[k] = clampFacingUp(machine, frames[k], kStock);
  return clampings;
}

// Every step of the program inside the travel; every toolpath point where a move ends comes back through forward
// kinematics with the setup's fixture; the stock stands on the table with its setup direction up.
void expectProgramOnThePath(const Machine& machine, const Toolpath& path, const FixturePlan& placement,
                            const PostOptions& base = {}) {
  ASSERT_TRUE(placement.allReachable()) << placement.unreachableText();
  PostOptions options = base;
  options.fixtures = placement.fixtures();
  const MachineProgram program = buildMachineProgram(machine, path, {flat10()}, "block", options);
  for (const SetupProgram& setup : program.setups) {
    int checked = 0, rows = 0;
    for (const CutterLocation& point : path) rows += point.setup == setup.setup ? 1 : 0;
    ASSERT_EQ(setup.fixture.origin, placement.fixtures().at(setup.setup).origin);
    for (const ProgramStep& step : setup.steps) {
      if (step.kind == StepKind::ToolChange) continue;
      EXPECT_EQ(limitViolation(machine, step.joints, 1e-6), "") << machine.name << " setup " << setup.setup;
      if (!step.at_row) continue;
      Placement at;
      at.fixture = setup.fixture;
      at.tool_length = 100;
      const ToolPose pose = forwardKinematics(machine, at, step.joints);
      EXPECT_LT((pose.tip - path[step.row].tip).norm(), 1e-6) << machine.name << " row " << step.row;
      EXPECT_LT(angleBetween(pose.axis, path[step.row].axis), 1e-6) << machine.name << " row " << step.row;
      ++checked;
    }
    EXPECT_GT(checked, rows / 2) << machine.name << " setup " << setup.setup;
  }
}

}  // namespace

TEST(FixturePlacement, EverySetupOfTheBlockRunsInsideTheTravelOfTheVmcAndTheTrunnion) {
  const Toolpath path = blockPath();
  for (const char* name : {"vmc_3axis", "trunnion_5axis"}) {
    const Machine machine = machineNamed(name);
    const FixturePlan placement = placeSetups(machine, path, {flat10()}, clampingsFor(machine));
    ASSERT_EQ(placement.setups.size(), 3u) << name;
    const std::vector<SetupFrame> frames = blockFrames();
    for (const SetupPlacement& p : placement.setups) {
      EXPECT_TRUE(p.reachable) << name << ": " << p.reason;
      // Facing up: the setup direction along the table's z, the stock's bottom on the table, none of it below.
      EXPECT_LT((p.fixture.directionToTable(frames[p.setup].z) - Vec3::UnitZ()).norm(), 1e-12) << name;
      EXPECT_LT((p.fixture.pointToTable(p.anchor) - p.table_point).norm(), 1e-9) << name;
      double lowest = 1e9;
      for (int c = 0; c < 8; ++c) {
        const Vec3 corner((c & 1) ? kStock.max.x() : kStock.min.x(), (c & 2) ? kStock.max.y() : kStock.min.y(),
                          (c & 4) ? kStock.max.z() : kStock.min.z());
        lowest = std::min(lowest, p.fixture.pointToTable(corner).z());
      }
      EXPECT_NEAR(lowest, machine.default_fixture.origin.z(), 1e-9) << name << " setup " << p.setup;
    }
    expectProgramOnThePath(machine, path, placement);
  }
}

TEST(FixturePlacement, TheSearchTurnsAndShiftsThePartWhereTheFirstPlacementLeavesTheTravel) {
  // X travel 80 mm only, away from the table point; Y long: the 104 mm stock fits only turned a quarter and moved.
  Machine machine = machineNamed("vmc_3axis");
  machine.joints[0].min = 300;
  machine.joints[0].max = 380;
  const Toolpath path = blockPath();
  const std::map<int, Clamping> clampings = clampingsFor(machine);
  const FixturePlan placement = placeSetups(machine, path, {flat10()}, {{0, clampings.at(0)}});
  ASSERT_EQ(placement.setups.size(), 3u);
  const SetupPlacement& top = placement.setups[0];
  ASSERT_TRUE(top.reachable) << top.reason;
  EXPECT_GT(top.candidates_tried, 2);
  EXPECT_NEAR(std::fmod(top.yaw_deg, 180.0), 90.0, 1e-9) << "the long side along Y";
  EXPECT_NEAR(top.table_point.x(), 340.0, 1e-6) << "the tips in the middle of X";
  // Setups 1 and 2 have no clamping: the machine file's fixture, tried alone, out of the X travel.
  for (int k : {1, 2}) {
    EXPECT_FALSE(placement.setups[k].reachable);
    EXPECT_EQ(placement.setups[k].candidates_tried, 1);
  }
  const std::string text = placement.unreachableText();
  EXPECT_NE(text.find("cannot reach setups 1, 2 in any placement tried; setup 1: "), std::string::npos) << text;
  EXPECT_NE(text.find("; setup 2: "), std::string::npos) << text;
  PostOptions only_top;
  only_top.only_setup = 0;
  expectProgramOnThePath(machine, path, FixturePlan{placement.machine, {top}}, only_top);
}

TEST(FixturePlacement, AMachineTooShortSaysWhichSetupsAndWhy) {
  // LinuxCNC's sim trunnion: Z 120 mm at most; a 100 mm assembly over a 44 mm stock needs more anywhere on the table.
  const Machine machine = machineNamed("trunnion_ac");
  const FixturePlan placement = placeSetups(machine, blockPath(), {flat10()}, clampingsFor(machine));
  ASSERT_EQ(placement.setups.size(), 3u);
  for (const SetupPlacement& p : placement.setups) {
    EXPECT_FALSE(p.reachable);
    EXPECT_GE(p.candidates_tried, 4) << "every turn tried";
    EXPECT_LE(p.candidates_tried, 8) << "four turns, each on the table point and centred on the travel";
    EXPECT_NE(p.reason.find("Z = "), std::string::npos) << p.reason;
    EXPECT_NE(p.reason.find("above its maximum 120"), std::string::npos) << p.reason;
  }
  const std::string text = placement.unreachableText();
  EXPECT_EQ(text.find("machine trunnion_ac cannot reach setups 0, 1, 2 in any placement tried; setup 0: "), 0u) << text;
  // Input the post refuses whatever the placement is an error, not an unreachable setup.
  EXPECT_THROW(placeSetups(machine, blockPath(), {}, clampingsFor(machine)), InputError);
}

TEST(FixturePlacement, AContinuousFiveAxisPassOnTheTrunnion) {
  // A ring of radius 25 on the block's top with the axis leaning 40 deg outwards: A and C move at every point.
  const Machine machine = machineNamed("trunnion_5axis");
  Toolpath path;
  for (int k = 0; k <= 36; ++k) {
    const double theta = k * 10 * kDeg;
    CutterLocation p;
    p.tool = "flat10";
    p.axis = Vec3(std::sin(40 * kDeg) * std::cos(theta), std::sin(40 * kDeg) * std::sin(theta), std::cos(40 * kDeg));
    p.tip = Vec3(25 * std::cos(theta), 25 * std::sin(theta), 38);
    p.move = k == 0 ? MoveKind::Rapid : MoveKind::Feed;
    if (k == 0) p.tip += 10 * p.axis;
    path.push_back(p);
  }
  const FixturePlan placement = placeSetups(machine, path, {flat10()}, {{0, clampingsFor(machine).at(0)}});
  ASSERT_TRUE(placement.allReachable()) << placement.unreachableText();
  EXPECT_EQ(placement.setups[0].candidates_tried, 1);
  expectProgramOnThePath(machine, path, placement);
  PostOptions options;
  options.fixtures = placement.fixtures();
  EXPECT_EQ(buildMachineProgram(machine, path, {flat10()}, "ring", options).mode, PostMode::FiveAxis);
}

TEST(FixturePlacement, PlanJsonBringsBackThePlacementForTheSameMachineAndReclampsForAnother) {
  const Machine vmc = machineNamed("vmc_3axis");
  const Toolpath path = blockPath();
  Machine shifted = vmc;  // the first placement fails: the recorded one is the shifted candidate
  shifted.joints[0].min = 300;
  shifted.joints[0].max = 700;
  const FixturePlan placement = placeSetups(shifted, path, {flat10()}, clampingsFor(shifted));
  ASSERT_TRUE(placement.allReachable()) << placement.unreachableText();

  nlohmann::json plan = {{"part", {{"bounding_box", {{"min", {-50, -30, 0}}, {"max", {50, 30, 40}}}}}}};
  for (const SetupFrame& f : blockFrames())
    plan["setups"].push_back({{"frame",
                               {{"origin", {f.origin.x(), f.origin.y(), f.origin.z()}},
                                {"x", {f.x.x(), f.x.y(), f.x.z()}},
                                {"y", {f.y.x(), f.y.y(), f.y.z()}},
                                {"z", {f.z.x(), f.z.y(), f.z.z()}}}}});
  // Without a record: the frames and the part's box grown by 2 mm give the clamping the CLI computes.
  const std::map<int, Clamping> unrecorded = clampingsFromPlanJson(plan, shifted);
  for (const auto& [k, clamping] : clampingsFor(shifted)) {
    EXPECT_LT((unrecorded.at(k).anchor - clamping.anchor).norm(), 1e-12) << k;
    EXPECT_TRUE(unrecorded.at(k).rotation.isApprox(clamping.rotation, 1e-12)) << k;
  }

  recordFixtures(plan, placement);
  const nlohmann::json reread = nlohmann::json::parse(plan.dump());
  ASSERT_EQ(reread["setups"][1]["fixture"]["machine"], "vmc_3axis");
  ASSERT_TRUE(reread["setups"][1]["fixture"]["reachable"].get<bool>());
  const FixturePlan again = placeSetups(shifted, path, {flat10()}, clampingsFromPlanJson(reread, shifted));
  for (std::size_t k = 0; k < again.setups.size(); ++k) {
    EXPECT_EQ(again.setups[k].candidates_tried, 1) << "the recorded placement, tried first, fits";
    EXPECT_LT((again.setups[k].fixture.origin - placement.setups[k].fixture.origin).norm(), 1e-9);
    EXPECT_TRUE(again.setups[k].fixture.rotation.isApprox(placement.setups[k].fixture.rotation, 1e-12));
  }

  // Another machine: clamped facing up on its own table point, searched afresh.
  const Machine trunnion = machineNamed("trunnion_5axis");
  const std::map<int, Clamping> other = clampingsFromPlanJson(reread, trunnion);
  for (const auto& [k, clamping] : clampingsFor(trunnion)) {
    EXPECT_LT((other.at(k).table_point - trunnion.default_fixture.origin).norm(), 1e-12) << k;
    EXPECT_TRUE(other.at(k).rotation.isApprox(clamping.rotation, 1e-12)) << k;
  }
  expectProgramOnThePath(trunnion, path, placeSetups(trunnion, path, {flat10()}, other));

  plan["setups"][0]["fixture"]["rotation"] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 2}};
  EXPECT_THROW(clampingsFromPlanJson(plan, shifted), InputError);
}

// machine.launch plan:=DIR setup:=K: the URDF's part frame sits where plan.json says setup K sat on this machine.
TEST(FixturePlacement, TheFixturePlanJsonRecordsForASetupPlacesTheUrdfPartFrame) {
  const Machine vmc = machineNamed("vmc_3axis");
  SetupPlacement placed;
  placed.setup = 1;
  placed.reachable = true;
  placed.fixture.rotation = rotationFromRpy(Vec3(kPi, 0, kPi / 2));  // upside down, turned 90 deg
  placed.fixture.origin = Vec3(100, 20, 50);
  nlohmann::json plan = {{"setups", {nlohmann::json::object(), nlohmann::json::object()}}};
  recordFixtures(plan, FixturePlan{"vmc_3axis", {placed}});
  const nlohmann::json reread = nlohmann::json::parse(plan.dump());

  const FixturePose fixture = recordedFixture(reread, 1, "vmc_3axis");
  EXPECT_LT((fixture.origin - placed.fixture.origin).norm(), 1e-12);
  EXPECT_TRUE(fixture.rotation.isApprox(placed.fixture.rotation, 1e-12));
  EXPECT_THROW(recordedFixture(reread, 1, "trunnion_5axis"), InputError);  // placed for another machine
  EXPECT_THROW(recordedFixture(reread, 0, "vmc_3axis"), InputError);       // not posted: no fixture
  EXPECT_THROW(recordedFixture(reread, 2, "vmc_3axis"), InputError);       // no such setup

  UrdfOptions options;
  options.setup = 1;
  options.fixture = fixture;
  const std::string urdf = machineUrdf(vmc, options);
  const std::size_t joint = urdf.find("<joint name=\"part_fixture\"");
  ASSERT_NE(joint, std::string::npos);
  const std::string origin = urdf.substr(joint, urdf.find("</joint>", joint) - joint);
  EXPECT_NE(origin.find("xyz=\"0.1 0.02 0.05\""), std::string::npos) << origin;
  Vec3 rpy;
  ASSERT_EQ(std::sscanf(origin.c_str() + origin.find("rpy=\""), "rpy=\"%lf %lf %lf", &rpy.x(), &rpy.y(), &rpy.z()), 3);
  EXPECT_TRUE(rotationFromRpy(rpy).isApprox(placed.fixture.rotation, 1e-9)) << origin;
  EXPECT_EQ(machineUrdf(vmc, UrdfOptions{}).find("xyz=\"0.1 0.02 0.05\""), std::string::npos);
}
