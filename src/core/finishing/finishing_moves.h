// Moves of the 2.5-D finishing passes (planar_finishing.cpp's internal helpers, not part of the library's interface):
// writing cutter locations in a frame, where a rapid may come down, and cutting one stretch of a wall.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <vector>

#include "art2part/finishing/planar_finishing.h"
#include "art2part/roughing/clearing_paths.h"
#include "art2part/roughing/link_clearance.h"
#include "art2part/roughing/shadow.h"

namespace art2part::finishing_detail {

constexpr double kSafeHeight = 1.0;  // mm above the allowance where a descent changes from rapid to feed
constexpr double kLinkClearance = 1.0;  // mm a link across keeps from the stock left, beyond the allowance

// Where links across may go below the clearance plane: at the heights the stock left before the pass proves clear
// (finishing only takes material away, so that stock bounds what is there at any point of it), never below `floor`
// (nothing is known below the lowest slab).
struct LinkWay {
  LinkClearance clearance;
  double floor = 0;
};

class PathWriter {
 public:
  PathWriter(const SetupFrame& frame, const Tool& tool, int setup, double clearance_z,
             std::shared_ptr<const LinkWay> link = nullptr)
      : frame_(frame), tool_(&tool), setup_(setup), clearance_z_(clearance_z), link_(std::move(link)) {}

  void move(const Vec3& p, MoveKind kind) {
    CutterLocation cl;
    cl.setup = setup_;
    cl.tool = tool_->id;
    cl.move = kind;
    cl.tip = fromFrame(p, frame_);
    cl.axis = frame_.z;
    if (!path_.empty() && (path_.back().tip - cl.tip).norm() < 1e-9) return;
    path_.push_back(cl);
    at_ = p;
    started_ = true;
  }
  // Clearing moves (clearLevel's, through safeDescents). With a link way, a hop over the clearance plane (straight
  // up, across, down) goes across at the lowest height the stock left proves clear instead, never under where the
  // descent's rapid ends; the retract that may start one is held until the next move shows whether it does.
  void clearing(const std::vector<ClearingPoint>& moves) {
    for (std::size_t i = 0; i < moves.size(); ++i) {
      const ClearingPoint& m = moves[i];
      const bool rapid = m.move == ClearingMove::Rapid, up_there = m.tip.z() >= clearance_z_ - 1e-9;
      if (link_ && started_ && rapid && up_there && (m.tip.head<2>() - at_.head<2>()).norm() < 1e-9 &&
          m.tip.z() > at_.z()) {
        retract_held_ = true;
        continue;
      }
      if (retract_held_ && rapid && up_there && i + 1 < moves.size()) {
        const ClearingPoint& down = moves[i + 1];
        if ((down.tip.head<2>() - m.tip.head<2>()).norm() < 1e-9 && down.tip.z() < m.tip.z()) {
          const double way = wayTo(m.tip.head<2>(), down.move == ClearingMove::Rapid ? down.tip.z() : at_.z());
          retract_held_ = false;
          move(Vec3(at_.x(), at_.y(), way), MoveKind::Rapid);
          move(Vec3(m.tip.x(), m.tip.y(), way), MoveKind::Rapid);
          continue;
        }
      }
      releaseRetract();
      move(m.tip, rapid ? MoveKind::Rapid : MoveKind::Feed);
    }
  }
  // To (x, y) at height z from wherever the tool is: up to the height the link proves clear (or the clearance plane),
  // across, down fast to `safe` (or only to `floor` when that is higher), then feed.
  void enter(const Point2& xy, double z, double safe, double floor) {
    retract_held_ = false;  // this goes up from where the tool is, as high as it must
    const double fast = std::max(safe, floor);
    const double way = wayTo(xy, at_.z());
    if (way < clearance_z_ - 1e-9) {
      move(Vec3(at_.x(), at_.y(), way), MoveKind::Rapid);
      move(Vec3(xy.x(), xy.y(), way), MoveKind::Rapid);
      if (fast < way) move(Vec3(xy.x(), xy.y(), fast), MoveKind::Rapid);
      move(Vec3(xy.x(), xy.y(), z), MoveKind::Feed);
      return;
    }
    if (started_ && at_.z() < clearance_z_ - 1e-9) move(Vec3(at_.x(), at_.y(), clearance_z_), MoveKind::Rapid);
    move(Vec3(xy.x(), xy.y(), clearance_z_), MoveKind::Rapid);
    if (fast < clearance_z_) move(Vec3(xy.x(), xy.y(), fast), MoveKind::Rapid);
    move(Vec3(xy.x(), xy.y(), z), MoveKind::Feed);
  }
  void retract() {
    releaseRetract();
    if (started_ && at_.z() < clearance_z_ - 1e-9) move(Vec3(at_.x(), at_.y(), clearance_z_), MoveKind::Rapid);
  }
  Toolpath take() {
    retract();
    return std::move(path_);
  }
  const Vec3& at() const { return at_; }
  bool started() const { return started_; }
  // Where the tool stands before this writer's first move (the end of another's): cuts are ordered from there. No
  // move is written; the first still comes over the clearance plane.
  void startAt(const Vec3& p) {
    if (!started_) at_ = p;
  }
  // Seconds of the path so far and a retract from where it ends, as the plan estimates them (estimateTime): feeds at
  // the tool's rate, rapids at `rapid_mm_min`. To compare two ways of writing the same cuts.
  double secondsToRetract(double rapid_mm_min) const {
    const double retract = started_ ? std::max(0.0, clearance_z_ - at_.z()) : 0.0;
    return 60 * (toolpathLength(path_, MoveKind::Feed) / std::max(tool_->feed_mm_min, 1.0) +
                 (toolpathLength(path_, MoveKind::Rapid) + retract) / std::max(rapid_mm_min, 1.0));
  }

