// Time parameterization: joint waypoints (the post's moves) -> a joint trajectory q(t) that respects every joint's
// maximum velocity and acceleration, runs feed moves at the tool's feed at the tip and rapids at the machine's rapid
// rates.
//
// Method (piecewise-constant acceleration, "linear segments with parabolic blends" along the path):
//   * The path is the polyline through the waypoints in joint space (what the controller runs between G-code points).
//     Segment i has direction e_i = dq_i / l_i, its length l_i = sqrt(sum_j (dq_ij / vmax_j)^2) in a velocity-scaled
//     metric (seconds), and the path speed sigma = ds/dt moves the joints at sigma e_i.
//   * Per segment: a speed limit V_i = min over joints vlimit_j / |e_ij| (vlimit = max velocity, or rapid velocity on a
//     rapid), lowered on a feed move so the tip moves at most at the feed (tip length of the segment from forward
//     kinematics), and an acceleration limit A_i = min over joints amax_j / |e_ij|.
//   * At an interior waypoint k the direction turns from e_{k-1} to e_k at a constant speed sigma_k, by a parabolic
//     blend of duration 2 tau_k, tau_k = sigma_k beta_k, beta_k = max_j |e_kj - e_{k-1,j}| / (2 amax_j): every joint
//     accelerates at most at amax_j. The blend starts and ends sigma_k tau_k before and after the waypoint (at most a
//     third of either segment). Its speed sigma_k is capped so that the tip stays within blend_tolerance of the
//     unblended path (below). Waypoints marked `stop`, the first and the last are passed at rest.
//   * Between blends the speed follows the time-optimal trapezoid (accelerate at A_i, cruise at V_i, decelerate) that
//     meets the blend speeds, which a forward and a backward pass over the waypoints make reachable.
//   The result is C1 (velocities continuous) and piecewise quadratic, so every joint's velocity and acceleration stay
//   within the limits at every instant (and so do finite differences of samples: they average the true values).
//
// Error bound: outside the blends the joints are exactly on the polyline; in a blend the tip is within
// blend_tolerance of where the unblended polyline puts it at the same path parameter (checked at 7 points per blend,
// the blend speed lowered until it holds; the deviation grows as sigma^2, smoothly, so between the checks it exceeds
// the tolerance only by terms of higher order). The post keeps the polyline's tip within chordal_tolerance of the CL
// path, so the tip stays within chordal_tolerance + blend_tolerance of toolpaths.csv.
// Time: no segment's tip moves faster than its feed, so the total time is at least the feed length / feed.
// Not modelled: tool change and M0 time (the trajectory stops there for no time), jerk, controller look-ahead.
#pragma once

#include <string>
#include <vector>

#include "art2part/kinematics/machine.h"
#include "art2part/post/machine_program.h"

namespace art2part {

struct JointWaypoint {
  JointPosition joints;             // mm, rad
  MoveKind move = MoveKind::Rapid;  // how the machine gets here from the previous waypoint
  double feed_mm_min = 0;           // feed move: the tip's feed relative to the part
  double tool_length = 0;           // the tool in the spindle on the way here (for the tip)
  bool stop = false;                // come to rest here (tool change, program stop)
};

// The post's motion: the start position, then one waypoint per move and retract; stops at tool changes and at the end
// of every setup.
std::vector<JointWaypoint> programWaypoints(const MachineProgram& program);

struct TrajectoryOptions {
  double blend_tolerance = 0.005;  // mm: the tip's deviation in a corner blend
};

// The straight path from waypoint i to i + 1: q(s) = start + s * direction, s in [0, length] (length in the
// velocity-scaled metric, seconds; direction in joint units per second).
struct TrajectorySegment {
  Eigen::VectorXd start, direction;
  double length = 0;
};

// One stretch of constant joint acceleration, described along the path.
//   straight piece on segment i: s(t) = s0 + sigma0 (t - start) + sigma_dot (t - start)^2 / 2, q = q_i(s)
//   blend around waypoint k (segment = k): the turn from direction e_{k-1} to e_k at constant speed sigma0, starting
//     at s0 = -sigma0^2 beta_k before the waypoint on segment k - 1: q = q_k + (s0 + sigma0 tau) e_{k-1}
//     + (e_k - e_{k-1}) tau^2 / (4 beta_k), tau = t - start in [0, 2 sigma0 beta_k]
struct TrajectoryPiece {
  double start = 0, duration = 0;  // s
  int segment = 0;
  bool blend = false;
  double s0 = 0, sigma0 = 0, sigma_dot = 0;
};

// Where the trajectory nominally is along the polyline: segment `segment` (waypoint segment -> segment + 1) at
// `fraction` of it. Outside blends the joints are exactly there; in a blend, at the path parameter s0 + sigma0 tau.
struct PathPoint {
  int segment = 0;
  double fraction = 0;
};

class JointTrajectory {
 public:
  JointTrajectory() = default;
  JointTrajectory(const Machine& machine, std::vector<JointWaypoint> waypoints, std::vector<TrajectorySegment> segments,
                  std::vector<double> corner_beta, std::vector<TrajectoryPiece> pieces);

  double duration() const;
  const std::vector<std::string>& jointNames() const { return joint_names_; }
  const std::vector<bool>& rotary() const { return rotary_; }
  // The waypoints as parameterized: consecutive duplicates merged (their stops kept).
  const std::vector<JointWaypoint>& waypoints() const { return waypoints_; }
  const std::vector<TrajectorySegment>& segments() const { return segments_; }
  const std::vector<TrajectoryPiece>& pieces() const { return pieces_; }

  // machine.joints order, mm and rad (per s, per s^2); t clamped to [0, duration].
  std::vector<double> positionAt(double t) const;
  std::vector<double> velocityAt(double t) const;
  std::vector<double> accelerationAt(double t) const;
  PathPoint pathPointAt(double t) const;
  // The joints on the polyline at a path point (no blending).
  std::vector<double> pathPosition(const PathPoint& point) const;

 private:
  const TrajectoryPiece* pieceAt(double t, double& tau) const;  // nullptr when there is no motion
  // The joints' time derivative of the given order (0 position, 1 velocity, 2 acceleration) at time t, clamped to
  // the motion; before any motion the first position and zero rates.
  std::vector<double> derivativeAt(double t, int order) const;

  std::vector<std::string> joint_names_;
  std::vector<bool> rotary_;
  std::vector<JointWaypoint> waypoints_;
  std::vector<TrajectorySegment> segments_;
  std::vector<double> corner_beta_;  // per waypoint; 0 at the ends and where the path does not turn
  std::vector<TrajectoryPiece> pieces_;
  Eigen::VectorXd first_;  // the first waypoint: where a trajectory without motion stays
};

// Throws InputError for an empty list, NaN, or joints outside the travel.
JointTrajectory parameterizeTrajectory(const Machine& machine, const std::vector<JointWaypoint>& waypoints,
                                       const TrajectoryOptions& options = {});

struct TrajectorySample {
  double time = 0;             // s
  std::vector<double> joints;  // machine.joints order, mm and rad
};

// At t = 0, 1/rate, 2/rate, ... and the last at the end.
std::vector<TrajectorySample> sampleTrajectory(const JointTrajectory& trajectory, double rate_hz);

// CSV: header `time,X,Y,Z,A,C` (the joint names), then one row per sample: seconds, mm and degrees (the units of the
// machine file and the G-code). Throws InputError when the file cannot be written.
void writeTrajectoryCsv(const JointTrajectory& trajectory, double rate_hz, const std::string& path);

}  // namespace art2part
