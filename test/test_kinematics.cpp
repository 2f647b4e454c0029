// Kinematics: machine files, forward and inverse kinematics, branches, C unwinding, the singularity, and the
// table-table models checked against numbers from LinuxCNC's own formulas.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "art2part/kinematics/inverse_kinematics.h"
#include "art2part/kinematics/machine.h"

using namespace art2part;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180;

std::string machinesDir() { return std::string(ART2PART_SOURCE_DIR) + "/config/machines"; }
Machine machineNamed(const std::string& name) { return loadMachine(machinesDir() + "/" + name + ".yaml"); }

JointPosition jointsAt(double x, double y, double z, double tilt_deg = 0, double rotary_deg = 0) {
  JointPosition joints;
  joints.linear = Vec3(x, y, z);
  joints.tilt = tilt_deg * kDeg;
  joints.rotary = rotary_deg * kDeg;
  return joints;
}

// Angle difference folded into (-pi, pi].
double wrapped(double angle) { return std::remainder(angle, 2 * kPi); }

// Uniform inside every joint's travel; C (200 turns of travel) within two turns of 0.
JointPosition randomJoints(const Machine& machine, std::mt19937& rng) {
  std::vector<double> values;
  for (const Joint& joint : machine.joints) {
    double lo = joint.min, hi = joint.max;
    if (joint.rotary) lo = std::max(lo, -4 * kPi), hi = std::min(hi, 4 * kPi);
    values.push_back(std::uniform_real_distribution<double>(lo, hi)(rng));
  }
  return jointPositionFromVector(machine, values);
}

// A part clamped skew, off the table's origin, and a tool of some length: nothing lines up by accident.
Placement skewPlacement(const Machine& machine) {
  Placement placement;
  placement.fixture.rotation = rotationFromRpy(Vec3(10, -20, 35) * kDeg);
  placement.fixture.origin = machine.kind == MachineKind::HeadBC ? Vec3(3, -4, -395) : Vec3(3, -4, 5);
  placement.tool_length = 42.5;
  return placement;
}

class EachMachine : public ::testing::TestWithParam<std::string> {};

INSTANTIATE_TEST_SUITE_P(Machines, EachMachine,
                         ::testing::Values("trunnion_ac", "trunnion_5axis", "trunnion_bc", "head_head_bc", "mill_3axis"));

class EachFiveAxisMachine : public ::testing::TestWithParam<std::string> {};

INSTANTIATE_TEST_SUITE_P(Machines, EachFiveAxisMachine,
                         ::testing::Values("trunnion_ac", "trunnion_bc", "head_head_bc"));

}  // namespace

// ---- machine files ------------------------------------------------------------------------------------------------

TEST(MachineFiles, EveryFileInConfigMachinesLoads) {
  int count = 0;
  for (const auto& entry : std::filesystem::directory_iterator(machinesDir())) {
    if (entry.path().extension() != ".yaml") continue;
    SCOPED_TRACE(entry.path().string());
    const Machine machine = loadMachine(entry.path().string());
    EXPECT_FALSE(machine.name.empty());
    EXPECT_EQ(machine.jointCount(), machine.fiveAxis() ? 5 : 3);
    for (const Joint& joint : machine.joints) {
      EXPECT_LT(joint.min, joint.max) << joint.name;
      EXPECT_GT(joint.max_velocity, 0) << joint.name;
      EXPECT_GT(joint.max_acceleration, 0) << joint.name;
      EXPECT_GT(joint.rapid_velocity, 0) << joint.name;
    }
    ++count;
  }
  EXPECT_GE(count, 4);
}

TEST(MachineFiles, TrunnionAcIsLinuxCncsXyzacTrtSim) {
  const Machine machine = machineNamed("trunnion_ac");
  EXPECT_EQ(machine.kind, MachineKind::TableTiltAC);
  EXPECT_EQ(kinematicsModuleName(machine.kind), "xyzac-trt-kins");
  EXPECT_EQ(machine.geometry.rot_point, Vec3(0, 0, 0));
  EXPECT_EQ(machine.geometry.offset, Vec3(0, 20, 10));  // sets :y-offset 20, sets :z-offset 10 in xyzac-trt.ini
  ASSERT_EQ(machine.jointCount(), 5);
  const char* letters[] = {"X", "Y", "Z", "A", "C"};
  for (int j = 0; j < 5; ++j) EXPECT_EQ(machine.joints[j].name, letters[j]);
  EXPECT_NEAR(machine.tiltJoint().min, -100 * kDeg, 1e-15);  // [JOINT_3] MIN_LIMIT = -100, MAX_LIMIT = 50
  EXPECT_NEAR(machine.tiltJoint().max, 50 * kDeg, 1e-15);
  EXPECT_NEAR(machine.tiltJoint().max_velocity, 30 * kDeg, 1e-15);
  EXPECT_NEAR(machine.joints[0].max_acceleration, 300, 0);
  EXPECT_TRUE(machine.tiltJoint().rotary);
  EXPECT_FALSE(machine.joints[2].rotary);
}

