// Post: G-code for LinuxCNC 2.9 from hand-made toolpaths. Every program goes through LinuxCNC's stand-alone
// interpreter (rs274 -g -t TOOLTABLE); its canonical moves (STRAIGHT_TRAVERSE / STRAIGHT_FEED, in the program's mm and
// degrees) are compared with our joints, and through forward kinematics with the toolpath: 1e-3 mm and 1e-3 deg.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "art2part/kinematics/inverse_kinematics.h"
#include "art2part/post/gcode.h"
#include "art2part/post/joint_trajectory.h"
#include "art2part/post/machine_program.h"

using namespace art2part;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180;

Machine machineNamed(const std::string& name) {
  return loadMachine(std::string(ART2PART_SOURCE_DIR) + "/config/machines/" + name + ".yaml");
}

Tool makeTool(const std::string& id, ToolType type) {
  Tool tool;
  tool.id = id;
  tool.type = type;
  tool.diameter = 6;
  tool.corner_radius = type == ToolType::Ball ? 3 : 0;
  tool.flute_length = 15;
  tool.shank_diameter = 6;
  tool.stickout = 30;
  tool.holder = {{20, 30}};
  tool.spindle_rpm = 8000;
  tool.feed_mm_min = 600;
  tool.plunge_mm_min = 200;
  return tool;
}

std::vector<Tool> shopTools() { return {makeTool("flat6", ToolType::Flat), makeTool("ball6", ToolType::Ball)}; }

CutterLocation point(int op, int setup, const std::string& tool, MoveKind move, const Vec3& tip, const Vec3& axis) {
  CutterLocation p;
  p.op = op;
  p.setup = setup;
  p.tool = tool;
  p.move = move;
  p.tip = tip;
  p.axis = axis.normalized();
  return p;
}

// A zig-zag pocket floor in the plane through `centre` normal to `axis`, 20 x 20 mm, entered and left from 8 mm up.
void addPocket(Toolpath& path, int op, int setup, const std::string& tool, const Vec3& centre, const Vec3& axis,
               const Vec3& across) {
  const Vec3 along = axis.cross(across).normalized();
  const Vec3 up = 8 * axis;
  auto at = [&](double u, double v) { return Vec3(centre + u * across + v * along); };
  path.push_back(point(op, setup, tool, MoveKind::Rapid, at(-10, -10) + up, axis));
  path.push_back(point(op, setup, tool, MoveKind::Feed, at(-10, -10), axis));
  for (int pass = 0; pass <= 5; ++pass) {
    const double v = -10 + 4 * pass;
    const bool forward = pass % 2 == 0;
    if (pass > 0) path.push_back(point(op, setup, tool, MoveKind::Feed, at(forward ? -10 : 10, v), axis));
    path.push_back(point(op, setup, tool, MoveKind::Feed, at(forward ? 10 : -10, v), axis));
  }
  path.push_back(point(op, setup, tool, MoveKind::Rapid, path.back().tip + up, axis));
}

// A 40 x 40 x 30 block: setup 0 pockets its top (flat), setup 1 a side face (flat, then ball), with the part turned
// on the table for setup 1.
Toolpath pocketsInTwoSetups() {
  Toolpath path;
  addPocket(path, 0, 0, "flat6", Vec3(0, 0, 27), Vec3::UnitZ(), Vec3::UnitX());
  addPocket(path, 1, 1, "flat6", Vec3(0, -17, 15), -Vec3::UnitY(), Vec3::UnitX());
  addPocket(path, 2, 1, "ball6", Vec3(0, -16, 15), -Vec3::UnitY(), Vec3::UnitZ());
  return path;
}

PostOptions turnedSetupOne() {
  PostOptions options;
  FixturePose turned;
  turned.rotation = rotationFromRpy(Vec3(0, 0, 90 * kDeg));
  turned.origin = Vec3(5, 0, 0);
  options.fixtures[1] = turned;
  return options;
}

// A continuous 5-axis path: a full circle with the axis leaning 30 deg outwards (C turns a whole turn and crosses
// +-180), a pass near the singularity (the axis sweeps past the C axis 0.6 deg off it: C swings half a turn), and one
// straight through it (C held).
Toolpath fiveAxisPath() {
  Toolpath path;
  const std::string tool = "ball6";
  for (int k = 0; k <= 72; ++k) {
    const double theta = k * 5 * kDeg;
    const Vec3 axis(std::sin(30 * kDeg) * std::cos(theta), std::sin(30 * kDeg) * std::sin(theta), std::cos(30 * kDeg));
    const Vec3 tip(15 * std::cos(theta), 15 * std::sin(theta), 10);
    if (k == 0) path.push_back(point(0, 0, tool, MoveKind::Rapid, tip + 10 * axis, axis));
    path.push_back(point(0, 0, tool, MoveKind::Feed, tip, axis));
  }
  for (double offset : {0.01, 0.0}) {
    const int op = offset > 0 ? 1 : 2;
    for (int k = 0; k <= 24; ++k) {
      const double psi = (30 - 2.5 * k) * kDeg;
      const Vec3 axis = Vec3(offset, std::sin(psi), std::cos(psi)).normalized();
      const Vec3 tip(-10 + k * 20.0 / 24, offset > 0 ? 2 : -2, 15);
      if (k == 0) path.push_back(point(op, 0, tool, MoveKind::Rapid, tip + 10 * axis, axis));
      path.push_back(point(op, 0, tool, MoveKind::Feed, tip, axis));
    }
    path.push_back(point(op, 0, tool, MoveKind::Rapid, path.back().tip + 10 * path.back().axis, path.back().axis));
  }
  return path;
}

