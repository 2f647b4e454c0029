// Time parameterization of a joint polyline: segment limits, corner blends capped by the joints' accelerations and the
// tip tolerance, forward and backward passes over the corner speeds, trapezoids between the blends. See
// joint_trajectory.h for the method and its bound.
#include <algorithm>
#include <cmath>
#include <limits>

#include "art2part/kinematics/inverse_kinematics.h"
#include "art2part/post/joint_trajectory.h"

namespace art2part {

namespace {

using Vector = Eigen::VectorXd;

constexpr int kBlendChecks = 8;       // the tip deviation of a blend is checked at 1/8 .. 7/8 of it
constexpr int kTipLengthPieces = 8;   // a segment's tip length: the chords of 8 pieces
constexpr double kBlendShare = 1.0 / 3;  // a blend takes at most a third of either segment

Vector toVector(const Machine& machine, const JointPosition& joints) {
  const std::vector<double> values = jointVector(machine, joints);
  return Eigen::Map<const Vector>(values.data(), static_cast<Eigen::Index>(values.size()));
}

JointPosition toJoints(const Machine& machine, const Vector& q) {
  return jointPositionFromVector(machine, std::vector<double>(q.data(), q.data() + q.size()));
}

Vec3 tipOf(const Machine& machine, double tool_length, const Vector& q) {
  return toolPoseInTable(machine, tool_length, toJoints(machine, q)).tip;
}

// Per segment: the speed and path-acceleration limits.
struct SegmentLimits {
  double speed = 0;  // V_i
  double accel = 0;  // A_i
};

class Parameterizer {
 public:
  Parameterizer(const Machine& machine, std::vector<JointWaypoint> waypoints, const TrajectoryOptions& options)
      : machine_(machine), options_(options), waypoints_(std::move(waypoints)) {}

  JointTrajectory run() {
    checkAndMerge();
    buildSegments();
    buildCorners();
    passes();
    buildPieces();
    return JointTrajectory(machine_, waypoints_, segments_, beta_, pieces_);
  }

 private:
  int joints() const { return machine_.jointCount(); }

  void checkAndMerge() {
    if (waypoints_.empty()) throw InputError("trajectory: no waypoints");
    std::vector<JointWaypoint> merged;
    for (size_t i = 0; i < waypoints_.size(); ++i) {
      const JointWaypoint& waypoint = waypoints_[i];
      const Vector q = toVector(machine_, waypoint.joints);
      if (!q.allFinite()) throw InputError("trajectory: waypoint " + std::to_string(i) + " has NaN joints");
      const std::string violation = limitViolation(machine_, waypoint.joints, 1e-6);
      if (!violation.empty())
        throw InputError("trajectory: waypoint " + std::to_string(i) + " leaves the travel (" + violation + ")");
      if (waypoint.move == MoveKind::Feed && !(waypoint.feed_mm_min > 0) && i > 0)
        throw InputError("trajectory: feed move to waypoint " + std::to_string(i) + " without a feed");
      if (!merged.empty() && scaledLength(toVector(machine_, merged.back().joints), q) < 1e-12) {
        merged.back().stop = merged.back().stop || waypoint.stop;
        continue;
      }
      merged.push_back(waypoint);
    }
    waypoints_ = std::move(merged);
    q_.clear();
    for (const JointWaypoint& waypoint : waypoints_) q_.push_back(toVector(machine_, waypoint.joints));
  }

  double scaledLength(const Vector& a, const Vector& b) const {
    double sum = 0;
    for (int j = 0; j < joints(); ++j) sum += std::pow((b[j] - a[j]) / machine_.joints[j].max_velocity, 2);
    return std::sqrt(sum);
  }

  // The tip's path length over segment i (chords of its forward kinematics).
  double tipLength(int i) const {
    const double tool = waypoints_[i + 1].tool_length;
    double length = 0;
    Vec3 previous = tipOf(machine_, tool, q_[i]);
    for (int k = 1; k <= kTipLengthPieces; ++k) {
      const Vec3 tip = tipOf(machine_, tool, q_[i] + (q_[i + 1] - q_[i]) * (static_cast<double>(k) / kTipLengthPieces));
      length += (tip - previous).norm();
      previous = tip;
    }
    return length;
  }