TEST(MachineFiles, OtherKinds) {
  EXPECT_EQ(machineNamed("trunnion_bc").kind, MachineKind::TableTiltBC);
  EXPECT_EQ(machineNamed("trunnion_bc").geometry.offset, Vec3(-20, 0, -15));
  const Machine head = machineNamed("head_head_bc");
  EXPECT_EQ(head.kind, MachineKind::HeadBC);
  EXPECT_EQ(head.geometry.pivot_length, 250);
  EXPECT_EQ(head.tiltJoint().name, "B");
  const Machine mill = machineNamed("mill_3axis");
  EXPECT_EQ(mill.kind, MachineKind::Mill3Axis);
  EXPECT_FALSE(mill.fiveAxis());
}

namespace {

const char* kGoodMachine = R"(name: test
kinematics: xyzac-trt-kins
geometry: {x-rot-point: 0, y-rot-point: 0, z-rot-point: 0, y-offset: 20, z-offset: 10}
joints:
  - {name: X, min: -200, max: 200, max_velocity: 20, max_acceleration: 300}
  - {name: Y, min: -100, max: 100, max_velocity: 20, max_acceleration: 300}
  - {name: Z, min: -120, max: 120, max_velocity: 20, max_acceleration: 300}
  - {name: A, min: -100, max: 50, max_velocity: 30, max_acceleration: 300}
  - {name: C, min: -36000, max: 36000, max_velocity: 30, max_acceleration: 300}
fixture:
  default: {origin: [0, 0, 0], rpy: [0, 0, 0]}
  setups:
    2: {origin: [1, 2, 3], rpy: [0, 0, 90]}
)";

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

// The error message of parsing `text`, or "" when it parses.
std::string parseError(const std::string& text) {
  try {
    parseMachine(text, "bad.yaml");
  } catch (const InputError& error) {
    return error.what();
  }
  return "";
}

}  // namespace

TEST(MachineFiles, GoodTextParsesWithSetupFixture) {
  const Machine machine = parseMachine(kGoodMachine, "good.yaml");
  EXPECT_EQ(machine.setup_fixtures.size(), 1u);
  const FixturePose& fixture = fixtureForSetup(machine, 2);
  EXPECT_TRUE(fixture.origin.isApprox(Vec3(1, 2, 3)));
  EXPECT_LT((fixture.directionToTable(Vec3::UnitX()) - Vec3::UnitY()).norm(), 1e-15);  // yaw 90 deg
  EXPECT_EQ(&fixtureForSetup(machine, 0), &machine.default_fixture);
  EXPECT_NEAR(machine.rotaryJoint().rapid_velocity, 30 * kDeg, 1e-15);  // defaults to max_velocity
  EXPECT_EQ(placementFor(machine, 2, 7).tool_length, 7);
}

TEST(MachineFiles, BadFilesNameTheKey) {
  struct Case {
    std::string text;
    std::vector<std::string> says;
  };
  const std::vector<Case> cases = {
      {replaced(kGoodMachine, "min: -100, max: 50,", "min: -100,"), {"bad.yaml:", "joints[3].max", "missing key"}},
      {replaced(kGoodMachine, "max: 50,", "max: fifty,"), {"bad.yaml:", "joints[3].max", "expected a number", "fifty"}},
      {replaced(kGoodMachine, "min: -100, max: 50,", "min: 50, max: -100,"), {"joints[3].min", "not below max"}},
      {replaced(kGoodMachine, "{name: A,", "{name: B,"), {"joints[3].name", "expected joint A"}},
      {replaced(kGoodMachine, "xyzac-trt-kins", "xyzac-kins"), {"kinematics", "unknown kinematics"}},
      {replaced(kGoodMachine, "y-offset: 20", "x-offset: 20"), {"geometry.x-offset", "unknown key"}},
      {replaced(kGoodMachine, ", z-offset: 10}", "}"), {"geometry.z-offset", "missing key"}},
      {replaced(kGoodMachine, "name: test\n", ""), {"name", "missing key"}},
      {replaced(kGoodMachine, "max_velocity: 30, max_acceleration: 300}\n  - {name: C",
                "max_velocity: -30, max_acceleration: 300}\n  - {name: C"),
       {"joints[3].max_velocity", "positive"}},
      {replaced(kGoodMachine, "  - {name: C, min: -36000, max: 36000, max_velocity: 30, max_acceleration: 300}\n", ""),
       {"joints", "5 joints (XYZAC)"}},
      {replaced(kGoodMachine, "origin: [1, 2, 3]", "origin: [1, 2]"), {"fixture.setups.2.origin", "3 numbers"}},
      {replaced(kGoodMachine, "    2: {", "    second: {"), {"fixture.setups.second", "setup index"}},
      {replaced(kGoodMachine, "max_acceleration: 300}\n  - {name: Y", "max_accel: 300}\n  - {name: Y"),
       {"joints[0].max_accel", "unknown key"}},
      {replaced(kGoodMachine, "rpy: [0, 0, 90]", "rpy: [0, 0, .nan]"), {"fixture.setups.2.rpy[2]", "finite"}},
      {"name: [unclosed", {"bad.yaml:", "not valid YAML"}},
      {"- just\n- a list\n", {"(top level)", "mapping"}},
  };
  for (const Case& c : cases) {
    const std::string message = parseError(c.text);
    ASSERT_FALSE(message.empty()) << "parsed without error:\n" << c.text;
    for (const std::string& part : c.says) EXPECT_NE(message.find(part), std::string::npos) << message;
  }
  EXPECT_NE(parseError(replaced(kGoodMachine, "z-offset: 10}", "z-offset: 10}\nfixture_pose: 3")).find("unknown key"),
            std::string::npos);
}