// ---- rs274 ---------------------------------------------------------------------------------------------------------

struct Rs274Run {
  int status = -1;
  std::string errors;  // stderr without rs274's "executing" line
  std::vector<std::array<double, 6>> moves;  // x y z a b c of every STRAIGHT_TRAVERSE / STRAIGHT_FEED
  std::vector<bool> feed;
};

std::string readFile(const std::string& path) {
  std::ifstream file(path);
  std::stringstream text;
  text << file.rdbuf();
  return text.str();
}

void writeFile(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

Rs274Run runRs274(const std::string& program_text, const std::string& tool_table, const std::string& name) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / ("art2part_test_post_" + name);
  std::filesystem::create_directories(dir);
  const std::string program = (dir / "program.ngc").string(), table = (dir / "tool.tbl").string();
  const std::string canon = (dir / "canon.txt").string(), err = (dir / "err.txt").string();
  writeFile(program, program_text);
  writeFile(table, tool_table);
  const std::string command = "rs274 -g -t " + table + " " + program + " " + canon + " > /dev/null 2> " + err;
  Rs274Run run;
  const int raw = std::system(command.c_str());
  run.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  std::istringstream errors(readFile(err));
  for (std::string line; std::getline(errors, line);)
    if (line != "executing" && !line.empty()) run.errors += line + "\n";
  static const std::regex move(R"((STRAIGHT_TRAVERSE|STRAIGHT_FEED)\(([^)]*)\))");
  std::istringstream lines(readFile(canon));
  for (std::string line; std::getline(lines, line);) {
    std::smatch match;
    if (!std::regex_search(line, match, move)) continue;
    std::array<double, 6> values{};
    std::istringstream numbers(match[2].str());
    char comma;
    for (int i = 0; i < 6; ++i) numbers >> values[i] >> comma;
    run.moves.push_back(values);
    run.feed.push_back(match[1] == "STRAIGHT_FEED");
  }
  return run;
}

Rs274Run expectAccepted(const std::string& program_text, const MachineProgram& program, const std::string& name) {
  const Rs274Run run = runRs274(program_text, toolTableText(program, ToolTableUnits::Inches), name);
  EXPECT_EQ(run.status, 0) << name << ": " << run.errors;
  EXPECT_EQ(run.errors, "") << name;
  return run;
}

// ---- what the interpreter should say -------------------------------------------------------------------------------

// One motion the program makes: the step, its program position (x y z a b c as rs274 prints them), and the tool.
struct ExpectedMove {
  const ProgramStep* step = nullptr;
  int setup = 0;  // index into program.setups
  std::array<double, 6> position{};
  double tool_length = 0;
};

int canonicalIndex(const std::string& joint_name) {
  const std::string names = "XYZABC";
  return static_cast<int>(names.find(joint_name));
}

// The steps that make rs274 move (a move whose words all round to the last ones written makes none), as the writer
// prints them.
std::vector<ExpectedMove> expectedMoves(const MachineProgram& program, const std::vector<int>& setups) {
  std::vector<ExpectedMove> moves;
  const Machine& machine = program.machine;
  std::vector<std::string> last(machine.jointCount());
  double tool_length = 0;
  for (int index : setups) {
    for (const ProgramStep& step : program.setups[index].steps) {
      if (step.kind == StepKind::ToolChange) {
        tool_length = program.tool(step.tool).length;
        std::fill(last.begin(), last.end(), std::string());
        continue;
      }
      ExpectedMove move{&step, index, {}, tool_length};
      const Vec3 xyz = programXyz(step.joints, tool_length);
      const std::vector<double> joints = jointVector(machine, step.joints);
      bool changed = step.kind == StepKind::Retract || step.cycle >= 0;  // a cycle's moves are made even when still
      for (int j = 0; j < machine.jointCount(); ++j) {
        const double value = machine.joints[j].rotary ? joints[j] / kDeg : xyz[j];
        move.position[canonicalIndex(machine.joints[j].name)] = value;
        const std::string text = gcodeNumber(value);
        changed = changed || text != last[j];
        last[j] = text;
      }
      if (changed) moves.push_back(move);
    }
  }
  return moves;
}

std::vector<int> allSetups(const MachineProgram& program) {
  std::vector<int> all;
  for (size_t i = 0; i < program.setups.size(); ++i) all.push_back(static_cast<int>(i));
  return all;
}

// rs274's moves, back to our joints (mm, rad).
JointPosition jointsOfCanonical(const Machine& machine, const std::array<double, 6>& move, double tool_length) {
  std::vector<double> values;
  for (const Joint& joint : machine.joints) {
    const double value = move[canonicalIndex(joint.name)];
    values.push_back(joint.rotary ? value * kDeg : value);
  }
  JointPosition joints = jointPositionFromVector(machine, values);
  joints.linear.z() += tool_length;
  return joints;
}

double distanceToSegment(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double f = ab.squaredNorm() > 0 ? std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0) : 0.0;
  return (p - (a + f * ab)).norm();
}

