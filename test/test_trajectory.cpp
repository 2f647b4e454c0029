// Time parameterization: every sample within every joint's velocity and acceleration limits (finite differences),
// the tip on the path within the stated bound, feed moves no faster than the feed at the tip, rapids at the machine's
// rapid rates; the CSV.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "art2part/kinematics/inverse_kinematics.h"
#include "art2part/post/joint_trajectory.h"
#include "art2part/post/machine_program.h"

using namespace art2part;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180;

Machine machineNamed(const std::string& name) {
  return loadMachine(std::string(ART2PART_SOURCE_DIR) + "/config/machines/" + name + ".yaml");
}

JointWaypoint waypointAt(const Vec3& linear, double tilt_deg, double rotary_deg, MoveKind move, double feed = 0) {
  JointWaypoint waypoint;
  waypoint.joints.linear = linear;
  waypoint.joints.tilt = tilt_deg * kDeg;
  waypoint.joints.rotary = rotary_deg * kDeg;
  waypoint.move = move;
  waypoint.feed_mm_min = feed;
  waypoint.tool_length = 60;
  return waypoint;
}

Tool ballTool() {
  Tool tool;
  tool.id = "ball6";
  tool.type = ToolType::Ball;
  tool.diameter = 6;
  tool.corner_radius = 3;
  tool.flute_length = 15;
  tool.shank_diameter = 6;
  tool.stickout = 30;
  tool.holder = {{20, 30}};
  tool.feed_mm_min = 600;
  tool.plunge_mm_min = 200;
  return tool;
}

CutterLocation point(int op, MoveKind move, const Vec3& tip, const Vec3& axis) {
  CutterLocation p;
  p.op = op;
  p.tool = "ball6";
  p.move = move;
  p.tip = tip;
  p.axis = axis.normalized();
  return p;
}

// A 5-axis path: a circle with the axis leaning 30 deg outwards (C one whole turn), then a pass 0.6 deg off the C axis
// (C swings half a turn in a few mm), then a zig-zag at a fixed axis.
Toolpath fiveAxisPath() {
  Toolpath path;
  for (int k = 0; k <= 72; ++k) {
    const double theta = k * 5 * kDeg;
    const Vec3 axis(0.5 * std::cos(theta), 0.5 * std::sin(theta), std::cos(30 * kDeg));
    const Vec3 tip(15 * std::cos(theta), 15 * std::sin(theta), 10);
    if (k == 0) path.push_back(point(0, MoveKind::Rapid, tip + 10 * axis, axis));
    path.push_back(point(0, MoveKind::Feed, tip, axis));
  }
  for (int k = 0; k <= 24; ++k) {
    const double psi = (30 - 2.5 * k) * kDeg;
    const Vec3 axis(0.01, std::sin(psi), std::cos(psi));
    const Vec3 tip(-10 + k * 20.0 / 24, 2, 15);
    if (k == 0) path.push_back(point(1, MoveKind::Rapid, tip + 10 * axis, axis));
    path.push_back(point(1, MoveKind::Feed, tip, axis));
  }
  for (int k = 0; k < 6; ++k) {
    path.push_back(point(2, MoveKind::Feed, Vec3(-10, -10 + 4 * k, 20), Vec3::UnitZ()));
    path.push_back(point(2, MoveKind::Feed, Vec3(10, -10 + 4 * k, 20), Vec3::UnitZ()));
  }
  path.push_back(point(2, MoveKind::Rapid, Vec3(10, 10, 30), Vec3::UnitZ()));
  return path;
}

double velocityLimit(const Joint& joint) { return std::max(joint.max_velocity, joint.rapid_velocity); }

// Finite differences of samples at `rate`: velocities and accelerations within every joint's limits.
void expectWithinLimits(const Machine& machine, const JointTrajectory& trajectory, double rate) {
  const double h = 1 / rate;
  const int count = static_cast<int>(trajectory.duration() * rate);
  std::vector<double> before = trajectory.positionAt(0), here = trajectory.positionAt(h);
  int reported = 0;
  for (int k = 2; k <= count; ++k) {
    const std::vector<double> after = trajectory.positionAt(k * h);
    for (int j = 0; j < machine.jointCount(); ++j) {
      const Joint& joint = machine.joints[j];
      const double velocity = (after[j] - here[j]) / h;
      const double acceleration = (after[j] - 2 * here[j] + before[j]) / (h * h);
      const bool fine = std::abs(velocity) <= velocityLimit(joint) * (1 + 1e-6) + 1e-9 &&
                        std::abs(acceleration) <= joint.max_acceleration * (1 + 1e-6) + 1e-6;
      if (!fine && reported++ < 5)
        ADD_FAILURE() << joint.name << " at t = " << k * h << ": v " << velocity << ", a " << acceleration;
    }
    before = here;
    here = after;
  }
}