TEST(MachineFiles, LoadNamesTheFile) {
  const std::string missing = machinesDir() + "/no_such_machine.yaml";
  try {
    loadMachine(missing);
    FAIL() << "no error";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find(missing), std::string::npos) << error.what();
  }
  const std::string path = (std::filesystem::temp_directory_path() / "art2part_bad_machine.yaml").string();
  std::ofstream(path) << replaced(kGoodMachine, "max: 50,", "max: [50],");
  try {
    loadMachine(path);
    FAIL() << "no error";
  } catch (const InputError& error) {
    const std::string message = error.what();
    EXPECT_EQ(message.rfind(path + ":", 0), 0u) << message;  // file:line: key: what
    EXPECT_NE(message.find("joints[3].max"), std::string::npos) << message;
  }
  std::filesystem::remove(path);
}

// ---- LinuxCNC's formulas ------------------------------------------------------------------------------------------
// Numbers evaluated by hand from the forward kinematics of LinuxCNC's src/emc/kinematics/trtfuncs.c
// (xyzacKinematicsForward, xyzbcKinematicsForward) and 5axiskins.c (fiveaxis_KinematicsForward), with the sim's HAL
// values. LinuxCNC's Cartesian position is in the table frame and includes the tool length offset in Z (motion adds it
// and the kinematics' tool-offset pin takes it back out), so with tool length 0 it is our tip in the table frame.

TEST(LinuxCncFormulas, XyzacTrtForward) {
  const Machine machine = machineNamed("trunnion_ac");  // y-offset 20, z-offset 10, rot-point 0
  // joints X 10, Y 20, Z 30, A 30, C 90 (cos C = 0, sin C = 1, cos A = 0.8660254037844386, sin A = 0.5):
  //   x = cos C (X - xr) + sin C cos A (Y - dy - yr) + sin C sin A (Z - dz - zr) + sin C dy + xr
  //     = 0 + 0.8660 * (20 - 20) + 0.5 * (30 - 10) + 20 = 30
  //   y = -sin C (X - xr) + cos C cos A (...) + cos C sin A (...) + cos C dy + yr = -10
  //   z = -sin A (Y - dy - yr) + cos A (Z - dz - zr) + dz + zr = 0 + 0.8660254037844386 * 20 + 10 = 27.320508075688775
  const ToolPose pose = toolPoseInTable(machine, 0, jointsAt(10, 20, 30, 30, 90));
  EXPECT_LT((pose.tip - Vec3(30, -10, 27.320508075688775)).norm(), 1e-12);
  // The tool axis is how the position moves with joint Z (the spindle going up): d(x, y, z)/dZ
  // = (sin C sin A, cos C sin A, cos A) = (0.5, 0, 0.8660254037844386).
  EXPECT_LT((pose.axis - Vec3(0.5, 0, 0.8660254037844386)).norm(), 1e-15);
  // A 5 mm tool: LinuxCNC's joint Z is 5 higher for the same tip (dz + tool-offset in its formula).
  EXPECT_LT((toolPoseInTable(machine, 5, jointsAt(10, 20, 35, 30, 90)).tip - pose.tip).norm(), 1e-12);

  // A C centre off the machine origin (x/y/z-rot-point 5, -3, 2), joints 12.5, -40, -60, A -75, C 200, by the same
  // formula: (-27.62874033658256, -70.71819429878565, -61.69274334585839).
  Machine moved = machine;
  moved.geometry.rot_point = Vec3(5, -3, 2);
  const JointPosition joints = jointsAt(12.5, -40, -60, -75, 200);
  const ToolPose moved_pose = toolPoseInTable(moved, 0, joints);
  EXPECT_LT((moved_pose.tip - Vec3(-27.62874033658256, -70.71819429878565, -61.69274334585839)).norm(), 1e-12);
  // ... and xyzacKinematicsInverse of that position at A -75, C 200 gives the joints back.
  Placement placement;
  const IkSolution back = inverseKinematics(moved, placement, moved_pose, joints);
  ASSERT_TRUE(back.ok()) << back.reason;
  EXPECT_LT((back.joints.linear - joints.linear).norm(), 1e-9);
  EXPECT_NEAR(back.joints.tilt, joints.tilt, 1e-12);
  EXPECT_NEAR(back.joints.rotary, joints.rotary, 1e-12);
}