  void buildSegments() {
    for (int i = 0; i + 1 < static_cast<int>(q_.size()); ++i) {
      TrajectorySegment segment;
      segment.start = q_[i];
      segment.length = scaledLength(q_[i], q_[i + 1]);
      segment.direction = (q_[i + 1] - q_[i]) / segment.length;
      const JointWaypoint& to = waypoints_[i + 1];
      SegmentLimits limit;
      limit.speed = limit.accel = std::numeric_limits<double>::infinity();
      for (int j = 0; j < joints(); ++j) {
        const double e = std::abs(segment.direction[j]);
        if (e == 0) continue;
        const Joint& joint = machine_.joints[j];
        const double velocity = to.move == MoveKind::Rapid ? joint.rapid_velocity : joint.max_velocity;
        limit.speed = std::min(limit.speed, velocity / e);
        limit.accel = std::min(limit.accel, joint.max_acceleration / e);
      }
      if (to.move == MoveKind::Feed) {
        const double tip = tipLength(i);
        if (tip > 0) limit.speed = std::min(limit.speed, to.feed_mm_min / 60 * segment.length / tip);
      }
      segments_.push_back(segment);
      limits_.push_back(limit);
    }
  }

  // beta_k = max_j |e_k - e_{k-1}|_j / (2 amax_j): the blend at speed sigma lasts 2 sigma beta_k.
  double cornerBeta(int k) const {
    const Vector turn = segments_[k].direction - segments_[k - 1].direction;
    double beta = 0;
    for (int j = 0; j < joints(); ++j) beta = std::max(beta, std::abs(turn[j]) / (2 * machine_.joints[j].max_acceleration));
    return beta;
  }

  // The blend's joints at local time tau (see TrajectoryPiece).
  Vector blendAt(int k, double sigma, double tau) const {
    const Vector& before = segments_[k - 1].direction;
    const Vector& after = segments_[k].direction;
    const double s0 = -sigma * sigma * beta_[k];
    return q_[k] + (s0 + sigma * tau) * before + (after - before) * (tau * tau / (4 * beta_[k]));
  }

  // The largest distance of the blended tip from the polyline's tip at the same path parameter.
  double blendDeviation(int k, double sigma) const {
    const double tau_total = 2 * sigma * beta_[k];
    const double s0 = -sigma * sigma * beta_[k];
    const double tool = waypoints_[k].tool_length;
    double deviation = 0;
    for (int m = 1; m < kBlendChecks; ++m) {
      const double tau = tau_total * m / kBlendChecks;
      const double s = s0 + sigma * tau;
      const Vector on_path = q_[k] + s * (s < 0 ? segments_[k - 1].direction : segments_[k].direction);
      deviation = std::max(deviation, (tipOf(machine_, tool, blendAt(k, sigma, tau)) -
                                       tipOf(machine_, tool, on_path)).norm());
    }
    return deviation;
  }

  // The fastest a corner may be passed: both segments' speed limits, the blend inside a third of each segment and
  // the tip within the blend tolerance.
  double cornerCap(int k) const {
    double cap = std::min(limits_[k - 1].speed, limits_[k].speed);
    if (beta_[k] == 0) return cap;
    cap = std::min(cap, std::sqrt(kBlendShare * std::min(segments_[k - 1].length, segments_[k].length) / beta_[k]));
    for (int attempt = 0; attempt < 60; ++attempt) {
      const double deviation = blendDeviation(k, cap);
      if (deviation <= options_.blend_tolerance) return cap;
      cap *= std::sqrt(0.8 * options_.blend_tolerance / deviation);  // the deviation grows as sigma^2
    }
    return 0;
  }

  void buildCorners() {
    const int n = static_cast<int>(q_.size());
    beta_.assign(n, 0.0);
    cap_.assign(n, 0.0);
    for (int k = 1; k + 1 < n; ++k) {
      if (waypoints_[k].stop) continue;
      beta_[k] = cornerBeta(k);
      cap_[k] = cornerCap(k);
    }
  }