// The interpreter's moves equal ours one for one; through FK they land on the toolpath; none leaves the travel.
void checkAgainstToolpath(const MachineProgram& program, const Toolpath& path, const Rs274Run& run,
                          const std::vector<int>& setups) {
  const Machine& machine = program.machine;
  const std::vector<ExpectedMove> expected = expectedMoves(program, setups);
  ASSERT_EQ(run.moves.size(), expected.size());
  for (size_t m = 0; m < expected.size(); ++m) {
    const ExpectedMove& move = expected[m];
    // A program starts wherever the machine is: its first move, the safe retract, says only Z.
    const bool first_retract = m == 0 && move.step->kind == StepKind::Retract;
    for (int c = 0; c < 6; ++c) {
      if (first_retract && c != 2) continue;
      ASSERT_NEAR(run.moves[m][c], move.position[c], 1e-3) << "move " << m << " coordinate " << c;
    }
    if (first_retract) continue;
    EXPECT_EQ(run.feed[m], move.step->kind == StepKind::Move && move.step->move == MoveKind::Feed) << "move " << m;
    const JointPosition joints = jointsOfCanonical(machine, run.moves[m], move.tool_length);
    EXPECT_EQ(limitViolation(machine, joints, 1e-3), "") << "move " << m;
    if (move.step->row < 0) continue;
    Placement placement;
    placement.fixture = program.setups[move.setup].fixture;
    placement.tool_length = move.tool_length;
    const ToolPose pose = forwardKinematics(machine, placement, joints);
    const CutterLocation& to = path[move.step->row];
    if (move.step->at_row) {
      EXPECT_LT((pose.tip - to.tip).norm(), 1e-3) << "move " << m << " row " << move.step->row;
      EXPECT_LT(angleBetween(pose.axis, to.axis), 1e-3 * kDeg) << "move " << m << " row " << move.step->row;
    } else {
      const CutterLocation& from = path[move.step->row - 1];
      EXPECT_LT(distanceToSegment(pose.tip, from.tip, to.tip), 1e-3) << "move " << m;
    }
  }
}

// ---- tests ---------------------------------------------------------------------------------------------------------

TEST(Post, ThreePlusTwoPocketsInTwoSetupsPassRs274AndLandOnTheToolpath) {
  const Machine machine = machineNamed("trunnion_ac");
  const Toolpath path = pocketsInTwoSetups();
  const MachineProgram program = buildMachineProgram(machine, path, shopTools(), "block", turnedSetupOne());
  ASSERT_EQ(program.mode, PostMode::ThreePlusTwo);
  ASSERT_EQ(program.setups.size(), 2u);
  EXPECT_EQ(program.setups[1].tools, (std::vector<int>{1, 2}));

  const std::string job = jobProgramText(program);
  EXPECT_NE(job.find("M0 (re-fixture for setup 1"), std::string::npos);
  EXPECT_NE(job.find("(part: block)"), std::string::npos);
  EXPECT_NE(job.find("T2 M6"), std::string::npos);
  EXPECT_NE(job.find("G43 H2"), std::string::npos);
  EXPECT_NE(job.find("M30"), std::string::npos);
  EXPECT_EQ(job.find("G93"), std::string::npos) << "3+2 cuts never turn a rotary";
  EXPECT_NE(job.find("G94 G64 P0.0050\n"), std::string::npos) << "3+2 blends X Y Z corners within the tolerance";
  const Rs274Run run = expectAccepted(job, program, "pockets_job");
  checkAgainstToolpath(program, path, run, allSetups(program));

  // Setup 1 turns the table once: A -90 (the side face up), and no rotary word while cutting.
  for (int index = 0; index < 2; ++index) {
    const Rs274Run alone = expectAccepted(setupProgramText(program, index), program, "pockets_setup");
    checkAgainstToolpath(program, path, alone, {index});
  }
  const std::vector<ExpectedMove> moves = expectedMoves(program, {1});
  int rotary_moves = 0;
  for (size_t m = 1; m < moves.size(); ++m)
    if (moves[m].position[3] != moves[m - 1].position[3] || moves[m].position[5] != moves[m - 1].position[5]) {
      ++rotary_moves;
      EXPECT_EQ(moves[m].step->row, -1) << "the rotaries turn only on the way in";
      EXPECT_NEAR(moves[m].position[2], program.retract_z - program.tool(1).length, 1e-9) << "at the safe height";
    }
  EXPECT_EQ(rotary_moves, 1);
  EXPECT_NEAR(moves.back().position[3], -90, 1e-6);
}

TEST(Post, RetractToTheSafeHeightBeforeEveryToolChangeAndRotaryMove) {
  const Machine machine = machineNamed("trunnion_ac");
  const MachineProgram program =
      buildMachineProgram(machine, pocketsInTwoSetups(), shopTools(), "block", turnedSetupOne());
  for (const SetupProgram& setup : program.setups) {
    JointPosition at = program.start;
    for (const ProgramStep& step : setup.steps) {
      const bool turns = step.kind == StepKind::Move && (step.joints.tilt != at.tilt || step.joints.rotary != at.rotary);
      if (step.kind == StepKind::ToolChange || turns) {
        EXPECT_EQ(at.linear.z(), program.retract_z);
      }
      if (step.kind != StepKind::ToolChange) at = step.joints;
    }
    EXPECT_EQ(at.linear.z(), program.retract_z) << "every setup ends at the safe height";
  }
  EXPECT_NEAR(program.retract_z, machine.joints[2].max - 1, 1e-12);
}