 private:
  // The height to go across at from where the tool is to `to`, no lower than `lowest` nor than the tool: the lowest the
  // link way proves clear, else the clearance plane.
  double wayTo(const Point2& to, double lowest) const {
    if (!started_ || !link_) return clearance_z_;
    return link_->clearance.lowestClear(at_.head<2>(), to, std::max({lowest, at_.z(), link_->floor}), clearance_z_);
  }
  void releaseRetract() {
    if (!retract_held_) return;
    retract_held_ = false;
    move(Vec3(at_.x(), at_.y(), clearance_z_), MoveKind::Rapid);
  }

  SetupFrame frame_;
  const Tool* tool_;  // never null: a pointer so that writers may be assigned (a trial's kept)
  int setup_;
  double clearance_z_;
  std::shared_ptr<const LinkWay> link_;  // shared by the writers of one tool's passes (and their trial copies)
  Toolpath path_;
  Vec3 at_ = Vec3::Zero();
  bool started_ = false;
  bool retract_held_ = false;  // a rapid straight up to the clearance plane not written yet (clearing)
};

// Where the tool may come straight down at rapid: its disc clear of the allowance roughing left on every face above
// the level (the allowed region eroded by that and a margin). A descent elsewhere moves to the nearest such point
// within reach, comes down there and feeds across at the height it came down to; failing that it feeds all the way.
class SafeDescent {
 public:
  SafeDescent(const Region& allowed, double allowance)
      : allowed_(allowed), safe_(offsetRegion(allowed, -(allowance + kDescentMargin))), locator_(safe_) {}

  // The point to come down at for a descent at `p`, and whether there is one (else feed down at p).
  bool at(const Point2& p, double max_shift, Point2& out) const {
    if (locator_.contains(p)) return out = p, true;
    double best = max_shift * max_shift;
    bool found = false;
    for (const ClipperLib::Path& ring : safe_)
      for (std::size_t i = 0; i < ring.size(); ++i) {
        const Point2 a = fromRegionPoint(ring[i]), b = fromRegionPoint(ring[(i + 1) % ring.size()]);
        const Point2 ab = b - a;
        const double t = ab.squaredNorm() > 0 ? std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0) : 0.0;
        const Point2 q = a + t * ab;
        const double d = (q - p).squaredNorm();
        if (d >= best) continue;
        // A hair inside the safe region, and a straight way from there to p in the allowed region.
        const Point2 inside = q + (q - p).normalized() * 0.01;
        if (!locator_.contains(inside) || !segmentInside(allowed_, inside, p)) continue;
        best = d, out = inside, found = true;
      }
    return found;
  }

 private:
  static constexpr double kDescentMargin = 0.2;
  const Region& allowed_;
  Region safe_;
  RegionLocator locator_;
};

// How far down a rapid may come at a point: to the top of the highest slab of stock roughing left whose material
// lies within the tool's radius (and a margin) of the point; below that the tool feeds. The part and its allowance
// are kept off by SafeDescent; what this sees is stock roughing could not reach.
class DescentLimit {
 public:
  DescentLimit(const std::vector<SlabState>& slabs, double radius) : slabs_(slabs), reach_(radius + kMargin) {}
  // The lowest height a rapid may reach at p (-infinity: all the way).
  double at(const Point2& p) const {
    const Point2 lo = p - Point2(reach_, reach_), hi = p + Point2(reach_, reach_);
    for (const SlabState& slab : slabs_) {  // top down
      const Region near = ringsMeeting(slab.remaining, lo, hi);
      if (near.empty()) continue;
      if (regionContains(near, p) || distanceToRings(near, p) <= reach_) return slab.top + kSafeHeight;
    }
    return -std::numeric_limits<double>::infinity();
  }

