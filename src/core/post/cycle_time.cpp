// Cycle time of a toolpath: chains of moves at the machine's limits, corner blends, trapezoids, tool and setup changes
// (cycle_time.h states the model).
#include "art2part/post/cycle_time.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace art2part {

namespace {

constexpr double kBlendShare = 1.0 / 3;  // a blend takes at most a third of either move (as joint_trajectory.cpp)
constexpr double kNoMotion = 1e-9;        // mm or rad: a move shorter than this and turning less is no move
constexpr double kInfinity = std::numeric_limits<double>::infinity();
constexpr double kDegree = 3.14159265358979323846 / 180;

// One move of a chain: from the row before to `row`.
struct ChainMove {
  int row = 0;
  double length = 0;       // mm; for a pure turn of the tool axis, its angle in rad
  bool pure_turn = false;  // the tip stays, the axis turns: timed on the rotary limits alone
  Vec3 direction = Vec3::Zero();  // unit, machine axes (zero for a pure turn)
  double speed = 0, accel = 0;    // limits along the move: mm/s, mm/s^2 (rad/s, rad/s^2 for a pure turn)
};

void checkLimits(const MotionLimits& limits) {
  const bool positive = (limits.feed_velocity.array() > 0).all() && (limits.rapid_velocity.array() > 0).all() &&
                        (limits.acceleration.array() > 0).all() && limits.blend_tolerance > 0;
  if (!positive) throw InputError("cycle time: velocities, accelerations and the blend tolerance must be positive");
  if (limits.rotary_velocity < 0 || limits.rotary_acceleration < 0 || limits.tool_change_s < 0 ||
      limits.setup_change_s < 0)
    throw InputError("cycle time: rotary limits and change times must not be negative");
}

// min over axes limit_j / |u_j|: the most along u that keeps every axis within its limit.
double alongDirection(const Vec3& limit, const Vec3& u) {
  double along = kInfinity;
  for (int j = 0; j < 3; ++j)
    if (std::abs(u[j]) > 0) along = std::min(along, limit[j] / std::abs(u[j]));
  return along;
}

class ChainTimer {
 public:
  ChainTimer(const Toolpath& path, const MotionLimits& limits, const Tool& tool, const Eigen::Matrix3d& rotation)
      : path_(path), limits_(limits), tool_(tool), rotation_(rotation) {}

  // The moves ending at rows first + 1 .. last (row first: the chain starts there at rest); each move's seconds to
  // `seconds_by_row`.
  void run(int first, int last, std::vector<double>& seconds_by_row) {
    buildMoves(first, last);
    if (moves_.empty()) return;
    buildCorners();
    passes();
    for (std::size_t i = 0; i < moves_.size(); ++i) {
      const double v0 = speed_[i], v1 = speed_[i + 1];
      const double straight = moves_[i].length - beta_[i] * v0 * v0 - beta_[i + 1] * v1 * v1;
      // Half of each blend at its ends: a blend lasts 2 v beta.
      seconds_by_row[moves_[i].row] +=
          trapezoidSeconds(straight, v0, v1, moves_[i].speed, moves_[i].accel) + beta_[i] * v0 + beta_[i + 1] * v1;
    }
  }

