// 3+2 drilling runs as canned cycles (machine_program.h): recognised in the toolpath, their motion laid out step by
// step exactly as rs274ngc expands G81 and G83 (LinuxCNC 2.9, interp_cycles.cc), so the program's steps, the G-code
// the writer prints for them and the trajectory all describe the one motion.
#include <cmath>
#include <string>

#include "art2part/post/gcode.h"
#include "program_builder.h"

namespace art2part::post_detail {

namespace {

constexpr double kSameXy = 1e-6;   // mm: joints this close in X and Y are on one drilling axis
constexpr double kSameZ = 1e-6;    // mm
// rs274ngc's G83: after each peck it rapids back down to 0.010 inch above the depth reached (G83_RAPID_DELTA).
constexpr double kG83RapidDelta = 0.010 * 25.4;

bool sameRotaries(const JointPosition& a, const JointPosition& b) { return a.tilt == b.tilt && a.rotary == b.rotary; }

bool sameXy(const JointPosition& a, const JointPosition& b) {
  return std::abs(a.linear.x() - b.linear.x()) < kSameXy && std::abs(a.linear.y() - b.linear.y()) < kSameXy &&
         sameRotaries(a, b);
}

// A value as the interpreter reads it back from the program (the writer prints 4 decimals).
double printed(double value) { return std::stod(gcodeNumber(value)); }

}  // namespace

int planDrillingCycle(ProgramBuilder& builder, const FixedOrientation& orientation, PointRun run, int row) {
  const Toolpath& path = builder.path();
  if (!builder.options().drilling_cycles || row + 2 >= run.end) return row;
  const PostTool& tool = builder.toolOf(row);
  if (tool.tool.type != ToolType::Drill) return row;
  if (path[row].move != MoveKind::Rapid || path[row + 1].move != MoveKind::Feed || path[row + 2].move != MoveKind::Rapid)
    return row;
  const JointPosition start = builder.current();
  const JointPosition r_plane = orientation.jointsFor(path[row].tip);
  const JointPosition bottom = orientation.jointsFor(path[row + 1].tip);
  const JointPosition back = orientation.jointsFor(path[row + 2].tip);
  // Straight down the spindle from where the tool stands above the R plane, or from across at the R plane's height
  // (the cycle's own first move: X Y at the height it starts from), and back up to the R plane.
  const bool above = sameXy(start, r_plane);
  const bool across = sameRotaries(start, r_plane) && std::abs(start.linear.z() - r_plane.linear.z()) < kSameZ;
  if (!(above || across) || !sameXy(r_plane, bottom) ||
      !sameXy(r_plane, back) ||
      std::abs(back.linear.z() - r_plane.linear.z()) > kSameZ || !(bottom.linear.z() < r_plane.linear.z() - kSameZ) ||
      start.linear.z() < r_plane.linear.z() - kSameZ)
    return row;

  // In program coordinates, as the interpreter reads the cycle's words.
  const double length = tool.length;
  const auto program_z = [&](const JointPosition& joints) { return printed(programXyz(joints, length).z()); };
  DrillCycle cycle;
  cycle.bottom = bottom;
  cycle.r_z = r_plane.linear.z();
  cycle.feed_mm_min = tool.tool.plunge_mm_min;
  const double depth = r_plane.linear.z() - bottom.linear.z();
  if (depth > builder.options().peck_ratio * tool.tool.diameter)
    cycle.peck = tool.tool.max_stepdown > 0 ? tool.tool.max_stepdown : tool.tool.diameter;
  // G98 when the toolpath goes straight back up to where the cycle began.
  int next = row + 3;
  cycle.retract_to_start = false;
  if (row + 3 < run.end && path[row + 3].move == MoveKind::Rapid &&
      start.linear.z() > r_plane.linear.z() + kSameZ) {
    const JointPosition up = orientation.jointsFor(path[row + 3].tip);
    if (sameXy(up, r_plane) && std::abs(up.linear.z() - start.linear.z()) < kSameZ) {
      cycle.retract_to_start = true;
      next = row + 4;
    }
  }
  cycle.clear_z = cycle.retract_to_start ? start.linear.z() : r_plane.linear.z();
  const int index = builder.addCycle(cycle);

  const auto at_z = [&](double z_program) {
    JointPosition joints = r_plane;
    joints.linear.z() = z_program + length;
    return joints;
  };
  const auto step = [&](MoveKind move, const JointPosition& joints, int to_row, bool at_row) {
    ProgramStep s;
    s.move = move;
    s.joints = joints;
    s.row = to_row;
    s.at_row = at_row;
    s.tip_length = std::abs(joints.linear.z() - builder.current().linear.z()) +
                   (joints.linear.head<2>() - builder.current().linear.head<2>()).norm();
    if (move == MoveKind::Feed) s.feed_mm_min = cycle.feed_mm_min;
    builder.cycleStep(s, index);
  };
  // Preliminary motion: X Y at the start height (no length when the tool stands above the R plane, but the interpreter
  // makes the move; from across, the toolpath's own rapid to the R plane), then down to R.
  JointPosition over = r_plane;
  over.linear.z() = start.linear.z();
  step(MoveKind::Rapid, over, row, !above);
  if (std::abs(start.linear.z() - r_plane.linear.z()) > kSameZ) step(MoveKind::Rapid, r_plane, row, true);
  if (cycle.peck > 0) {
    // G83: for (d = r - q; d > z; d -= q) { feed to d; rapid to r; rapid to d + delta }, then the last feed.
    const double r = program_z(r_plane), z = program_z(bottom), q = printed(cycle.peck);
    for (double d = r - q; d > z; d -= q) {
      step(MoveKind::Feed, at_z(d), row + 1, false);
      step(MoveKind::Rapid, at_z(r), row + 1, false);
      step(MoveKind::Rapid, at_z(d + kG83RapidDelta), row + 1, false);
    }
  }
  step(MoveKind::Feed, bottom, row + 1, true);
  JointPosition clear = r_plane;
  clear.linear.z() = cycle.clear_z;
  step(MoveKind::Rapid, clear, next - 1, true);
  return next;
}

}  // namespace art2part::post_detail