// The velocities are continuous from piece to piece (the trajectory is C1).
void expectContinuousVelocity(const JointTrajectory& trajectory) {
  const auto& pieces = trajectory.pieces();
  for (size_t p = 1; p < pieces.size(); ++p) {
    const double t = pieces[p].start;
    const std::vector<double> left = trajectory.velocityAt(t - 1e-12), right = trajectory.velocityAt(t + 1e-12);
    for (size_t j = 0; j < left.size(); ++j) ASSERT_NEAR(left[j], right[j], 1e-6) << "piece " << p << " joint " << j;
  }
}

Vec3 tipAt(const Machine& machine, double tool_length, const std::vector<double>& joints) {
  return toolPoseInTable(machine, tool_length, jointPositionFromVector(machine, joints)).tip;
}

// The tip within the blend tolerance of where the unblended polyline puts it; returns the largest deviation.
double largestTipDeviation(const Machine& machine, const JointTrajectory& trajectory, double rate) {
  double largest = 0;
  for (double t = 0; t <= trajectory.duration(); t += 1 / rate) {
    const PathPoint at = trajectory.pathPointAt(t);
    const double tool = trajectory.waypoints()[at.segment + 1].tool_length;
    const Vec3 tip = tipAt(machine, tool, trajectory.positionAt(t));
    largest = std::max(largest, (tip - tipAt(machine, tool, trajectory.pathPosition(at))).norm());
  }
  return largest;
}

// Seconds the feed moves need at their feed: the tip's chord lengths over the feed.
double feedTime(const Machine& machine, const std::vector<JointWaypoint>& waypoints) {
  double seconds = 0;
  for (size_t i = 1; i < waypoints.size(); ++i) {
    if (waypoints[i].move != MoveKind::Feed) continue;
    const double tool = waypoints[i].tool_length;
    const double length = (toolPoseInTable(machine, tool, waypoints[i].joints).tip -
                           toolPoseInTable(machine, tool, waypoints[i - 1].joints).tip)
                              .norm();
    seconds += 60 * length / waypoints[i].feed_mm_min;
  }
  return seconds;
}

TEST(Trajectory, RapidRunsAtTheRapidRateWithTrapezoidalRamps) {
  Machine machine = machineNamed("trunnion_ac");
  machine.joints[0].rapid_velocity = 15;  // slower than its 20 mm/s feed limit, to tell them apart
  const std::vector<JointWaypoint> waypoints = {waypointAt(Vec3::Zero(), 0, 0, MoveKind::Rapid),
                                                waypointAt(Vec3(150, 0, 0), 0, 0, MoveKind::Rapid)};
  const JointTrajectory trajectory = parameterizeTrajectory(machine, waypoints);
  const double v = 15, a = machine.joints[0].max_acceleration;
  EXPECT_NEAR(trajectory.duration(), 150 / v + v / a, 1e-9);
  EXPECT_NEAR(trajectory.velocityAt(trajectory.duration() / 2)[0], v, 1e-9);
  EXPECT_NEAR(trajectory.accelerationAt(0.01)[0], a, 1e-9);
  EXPECT_NEAR(trajectory.positionAt(trajectory.duration())[0], 150, 1e-9);
  expectWithinLimits(machine, trajectory, 1000);

  // A rapid of X and C together: coordinated, the slower joint (C: 90 deg at 30 deg/s) at its rapid rate.
  const JointTrajectory both = parameterizeTrajectory(
      machine, {waypointAt(Vec3::Zero(), 0, 0, MoveKind::Rapid), waypointAt(Vec3(10, 0, 0), 0, 90, MoveKind::Rapid)});
  const std::vector<double> middle = both.velocityAt(both.duration() / 2);
  EXPECT_NEAR(middle[4], 30 * kDeg, 1e-9);
  EXPECT_NEAR(middle[0] / middle[4], 10 / (90 * kDeg), 1e-9);
  expectWithinLimits(machine, both, 1000);
}