 private:
  void buildMoves(int first, int last) {
    moves_.clear();
    for (int row = first + 1; row <= last; ++row) {
      const CutterLocation &from = path_[row - 1], &to = path_[row];
      const Vec3 motion = to.tip - from.tip;
      const double length = motion.norm();
      const double turn = std::acos(std::clamp(from.axis.normalized().dot(to.axis.normalized()), -1.0, 1.0));
      const bool rotary = limits_.rotary_velocity > 0 && limits_.rotary_acceleration > 0;
      if (length < kNoMotion && (turn < kNoMotion || !rotary)) continue;
      ChainMove move;
      move.row = row;
      if (length < kNoMotion) {
        move.pure_turn = true;
        move.length = turn;
        move.speed = limits_.rotary_velocity;
        move.accel = limits_.rotary_acceleration;
        moves_.push_back(move);
        continue;
      }
      move.length = length;
      move.direction = rotation_ * (motion / length);
      const bool rapid = to.move == MoveKind::Rapid;
      move.speed = alongDirection(rapid ? limits_.rapid_velocity : limits_.feed_velocity, move.direction);
      move.accel = alongDirection(limits_.acceleration, move.direction);
      if (!rapid) {
        const double down = -(motion / length).dot(to.axis.normalized());  // share of the move down the tool axis
        const bool plunge = down >= std::cos(limits_.plunge_angle_deg * kDegree);
        move.speed = std::min(move.speed, (plunge ? tool_.plunge_mm_min : tool_.feed_mm_min) / 60);
      }
      if (rotary && turn >= kNoMotion) {
        move.speed = std::min(move.speed, limits_.rotary_velocity * length / turn);
        move.accel = std::min(move.accel, limits_.rotary_acceleration * length / turn);
      }
      moves_.push_back(move);
    }
  }

  // Corner k lies between moves k - 1 and k; corners 0 and n (the chain's ends) are passed at rest.
  void buildCorners() {
    const std::size_t n = moves_.size();
    beta_.assign(n + 1, 0.0);
    cap_.assign(n + 1, 0.0);
    for (std::size_t k = 1; k < n; ++k) {
      const ChainMove &before = moves_[k - 1], &after = moves_[k];
      if (before.pure_turn || after.pure_turn) continue;  // a turn on the spot starts and ends at rest
      const Vec3 turn = after.direction - before.direction;
      double beta = 0;
      for (int j = 0; j < 3; ++j) beta = std::max(beta, std::abs(turn[j]) / (2 * limits_.acceleration[j]));
      double cap = std::min(before.speed, after.speed);
      if (beta > 0) {
        cap = std::min(cap, std::sqrt(kBlendShare * std::min(before.length, after.length) / beta));
        cap = std::min(cap, std::sqrt(4 * limits_.blend_tolerance / (turn.norm() * beta)));  // |turn| v^2 beta / 4
      }
      beta_[k] = beta;
      cap_[k] = cap;
    }
  }

  // The straight length of move i when its corners are passed at their caps (the least it will have).
  double straightAtCaps(std::size_t i) const {
    return moves_[i].length - beta_[i] * cap_[i] * cap_[i] - beta_[i + 1] * cap_[i + 1] * cap_[i + 1];
  }

  // Forward and backward: every corner speed reachable from its neighbours at the moves' accelerations.
  void passes() {
    speed_ = cap_;
    const std::size_t n = moves_.size();
    for (std::size_t i = 0; i < n; ++i) {
      const double reach = speed_[i] * speed_[i] + 2 * moves_[i].accel * std::max(0.0, straightAtCaps(i));
      speed_[i + 1] = std::min(speed_[i + 1], std::sqrt(reach));
    }
    for (std::size_t i = n; i-- > 0;) {
      const double reach = speed_[i + 1] * speed_[i + 1] + 2 * moves_[i].accel * std::max(0.0, straightAtCaps(i));
      speed_[i] = std::min(speed_[i], std::sqrt(reach));
    }
  }

  const Toolpath& path_;
  const MotionLimits& limits_;
  const Tool& tool_;
  const Eigen::Matrix3d& rotation_;
  std::vector<ChainMove> moves_;
  std::vector<double> beta_, cap_, speed_;  // per corner
};

// Whether row m carries on from row m - 1 without a stop (the same tool in the same setup).
bool continues(const Toolpath& path, std::size_t m) {
  return m > 0 && path[m - 1].tool == path[m].tool && path[m - 1].setup == path[m].setup;
}

}  // namespace

CycleTime& CycleTime::operator+=(const CycleTime& other) {
  cutting_s += other.cutting_s;
  rapid_s += other.rapid_s;
  tool_change_s += other.tool_change_s;
  setup_change_s += other.setup_change_s;
  cutting_mm += other.cutting_mm;
  rapid_mm += other.rapid_mm;
  tool_changes += other.tool_changes;
  setup_changes += other.setup_changes;
  return *this;
}

