// Cycle time (post/cycle_time.h) on hand-made paths with known answers, the machine file's change times, and the
// plan's figures (plan_figures.h): each operation's removed volume, measured by the simulation, sums to what the
// verification removed; a roughing operation run twice removes nothing the second time and is dropped
// (useless_operations.h).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numeric>
#include <set>
#include <string>

#include "art2part/geometry/part.h"
#include "art2part/kinematics/machine.h"
#include "art2part/plan/plan_figures.h"
#include "art2part/plan/plan_json.h"
#include "art2part/plan/useless_operations.h"
#include "art2part/post/cycle_time.h"
#include "art2part/post/joint_trajectory.h"
#include "test_solids.h"

namespace art2part {
namespace {

const std::string kConfig = std::string(ART2PART_SOURCE_DIR) + "/config";

Tool millWithFeed(const std::string& id, double feed_mm_min, double plunge_mm_min) {
  Tool tool;
  tool.id = id;
  tool.diameter = 10;
  tool.flute_length = 20;
  tool.shank_diameter = 10;
  tool.stickout = 40;
  tool.feed_mm_min = feed_mm_min;
  tool.plunge_mm_min = plunge_mm_min;
  return tool;
}

CutterLocation at(const Vec3& tip, MoveKind move, const std::string& tool = "t1", int op = 0, int setup = 0) {
  CutterLocation c = cutterLocation(setup, tool, move, tip, Vec3::UnitZ());
  c.op = op;
  return c;
}

MotionLimits uniformLimits(double velocity, double acceleration) {
  MotionLimits limits;
  limits.feed_velocity = limits.rapid_velocity = Vec3::Constant(velocity);
  limits.acceleration = Vec3::Constant(acceleration);
  return limits;
}

TEST(CycleTime, LongStraightFeedTakesItsLengthOverTheFeed) {
  const Tool tool = millWithFeed("t1", 1200, 300);  // 20 mm/s
  const Toolpath path = {at(Vec3(0, 0, 0), MoveKind::Rapid), at(Vec3(1000, 0, 0), MoveKind::Feed)};
  const PathTime time = cycleTime(path, {tool}, uniformLimits(400, 3000));
  // The trapezoid: L / v plus the time lost accelerating and stopping, v / a.
  EXPECT_NEAR(time.total.cutting_s, 1000.0 / 20 + 20.0 / 3000, 1e-9);
  EXPECT_NEAR(time.total.cutting_s, 1000.0 / 20, 0.001 * 50);
  EXPECT_DOUBLE_EQ(time.total.cutting_mm, 1000);
  EXPECT_EQ(time.total.rapid_s, 0);
}

TEST(CycleTime, ShortMoveNeverReachesFullSpeed) {
  const Tool tool = millWithFeed("t1", 1200, 300);
  const Toolpath path = {at(Vec3(0, 0, 0), MoveKind::Rapid), at(Vec3(1, 0, 0), MoveKind::Rapid)};
  const PathTime time = cycleTime(path, {tool}, uniformLimits(400, 3000));
  // Accelerate over half, decelerate over the other half: 2 sqrt(L / a); the peak sqrt(a L) = 55 mm/s < 400.
  EXPECT_NEAR(time.total.rapid_s, 2 * std::sqrt(1.0 / 3000), 1e-12);
}

TEST(CycleTime, DiagonalMoveIsHeldByEachAxisLimit) {
  const Tool tool = millWithFeed("t1", 1200, 300);
  MotionLimits limits = uniformLimits(400, 3000);
  limits.rapid_velocity = Vec3(100, 400, 400);  // X is slow: a 45 deg rapid runs at 100 / cos 45 along the path
  const double length = 1000;
  const Toolpath path = {at(Vec3(0, 0, 0), MoveKind::Rapid),
                         at(Vec3(length, length, 0) / std::sqrt(2.0), MoveKind::Rapid)};
  const double speed = 100 * std::sqrt(2.0), accel = 3000 * std::sqrt(2.0);
  EXPECT_NEAR(cycleTime(path, {tool}, limits).total.rapid_s, length / speed + speed / accel, 1e-9);
}

TEST(CycleTime, RightAngleCornerIsSlowerThanAStraightLine) {
  const Tool tool = millWithFeed("t1", 1200, 300);
  const MotionLimits limits = uniformLimits(400, 3000);
  const Toolpath straight = {at(Vec3(0, 0, 0), MoveKind::Rapid), at(Vec3(50, 0, 0), MoveKind::Rapid),
                             at(Vec3(100, 0, 0), MoveKind::Rapid)};
  const Toolpath corner = {at(Vec3(0, 0, 0), MoveKind::Rapid), at(Vec3(50, 0, 0), MoveKind::Rapid),
                           at(Vec3(50, 50, 0), MoveKind::Rapid)};
  const double line = cycleTime(straight, {tool}, limits).total.rapid_s;
  const double turned = cycleTime(corner, {tool}, limits).total.rapid_s;
  // A straight continuation is one move: 100 mm at 400 mm/s from rest to rest.
  EXPECT_NEAR(line, trapezoidSeconds(100, 0, 0, 400, 3000), 1e-9);
  // The corner is passed at the speed a 5 um blend allows (about 9 mm/s): nearly two moves from rest to rest.
  EXPECT_GT(turned, 1.2 * line);
  EXPECT_LE(turned, 2 * trapezoidSeconds(50, 0, 0, 400, 3000) + 1e-9);
  EXPECT_GT(turned, 0.95 * 2 * trapezoidSeconds(50, 0, 0, 400, 3000));
  // A looser blend tolerance passes the corner faster.
  MotionLimits loose = limits;
  loose.blend_tolerance = 0.5;
  EXPECT_LT(cycleTime(corner, {tool}, loose).total.rapid_s, turned);
}

// The model applies the post's trajectory rules in the part frame: on a 3-axis machine whose part frame is its table
// frame the two agree on a path of rapids, feeds and corners.
TEST(CycleTime, AgreesWithThePostsTrajectory) {
  const Machine machine = loadMachine(kConfig + "/machines/vmc_3axis.yaml");
  const Tool tool = millWithFeed("t1", 1200, 300);
  const std::vector<Vec3> tips = {Vec3(0, 0, 100), Vec3(0, 0, 50),   Vec3(100, 0, 50),  Vec3(100, 5, 50),
                                  Vec3(0, 5, 50),   Vec3(0, 10, 50), Vec3(100, 10, 50), Vec3(100, 10, 100)};
  Toolpath path;
  std::vector<JointWaypoint> waypoints;
  for (std::size_t i = 0; i < tips.size(); ++i) {
    const MoveKind move = i < 2 || i + 1 == tips.size() ? MoveKind::Rapid : MoveKind::Feed;
    path.push_back(at(tips[i], move));
    JointWaypoint w;
    w.joints.linear = tips[i];  // tool length 0: the gauge point is the tip
    w.move = move;
    w.feed_mm_min = tool.feed_mm_min;
    waypoints.push_back(w);
  }
  const double trajectory = parameterizeTrajectory(machine, waypoints).duration();
  const double model = cycleTime(path, {tool}, motionLimits(machine)).total.motion_s();
  EXPECT_NEAR(model, trajectory, 0.002 * trajectory);  // 0.01 % on this path
}

TEST(CycleTime, PlungeRunsAtThePlungeFeed) {
  const Tool tool = millWithFeed("t1", 1200, 300);  // plunge 5 mm/s
  const Toolpath path = {at(Vec3(0, 0, 10), MoveKind::Rapid), at(Vec3(0, 0, 0), MoveKind::Feed)};
  EXPECT_NEAR(cycleTime(path, {tool}, uniformLimits(400, 3000)).total.cutting_s, 10.0 / 5 + 5.0 / 3000, 1e-9);
  // Going up the axis, or down a ramp shallower than the plunge angle, is no plunge: the cutting feed (as the post).
  const Toolpath up = {at(Vec3(0, 0, 0), MoveKind::Rapid), at(Vec3(0, 0, 10), MoveKind::Feed)};
  EXPECT_NEAR(cycleTime(up, {tool}, uniformLimits(400, 3000)).total.cutting_s, 10.0 / 20 + 20.0 / 3000, 1e-9);
  const Toolpath ramp = {at(Vec3(0, 0, 10), MoveKind::Rapid), at(Vec3(10 * std::sqrt(3.0), 0, 0), MoveKind::Feed)};
  const double ramp_accel = 3000 / (std::sqrt(3.0) / 2);  // X, the larger component, limits it
  EXPECT_NEAR(cycleTime(ramp, {tool}, uniformLimits(400, 3000)).total.cutting_s, 20.0 / 20 + 20.0 / ramp_accel, 1e-9);
}

TEST(CycleTime, ToolChangeCountedOncePerChange) {
  const std::vector<Tool> tools = {millWithFeed("t1", 1200, 300), millWithFeed("t2", 600, 200)};
  MotionLimits limits = uniformLimits(400, 3000);
  limits.tool_change_s = 7;
  limits.setup_change_s = 300;
  const Toolpath path = {at(Vec3(0, 0, 0), MoveKind::Rapid, "t1", 0), at(Vec3(10, 0, 0), MoveKind::Feed, "t1", 0),
                         at(Vec3(20, 0, 0), MoveKind::Feed, "t1", 0), at(Vec3(0, 0, 0), MoveKind::Rapid, "t2", 1),
                         at(Vec3(0, 10, 0), MoveKind::Feed, "t2", 1), at(Vec3(0, 0, 0), MoveKind::Rapid, "t1", 2, 1),
                         at(Vec3(5, 0, 0), MoveKind::Feed, "t1", 2, 1)};
  const PathTime time = cycleTime(path, tools, limits);
  // The first load, t1 -> t2, t2 -> t1; one change of clamping.
  EXPECT_EQ(time.total.tool_changes, 3);
  EXPECT_DOUBLE_EQ(time.total.tool_change_s, 21);
  EXPECT_EQ(time.total.setup_changes, 1);
  EXPECT_DOUBLE_EQ(time.total.setup_change_s, 300);
  for (int op = 0; op < 3; ++op) EXPECT_EQ(time.by_op.at(op).tool_changes, 1) << op;
  EXPECT_EQ(time.by_op.at(2).setup_changes, 0);  // a setup change belongs to the setup, not to an operation
  EXPECT_EQ(time.by_setup.at(1).setup_changes, 1);
  // Each chain starts at rest where its tool was put: no motion is timed across a change.
  EXPECT_DOUBLE_EQ(time.total.cutting_mm, 20 + 10 + 5);
  EXPECT_DOUBLE_EQ(time.total.rapid_mm, 0);
  EXPECT_NEAR(time.total.total_s(), time.total.cutting_s + 21 + 300, 1e-12);
  double ops = 0;
  for (const auto& [op, t] : time.by_op) ops += t.total_s();
  EXPECT_NEAR(ops + 300, time.total.total_s(), 1e-9);
}

TEST(CycleTime, AxisTurnHeldByTheRotaryLimits) {
  const Tool tool = millWithFeed("t1", 1200, 300);
  MotionLimits limits = uniformLimits(400, 3000);
  limits.rotary_velocity = 1.0;  // rad/s
  limits.rotary_acceleration = 4.0;
  const double quarter = std::acos(0.0);
  Toolpath path = {at(Vec3(0, 0, 0), MoveKind::Rapid), at(Vec3(0, 0, 0), MoveKind::Rapid)};
  path[1].axis = Vec3::UnitX();
  EXPECT_NEAR(cycleTime(path, {tool}, limits).total.rapid_s, trapezoidSeconds(quarter, 0, 0, 1.0, 4.0), 1e-12);
  // Turning while it moves 1 mm: the rotary joints, not the slides, set the pace.
  path[1].tip = Vec3(1, 0, 0);
  EXPECT_GT(cycleTime(path, {tool}, limits).total.rapid_s, quarter / 1.0);
  // Without rotary joints the turn costs nothing (3-axis model).
  EXPECT_NEAR(cycleTime(path, {tool}, uniformLimits(400, 3000)).total.rapid_s, 2 * std::sqrt(1.0 / 3000), 1e-12);
}

TEST(CycleTime, BadInputIsRefused) {
  const Toolpath path = {at(Vec3(0, 0, 0), MoveKind::Rapid), at(Vec3(1, 0, 0), MoveKind::Feed)};
  EXPECT_THROW(cycleTime(path, {millWithFeed("other", 1200, 300)}, MotionLimits{}), InputError);
  EXPECT_THROW(cycleTime(path, {millWithFeed("t1", 0, 300)}, MotionLimits{}), InputError);
  MotionLimits bad;
  bad.acceleration.x() = 0;
  EXPECT_THROW(cycleTime(path, {millWithFeed("t1", 1200, 300)}, bad), InputError);
}

TEST(CycleTime, MachineFileGivesItsLimitsAndChangeTimes) {
  const Machine vmc = loadMachine(kConfig + "/machines/vmc_3axis.yaml");
  const MotionLimits limits = motionLimits(vmc);
  EXPECT_DOUBLE_EQ(limits.rapid_velocity.x(), vmc.joints[0].rapid_velocity);
  EXPECT_DOUBLE_EQ(limits.acceleration.z(), vmc.joints[2].max_acceleration);
  EXPECT_DOUBLE_EQ(limits.tool_change_s, vmc.tool_change_s);
  EXPECT_EQ(limits.rotary_velocity, 0);
  const Machine five = loadMachine(kConfig + "/machines/trunnion_5axis.yaml");
  EXPECT_GT(motionLimits(five).rotary_velocity, 0);
  // Left out: the defaults; given: read; negative: refused naming the key.
  const std::string base = "name: m\nkinematics: trivkins\njoints:\n"
                           "  - {name: X, min: -1, max: 1, max_velocity: 1, max_acceleration: 1}\n"
                           "  - {name: Y, min: -1, max: 1, max_velocity: 1, max_acceleration: 1}\n"
                           "  - {name: Z, min: -1, max: 1, max_velocity: 1, max_acceleration: 1}\n";
  EXPECT_DOUBLE_EQ(parseMachine(base, "m").tool_change_s, kDefaultToolChangeSeconds);
  EXPECT_DOUBLE_EQ(parseMachine(base + "setup_change_s: 120\n", "m").setup_change_s, 120);
  try {
    parseMachine(base + "tool_change_s: -3\n", "m");
    FAIL() << "a negative tool change time was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("tool_change_s"), std::string::npos) << e.what();
  }
  // No machine: the documented default.
  EXPECT_DOUBLE_EQ(motionLimits(Machine{}).rapid_velocity.x(), MotionLimits{}.rapid_velocity.x());
}

TEST(PlanFigures, RemovedVolumePerOperationSumsToTheSimulation) {
  const Part part = test::stepPart(test::pocketedBlock(Vec3(0, 0, 0), Vec3(60, 40, 20), 30, 20, 8, 4), "pocket");
  const ToolLibrary library = loadToolLibrary(kConfig + "/tools.yaml");
  PlanOptions options;
  options.visibility.level = 2;
  const PlanResult plan = planPart(part, library, options);
  ASSERT_TRUE(plan.verified);
  ASSERT_FALSE(plan.operations.empty());
  double sum = 0;
  int gouges = 0, collisions = 0;
  for (const auto& [op, check] : plan.verification.by_op) {
    EXPECT_GE(check.swept.removed_mm3, 0) << "op " << op;
    sum += check.swept.removed_mm3;
    gouges += check.gouges;
    collisions += check.collisions;
  }
  const double removed = plan.verification.removed_volume_mm3;
  ASSERT_GT(removed, 0);
  EXPECT_NEAR(sum, removed, 1e-6 * removed);
  EXPECT_EQ(gouges, plan.verification.gouges);
  EXPECT_EQ(collisions, plan.verification.collisions);
  EXPECT_EQ(plan.verification.by_op.size(), plan.operations.size()) << "every operation is checked";

  const Machine machine = loadMachine(kConfig + "/machines/vmc_3axis.yaml");
  const PlanFigures figures = planFigures(plan, machine);
  ASSERT_EQ(figures.operations.size(), plan.operations.size());
  EXPECT_GT(figures.operations.front().removed_mm3, 0);  // the first roughing clears the most
  EXPECT_GT(figures.roughing_bound_s, 0);

  // Useless: a roughing operation under the share of the roughing's volume, with its reason; finishing never.
  for (const OperationFigures& f : figures.operations) {
    const bool under = f.removed_mm3 < kUselessRemovalShare * figures.roughing_removed_mm3;
    EXPECT_EQ(f.useless, !f.finishing && under) << "operation " << f.index;
    EXPECT_EQ(f.useless_reason.empty(), !f.useless) << "operation " << f.index;
  }

  const nlohmann::json j = planJson(part, plan, machine);
  double ops = 0;
  for (const nlohmann::json& op : j["operations"]) {
    for (const char* key : {"removed_mm3", "axial_depth_mm", "deepest_level_cut_mm", "gouges", "collisions"})
      ASSERT_TRUE(op.contains(key)) << key << " in " << op.dump();
    EXPECT_GT(op["time_s"].get<double>(), 0);
    EXPECT_NEAR(op["time_s"].get<double>(), op["time"]["cutting_s"].get<double>() + op["time"]["rapid_s"].get<double>() +
                                                 op["time"]["tool_change_s"].get<double>(), 1e-9);
    ops += op["time_s"].get<double>();
  }
  const nlohmann::json& total = j["machining_time"];
  EXPECT_NEAR(total["total_s"].get<double>(), ops + total["setup_change_s"].get<double>(), 1e-6);
  std::set<int> setups_cut;
  for (const CutterLocation& c : plan.toolpath) setups_cut.insert(c.setup);
  EXPECT_EQ(total["setup_changes"].get<int>(), static_cast<int>(setups_cut.size()) - 1);  // the path runs setup by setup
  EXPECT_EQ(total["machine"], "vmc_3axis");
  double setups = 0;
  for (const nlohmann::json& s : j["setups"]) setups += s["time"]["total_s"].get<double>();
  EXPECT_NEAR(setups, total["total_s"].get<double>(), 1e-6);
}

// A verification with no earlier sweep to resume from, keeping no checkpoint, never stopped.
const std::vector<SweepCheckpoint> kNoSweeps;
const TrialSweep kWholeSweep{kNoSweeps, 0, {}};

// The pocketed block planned at visibility level 2 without finishing, its useless roughing left in (drop_useless
// false): the plan the useless-operation tests change and verify again.
struct PocketPlan {
  Part part = test::stepPart(test::pocketedBlock(Vec3(0, 0, 0), Vec3(60, 40, 20), 30, 20, 8, 4), "pocket");
  ToolLibrary library = loadToolLibrary(kConfig + "/tools.yaml");
  PlanOptions options;
  PlanResult plan;
};

PocketPlan pocketPlan() {
  PocketPlan pocket;
  pocket.options.visibility.level = 2;
  pocket.options.finish = false;
  pocket.options.drop_useless = false;
  pocket.plan = planPart(pocket.part, pocket.library, pocket.options);
  return pocket;
}

// The first roughing operation run again right after itself removes nothing the second time: the simulation finds it
// useless, and the plan without it is the plan as planned, as clean. A verification finding more without it puts the
// plan back exactly.
TEST(UselessOperations, ARoughingRunTwiceIsDroppedWhenThePlanWithoutItIsAsClean) {
  PocketPlan pocket = pocketPlan();
  const Part& part = pocket.part;
  PlanResult& plan = pocket.plan;
  ASSERT_TRUE(plan.verified);
  ASSERT_FALSE(plan.roughing.operations.empty());
  EXPECT_EQ(plan.useless.found, 0) << "drop_useless false: nothing looked at";
  const std::vector<int> useless_as_planned = uselessRoughing(plan);
  const VerificationReport as_planned = plan.verification;
  const Toolpath original = plan.toolpath;

  const auto verifier = [&](const PlanResult& p, VerificationState& state, const TrialSweep&) {
    return verifyToolpath(part.mesh, part.triangle_face, p.toolpath, p.tools,
                          planVerifyOptions(part, p, pocket.library, pocket.options), &state);
  };
  plan.roughing.operations.insert(plan.roughing.operations.begin() + 1, plan.roughing.operations.front());
  combinePlan(plan, part, pocket.library, pocket.options);
  plan.verification = verifier(plan, plan.simulation, kWholeSweep);
  EXPECT_NEAR(plan.verification.leftover_volume_mm3, as_planned.leftover_volume_mm3, 1e-6 * as_planned.stock_volume_mm3);
  const std::vector<int> useless = uselessRoughing(plan);
  ASSERT_NE(std::find(useless.begin(), useless.end(), 1), useless.end()) << "the second run is useless";
  EXPECT_EQ(std::find(useless.begin(), useless.end(), 0), useless.end()) << "the first run is not";

  PlanResult refused = plan;
  const auto one_more_collision = [&](const PlanResult& p, VerificationState& state, const TrialSweep& trial) {
    VerificationReport report = verifier(p, state, trial);
    ++report.collisions;
    return report;
  };
  dropUselessRoughing(refused, part, pocket.library, pocket.options, one_more_collision);
  EXPECT_EQ(refused.useless.found, static_cast<int>(useless.size()));
  EXPECT_FALSE(refused.useless.dropped);
  EXPECT_NE(refused.useless.kept_why.find("collisions"), std::string::npos) << refused.useless.kept_why;
  ASSERT_EQ(refused.toolpath.size(), plan.toolpath.size()) << "put back as it was";
  for (std::size_t i = 0; i < plan.toolpath.size(); ++i) {
    ASSERT_EQ(refused.toolpath[i].tip, plan.toolpath[i].tip) << "row " << i;
    ASSERT_EQ(refused.toolpath[i].op, plan.toolpath[i].op) << "row " << i;
  }
  EXPECT_EQ(refused.operations.size(), plan.operations.size());
  EXPECT_EQ(refused.roughing.dropped.size(), plan.roughing.dropped.size());
  EXPECT_EQ(refused.verification.leftover_volume_mm3, plan.verification.leftover_volume_mm3);
  EXPECT_EQ(refused.verification.collisions, plan.verification.collisions);

  const std::size_t dropped_before = plan.roughing.dropped.size();
  dropUselessRoughing(plan, part, pocket.library, pocket.options, verifier);
  ASSERT_TRUE(plan.useless.dropped) << plan.useless.kept_why;
  EXPECT_TRUE(plan.useless.kept_why.empty());
  ASSERT_EQ(plan.roughing.dropped.size(), dropped_before + useless.size());
  const double roughing_removed = as_planned.removed_volume_mm3;
  for (std::size_t i = dropped_before; i < plan.roughing.dropped.size(); ++i) {
    const DroppedOperation& d = plan.roughing.dropped[i];
    EXPECT_TRUE(d.simulated);
    EXPECT_LT(d.removed_mm3, kUselessRemovalShare * roughing_removed);
    EXPECT_GT(d.seconds, 0);
    EXPECT_FALSE(d.reason.empty());
  }
  // Judged by the simulation of the plan as it now is: as clean as the plan as planned, and with nothing more left than
  // what the dropped operations removed.
  EXPECT_LE(plan.verification.gouges, as_planned.gouges);
  EXPECT_LE(plan.verification.collisions, as_planned.collisions);
  double dropped_removed = 0;
  for (std::size_t i = dropped_before; i < plan.roughing.dropped.size(); ++i)
    dropped_removed += plan.roughing.dropped[i].removed_mm3;
  EXPECT_LE(plan.verification.leftover_volume_mm3,
            as_planned.leftover_volume_mm3 + dropped_removed + 1e-6 * as_planned.stock_volume_mm3);
  EXPECT_TRUE(uselessRoughing(plan).size() <= useless_as_planned.size());
  if (useless_as_planned.empty()) {  // then only the second run went: the plan as planned, row for row
    ASSERT_EQ(plan.toolpath.size(), original.size());
    for (std::size_t i = 0; i < original.size(); ++i) ASSERT_EQ(plan.toolpath[i].tip, original[i].tip) << "row " << i;
    EXPECT_EQ(plan.verification.leftover_volume_mm3, as_planned.leftover_volume_mm3);
  }
  const nlohmann::json j = planJson(part, plan, loadMachine(kConfig + "/machines/vmc_3axis.yaml"));
  ASSERT_TRUE(j.contains("useless_roughing"));
  EXPECT_TRUE(j["useless_roughing"]["dropped"].get<bool>());
  EXPECT_TRUE(j["dropped_operations"].back().contains("removed_mm3"));
  EXPECT_EQ(j["useless_roughing"]["kept"].get<int>(), 0);
}

// The pocket plan (two setups) with its first roughing operation and its last each run twice, verified again by a
// verifier that adds a collision to the first setup (and the last, with `last_finds_too`) while the first setup's
// second run is gone (the run the first setup's rest relies on): both second runs are useless.
class UselessRunsInTwoSetups : public ::testing::Test {
 protected:
  static long roughingIn(const PlanResult& p, int setup) {
    return std::count_if(p.roughing.operations.begin(), p.roughing.operations.end(),
                         [&](const RoughingOperation& op) { return op.setup == setup; });
  }
  void runTwice(bool last_finds_too) {
    PlanResult& plan = pocket.plan;
    ASSERT_TRUE(plan.verified);
    std::vector<RoughingOperation>& ops = plan.roughing.operations;
    ASSERT_GE(ops.size(), 2u);
    first_setup = ops.front().setup, last_setup = ops.back().setup;
    ASSERT_NE(first_setup, last_setup) << "the part needs two setups for this test";
    ops.push_back(ops.back());
    ops.insert(ops.begin() + 1, ops.front());
    first_setup_ops = roughingIn(plan, first_setup), last_setup_ops = roughingIn(plan, last_setup);
    finding_setups = {first_setup};
    if (last_finds_too) finding_setups.push_back(last_setup);
    combinePlan(plan, pocket.part, pocket.library, pocket.options);
    plan.verification = verifier(plan, plan.simulation, kWholeSweep);
    ASSERT_EQ(plan.verification.collisions, 0);
    const std::vector<int> useless = uselessRoughing(plan);
    ASSERT_NE(std::find(useless.begin(), useless.end(), 1), useless.end());
    ASSERT_NE(std::find(useless.begin(), useless.end(), static_cast<int>(ops.size()) - 1), useless.end());
    verifications = 0;
  }
  // A collision added to the first operation of each of finding_setups whose rows lie before `end_row`, while the
  // first setup's second run is gone.
  void addCollisions(const PlanResult& p, int end_row, VerificationReport& report) const {
    if (roughingIn(p, first_setup) >= first_setup_ops) return;
    for (const int setup : finding_setups)
      for (const PlanOperation& op : p.operations)
        if (op.setup == setup) {
          if (static_cast<int>(op.first_point) < end_row) {
            ++report.by_op[op.index].collisions;
            ++report.collisions;
          }
          break;
        }
  }
  // The verifier of the tests: the simulation with those collisions added. `gated`: it takes the trial's checkpoints
  // and gate (as planPart's does: the gate sees the added collisions too); else it sweeps the whole path (as the cell's
  // service does). rows_swept adds up the rows each verification swept.
  PlanVerifier verifierOf(bool gated) {
    return [this, gated](const PlanResult& p, VerificationState& state, const TrialSweep& trial) {
      ++verifications;
      VerifyOptions options = planVerifyOptions(pocket.part, p, pocket.library, pocket.options);
      if (gated) {
        options.checkpoints = trial.checkpoints;
        options.keep_sweeping = [&](int row, const VerificationReport& so_far) {
          VerificationReport seen = so_far;
          addCollisions(p, row, seen);
          return trial.keep_sweeping(row, seen);
        };
      }
      VerificationReport report = verifyToolpath(pocket.part.mesh, pocket.part.triangle_face, p.toolpath, p.tools,
                                                 options, &state, {}, gated ? trial.resume_from : kNoSweeps);
      const int end_row = report.stopped_at_row > 0 ? report.stopped_at_row : static_cast<int>(p.toolpath.size());
      rows_swept += end_row - report.resumed_at_row;
      addCollisions(p, end_row, report);
      return report;
    };
  }
  // The first setup's runs all kept, the last setup's second one left out, the plan as kept verified clean.
  void expectOnlyTheLastSetupsRunLeftOut(std::size_t dropped_before) {
    const PlanResult& plan = pocket.plan;
    EXPECT_TRUE(plan.useless.dropped) << plan.useless.kept_why;
    EXPECT_GE(plan.useless.kept, 1);
    EXPECT_LT(plan.useless.kept, plan.useless.found);
    EXPECT_NE(plan.useless.kept_why.find("setups " + std::to_string(first_setup) + " kept: without all of them"),
              std::string::npos)
        << plan.useless.kept_why;
    EXPECT_EQ(roughingIn(plan, first_setup), first_setup_ops);
    EXPECT_LT(roughingIn(plan, last_setup), last_setup_ops);
    ASSERT_GT(plan.roughing.dropped.size(), dropped_before);
    for (std::size_t i = dropped_before; i < plan.roughing.dropped.size(); ++i)
      EXPECT_NE(plan.roughing.dropped[i].setup, first_setup);
    EXPECT_EQ(plan.verification.collisions, 0);  // the verification of the plan as kept
  }