TEST(LinuxCncFormulas, XyzbcTrtForward) {
  const Machine machine = machineNamed("trunnion_bc");  // x-offset -20, z-offset -15, rot-point 0
  // joints X 10, Y 20, Z 30, B 30, C 90:
  //   x = cos C cos B (X - dx - xr) + sin C (Y - yr) - cos C sin B (Z - dz - zr) + cos C dx + xr = 20
  //   y = -sin C cos B (X - dx - xr) + cos C (Y - yr) + sin C sin B (Z - dz - zr) - sin C dx + yr
  //     = -0.8660254 * 30 + 0.5 * 45 + 20 = 16.519237886466836
  //   z = sin B (X - dx - xr) + cos B (Z - dz - zr) + dz + zr = 15 + 0.8660254 * 45 - 15 = 38.97114317029974
  const ToolPose pose = toolPoseInTable(machine, 0, jointsAt(10, 20, 30, 30, 90));
  EXPECT_LT((pose.tip - Vec3(20, 16.519237886466836, 38.97114317029974)).norm(), 1e-12);
  // d(x, y, z)/dZ = (-cos C sin B, sin C sin B, cos B) = (0, 0.5, 0.8660254037844386)
  EXPECT_LT((pose.axis - Vec3(0, 0.5, 0.8660254037844386)).norm(), 1e-15);
  Machine moved = machine;
  moved.geometry.rot_point = Vec3(5, -3, 2);
  // joints -33, 44, -55, B -60, C -135 -> (17.991720237865508, -82.45975766940099, -18.41154273188011)
  EXPECT_LT((toolPoseInTable(moved, 0, jointsAt(-33, 44, -55, -60, -135)).tip -
             Vec3(17.991720237865508, -82.45975766940099, -18.41154273188011))
                .norm(),
            1e-12);
}

TEST(LinuxCncFormulas, FiveAxisKinsForward) {
  const Machine machine = machineNamed("head_head_bc");  // pivot-length 250
  // pos = joints + (0, 0, L) + s2r(L, C, 180 - B), s2r(r, t, p) = r (sin p cos t, sin p sin t, cos p), L = 250:
  //   B 30, C 90: (10, 20 + 125, 30 + 250 - 216.50635094610965) = (10, 145, 63.49364905389032)
  //   B 30, C 0:  (10 + 125, 20, 63.49364905389032)
  EXPECT_LT((toolPoseInTable(machine, 0, jointsAt(10, 20, 30, 30, 90)).tip - Vec3(10, 145, 63.49364905389032)).norm(),
            1e-12);
  const ToolPose pose = toolPoseInTable(machine, 0, jointsAt(10, 20, 30, 30, 0));
  EXPECT_LT((pose.tip - Vec3(135, 20, 63.49364905389032)).norm(), 1e-12);
  EXPECT_LT((pose.axis - Vec3(-0.5, 0, 0.8660254037844386)).norm(), 1e-15);  // from the tip back to the pivot
  // The sim feeds pivot-length + tool length to 5axiskins and motion adds the tool length in Z: the same tip for a
  // 100 mm tool is (10 + 350 sin B, 20, 30 + 350 - 350 cos B) - (0, 0, 100) + (0, 0, 100).
  const ToolPose long_tool = toolPoseInTable(machine, 100, jointsAt(10, 20, 30, 30, 0));
  EXPECT_LT((long_tool.tip - Vec3(10 + 175, 20, 30 + 250 - 350 * 0.8660254037844386)).norm(), 1e-12);
}

// ---- forward and inverse ------------------------------------------------------------------------------------------