TEST(Post, FiveAxisPathPassesRs274WithCContinuousAndInsideTheTravel) {
  const Machine machine = machineNamed("trunnion_ac");
  const Toolpath path = fiveAxisPath();
  const MachineProgram program = buildMachineProgram(machine, path, shopTools(), "circle", {});
  ASSERT_EQ(program.mode, PostMode::FiveAxis);
  const std::string job = jobProgramText(program);
  EXPECT_NE(job.find("G93 G1"), std::string::npos);
  // Exact path: LinuxCNC's G64 P would blend only the X Y Z joints within P (test/linuxcnc/run_sim_test.sh measures it).
  EXPECT_NE(job.find("G94 G61\n"), std::string::npos);
  EXPECT_EQ(job.find("G64"), std::string::npos);
  const Rs274Run run = expectAccepted(job, program, "five_axis");
  checkAgainstToolpath(program, path, run, {0});

  // C never turns more than a move needs: no move turns it half a turn, and over the circle it turns one whole turn
  // continuously (past +-180, not wrapped back).
  double c_min = 1e9, c_max = -1e9;
  for (size_t m = 1; m < run.moves.size(); ++m) {
    EXPECT_LT(std::abs(run.moves[m][5] - run.moves[m - 1][5]), 180.0) << "move " << m;
    c_min = std::min(c_min, run.moves[m][5]);
    c_max = std::max(c_max, run.moves[m][5]);
  }
  EXPECT_GT(c_max - c_min, 359.0);
  EXPECT_TRUE(c_max > 180.0 || c_min < -180.0) << "C crossed +-180 without a jump";
}

TEST(Post, FiveAxisMovesKeepTheTipWithinTheChordalToleranceBetweenPoints) {
  const Machine machine = machineNamed("trunnion_ac");
  const Toolpath path = fiveAxisPath();
  PostOptions options;
  const MachineProgram program = buildMachineProgram(machine, path, shopTools(), "circle", options);
  const SetupProgram& setup = program.setups[0];
  Placement placement;
  placement.fixture = setup.fixture;
  placement.tool_length = program.tool(1).length;
  JointPosition at = program.start;
  int subdivided = 0;
  for (const ProgramStep& step : setup.steps) {
    const bool cutting = step.kind == StepKind::Move && step.row > 0 && path[step.row].move == MoveKind::Feed &&
                         path[step.row - 1].op == path[step.row].op;
    if (cutting) {
      if (!step.at_row) ++subdivided;
      const Vec3& a = path[step.row - 1].tip;
      const Vec3& b = path[step.row].tip;
      for (int k = 0; k <= 50; ++k) {  // the joints interpolated linearly, as the controller does
        const double f = k / 50.0;
        JointPosition joints;
        joints.linear = at.linear + f * (step.joints.linear - at.linear);
        joints.tilt = at.tilt + f * (step.joints.tilt - at.tilt);
        joints.rotary = at.rotary + f * (step.joints.rotary - at.rotary);
        const Vec3 tip = forwardKinematics(machine, placement, joints).tip;
        ASSERT_LT(distanceToSegment(tip, a, b), options.chordal_tolerance * 1.05) << "row " << step.row;
      }
    }
    if (step.kind != StepKind::ToolChange) at = step.joints;
  }
  EXPECT_GT(subdivided, 10) << "the moves near the singularity need subdividing";
}

TEST(Post, SingularPassHoldsC) {
  const Machine machine = machineNamed("trunnion_ac");
  const Toolpath path = fiveAxisPath();
  const MachineProgram program = buildMachineProgram(machine, path, shopTools(), "circle", {});
  // Op 2 goes straight through the C axis: C stays where it was all along.
  double c_first = 0;
  bool seen = false;
  for (const ProgramStep& step : program.setups[0].steps) {
    if (step.kind != StepKind::Move || step.row < 0 || path[step.row].op != 2 || path[step.row].move != MoveKind::Feed)
      continue;
    if (!seen) c_first = step.joints.rotary, seen = true;
    EXPECT_NEAR(step.joints.rotary, c_first, 1e-9) << "row " << step.row;
  }
  EXPECT_TRUE(seen);
}

// ---- through the singularity (issue 17): ball finishing over a dome of radius 30, the tool axis along the normal ----
// The dome's centre lies 36 mm off the C axis, so turning C moves the part under the tool: C must not jump.

const Vec3 kDomeCentre(30, 20, -15);

Vec3 domeNormal(double x, double y) { return Vec3(x, y, std::sqrt(30 * 30 - x * x - y * y)) / 30; }
Vec3 domePoint(double x, double y) { return kDomeCentre + 30 * domeNormal(x, y); }

// A feed along the dome through the given (x, y) in straight steps of about `step`, the axis along the normal,
// entered and left by rapids 10 mm up the axis.
void addDomePass(Toolpath& path, int op, const std::vector<Eigen::Vector2d>& corners, double step = 1.5) {
  std::vector<Eigen::Vector2d> xys;
  for (size_t c = 0; c + 1 < corners.size(); ++c) {
    const int n = std::max(1, static_cast<int>(std::round((corners[c + 1] - corners[c]).norm() / step)));
    for (int k = c == 0 ? 0 : 1; k <= n; ++k)
      xys.push_back(corners[c] + (corners[c + 1] - corners[c]) * (static_cast<double>(k) / n));
  }
  auto at = [&](const Eigen::Vector2d& xy, MoveKind move, double up) {
    const Vec3 normal = domeNormal(xy.x(), xy.y());
    return point(op, 0, "ball6", move, domePoint(xy.x(), xy.y()) + up * normal, normal);
  };
  path.push_back(at(xys.front(), MoveKind::Rapid, 10));
  for (const Eigen::Vector2d& xy : xys) path.push_back(at(xy, MoveKind::Feed, 0));
  path.push_back(at(xys.back(), MoveKind::Rapid, 10));
}