  PocketPlan pocket = pocketPlan();
  int first_setup = -1, last_setup = -1;
  long first_setup_ops = 0, last_setup_ops = 0;
  std::vector<int> finding_setups;
  int verifications = 0;
  long rows_swept = 0;
  PlanVerifier verifier = verifierOf(false);
};

// When the simulation without both second runs finds a collision in the first setup only, that setup's useless run
// is put back and the other setup's left out.
TEST_F(UselessRunsInTwoSetups, TheUselessOfASetupWithFindingsStayTheOthersGo) {
  ASSERT_NO_FATAL_FAILURE(runTwice(false));
  const std::size_t dropped_before = pocket.plan.roughing.dropped.size();
  dropUselessRoughing(pocket.plan, pocket.part, pocket.library, pocket.options, verifier);
  expectOnlyTheLastSetupsRunLeftOut(dropped_before);
}

// The first setup's missing run shows in the last setup too (the stock it leaves reaches the later setup's cuts):
// without both runs, both setups have findings. Putting back the earliest setup's alone is tried first: clean, so the
// last setup's run goes. Putting back every setup with findings at once kept both runs.
TEST_F(UselessRunsInTwoSetups, AnEarlierSetupsDropIsPutBackBeforeALaterSetupsFindingsKeepItsOwn) {
  ASSERT_NO_FATAL_FAILURE(runTwice(true));
  const std::size_t dropped_before = pocket.plan.roughing.dropped.size();
  dropUselessRoughing(pocket.plan, pocket.part, pocket.library, pocket.options, verifier);
  EXPECT_EQ(verifications, 2) << "without all; then with the first setup's put back";
  expectOnlyTheLastSetupsRunLeftOut(dropped_before);
}

// The same rounds with the trials' checkpoints and gate, as planPart verifies: the first round stops where the first
// setup finds more, the second resumes where its rows part from the plan as planned. The decisions are those of whole
// sweeps (the cell's), for about half the rows: the gated rounds sweep each setup once, the whole ones both twice.
TEST_F(UselessRunsInTwoSetups, RoundsStoppedAtTheFirstSetupThatFindsMoreDecideAsWholeSweeps) {
  ASSERT_NO_FATAL_FAILURE(runTwice(true));
  PlanResult whole = pocket.plan;
  dropUselessRoughing(whole, pocket.part, pocket.library, pocket.options, verifier);
  const long whole_rows = rows_swept;
  EXPECT_EQ(verifications, 2);

  // The plan as planned verified again keeping its checkpoints, as planPart's first verification does.
  PlanResult& gated = pocket.plan;
  VerifyOptions first = planVerifyOptions(pocket.part, gated, pocket.library, pocket.options);
  first.checkpoints = pocket.options.resume_checkpoints;
  gated.verification = verifyToolpath(pocket.part.mesh, pocket.part.triangle_face, gated.toolpath, gated.tools, first,
                                      &gated.simulation);
  ASSERT_FALSE(gated.simulation.checkpoints.empty());
  verifications = 0;
  rows_swept = 0;
  std::vector<VerificationReport> rounds;
  const std::size_t dropped_before = gated.roughing.dropped.size();
  const PlanVerifier gated_verifier = verifierOf(true);
  dropUselessRoughing(gated, pocket.part, pocket.library, pocket.options,
                      [&](const PlanResult& p, VerificationState& state, const TrialSweep& trial) {
                        rounds.push_back(gated_verifier(p, state, trial));
                        return rounds.back();
                      });
  ASSERT_EQ(rounds.size(), 2u);
  EXPECT_GT(rounds[0].stopped_at_row, 0) << "the first round stops after the first setup";
  EXPECT_FALSE(rounds[0].passed());
  EXPECT_GT(rounds[1].resumed_at_row, 0) << "the second resumes at the last setup";
  EXPECT_EQ(rounds[1].stopped_at_row, 0);
  EXPECT_LT(rows_swept, whole_rows * 3 / 4);

  EXPECT_EQ(gated.useless.dropped, whole.useless.dropped);
  EXPECT_EQ(gated.useless.kept, whole.useless.kept);
  EXPECT_EQ(gated.useless.kept_why, whole.useless.kept_why);
  ASSERT_EQ(gated.toolpath.size(), whole.toolpath.size());
  for (std::size_t i = 0; i < whole.toolpath.size(); ++i) ASSERT_EQ(gated.toolpath[i].tip, whole.toolpath[i].tip);
  EXPECT_EQ(gated.verification.collisions, whole.verification.collisions);
  EXPECT_EQ(gated.verification.gouges, whole.verification.gouges);
  EXPECT_DOUBLE_EQ(gated.verification.leftover_volume_mm3, whole.verification.leftover_volume_mm3);
  EXPECT_DOUBLE_EQ(gated.verification.removed_volume_mm3, whole.verification.removed_volume_mm3);
  expectOnlyTheLastSetupsRunLeftOut(dropped_before);
}

// featuretype's finishing, setup by setup: each run of one tool's milling operations after a tool change is in the
// order with the least travel across (every order tried; the ops' clearance points compared in the plane, as they
// stand at one height), at least one crossing between two of them stays under the clearance plane, and the
// simulation of the whole plan finds no gouge and no collision.
TEST(FinishingOrder, OneToolsOperationsTravelLeastAndCrossLowWithoutCollision) {
  const Part part = loadPart(std::string(ART2PART_SHARED_PARTS) + "/featuretype.STEP");
  const PlanResult plan = planPart(part, loadToolLibrary(kConfig + "/tools.yaml"), PlanOptions{});
  ASSERT_TRUE(plan.verified);
  EXPECT_EQ(plan.verification.gouges, 0);
  EXPECT_EQ(plan.verification.collisions, 0);
  auto flat = [](const Vec3& p) { return Eigen::Vector2d(p.x(), p.y()); };
  int runs = 0, low = 0;
  const std::vector<PlanOperation>& ops = plan.operations;
  for (std::size_t i = 0; i < ops.size();) {
    auto milling = [&](std::size_t k) { return ops[k].finishing && ops[k].kind != "drill" && ops[k].kind != "helix"; };
    std::size_t end = i + 1;
    while (end < ops.size() && milling(i) && milling(end) && ops[end].tool == ops[i].tool &&
           ops[end].setup == ops[i].setup)
      ++end;
    const bool after_change = i == 0 || ops[i - 1].tool != ops[i].tool || ops[i - 1].setup != ops[i].setup;
    if (end - i >= 2 && end - i <= 7 && after_change) {
      ++runs;
      std::vector<Eigen::Vector2d> entry, exit;
      for (std::size_t k = i; k < end; ++k) {
        entry.push_back(flat(plan.toolpath[ops[k].first_point].tip));
        exit.push_back(flat(plan.toolpath[ops[k].first_point + ops[k].points - 1].tip));
      }
      auto travel = [&](const std::vector<std::size_t>& order) {
        double sum = 0;
        for (std::size_t k = 1; k < order.size(); ++k) sum += (exit[order[k - 1]] - entry[order[k]]).norm();
        return sum;
      };
      std::vector<std::size_t> order(end - i);
      std::iota(order.begin(), order.end(), std::size_t{0});
      const double planned = travel(order);
      double least = std::numeric_limits<double>::infinity();
      do least = std::min(least, travel(order));
      while (std::next_permutation(order.begin(), order.end()));
      EXPECT_NEAR(planned, least, 1e-3) << "operations " << ops[i].index << " to " << ops[end - 1].index;
    }
    // Under its own clearance plane: the operation's highest point (a surface operation's is under the setup's).
    auto highest = [&](std::size_t k) {
      double top = -std::numeric_limits<double>::infinity();
      for (std::size_t r = 0; r < ops[k].points; ++r)
        top = std::max(top, plan.toolpath[ops[k].first_point + r].tip.z());
      return top;
    };
    for (std::size_t k = i + 1; k < end; ++k) {
      const CutterLocation& left = plan.toolpath[ops[k - 1].first_point + ops[k - 1].points - 1];
      const CutterLocation& entered = plan.toolpath[ops[k].first_point];
      if (left.axis.z() > 1 - 1e-9 && left.tip.z() < highest(k - 1) - 1 && entered.tip.z() < highest(k) - 1) ++low;
    }
    i = end;
  }
  std::printf("%d runs of one tool's operations tried every order, %d crossings between them kept low\n", runs, low);
  EXPECT_GE(runs, 1);
  EXPECT_GE(low, 1);
}

}  // namespace
}  // namespace art2part