  // The straight length of segment i when its corners are passed at their caps (the least it will have).
  double straightLength(int i) const {
    return segments_[i].length - beta_[i] * cap_[i] * cap_[i] - beta_[i + 1] * cap_[i + 1] * cap_[i + 1];
  }

  void passes() {
    sigma_ = cap_;
    const int segments = static_cast<int>(segments_.size());
    for (int i = 0; i < segments; ++i) {
      const double reach = sigma_[i] * sigma_[i] + 2 * limits_[i].accel * std::max(0.0, straightLength(i));
      sigma_[i + 1] = std::min(sigma_[i + 1], std::sqrt(reach));
    }
    for (int i = segments - 1; i >= 0; --i) {
      const double reach = sigma_[i + 1] * sigma_[i + 1] + 2 * limits_[i].accel * std::max(0.0, straightLength(i));
      sigma_[i] = std::min(sigma_[i], std::sqrt(reach));
    }
  }

  void addPiece(TrajectoryPiece piece) {
    if (!(piece.duration > 0)) return;
    piece.start = time_;
    time_ += piece.duration;
    pieces_.push_back(piece);
  }

  void addBlend(int k) {
    const double sigma = sigma_[k];
    if (beta_[k] == 0 || sigma == 0) return;
    TrajectoryPiece piece;
    piece.blend = true;
    piece.segment = k;
    piece.s0 = -sigma * sigma * beta_[k];
    piece.sigma0 = sigma;
    piece.duration = 2 * sigma * beta_[k];
    addPiece(piece);
  }

  // The time-optimal trapezoid on segment i between the blends: from sigma_i to sigma_{i+1}.
  void addStraight(int i) {
    const double from = sigma_[i], to = sigma_[i + 1];
    const double s_begin = beta_[i] * from * from;
    const double s_end = segments_[i].length - beta_[i + 1] * to * to;
    const double length = std::max(0.0, s_end - s_begin);
    const double accel = limits_[i].accel;
    const double peak = std::max(std::max(from, to),
                                 std::min(limits_[i].speed, std::sqrt(0.5 * (from * from + to * to) + accel * length)));
    const double speeding = (peak * peak - from * from) / (2 * accel);
    const double slowing = (peak * peak - to * to) / (2 * accel);
    const double cruise = std::max(0.0, length - speeding - slowing);
    TrajectoryPiece piece;
    piece.segment = i;
    piece.s0 = s_begin;
    piece.sigma0 = from;
    piece.sigma_dot = accel;
    piece.duration = (peak - from) / accel;
    addPiece(piece);
    piece.s0 = s_begin + speeding;
    piece.sigma0 = peak;
    piece.sigma_dot = 0;
    piece.duration = peak > 0 ? cruise / peak : 0;
    addPiece(piece);
    piece.s0 = s_begin + speeding + cruise;
    piece.sigma_dot = -accel;
    piece.duration = (peak - to) / accel;
    addPiece(piece);
  }

  void buildPieces() {
    const int n = static_cast<int>(q_.size());
    for (int k = 0; k < n; ++k) {
      if (k > 0 && k + 1 < n) addBlend(k);
      if (k + 1 < n) addStraight(k);
    }
  }

  const Machine& machine_;
  TrajectoryOptions options_;
  std::vector<JointWaypoint> waypoints_;
  std::vector<Vector> q_;
  std::vector<TrajectorySegment> segments_;
  std::vector<SegmentLimits> limits_;
  std::vector<double> beta_, cap_, sigma_;
  std::vector<TrajectoryPiece> pieces_;
  double time_ = 0;
};

}  // namespace

JointTrajectory parameterizeTrajectory(const Machine& machine, const std::vector<JointWaypoint>& waypoints,
                                       const TrajectoryOptions& options) {
  if (!(options.blend_tolerance > 0)) throw InputError("trajectory: the blend tolerance must be positive");
  return Parameterizer(machine, waypoints, options).run();
}

}  // namespace art2part