// Every feed of the path is one continuous run of feed moves in the program: no retract, no reposition in between.
void expectNoLift(const MachineProgram& program, const Toolpath& path) {
  int last_op = -1;
  bool cutting = false;
  for (const ProgramStep& step : program.setups[0].steps) {
    const bool feed = step.kind == StepKind::Move && step.row > 0 && path[step.row].move == MoveKind::Feed &&
                      path[step.row - 1].move == MoveKind::Feed;
    if (feed) {
      EXPECT_TRUE(cutting || path[step.row - 1].op != last_op) << "row " << step.row << ": the pass was interrupted";
      EXPECT_EQ(step.move, MoveKind::Feed) << "row " << step.row;
      cutting = true;
      last_op = path[step.row].op;
    } else if (step.kind != StepKind::Move || step.row < 0 || path[step.row].move == MoveKind::Rapid) {
      cutting = false;
    }
  }
}

TEST(Post, DomeRasterPassesStraightThroughTheSingularity) {
  // Five lines along x over the dome; the middle one (y = 0) passes the apex: the axis tilts -x, is vertical at x = 0
  // (A = 0: C free), then tilts +x. C carries on without a flip and the lines post without a lift.
  Toolpath path;
  int op = 0;
  for (double y : {-6.0, -3.0, 0.0, 3.0, 6.0}) addDomePass(path, op++, {{-15, y}, {15, y}});
  const Machine machine = machineNamed("trunnion_ac");
  const MachineProgram program = buildMachineProgram(machine, path, shopTools(), "dome", {});
  ASSERT_EQ(program.mode, PostMode::FiveAxis);
  const Rs274Run run = expectAccepted(jobProgramText(program), program, "dome");
  checkAgainstToolpath(program, path, run, {0});
  expectNoLift(program, path);
  // Along the middle line C never moves (the axis stays in the plane y = 0) and A passes through 0.
  double c = NAN, a_min = 1e9, a_max = -1e9;
  for (const ProgramStep& step : program.setups[0].steps) {
    if (step.kind != StepKind::Move || step.row < 0 || path[step.row].op != 2 || path[step.row].move != MoveKind::Feed)
      continue;
    if (std::isnan(c)) c = step.joints.rotary;
    EXPECT_NEAR(step.joints.rotary, c, 1e-9) << "row " << step.row;
    a_min = std::min(a_min, step.joints.tilt);
    a_max = std::max(a_max, step.joints.tilt);
  }
  EXPECT_NEAR(std::abs(std::remainder(c, kPi)), 0.5 * kPi, 1e-9) << "C at +-90 deg: the axis tilts along x";
  EXPECT_LT(a_min, -25 * kDeg);
  EXPECT_GT(a_max, 25 * kDeg);
}

TEST(Post, PassStartingVerticalTakesCFromWhereItTilts) {
  // From the apex (vertical) down the +x side, and one from the apex along +y then -x: the first pose's C is the one
  // the first tilted pose needs, so the feeds post without a lift.
  Toolpath path;
  addDomePass(path, 0, {{0, 0}, {15, 0}});
  addDomePass(path, 1, {{0, 0}, {0, 12}});
  addDomePass(path, 2, {{0, 0}, {0, 0.5}, {-12, 0.5}}, 0.5);
  const Machine machine = machineNamed("trunnion_ac");
  const MachineProgram program = buildMachineProgram(machine, path, shopTools(), "dome", {});
  const Rs274Run run = expectAccepted(jobProgramText(program), program, "dome_vertical_start");
  checkAgainstToolpath(program, path, run, {0});
  expectNoLift(program, path);
}

TEST(Post, PassTurningAtTheApexTurnsCInPlace) {
  // Along x up to the apex, then along y away from it: the axis leaves the plane y = 0 for the plane x = 0. At the
  // vertical pose C turns a quarter turn in place (the tip held on the apex, the joints subdivided so it stays within
  // the chordal tolerance) instead of a lift.
  Toolpath path;
  addDomePass(path, 0, {{-12, 0}, {0, 0}, {0, 12}});
  const Machine machine = machineNamed("trunnion_ac");
  const MachineProgram program = buildMachineProgram(machine, path, shopTools(), "dome", {});
  const Rs274Run run = expectAccepted(jobProgramText(program), program, "dome_turn");
  checkAgainstToolpath(program, path, run, {0});
  expectNoLift(program, path);
  // The turn: feed steps at the apex whose C changes while A stays 0, together a quarter turn.
  double turned = 0;
  JointPosition at = program.start;
  for (const ProgramStep& step : program.setups[0].steps) {
    if (step.kind == StepKind::Move && step.move == MoveKind::Feed && std::abs(step.joints.tilt) < 1e-9 &&
        std::abs(at.tilt) < 1e-9)
      turned += std::abs(step.joints.rotary - at.rotary);
    if (step.kind != StepKind::ToolChange) at = step.joints;
  }
  EXPECT_NEAR(turned, 0.5 * kPi, 1e-6);
}