TEST_P(EachMachine, ForwardOfInverseIsThePoseForRandomReachablePoses) {
  const Machine machine = machineNamed(GetParam());
  const Placement placement = skewPlacement(machine);
  std::mt19937 rng(7001);
  const IkOptions options;
  JointPosition previous;  // from home; then each from the solution before (C wanders over many turns)
  double worst_tip = 0, worst_axis = 0;
  int held = 0;
  const int samples = 100000;
  for (int i = 0; i < samples; ++i) {
    const ToolPose pose = forwardKinematics(machine, placement, randomJoints(machine, rng));
    const IkSolution solution = inverseKinematics(machine, placement, pose, previous, options);
    ASSERT_TRUE(solution.ok()) << "sample " << i << ": " << solution.reason;
    ASSERT_EQ(limitViolation(machine, solution.joints), "");
    const ToolPose back = forwardKinematics(machine, placement, solution.joints);
    const double axis_error = angleBetween(back.axis, pose.axis);
    worst_tip = std::max(worst_tip, (back.tip - pose.tip).norm());
    if (solution.rotary_held) {
      ++held;
      EXPECT_LE(axis_error, options.axis_tolerance);
    } else {
      worst_axis = std::max(worst_axis, axis_error);
    }
    previous = solution.joints;
  }
  EXPECT_LE(worst_tip, 1e-9);
  EXPECT_LE(worst_axis, 1e-9);
  EXPECT_EQ(held, 0);  // a random pose within 1e-6 rad of the C axis: about 1 in 10^6
  std::printf("%s: %d poses, worst tip error %.3g mm, worst axis error %.3g rad\n", machine.name.c_str(), samples,
              worst_tip, worst_axis);
}

TEST_P(EachMachine, InverseOfForwardGivesTheJointsOrTheOtherBranch) {
  const Machine machine = machineNamed(GetParam());
  const Placement placement = skewPlacement(machine);
  std::mt19937 rng(7002);
  for (int i = 0; i < 20000; ++i) {
    const JointPosition q = randomJoints(machine, rng);
    const ToolPose pose = forwardKinematics(machine, placement, q);
    // From q itself, q is the nearest solution.
    const IkSolution same = inverseKinematics(machine, placement, pose, q);
    ASSERT_TRUE(same.ok()) << same.reason;
    ASSERT_LT((same.joints.linear - q.linear).norm(), 1e-9);
    ASSERT_NEAR(same.joints.tilt, q.tilt, 1e-9);
    ASSERT_NEAR(same.joints.rotary, q.rotary, 1e-9);
    // Every branch reaches the same pose; a 5-axis machine has two: (tilt, C) and (-tilt, C + 180).
    const std::vector<JointPosition> branches = inverseKinematicsBranches(machine, placement, pose, q);
    ASSERT_EQ(branches.size(), machine.fiveAxis() ? 2u : 1u);
    for (const JointPosition& branch : branches) {
      const ToolPose back = forwardKinematics(machine, placement, branch);
      ASSERT_LT((back.tip - pose.tip).norm(), 1e-9);
      ASSERT_LT(angleBetween(back.axis, pose.axis), 1e-9);
    }
    if (machine.fiveAxis()) {
      // One branch is q itself (both angles at the turn nearest q), the other its flip.
      auto is_q = [&](const JointPosition& b) {
        return std::abs(b.tilt - q.tilt) < 1e-9 && std::abs(b.rotary - q.rotary) < 1e-9;
      };
      ASSERT_NE(is_q(branches[0]), is_q(branches[1]));
      const JointPosition& other = is_q(branches[0]) ? branches[1] : branches[0];
      ASSERT_NEAR(wrapped(other.tilt + q.tilt), 0, 1e-9);
      ASSERT_NEAR(std::abs(wrapped(other.rotary - q.rotary)), kPi, 1e-9);
      ASSERT_LE(std::abs(other.rotary - q.rotary), kPi + 1e-9);  // the turn nearest q
    }
  }
}

// ---- reachability -------------------------------------------------------------------------------------------------

TEST(InverseKinematics, ReportsPosesNoBranchReaches) {
  const Machine machine = machineNamed("trunnion_ac");  // A -100 .. 50 deg
  const Placement placement;
  // Tilted 110 deg: A +110 or -110, both beyond the trunnion's travel.
  ToolPose pose;
  pose.tip = Vec3(0, 0, 0);
  pose.axis = Vec3(0, std::sin(110 * kDeg), std::cos(110 * kDeg));
  IkSolution solution = inverseKinematics(machine, placement, pose, JointPosition{});
  EXPECT_EQ(solution.status, IkStatus::OutsideLimits);
  EXPECT_NE(solution.reason.find("A = 110.0000 deg above its maximum 50 deg"), std::string::npos) << solution.reason;
  EXPECT_NE(solution.reason.find("A = -110.0000 deg below its minimum -100 deg"), std::string::npos)
      << solution.reason;
  // A tip beyond X's travel.
  pose.axis = Vec3::UnitZ();
  pose.tip = Vec3(1000, 0, 0);
  solution = inverseKinematics(machine, placement, pose, JointPosition{});
  EXPECT_EQ(solution.status, IkStatus::OutsideLimits);
  EXPECT_NE(solution.reason.find("X = 1000.0000 mm above its maximum 200 mm"), std::string::npos) << solution.reason;
  // Nonsense.
  pose.tip = Vec3(std::nan(""), 0, 0);
  EXPECT_EQ(inverseKinematics(machine, placement, pose, JointPosition{}).status, IkStatus::InvalidPose);
  pose.tip = Vec3::Zero();
  pose.axis = Vec3::Zero();
  EXPECT_EQ(inverseKinematics(machine, placement, pose, JointPosition{}).status, IkStatus::InvalidPose);
}