TEST(Trajectory, FeedMovesRunAtTheFeedAtTheTip) {
  const Machine machine = machineNamed("trunnion_ac");
  // 100 mm along X at 600 mm/min = 10 mm/s.
  const JointTrajectory line = parameterizeTrajectory(
      machine, {waypointAt(Vec3::Zero(), 0, 0, MoveKind::Rapid), waypointAt(Vec3(100, 0, 0), 0, 0, MoveKind::Feed, 600)});
  EXPECT_NEAR(line.velocityAt(line.duration() / 2)[0], 10, 1e-9);
  EXPECT_GE(line.duration(), 10.0);
  EXPECT_NEAR(line.duration(), 10 + 10.0 / 300, 1e-9);

  // A turn of C under a tip 30 mm off its axis: the tip's speed on the arc is the feed.
  const Vec3 gauge(0, 30, 60);
  std::vector<JointWaypoint> arc = {waypointAt(gauge, 0, 0, MoveKind::Rapid)};
  for (int k = 1; k <= 36; ++k) {
    const double c = k * 5 * kDeg;
    JointWaypoint waypoint = waypointAt(Vec3(30 * std::sin(c), 30 * std::cos(c), 60), 0, k * 5, MoveKind::Feed, 600);
    arc.push_back(waypoint);
  }
  const JointTrajectory turn = parameterizeTrajectory(machine, arc);
  EXPECT_GE(turn.duration(), feedTime(machine, arc));
  const double t = turn.duration() / 2, dt = 1e-4;
  const Vec3 speed = (tipAt(machine, 60, turn.positionAt(t + dt)) - tipAt(machine, 60, turn.positionAt(t))) / dt;
  EXPECT_LE(speed.norm(), 10 * (1 + 1e-3));
  EXPECT_GT(speed.norm(), 9.9);
  expectWithinLimits(machine, turn, 1000);
}

TEST(Trajectory, FiveAxisProgramRespectsEveryLimitAndFollowsThePath) {
  const Machine machine = machineNamed("trunnion_ac");
  const Toolpath path = fiveAxisPath();
  const MachineProgram program = buildMachineProgram(machine, path, {ballTool()}, "circle", {});
  const std::vector<JointWaypoint> waypoints = programWaypoints(program);
  TrajectoryOptions options;
  const JointTrajectory trajectory = parameterizeTrajectory(machine, waypoints, options);
  EXPECT_GT(trajectory.duration(), 0);
  expectContinuousVelocity(trajectory);
  expectWithinLimits(machine, trajectory, 1000);
  EXPECT_LE(largestTipDeviation(machine, trajectory, 1000), options.blend_tolerance * 1.01);
  EXPECT_GE(trajectory.duration(), feedTime(machine, waypoints));
  double cl_feed_seconds = 0;
  for (size_t i = 1; i < path.size(); ++i)
    if (path[i].move == MoveKind::Feed) cl_feed_seconds += 60 * (path[i].tip - path[i - 1].tip).norm() / 600;
  EXPECT_GE(trajectory.duration(), cl_feed_seconds);

  // Begins and ends at rest on the first and last waypoint; inside the travel throughout.
  const std::vector<double> first = jointVector(machine, waypoints.front().joints);
  const std::vector<double> last = jointVector(machine, waypoints.back().joints);
  for (int j = 0; j < machine.jointCount(); ++j) {
    EXPECT_NEAR(trajectory.positionAt(0)[j], first[j], 1e-9);
    EXPECT_NEAR(trajectory.positionAt(trajectory.duration())[j], last[j], 1e-9);
    EXPECT_NEAR(trajectory.velocityAt(trajectory.duration())[j], 0, 1e-9);
  }
  for (const TrajectorySample& sample : sampleTrajectory(trajectory, 50))
    ASSERT_EQ(limitViolation(machine, jointPositionFromVector(machine, sample.joints), 1e-9), "") << sample.time;
}

TEST(Trajectory, TighterBlendToleranceKeepsTheTipCloser) {
  const Machine machine = machineNamed("trunnion_ac");
  const MachineProgram program = buildMachineProgram(machine, fiveAxisPath(), {ballTool()}, "circle", {});
  TrajectoryOptions loose, tight;
  loose.blend_tolerance = 0.05;
  tight.blend_tolerance = 0.0005;
  const JointTrajectory fast = parameterizeTrajectory(machine, programWaypoints(program), loose);
  const JointTrajectory slow = parameterizeTrajectory(machine, programWaypoints(program), tight);
  EXPECT_LE(largestTipDeviation(machine, fast, 500), loose.blend_tolerance * 1.01);
  EXPECT_LE(largestTipDeviation(machine, slow, 500), tight.blend_tolerance * 1.01);
  EXPECT_GE(slow.duration(), fast.duration());
  expectWithinLimits(machine, slow, 500);
}