TEST(Post, TableTiltBCPathPassesRs274) {
  const Machine machine = machineNamed("trunnion_bc");
  const Toolpath path = fiveAxisPath();
  const MachineProgram program = buildMachineProgram(machine, path, shopTools(), "circle", {});
  const Rs274Run run = expectAccepted(jobProgramText(program), program, "five_axis_bc");
  checkAgainstToolpath(program, path, run, {0});
}

TEST(Post, ThreeAxisMillRunsItsUprightSetupAndRefusesATiltedOne) {
  const Machine machine = machineNamed("mill_3axis");
  Toolpath upright;
  addPocket(upright, 0, 0, "flat6", Vec3(0, 0, 27), Vec3::UnitZ(), Vec3::UnitX());
  const MachineProgram program = buildMachineProgram(machine, upright, shopTools(), "block", {});
  const std::string job = jobProgramText(program);
  EXPECT_NE(job.find("G10 L2 P1 X0 Y0 Z0\n"), std::string::npos);
  const Rs274Run run = expectAccepted(job, program, "mill");
  checkAgainstToolpath(program, upright, run, {0});

  try {
    buildMachineProgram(machine, pocketsInTwoSetups(), shopTools(), "block", {});
    FAIL() << "a 3-axis mill cannot tilt the tool";
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("toolpaths.csv line 16"), std::string::npos) << message;
    EXPECT_NE(message.find("setup 1"), std::string::npos) << message;
    EXPECT_NE(message.find("3-axis machine cannot tilt the tool"), std::string::npos) << message;
  }
  PostOptions five;
  five.mode = PostMode::FiveAxis;
  EXPECT_THROW(buildMachineProgram(machine, upright, shopTools(), "block", five), InputError);
}

TEST(Post, UnreachablePosesAndBadInputAreReported) {
  const Machine machine = machineNamed("trunnion_ac");
  // An axis pointing down needs |A| > 100 deg on both branches.
  Toolpath down;
  down.push_back(point(0, 0, "flat6", MoveKind::Rapid, Vec3(0, 0, 40), Vec3(0, 0.2, -1)));
  down.push_back(point(0, 0, "flat6", MoveKind::Feed, Vec3(0, 0, 30), Vec3(0, 0.2, -1)));
  try {
    buildMachineProgram(machine, down, shopTools(), "part", {});
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no orientation of setup 0 keeps every point inside the travel"),
              std::string::npos) << e.what();
  }
  PostOptions five;
  five.mode = PostMode::FiveAxis;
  try {
    buildMachineProgram(machine, down, shopTools(), "part", five);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("toolpaths.csv line 2 (op 0, setup 0, tool 'flat6'): machine trunnion_ac "
                                         "cannot reach this tool pose: no solution inside the joint limits"),
              std::string::npos) << e.what();
  }
  Toolpath unknown = pocketsInTwoSetups();
  unknown[3].tool = "nosuch";
  EXPECT_THROW(buildMachineProgram(machine, unknown, shopTools(), "part", {}), InputError);
  Toolpath back_again = pocketsInTwoSetups();
  back_again.push_back(back_again.front());  // setup 0 again after setup 1
  EXPECT_THROW(buildMachineProgram(machine, back_again, shopTools(), "part", {}), InputError);
  PostOptions three;
  three.mode = PostMode::ThreePlusTwo;
  EXPECT_THROW(buildMachineProgram(machine, fiveAxisPath(), shopTools(), "part", three), InputError);
  EXPECT_THROW(buildMachineProgram(machine, {}, shopTools(), "part", {}), InputError);
}

TEST(Post, ThreePlusTwoTakesTheTurnOfCInsideItsTravel) {
  Machine machine = machineNamed("trunnion_ac");
  machine.joints[3].min = 0;            // A 0..50: only the positive branch
  machine.joints[4].min = 0;            // C 0..360: the nearest turn of -90 is outside, 270 inside
  machine.joints[4].max = 2 * kPi;
  Toolpath path;
  addPocket(path, 0, 0, "flat6", Vec3(0, 0, 20), Vec3(-0.5, 0, std::cos(30 * kDeg)), Vec3::UnitY());
  const MachineProgram program = buildMachineProgram(machine, path, shopTools(), "part", {});
  const ProgramStep& last = program.setups[0].steps.back();
  EXPECT_NEAR(last.joints.tilt, 30 * kDeg, 1e-9);
  EXPECT_NEAR(last.joints.rotary, 270 * kDeg, 1e-9);
}

// ---- drilling cycles -----------------------------------------------------------------------------------------------

Tool drillTool() {
  Tool tool = makeTool("drill6.8", ToolType::Drill);
  tool.diameter = 6.8;
  tool.shank_diameter = 6.8;
  tool.point_angle_deg = 118;
  tool.flute_length = 28;  // as long as the others (60 mm with the holder): the test machines' travel is short
  tool.plunge_mm_min = tool.feed_mm_min = 500;
  tool.max_stepdown = 10;  // the peck
  return tool;
}

std::vector<Tool> drillingTools() { return {drillTool(), makeTool("flat6", ToolType::Flat)}; }