double trapezoidSeconds(double length, double v0, double v1, double speed, double accel) {
  length = std::max(length, 0.0);
  const double peak_squared = accel * length + 0.5 * (v0 * v0 + v1 * v1);
  if (peak_squared <= speed * speed) return std::max(0.0, 2 * std::sqrt(peak_squared) - v0 - v1) / accel;
  const double ramps = (speed * speed - v0 * v0 + speed * speed - v1 * v1) / (2 * accel);
  return (2 * speed - v0 - v1) / accel + std::max(0.0, length - ramps) / speed;
}

MotionLimits motionLimits(const Machine& machine) {
  MotionLimits limits;
  if (machine.joints.size() < 3) return limits;
  for (int j = 0; j < 3; ++j) {
    limits.feed_velocity[j] = machine.joints[j].max_velocity;
    limits.rapid_velocity[j] = machine.joints[j].rapid_velocity;
    limits.acceleration[j] = machine.joints[j].max_acceleration;
  }
  if (machine.fiveAxis()) {
    limits.rotary_velocity = std::min(machine.tiltJoint().max_velocity, machine.rotaryJoint().max_velocity);
    limits.rotary_acceleration = std::min(machine.tiltJoint().max_acceleration, machine.rotaryJoint().max_acceleration);
  }
  limits.tool_change_s = machine.tool_change_s;
  limits.setup_change_s = machine.setup_change_s;
  return limits;
}

PathTime cycleTime(const Toolpath& path, const std::vector<Tool>& tools, const MotionLimits& limits,
                   const std::map<int, Eigen::Matrix3d>& setup_rotation) {
  checkLimits(limits);
  std::map<std::string, const Tool*> by_id;
  for (const Tool& tool : tools) by_id[tool.id] = &tool;
  auto toolOf = [&](std::size_t row) -> const Tool& {
    const auto it = by_id.find(path[row].tool);
    if (it == by_id.end())
      throw InputError("cycle time: toolpath point " + std::to_string(row) + " uses tool '" + path[row].tool +
                       "', which the tools do not describe");
    if (!(it->second->feed_mm_min > 0) || !(it->second->plunge_mm_min > 0))
      throw InputError("cycle time: tool '" + it->first + "' has no positive feed and plunge feed");
    return *it->second;
  };

  std::vector<double> seconds(path.size(), 0.0);
  const Eigen::Matrix3d identity = Eigen::Matrix3d::Identity();
  for (std::size_t first = 0; first < path.size();) {
    std::size_t last = first;
    while (last + 1 < path.size() && continues(path, last + 1)) ++last;
    const auto rotation = setup_rotation.find(path[first].setup);
    ChainTimer(path, limits, toolOf(first), rotation == setup_rotation.end() ? identity : rotation->second)
        .run(static_cast<int>(first), static_cast<int>(last), seconds);
    first = last + 1;
  }

  PathTime time;
  std::string spindle;  // the tool loaded: none at the start
  for (std::size_t row = 0; row < path.size(); ++row) {
    const CutterLocation& at = path[row];
    CycleTime piece;
    if (row > 0 && at.setup != path[row - 1].setup) {
      CycleTime change;
      change.setup_changes = 1;
      change.setup_change_s = limits.setup_change_s;
      time.by_setup[at.setup] += change;
      time.total += change;
    }
    if (at.tool != spindle) {
      piece.tool_changes = 1;
      piece.tool_change_s = limits.tool_change_s;
      spindle = at.tool;
    }
    if (row > 0 && continues(path, row)) {
      const double length = (at.tip - path[row - 1].tip).norm();
      (at.move == MoveKind::Rapid ? piece.rapid_s : piece.cutting_s) = seconds[row];
      (at.move == MoveKind::Rapid ? piece.rapid_mm : piece.cutting_mm) = length;
    }
    time.by_op[at.op] += piece;
    time.by_setup[at.setup] += piece;
    time.total += piece;
  }
  return time;
}

}  // namespace art2part
