// Cycle time: how long a machine takes to run a toolpath (toolpaths.csv), move by move, at its velocity and
// acceleration limits, plus its tool changes and setup changes. plan.json's times come from here.
//
// Model (the rules of the post's time parameterization, joint_trajectory.h, applied to the path in the part frame):
//   * The path runs setup by setup; within a setup the part frame is turned into the machine's X Y Z by the setup's
//     rotation (the setup frame along the table's axes, as a 3-axis setup clamps it), so each axis's limits apply
//     to its own component of a move.
//   * A chain of moves is what runs without a stop: it starts at rest at a row whose tool or setup differs from the
//     row before (a tool change or a new clamping: no motion is timed from the tool-change position) and ends at rest
//     at the chain's last row.
//   * Per move (segment from the previous row to this one, length L mm, unit direction u in machine axes):
//       speed limit V = min over axes vlimit_j / |u_j| (vlimit = the axis's rapid velocity on a rapid, its maximum
//       velocity on a feed), and on a feed move also the feed the post writes for it (machine_program.h): the
//       tool's plunge feed when the move heads down the tool axis steeper than plunge_angle_deg from it, otherwise
//       its cutting feed;
//       acceleration limit A = min over axes amax_j / |u_j|.
//   * At a corner between moves the direction turns from u1 to u2 at a constant speed v by a parabolic blend of
//     2 v beta seconds, beta = max_j |u2_j - u1_j| / (2 amax_j): every axis accelerates at most at amax_j. The blend
//     covers v^2 beta of path on either side, at most a third of either move, and its tip is at most
//     |u2 - u1| v^2 beta / 4 off the corner: v is capped so that this stays within the blend tolerance. A straight
//     continuation (u1 = u2) has no blend and passes at the lower of the two speed limits.
//   * Between blends each move follows the time-optimal trapezoid (accelerate at A, cruise at V, decelerate) that
//     meets the corner speeds, which a forward and a backward pass over the chain make reachable.
//   * A move whose tool axis turns by theta (5-axis) is also held to the machine's slowest rotary joint: its speed to
//     omega L / theta and its acceleration to alpha L / theta (a pure turn, L = 0, takes the trapezoid of theta at
//     omega and alpha from rest to rest). Simplification: the rotary joints' motion is taken as the turn of the tool
//     axis (a C axis swinging near the pole moves more); on a machine without rotary joints axis turns cost no time.
//   * Tool change: tool_change_s each time the row's tool differs from the one in the spindle, the first load
//     included; setup change: setup_change_s each time the setup differs from the row before.
// Not modelled: jerk, controller look-ahead beyond one corner, spindle start, the move from the tool-change position.
#pragma once

#include <map>
#include <vector>

#include "art2part/kinematics/machine.h"
#include "art2part/tooling/tool.h"
#include "art2part/tooling/toolpath.h"

namespace art2part {

// What the time model needs of a machine.
struct MotionLimits {
  Vec3 feed_velocity = Vec3::Constant(400);  // mm/s per machine axis X Y Z: the most a feed move reaches
  Vec3 rapid_velocity = Vec3::Constant(400); // mm/s per axis on a rapid
  Vec3 acceleration = Vec3::Constant(3000);  // mm/s^2 per axis
  double rotary_velocity = 0;      // rad/s of the slowest rotary joint; 0: the machine has none
  double rotary_acceleration = 0;  // rad/s^2 of the slowest rotary joint
  double blend_tolerance = 0.005;  // mm: how far a corner blend may leave the path (TrajectoryOptions' default)
  double plunge_angle_deg = 45;    // a feed move heading down the axis within this of it plunges (PostOptions')
  double tool_change_s = kDefaultToolChangeSeconds;    // per tool change
  double setup_change_s = kDefaultSetupChangeSeconds;  // per change of clamping between setups
};

// The machine's limits (its X Y Z joints, its slowest rotary joint, its change times). A machine without joints (none
// given) has the documented default: the limits above, those of config/machines/vmc_3axis.yaml, the default machine
// of `art2part plan`.
MotionLimits motionLimits(const Machine& machine);

// Time and length of a piece of a path, split by what the machine does.
struct CycleTime {
  double cutting_s = 0;       // feed moves
  double rapid_s = 0;         // rapid moves
  double tool_change_s = 0;   // tool changes
  double setup_change_s = 0;  // changes of clamping
  double cutting_mm = 0, rapid_mm = 0;  // path length of the feed and the rapid moves
  int tool_changes = 0, setup_changes = 0;

  double motion_s() const { return cutting_s + rapid_s; }
  double total_s() const { return cutting_s + rapid_s + tool_change_s + setup_change_s; }
  CycleTime& operator+=(const CycleTime& other);
};

// A whole path's time: per operation (toolpaths.csv's op), per setup and in all. An operation holds its moves and the
// tool change that starts it; a setup also holds the setup change that starts it.
struct PathTime {
  std::map<int, CycleTime> by_op;
  std::map<int, CycleTime> by_setup;
  CycleTime total;
};

// `setup_rotation`: per setup index, the rotation from the part frame to the machine's axes (a setup without one:
// identity). Feeds come from `tools` (feed_mm_min, plunge_mm_min). Throws InputError for a tool id the path uses but
// `tools` lacks, a tool without a positive feed, or limits that are not positive.
PathTime cycleTime(const Toolpath& path, const std::vector<Tool>& tools, const MotionLimits& limits,
                   const std::map<int, Eigen::Matrix3d>& setup_rotation = {});

// Pieces of the model, for the tests: the time of a straight move of `length` starting at speed v0 and ending at v1
// under speed limit `speed` and acceleration `accel` (the trapezoid, or the triangle when it never cruises). v0 and v1
// must be reachable from each other over the length.
double trapezoidSeconds(double length, double v0, double v1, double speed, double accel);

}  // namespace art2part