// Holes drilled along `axis` from mouths at `mouths` (part frame), R plane 2 mm over each mouth, depth `depths`: as
// holes.h's drillingPath lays them out (clearance 10 mm over the highest mouth). `last_up`: the last hole goes back up
// to the clearance (G98) or stops at its R plane (G99).
void addDrilling(Toolpath& path, int op, int setup, const Vec3& axis, const std::vector<Vec3>& mouths,
                 const std::vector<double>& depths, bool last_up = true) {
  double top = -1e9;
  for (const Vec3& mouth : mouths) top = std::max(top, mouth.dot(axis));
  for (size_t h = 0; h < mouths.size(); ++h) {
    const Vec3 above = mouths[h] + (top + 10 - mouths[h].dot(axis)) * axis, r_plane = mouths[h] + 2 * axis;
    path.push_back(point(op, setup, "drill6.8", MoveKind::Rapid, above, axis));
    path.push_back(point(op, setup, "drill6.8", MoveKind::Rapid, r_plane, axis));
    path.push_back(point(op, setup, "drill6.8", MoveKind::Feed, mouths[h] - depths[h] * axis, axis));
    path.push_back(point(op, setup, "drill6.8", MoveKind::Rapid, r_plane, axis));
    if (h + 1 < mouths.size() || last_up) path.push_back(point(op, setup, "drill6.8", MoveKind::Rapid, above, axis));
  }
}

// Setup 0 from the top: a 10 mm hole (12 mm of feed: G81) and a 25 mm one (27 mm: G83, pecks of 10); setup 1 from
// the side (-y, the part turned for it), ending at its R plane (G99); then a pocket with the flat mill.
Toolpath drillingJob() {
  Toolpath path;
  addDrilling(path, 0, 0, Vec3::UnitZ(), {Vec3(0, 0, 20), Vec3(15, 5, 20)}, {10, 25});
  addDrilling(path, 1, 1, -Vec3::UnitY(), {Vec3(-5, -15, 10), Vec3(5, -15, 12)}, {8, 6}, false);
  addPocket(path, 2, 1, "flat6", Vec3(0, -17, 15), -Vec3::UnitY(), Vec3::UnitX());
  return path;
}

int countOf(const std::string& text, const std::string& what) {
  int count = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++count;
  return count;
}

TEST(Post, DrillingRunsBecomeCannedCyclesThatRs274ExpandsIntoOurSteps) {
  for (const char* name : {"trunnion_ac", "mill_3axis"}) {
    SCOPED_TRACE(name);
    const Machine machine = machineNamed(name);
    Toolpath path = drillingJob();
    if (!machine.fiveAxis()) path.resize(10);  // the mill makes only the upright setup 0
    const MachineProgram program = buildMachineProgram(machine, path, drillingTools(), "drilled", turnedSetupOne());
    ASSERT_EQ(program.mode, PostMode::ThreePlusTwo);
    const std::string job = jobProgramText(program);
    EXPECT_EQ(countOf(job, "G98 G81 "), machine.fiveAxis() ? 2 : 1) << job;
    EXPECT_EQ(countOf(job, "G98 G83 "), 1) << job;
    EXPECT_NE(job.find(" Q10.0000 F500.000"), std::string::npos) << job;
    if (machine.fiveAxis()) {
      EXPECT_EQ(countOf(job, "G99 G81 "), 1) << job;  // the last hole stops at its R plane
    }
    EXPECT_GE(countOf(job, "G80\n"), machine.fiveAxis() ? 3 : 2) << job;
    // Every cycle is one line; the steps are its motion: rs274's canonical moves equal them one for one and land on
    // the toolpath (checkAgainstToolpath), pecks included.
    const Rs274Run run = expectAccepted(job, program, std::string("drilling_") + name);
    checkAgainstToolpath(program, path, run, allSetups(program));
    // G83 from R 22 with Q 10 to -5: feeds to 12, to 2 (each followed by a rapid out to R and back to 0.254 mm over
    // the depth), and to -5.
    std::vector<double> feeds;
    for (size_t m = 0; m < run.moves.size(); ++m)
      if (run.feed[m] && std::abs(run.moves[m][0] - 15) < 1e-6 && std::abs(run.moves[m][1] - 5) < 1e-6)
        feeds.push_back(run.moves[m][2]);
    EXPECT_EQ(feeds, (std::vector<double>{12, 2, -5}));
  }
}

// A drilling run that crosses between holes at their R planes' height (hole_links.h, over open ground) instead of
// going up to the clearance level: each hole is still one cycle, the crossing its first move (X Y at the height it
// starts from), and rs274 runs exactly the toolpath's motion.
TEST(Post, ACycleEnteredAcrossAtItsRPlanesHeightIsStillOneCycle) {
  const Machine machine = machineNamed("mill_3axis");
  Toolpath path;
  const Vec3 axis = Vec3::UnitZ();
  const std::vector<Vec3> mouths{Vec3(0, 0, 20), Vec3(15, 5, 20), Vec3(30, 0, 20)};
  path.push_back(point(0, 0, "drill6.8", MoveKind::Rapid, mouths[0] + 10 * axis, axis));
  for (const Vec3& mouth : mouths) {
    path.push_back(point(0, 0, "drill6.8", MoveKind::Rapid, mouth + 2 * axis, axis));
    path.push_back(point(0, 0, "drill6.8", MoveKind::Feed, mouth - 8 * axis, axis));
    path.push_back(point(0, 0, "drill6.8", MoveKind::Rapid, mouth + 2 * axis, axis));
  }
  path.push_back(point(0, 0, "drill6.8", MoveKind::Rapid, mouths.back() + 10 * axis, axis));
  const MachineProgram program = buildMachineProgram(machine, path, drillingTools(), "drilled", turnedSetupOne());
  const std::string job = jobProgramText(program);
  EXPECT_EQ(countOf(job, "G99 G81 "), 3) << job;
  std::size_t cycles = 0;
  for (const SetupProgram& setup : program.setups) cycles += setup.cycles.size();
  EXPECT_EQ(cycles, 3u);
  checkAgainstToolpath(program, path, expectAccepted(job, program, "drilling_across"), allSetups(program));
}