TEST(InverseKinematics, TakesTheOtherBranchWhenTheNearerLeavesTheTravel) {
  const Machine machine = machineNamed("trunnion_ac");
  ToolPose pose;
  pose.axis = Vec3(0, std::sin(70 * kDeg), std::cos(70 * kDeg));  // A +70 (beyond 50) or A -70 with C 180
  const IkSolution solution = inverseKinematics(machine, Placement{}, pose, jointsAt(0, 0, 0, 45, 0));
  ASSERT_TRUE(solution.ok()) << solution.reason;
  EXPECT_NEAR(solution.joints.tilt, -70 * kDeg, 1e-12);
  EXPECT_NEAR(std::abs(solution.joints.rotary), kPi, 1e-12);
  // With both inside, the nearer one: from A +45 that is A +40, C 0; from A -45, C 180 it is A -40, C 180.
  pose.axis = Vec3(0, std::sin(40 * kDeg), std::cos(40 * kDeg));
  EXPECT_NEAR(inverseKinematics(machine, Placement{}, pose, jointsAt(0, 0, 0, 45, 0)).joints.tilt, 40 * kDeg, 1e-12);
  const IkSolution flipped = inverseKinematics(machine, Placement{}, pose, jointsAt(0, 0, 0, -45, 180));
  EXPECT_NEAR(flipped.joints.tilt, -40 * kDeg, 1e-12);
  EXPECT_NEAR(flipped.joints.rotary, kPi, 1e-12);
}

TEST(InverseKinematics, ThreeAxisMachineRejectsTiltedAxes) {
  const Machine machine = machineNamed("mill_3axis");
  Placement placement;
  placement.tool_length = 30;
  ToolPose pose;
  pose.tip = Vec3(10, 20, -5);
  pose.axis = Vec3(0, std::sin(10 * kDeg), std::cos(10 * kDeg));
  const IkSolution tilted = inverseKinematics(machine, placement, pose, JointPosition{});
  EXPECT_EQ(tilted.status, IkStatus::AxisUnreachable);
  EXPECT_NE(tilted.reason.find("3-axis"), std::string::npos) << tilted.reason;
  EXPECT_TRUE(inverseKinematicsBranches(machine, placement, pose, JointPosition{}).empty());
  pose.axis = Vec3::UnitZ();
  const IkSolution upright = inverseKinematics(machine, placement, pose, JointPosition{});
  ASSERT_TRUE(upright.ok()) << upright.reason;
  EXPECT_LT((upright.joints.linear - Vec3(10, 20, 25)).norm(), 1e-12);  // gauge point = tip + tool length
  // A setup along the part's +x: the fixture turns it up, and then that axis is the spindle's.
  placement.fixture = fixtureFacingUp(Vec3(0, 1, 0), Vec3(0, 0, 1), Vec3(1, 0, 0), Vec3(0, 0, 0), Vec3(0, 0, -20));
  pose.tip = Vec3::Zero();
  pose.axis = Vec3::UnitX();
  const IkSolution setup = inverseKinematics(machine, placement, pose, JointPosition{});
  ASSERT_TRUE(setup.ok()) << setup.reason;
  EXPECT_LT((setup.joints.linear - Vec3(0, 0, 10)).norm(), 1e-12);
  pose.axis = Vec3::UnitZ();
  EXPECT_EQ(inverseKinematics(machine, placement, pose, JointPosition{}).status, IkStatus::AxisUnreachable);
}

// ---- continuity ---------------------------------------------------------------------------------------------------

namespace {

// Poses with the rotaries at tilt 30 deg and C = C0 + step * i (i = 0 .. count - 1), the linear joints mid-travel.
std::vector<ToolPose> rotarySweep(const Machine& machine, const Placement& placement, double c0_deg, double step_deg,
                                  int count) {
  std::vector<ToolPose> poses;
  for (int i = 0; i < count; ++i) {
    JointPosition q;
    for (int k = 0; k < 3; ++k) q.linear[k] = 0.5 * (machine.joints[k].min + machine.joints[k].max) + 3 * k;
    q.tilt = 30 * kDeg;
    q.rotary = (c0_deg + step_deg * i) * kDeg;
    poses.push_back(forwardKinematics(machine, placement, q));
  }
  return poses;
}

}  // namespace