 private:
  static constexpr double kMargin = 0.5;
  static double distanceToRings(const Region& region, const Point2& p) {
    double best = std::numeric_limits<double>::infinity();
    for (const ClipperLib::Path& ring : region)
      for (std::size_t i = 0; i < ring.size(); ++i) {
        const Point2 a = fromRegionPoint(ring[i]), b = fromRegionPoint(ring[(i + 1) % ring.size()]);
        const Point2 ab = b - a;
        const double t = ab.squaredNorm() > 0 ? std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0) : 0.0;
        best = std::min(best, (a + t * ab - p).norm());
      }
    return best;
  }
  const std::vector<SlabState>& slabs_;
  double reach_;
};

// Rapid descents (below the clearance plane) moved to where the tool comes down clear of the allowance, joined to the
// descent's foot by a feed; where there is none nearby, the descent is a feed.
std::vector<ClearingPoint> safeDescents(const std::vector<ClearingPoint>& moves, const SafeDescent& safe,
                                        const DescentLimit& limit, double max_shift);

// Cuts one stretch of ring at height z: entered from the open side (the region lies left of a climb stretch) where
// the straight lead-in stays in the region, else straight down at its first point.
void cutStretch(const ContourStretch& s, double z, double top, double lead, const Region& allowed,
                const SafeDescent& safe, const DescentLimit& limit, PathWriter& out);

// One level's floor clearing (its centre region, z and top), with the level's allowed region and safe descents.
struct FloorLevel {
  ClearingLevel clear;
  std::shared_ptr<const Region> allowed;
  std::shared_ptr<const SafeDescent> safe;  // over *allowed
};
// Clears the floors piece by piece (the connected pieces of every level's centre, PieceSchedule with the level index
// as the depth), the piece nearest the tool first, each only once every piece of a level above within `reach` of it
// is cut: the walls' rule (cutWalls); that order then shortened by or-opt under the same rule (ordered_tour.h: a
// piece entered at its first move at its level and left at its last, whatever the order), kept where quicker as
// written. Each piece as clearLevel clears it, its descents moved by safeDescents. Kept where its moves take less
// time than level after level (clearLevel over each level's whole centre), feeds at the tool's rate and rapids at
// `rapid_mm_min`: the links differ (a descent where no rapid may come is a feed; Ailette's flat1 fed 78 mm more down
// piece by piece). Each order is written twice: each piece (each level) started at its cheapest entry, and started
// where it is quickest to reach from where the one before left the tool (ClearingLevel::start_near); the quickest
// of all is kept. Why: level after level, the face mill crossed the part between the floors at both ends at every
// level; nearest first, it still left pieces behind to come back for.
void cutFloors(const std::vector<FloorLevel>& floors, const ClearingOptions& clearing, const DescentLimit& limit,
               double reach, double rapid_mm_min, PathWriter& out);

// A wall stretch to cut at one level (`top`: the level's allowance top), with the level's allowed region and safe
// descents, which the level's stretches share.
struct WallStretch {
  ContourStretch stretch;
  double z = 0, top = 0;
  std::shared_ptr<const Region> allowed;
  std::shared_ptr<const SafeDescent> safe;
};
// Cuts the stretches nearest first (x-y distance from the tool to a stretch's start plus the height between), each only
// once every stretch at a higher level over it is cut (their boxes, grown by `reach`, meet; TopDownSchedule): down one
// wall band by band before crossing to the next; that order then shortened by or-opt under the same rule
// (ordered_tour.h: each stretch is entered and left at its ends whatever the order), kept where the moves it writes
// take less time (feed at the tool's rate, rapids at `rapid_mm_min`). Why: level after level, the tool crossed the
// part between walls at every level. Closed stretches (whole rings) start at their first vertex or, where that is
// quicker as written, each at its vertex nearest the tool where the order first reaches it (among those with a
// lead-in in the level's allowed region).
void cutWalls(const std::vector<WallStretch>& walls, double lead, double reach, const DescentLimit& limit,
              double rapid_mm_min, PathWriter& out);

}  // namespace art2part::finishing_detail