TEST(Post, FiveAxisModeAndCyclesOffKeepPlainMoves) {
  const Machine machine = machineNamed("trunnion_ac");
  PostOptions five = turnedSetupOne();
  five.mode = PostMode::FiveAxis;
  const Toolpath path = drillingJob();
  const MachineProgram continuous = buildMachineProgram(machine, path, drillingTools(), "drilled", five);
  std::string job = jobProgramText(continuous);
  EXPECT_EQ(job.find("G81"), std::string::npos);
  EXPECT_EQ(job.find("G83"), std::string::npos);
  checkAgainstToolpath(continuous, path, expectAccepted(job, continuous, "drilling_5axis"), allSetups(continuous));
  PostOptions off = turnedSetupOne();
  off.drilling_cycles = false;
  const MachineProgram plain = buildMachineProgram(machine, path, drillingTools(), "drilled", off);
  job = jobProgramText(plain);
  EXPECT_EQ(job.find("G81"), std::string::npos);
  for (const SetupProgram& setup : plain.setups) EXPECT_TRUE(setup.cycles.empty());
}

// The trajectory is the cycle's motion: its feed moves travel what rs274's STRAIGHT_FEEDs do (the pecks' extra
// length included), at the drill's feed.
TEST(Post, TrajectoryTimesTheCyclesMotion) {
  const Machine machine = machineNamed("mill_3axis");
  Toolpath path = drillingJob();
  path.resize(10);
  const MachineProgram program = buildMachineProgram(machine, path, drillingTools(), "drilled", {});
  const Rs274Run run = expectAccepted(jobProgramText(program), program, "drilling_time");
  double canonical_feed = 0;
  for (size_t m = 1; m < run.moves.size(); ++m)
    if (run.feed[m]) canonical_feed += std::abs(run.moves[m][2] - run.moves[m - 1][2]);
  const std::vector<JointWaypoint> waypoints = programWaypoints(program);
  double feed = 0;
  for (size_t w = 1; w < waypoints.size(); ++w)
    if (waypoints[w].move == MoveKind::Feed) feed += (waypoints[w].joints.linear - waypoints[w - 1].joints.linear).norm();
  // 12 mm of G81; G83 from R 22: 10, 10 + 0.254, 7 + 0.254 (to -5): 27.508 mm.
  EXPECT_NEAR(canonical_feed, 12 + 10 + 10.254 + 7.254, 1e-3);
  EXPECT_NEAR(feed, canonical_feed, 1e-3);
  const JointTrajectory trajectory = parameterizeTrajectory(machine, waypoints);
  EXPECT_GT(trajectory.duration(), 60 * feed / 500);
}

TEST(Post, ToolTablesInMillimetresAndForRs274InInches) {
  const Machine machine = machineNamed("trunnion_ac");
  const MachineProgram program = buildMachineProgram(machine, pocketsInTwoSetups(), shopTools(), "block", {});
  EXPECT_EQ(toolTableText(program, ToolTableUnits::Millimetres),
            "T1 P1 Z60.000000 D6.000000 ;flat6 flat\nT2 P2 Z60.000000 D6.000000 ;ball6 ball\n");
  EXPECT_NE(toolTableText(program, ToolTableUnits::Inches).find("T1 P1 Z2.362205 D0.236220"), std::string::npos);
}

TEST(Post, CommandWritesTheProgramsTheToolTablesAndTheTrajectory) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "art2part_test_post_cli";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  writeToolpathsCsv(pocketsInTwoSetups(), (dir / "toolpaths.csv").string());
  writeToolsJson(shopTools(), (dir / "tools.json").string());
  const std::string machine = std::string(ART2PART_SOURCE_DIR) + "/config/machines/trunnion_ac.yaml";
  const std::string command = std::string(ART2PART_CLI) + " post " + dir.string() + " --machine " + machine +
                              " --out " + (dir / "out").string() + " --rate 50 > " + (dir / "log").string() + " 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0) << readFile((dir / "log").string());
  for (const char* name : {"program.ngc", "setup_0.ngc", "setup_1.ngc", "tool.tbl", "tool_rs274.tbl", "trajectory.csv"})
    EXPECT_TRUE(std::filesystem::exists(dir / "out" / name)) << name;
  const std::string csv = readFile((dir / "out" / "trajectory.csv").string());
  EXPECT_EQ(csv.substr(0, csv.find('\n')), "time,X,Y,Z,A,C");
  const std::string run = "rs274 -g -t " + (dir / "out" / "tool_rs274.tbl").string() + " " +
                          (dir / "out" / "program.ngc").string() + " " + (dir / "canon").string() + " > /dev/null 2>&1";
  EXPECT_EQ(std::system(run.c_str()), 0);

  const std::string bad = std::string(ART2PART_CLI) + " post " + dir.string() + " --machine " +
                          std::string(ART2PART_SOURCE_DIR) + "/config/machines/mill_3axis.yaml --out " +
                          (dir / "mill").string() + " > " + (dir / "log").string() + " 2>&1";
  const int status = std::system(bad.c_str());
  EXPECT_EQ(WEXITSTATUS(status), 1);
  EXPECT_NE(readFile((dir / "log").string()).find("cannot tilt the tool"), std::string::npos);
}

}  // namespace