TEST_P(EachFiveAxisMachine, CUnwindsThroughTwoTurnsWithoutAJump) {
  const Machine machine = machineNamed(GetParam());
  const Placement placement = skewPlacement(machine);
  // From C 170 deg, 720 deg in 1 deg steps: across +-180 twice.
  const std::vector<ToolPose> poses = rotarySweep(machine, placement, 170, 1, 721);
  const std::vector<IkSolution> path = inverseKinematicsPath(machine, placement, poses, jointsAt(0, 0, 0, 20, 170));
  ASSERT_EQ(path.size(), poses.size());
  for (std::size_t i = 0; i < path.size(); ++i) {
    ASSERT_TRUE(path[i].ok()) << i << ": " << path[i].reason;
    if (i == 0) continue;
    ASSERT_NEAR(path[i].joints.rotary - path[i - 1].joints.rotary, 1 * kDeg, 1e-9) << "step " << i;
    ASSERT_NEAR(path[i].joints.tilt, path[i - 1].joints.tilt, 1e-9) << "step " << i;
  }
  EXPECT_NEAR(path.back().joints.rotary - path.front().joints.rotary, 720 * kDeg, 1e-9);
  // And back the other way.
  const std::vector<ToolPose> back = rotarySweep(machine, placement, 170, -1, 721);
  const std::vector<IkSolution> reverse = inverseKinematicsPath(machine, placement, back, path.front().joints);
  for (std::size_t i = 1; i < reverse.size(); ++i) {
    ASSERT_NEAR(reverse[i].joints.rotary - reverse[i - 1].joints.rotary, -1 * kDeg, 1e-9) << "step " << i;
  }
}

TEST(InverseKinematics, LimitedCUnwindsOnlyWhereItsTravelEnds) {
  Machine machine = machineNamed("trunnion_ac");
  machine.joints[4].min = -200 * kDeg;
  machine.joints[4].max = 200 * kDeg;
  const Placement placement;
  const std::vector<ToolPose> poses = rotarySweep(machine, placement, 0, 1, 721);
  const std::vector<IkSolution> path = inverseKinematicsPath(machine, placement, poses, JointPosition{});
  int unwinds = 0;
  for (std::size_t i = 0; i < path.size(); ++i) {
    ASSERT_TRUE(path[i].ok()) << i << ": " << path[i].reason;
    ASSERT_EQ(limitViolation(machine, path[i].joints), "");
    if (i == 0) continue;
    const double step = path[i].joints.rotary - path[i - 1].joints.rotary;
    if (std::abs(step - 1 * kDeg) > 1e-9) {
      // Only where going on by the 1 deg the move needs would leave C's travel.
      ASSERT_GT(path[i - 1].joints.rotary + 1 * kDeg, machine.joints[4].max) << "step " << i;
      ++unwinds;
    }
  }
  EXPECT_GE(unwinds, 1);
  EXPECT_LE(unwinds, 3);
}

TEST_P(EachFiveAxisMachine, SingularAxisHoldsC) {
  const Machine machine = machineNamed(GetParam());
  const Placement placement;
  const JointPosition previous = jointsAt(0, 0, 0, 20, 37);
  // Along the C axis exactly: C stays where it was, the tilt goes to 0.
  const JointPosition upright = jointsAt(0, 0, machine.kind == MachineKind::HeadBC ? -100 : 0, 0, 123);
  ToolPose pose = forwardKinematics(machine, placement, upright);
  IkSolution solution = inverseKinematics(machine, placement, pose, previous);
  ASSERT_TRUE(solution.ok()) << solution.reason;
  EXPECT_TRUE(solution.rotary_held);
  EXPECT_EQ(solution.joints.rotary, previous.rotary);
  EXPECT_NEAR(solution.joints.tilt, 0, 1e-15);
  EXPECT_LT(solution.axis_error, 1e-15);
  EXPECT_LT((forwardKinematics(machine, placement, solution.joints).tip - pose.tip).norm(), 1e-9);
  // 1e-8 rad off the C axis, in a direction C 37 cannot tilt to: held, the axis off by no more than that.
  const JointPosition almost = jointsAt(0, 0, upright.linear.z(), 1e-8 / kDeg, 123);
  pose = forwardKinematics(machine, placement, almost);
  solution = inverseKinematics(machine, placement, pose, previous);
  ASSERT_TRUE(solution.ok()) << solution.reason;
  EXPECT_TRUE(solution.rotary_held);
  EXPECT_EQ(solution.joints.rotary, previous.rotary);
  EXPECT_LE(solution.axis_error, 1e-8 * 1.0001);
  EXPECT_LT((forwardKinematics(machine, placement, solution.joints).tip - pose.tip).norm(), 1e-9);
  // A path over the pole (the tilt from +30 to -30 deg at one C) never turns C.
  std::vector<ToolPose> over;
  for (int i = 0; i <= 60; ++i) {
    over.push_back(forwardKinematics(machine, placement, jointsAt(0, 0, upright.linear.z(), 30 - i, 37)));
  }
  const std::vector<IkSolution> path = inverseKinematicsPath(machine, placement, over, previous);
  for (std::size_t i = 0; i < path.size(); ++i) {
    ASSERT_TRUE(path[i].ok()) << path[i].reason;
    ASSERT_NEAR(path[i].joints.rotary, 37 * kDeg, 1e-12) << i;
    ASSERT_NEAR(path[i].joints.tilt, (30.0 - i) * kDeg, 1e-12) << i;
  }
  EXPECT_TRUE(path[30].rotary_held);
}