TEST(Trajectory, ThreePlusTwoProgramOnTheThreeAxisMill) {
  const Machine machine = machineNamed("mill_3axis");
  Toolpath path;
  path.push_back(point(0, MoveKind::Rapid, Vec3(-10, -10, 10), Vec3::UnitZ()));
  for (int k = 0; k < 6; ++k) {
    path.push_back(point(0, MoveKind::Feed, Vec3(k % 2 ? 10 : -10, -10 + 4 * k, 0), Vec3::UnitZ()));
    path.push_back(point(0, MoveKind::Feed, Vec3(k % 2 ? -10 : 10, -10 + 4 * k, 0), Vec3::UnitZ()));
  }
  const MachineProgram program = buildMachineProgram(machine, path, {ballTool()}, "pocket", {});
  const std::vector<JointWaypoint> waypoints = programWaypoints(program);
  const JointTrajectory trajectory = parameterizeTrajectory(machine, waypoints);
  expectContinuousVelocity(trajectory);
  expectWithinLimits(machine, trajectory, 1000);
  EXPECT_LE(largestTipDeviation(machine, trajectory, 1000), 0.005 * 1.01);
  EXPECT_GE(trajectory.duration(), feedTime(machine, waypoints));
}

TEST(Trajectory, StopsAreReachedAtRest) {
  const Machine machine = machineNamed("trunnion_ac");
  std::vector<JointWaypoint> waypoints = {waypointAt(Vec3::Zero(), 0, 0, MoveKind::Rapid),
                                          waypointAt(Vec3(50, 0, 0), 0, 0, MoveKind::Rapid),
                                          waypointAt(Vec3(100, 0, 0), 0, 0, MoveKind::Rapid)};
  const JointTrajectory through = parameterizeTrajectory(machine, waypoints);
  waypoints[1].stop = true;
  const JointTrajectory stopping = parameterizeTrajectory(machine, waypoints);
  EXPECT_NEAR(through.duration(), 100.0 / 20 + 20.0 / 300, 1e-9) << "collinear: no slowing down";
  EXPECT_NEAR(stopping.duration(), 2 * (50.0 / 20 + 20.0 / 300), 1e-9);
  expectWithinLimits(machine, stopping, 1000);
}

TEST(Trajectory, BadWaypointsAreRefused) {
  const Machine machine = machineNamed("trunnion_ac");
  EXPECT_THROW(parameterizeTrajectory(machine, {}), InputError);
  EXPECT_THROW(parameterizeTrajectory(machine, {waypointAt(Vec3(500, 0, 0), 0, 0, MoveKind::Rapid)}), InputError);
  EXPECT_THROW(parameterizeTrajectory(machine, {waypointAt(Vec3::Zero(), 0, 0, MoveKind::Rapid),
                                                waypointAt(Vec3(5, 0, 0), 0, 0, MoveKind::Feed, 0)}),
               InputError);
  const JointTrajectory still = parameterizeTrajectory(machine, {waypointAt(Vec3(1, 2, 3), 0, 0, MoveKind::Rapid)});
  EXPECT_EQ(still.duration(), 0);
  EXPECT_EQ(still.positionAt(1)[2], 3);
}

TEST(Trajectory, CsvHasTimeThenJointsInMillimetresAndDegrees) {
  const Machine machine = machineNamed("trunnion_ac");
  const JointTrajectory trajectory = parameterizeTrajectory(
      machine, {waypointAt(Vec3::Zero(), 0, 0, MoveKind::Rapid), waypointAt(Vec3(10, 0, 0), -30, 90, MoveKind::Rapid)});
  const std::string file = (std::filesystem::temp_directory_path() / "art2part_test_trajectory.csv").string();
  writeTrajectoryCsv(trajectory, 100, file);
  std::ifstream in(file);
  std::string line, header, last;
  std::getline(in, header);
  int rows = 0;
  while (std::getline(in, line)) last = line, ++rows;
  EXPECT_EQ(header, "time,X,Y,Z,A,C");
  EXPECT_EQ(rows, static_cast<int>(sampleTrajectory(trajectory, 100).size()));
  std::stringstream fields(last);
  std::vector<double> values;
  for (std::string field; std::getline(fields, field, ',');) values.push_back(std::stod(field));
  ASSERT_EQ(values.size(), 6u);
  EXPECT_NEAR(values[0], trajectory.duration(), 1e-6);
  EXPECT_NEAR(values[1], 10, 1e-6);
  EXPECT_NEAR(values[4], -30, 1e-6);
  EXPECT_NEAR(values[5], 90, 1e-6);
}

}  // namespace