TEST_P(EachFiveAxisMachine, SingularPosesTakeCFromTheNextRegularPose) {
  const Machine machine = machineNamed(GetParam());
  const Placement placement;
  const double z = machine.kind == MachineKind::HeadBC ? -100 : 0;
  const JointPosition previous = jointsAt(0, 0, 0, 20, 37);
  // Three vertical poses, then the axis tilting at C = 110 deg: the vertical ones take C 110 (not the 37 before), so
  // the tilt follows without turning C; two vertical poses at the end hold the last C.
  std::vector<ToolPose> poses;
  for (int i = 0; i < 3; ++i) poses.push_back(forwardKinematics(machine, placement, jointsAt(i, 0, z, 0, 0)));
  for (int i = 1; i <= 10; ++i) poses.push_back(forwardKinematics(machine, placement, jointsAt(3, 0, z, 2 * i, 110)));
  for (int i = 0; i < 2; ++i) poses.push_back(forwardKinematics(machine, placement, jointsAt(4, i, z, 0, 0)));
  EXPECT_TRUE(singularPose(machine, placement, poses[0]));
  EXPECT_FALSE(singularPose(machine, placement, poses[3]));
  const std::vector<IkSolution> path = inverseKinematicsPath(machine, placement, poses, previous);
  for (std::size_t i = 0; i < path.size(); ++i) {
    ASSERT_TRUE(path[i].ok()) << path[i].reason;
    EXPECT_NEAR(path[i].joints.rotary, 110 * kDeg, 1e-12) << i;
    EXPECT_LT((forwardKinematics(machine, placement, path[i].joints).tip - poses[i].tip).norm(), 1e-9) << i;
  }
  EXPECT_TRUE(path[0].rotary_held && path[2].rotary_held && path[14].rotary_held);
  EXPECT_NEAR(path[3].joints.tilt, 2 * kDeg, 1e-12);
  // From C = 290 the nearer branch of the tilted poses is (-tilt, C + 180): the vertical poses take 290.
  const std::vector<IkSolution> other = inverseKinematicsPath(machine, placement, poses, jointsAt(0, 0, 0, 0, 290));
  EXPECT_NEAR(other[0].joints.rotary, 290 * kDeg, 1e-12);
  EXPECT_NEAR(other[3].joints.rotary, 290 * kDeg, 1e-12);
  EXPECT_NEAR(other[3].joints.tilt, -2 * kDeg, 1e-12);
  EXPECT_FALSE(singularPose(machineNamed("mill_3axis"), placement, poses[0]));
}

TEST(MachineHelpers, RpyAndJointVectorsRoundTrip) {
  const Vec3 rpy(0.3, -0.7, 2.9);
  EXPECT_LT((rpyFromRotation(rotationFromRpy(rpy)) - rpy).norm(), 1e-12);
  const Machine machine = machineNamed("trunnion_ac");
  const JointPosition q = jointsAt(1, 2, 3, 4, 5);
  const JointPosition back = jointPositionFromVector(machine, jointVector(machine, q));
  EXPECT_EQ(back.linear, q.linear);
  EXPECT_EQ(back.tilt, q.tilt);
  EXPECT_EQ(back.rotary, q.rotary);
  EXPECT_THROW(jointPositionFromVector(machine, {1, 2, 3}), InputError);
  EXPECT_EQ(limitViolation(machine, q), "");
  EXPECT_EQ(limitViolation(machine, jointsAt(0, 0, 0, 60, 0)), "A = 60.0000 deg above its maximum 50 deg");
}
