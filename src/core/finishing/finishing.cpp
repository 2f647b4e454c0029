// The finishing stage over every setup (finishing.h).
#include "art2part/finishing/finishing.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <sstream>
#include <tuple>

#include "art2part/common/angles.h"
#include "art2part/common/number_text.h"
#include "art2part/common/parallel.h"
#include "art2part/finishing/admissible.h"
#include "art2part/finishing/face_assignment.h"
#include "art2part/finishing/hole_links.h"
#include "art2part/finishing/planar_finishing.h"
#include "art2part/finishing/stock_after_roughing.h"
#include "art2part/geometry/ordered_tour.h"
#include "art2part/geometry/solid_closure.h"
#include "art2part/roughing/shadow.h"
#include "finishing_context.h"

namespace art2part {

const char* finishingKindName(FinishingKind kind) {
  switch (kind) {
    case FinishingKind::FaceMill: return "face_mill";
    case FinishingKind::SideMill: return "side_mill";
    case FinishingKind::Contour: return "contour";
    case FinishingKind::Drill: return "drill";
    case FinishingKind::Helix: return "helix";
    case FinishingKind::Surface3Axis: return "surface_3axis";
    case FinishingKind::Surface5Axis: return "surface_5axis";
    case FinishingKind::Rest: return "rest";
  }
  return "?";
}

const char* faceStatusName(FaceStatus status) {
  switch (status) {
    case FaceStatus::Finished: return "finished";
    case FaceStatus::Partial: return "partial";
    case FaceStatus::Unmachinable: return "unmachinable";
  }
  return "?";
}

namespace finishing_detail {

SetupFrame frameFor(const Part& part, const Setup& setup, const Vec3& d) {
  if (setup.frame.z.dot(d) > std::cos(1e-6)) return setup.frame;
  return setupFrame(part, d);
}

bool setupsOwnDirection(const Setup& setup, const Vec3& d) { return d.dot(setup.frame.z) > std::cos(1e-6); }

std::vector<SlabState> stockLeftAlong(const Context& c, int setup_index, const Vec3& direction) {
  const Setup& setup = c.in.setups.setups[setup_index];
  if (setupsOwnDirection(setup, direction) && setup_index < static_cast<int>(c.in.roughing.stock_left.size()))
    return c.in.roughing.stock_left[setup_index];
  return c.after_roughing.slabs(setup_index, frameFor(c.in.part, setup, direction));
}

HoleLink linkOverStockLeft(const Context& c, int setup_index, const Vec3& axis, const Tool& tool) {
  return linkOverStock(stockLeftAlong(c, setup_index, axis), frameFor(c.in.part, c.in.setups.setups[setup_index], axis),
                       tool, c.options.tools.holder_margin);
}

// What roughing left along a group's direction beyond the skins finishing leaves its tools (stockBeyondSkin): beyond
// the allowance for planar finishing, beyond the surface skin for surface finishing.
struct StockBeyond {
  std::vector<SlabState> allowance, surface_skin;
};

// StockBeyond worked out once per setup and direction (the part's shadows at the slabs, the most of its work, once for
// both): a group's planar and surface finishing, and the groups of later rounds along the same direction, ask for the
// same. Threads may ask side by side; each answer is worked out once, by the first thread to ask for it.
class StockBeyondCache {
 public:
  const StockBeyond& get(int setup, const Vec3& direction, const std::function<StockBeyond()>& work_out) {
    std::shared_ptr<Entry> entry;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      std::shared_ptr<Entry>& slot = kept_[Key{setup, direction.x(), direction.y(), direction.z()}];
      if (!slot) slot = std::make_shared<Entry>();
      entry = slot;
    }
    std::call_once(entry->once, [&] { entry->stock = work_out(); });
    return entry->stock;
  }

 private:
  struct Entry {
    std::once_flag once;
    StockBeyond stock;
  };
  using Key = std::tuple<int, double, double, double>;
  std::mutex mutex_;
  std::map<Key, std::shared_ptr<Entry>> kept_;
};

}  // namespace finishing_detail

using namespace finishing_detail;

namespace {

constexpr double kFinished = 0.99;   // a face whose reached share is at least this counts as finished
// A face reached at most this share by its choice tries its next choice. "At most", to within kShareNoise: a face
// whose walls a tool reaches half way down is at the threshold exactly, and its retry must not hang on the rounding.
constexpr double kRetryShare = 0.5;
constexpr double kShareNoise = 1e-9;
constexpr int kRounds = 3;           // choices tried per face at most
constexpr double kProgressSeconds = 0.25;  // reports while a round's groups are planned
constexpr double kSpotPointDeg = 90;  // a spot drill's point

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void checkOptions(const FinishingOptions& o) {
  auto positive = [](double v) { return std::isfinite(v) && v > 0; };
  auto nonNegative = [](double v) { return std::isfinite(v) && v >= 0; };
  if (!nonNegative(o.allowance) || o.allowance > 10) throw InputError("finishing: allowance must be 0..10 mm");
  if (!positive(o.clearance)) throw InputError("finishing: clearance must be positive (mm)");
  if (!positive(o.rapid_mm_min) || !nonNegative(o.tool_change_s))
    throw InputError("finishing: rapid rate must be positive and tool change time not negative");
  if (!(o.planar.floor_stepover > 0 && o.planar.floor_stepover <= 0.95))
    throw InputError("finishing: floor stepover must be in (0, 0.95] of the diameter");
  if (!nonNegative(o.planar.square_angle_deg) || o.planar.square_angle_deg > 5)
    throw InputError("finishing: square angle must be 0..5 deg");
  if (!positive(o.surface.scallop) || o.surface.scallop > 1) throw InputError("finishing: scallop must be in (0, 1] mm");
  if (!(o.tools.area_fraction > 0 && o.tools.area_fraction <= 1) || o.tools.max_rest_tools < 0)
    throw InputError("finishing: area fraction must be in (0, 1] and rest tools not negative");
}

// Flat end mills by diameter, largest first; balls likewise. Not the high-efficiency roughing cutters: their
// engagement limit rules out full-width and slotting passes.
std::vector<const Tool*> toolsOfType(const ToolLibrary& library, ToolType type) {
  std::vector<const Tool*> tools;
  for (const Tool& t : library.tools)
    if (t.type == type && t.max_engagement_deg == 0) tools.push_back(&t);
  std::stable_sort(tools.begin(), tools.end(), [](const Tool* a, const Tool* b) {
    if (a->diameter != b->diameter) return a->diameter > b->diameter;
    return a->flute_length < b->flute_length;
  });
  return tools;
}

// A group of faces finished along one direction in one setup.
struct Group {
  int setup = 0;
  Vec3 direction = Vec3::UnitZ();
  std::vector<PlanarTarget> planar;
  std::vector<int> surface;  // faces
};

// What planning one group gives: its operations and its notes on its faces, taken into the plan and the tally in the
// groups' order once a round's groups are all planned, so the plan is the same whatever ran side by side.
struct GroupOutcome {
  struct Note {
    int face = -1, choice = -1;
    double share = 0;
    std::string why;
  };
  std::vector<FinishingOperation> ops;
  std::vector<Note> notes;
  void note(int face, int choice, double share, const std::string& why) { notes.push_back({face, choice, share, why}); }
};


std::string number(double v) { return numberText(v, 3); }

void estimateTime(FinishingOperation& op, const ToolLibrary& library, const FinishingOptions& options) {
  op.feed_mm = toolpathLength(op.path, MoveKind::Feed);
  op.rapid_mm = toolpathLength(op.path, MoveKind::Rapid);
  const Tool* tool = library.find(op.tool);
  const double feed = tool ? std::max(1.0, tool->feed_mm_min) : 1000.0;
  op.seconds = 60.0 * (op.feed_mm / feed + op.rapid_mm / options.rapid_mm_min);
}

// A spot drill: a drill with the 90 deg point that centres holes (and chamfers them).
bool isSpotDrill(const Tool* tool) {
  return tool && tool->type == ToolType::Drill && std::abs(tool->point_angle_deg - kSpotPointDeg) < 1;
}

// Order of a setup's operations: each tool once, flat end mills (largest first, rest tools after), then ball and bull
// end mills, then drills (the spot drill first); within a tool, operations in the order planned.
int toolClass(const Tool* tool) {
  if (!tool) return 3;
  switch (tool->type) {
    case ToolType::Flat: return 0;
    case ToolType::Ball:
    case ToolType::Bull: return 1;
    case ToolType::Drill: return 2;
  }
  return 3;
}



std::vector<SlabState> stockLeftAlong(const Context& c, const Group& group) {
  return stockLeftAlong(c, group.setup, group.direction);
}

double surfaceSkin(const FinishingOptions& options) { return std::max(options.surface.skin, options.allowance); }

// What roughing left in the group's frame beyond the skins.
const StockBeyond& stockBeyondAlong(const Context& c, const Group& group) {
  return c.stock_beyond.get(group.setup, group.direction, [&] {
    const std::vector<SlabState> left = stockLeftAlong(c, group);
    if (left.empty()) return StockBeyond{};
    const SetupFrame frame = frameFor(c.in.part, c.in.setups.setups[group.setup], group.direction);
    const ShadowStack shadows = slabShadows(left, toFrame(c.solid.mesh.vertices, frame), c.solid.mesh.triangles);
    return StockBeyond{stockBeyondSkin(left, c.options.allowance, shadows),
                       stockBeyondSkin(left, surfaceSkin(c.options), shadows)};
  });
}

void runPlanarGroup(const Context& c, const Group& group, const std::vector<int>& tried, GroupOutcome& out) {
  const Setup& setup = c.in.setups.setups[group.setup];
  PlanarGroup pg;
  pg.setup = group.setup;
  pg.frame = frameFor(c.in.part, setup, group.direction);
  pg.targets = group.planar;
  pg.stock = c.stock;
  pg.stock_beyond = stockBeyondAlong(c, group).allowance;
  PlanarResult result = finishPlanar(c.solid, pg, c.flats, c.options);
  for (const PlanarReach& r : result.reach) {
    std::string why;
    if (r.depth > 0 && r.deepest_reached < r.depth - 0.5)
      why = number(r.depth) + " mm deep: the flutes reach " + number(r.deepest_reached) +
            " mm down with the shank and holder clear";
    out.note(r.face, tried[r.face], r.size > 0 ? r.reached / r.size : 0, why);
  }
  for (FinishingOperation& op : result.operations) out.ops.push_back(std::move(op));
}

void runSurfaceGroup(const Context& c, const Group& group, const std::vector<int>& tried, GroupOutcome& out) {
  const Part& part = c.in.part;
  const Setup& setup = c.in.setups.setups[group.setup];
  // The largest ball whose radius fits the faces' concave curvature.
  double least = std::numeric_limits<double>::infinity();
  for (int f : group.surface) least = std::min(least, concaveRadius(part, f, c.triangles[f]));
  const Tool* ball = nullptr;
  for (const Tool* t : c.balls)
    if (t->diameter / 2 <= least + 1e-9) {
      ball = t;
      break;
    }
  if (!ball && !c.balls.empty()) ball = c.balls.back();
  if (!ball) return;
  SurfaceFinishingOptions so = c.options.surface;
  so.skin = surfaceSkin(c.options);
  so.holder_margin = c.options.tools.holder_margin;
  const bool five = c.options.mode == MachineMode::FiveAxis;
  SurfaceFinishingResult r =
      five ? finishSurfaces5Axis(c.solid, group.surface, setup.frame, group.direction, *ball, group.setup, so)
           : finishSurfaces3Axis(c.solid, group.surface, frameFor(part, setup, group.direction), *ball, group.setup, so,
                                 stockBeyondAlong(c, group).surface_skin);
  double area = 0;
  for (int f : group.surface) area += part.faces[f].area;
  const double share = area > 0 && !r.path.empty() ? std::clamp(r.planned_area_mm2 / area, 0.0, 1.0) : 0;
  for (int f : group.surface) {
    std::string why;
    if (r.skipped_area_mm2 > 0) why = "the shank or holder cannot clear " + number(r.skipped_area_mm2) + " mm2 of its group";
    const double radius = concaveRadius(part, f, c.triangles[f]);
    if (ball->diameter / 2 > radius + 1e-9)
      why = "concave radius " + number(radius) + " mm below the smallest ball's " + number(ball->diameter / 2) + " mm";
    out.note(f, tried[f], share, why);
  }
  if (r.path.empty()) return;
  FinishingOperation op;
  op.setup = group.setup;
  op.kind = five ? FinishingKind::Surface5Axis : FinishingKind::Surface3Axis;
  op.tool = ball->id;
  op.direction = group.direction;
  op.faces = group.surface;
  op.path = std::move(r.path);
  op.plan_seconds = r.seconds;
  out.ops.push_back(std::move(op));
}

// Each run of `ops` with one tool in the order with the least travel between them (each entered and left over the
// clearance plane: the order of operations planned from the same stock changes no cut), from `roughing_end` (where
// the setup's roughing leaves its last tool, and which) when that is the run's tool. Drilling and hole milling keep
// their places and split the runs: a hole's operations follow one another in the order the hole plan gave.
void shortenToolRuns(std::vector<FinishingOperation>& ops,
                     const std::optional<std::pair<std::string, Vec3>>& roughing_end) {
  auto fixed = [](const FinishingOperation& op) {
    return op.kind == FinishingKind::Drill || op.kind == FinishingKind::Helix || op.path.empty();
  };
  for (std::size_t first = 0; first < ops.size();) {
    std::size_t end = first;
    while (end < ops.size() && ops[end].tool == ops[first].tool && !fixed(ops[end])) ++end;
    if (end - first < 2) {
      first = std::max(end, first + 1);
      continue;
    }
    std::vector<TourStop> stops;
    for (std::size_t i = first; i < end; ++i) stops.push_back({ops[i].path.front().tip, ops[i].path.back().tip});
    std::optional<Vec3> start;
    if (first > 0 && ops[first - 1].tool == ops[first].tool && !ops[first - 1].path.empty())
      start = ops[first - 1].path.back().tip;
    else if (first == 0 && roughing_end && roughing_end->first == ops[first].tool)
      start = roughing_end->second;
    std::vector<FinishingOperation> run;
    for (std::size_t k : leastTravelOrder(stops, start)) run.push_back(std::move(ops[first + k]));
    std::move(run.begin(), run.end(), ops.begin() + static_cast<std::ptrdiff_t>(first));
    first = end;
  }
}

// Whether `path` ends with a rapid straight up `axis`, and whether it starts with a rapid straight down it: how a
// finishing operation leaves and enters its clearance plane.
bool leavesUp(const Toolpath& path, const Vec3& axis) {
  const std::size_t n = path.size();
  if (n < 2 || path[n - 1].move != MoveKind::Rapid) return false;
  const Vec3 up = path[n - 1].tip - path[n - 2].tip;
  return up.cross(axis).norm() < 1e-9 && up.dot(axis) > 0;
}
bool entersDown(const Toolpath& path, const Vec3& axis) {
  return path.size() >= 2 && path[0].move == MoveKind::Rapid && path[1].move == MoveKind::Rapid &&
         (path[1].tip - path[0].tip).cross(axis).norm() < 1e-9 && (path[0].tip - path[1].tip).dot(axis) > 0;
}

// Between two operations of one tool along the setup's own direction, the tool crosses at the lowest height the
// stock roughing left proves clear for the whole tool (hole_links.h: finishing before either only takes stock
// away) instead of over the clearance plane: the first's retract ends there, the second's descent starts there.
void lowerToolRunLinks(const Context& c, int setup_index, std::vector<FinishingOperation>& ops) {
  const Setup& setup = c.in.setups.setups[setup_index];
  const Vec3 axis = setup.frame.z;
  std::map<std::string, HoleLink> links;  // by tool
  for (std::size_t i = 1; i < ops.size(); ++i) {
    Toolpath& a = ops[i - 1].path;
    Toolpath& b = ops[i].path;
    if (ops[i - 1].tool != ops[i].tool || !leavesUp(a, axis) || !entersDown(b, axis)) continue;
    if (!setupsOwnDirection(setup, a.back().axis) || !setupsOwnDirection(setup, b.front().axis)) continue;
    const double top = a.back().tip.dot(axis);
    if (std::abs(b.front().tip.dot(axis) - top) > 1e-6) continue;
    const Tool* tool = c.in.library.find(ops[i].tool);
    if (!tool) continue;
    auto link = links.find(ops[i].tool);
    if (link == links.end()) link = links.emplace(ops[i].tool, linkOverStockLeft(c, setup_index, axis, *tool)).first;
    const Vec3 from = a[a.size() - 2].tip, to = b[1].tip;
    const double lowest = std::max(from.dot(axis), to.dot(axis));
    const double height = link->second(from, to, lowest, top);
    if (height >= top - 1e-6) continue;
    a.back().tip = from + axis * (height - from.dot(axis));
    b.front().tip = to + axis * (height - to.dot(axis));
  }
}

// Each setup's operations in machining order, each tool loaded once; the plan's operations, tool changes and time.
void orderOperations(const Context& c, std::vector<std::vector<FinishingOperation>>& per_setup, FinishingPlan& plan) {
  plan.tool_changes_per_setup.assign(per_setup.size(), 0);
  for (int k = 0; k < static_cast<int>(per_setup.size()); ++k) {
    std::vector<FinishingOperation>& ops = per_setup[k];
    std::map<std::string, int> first;  // tool -> first position
    for (int i = 0; i < static_cast<int>(ops.size()); ++i) first.try_emplace(ops[i].tool, i);
    std::stable_sort(ops.begin(), ops.end(), [&](const FinishingOperation& a, const FinishingOperation& b) {
      const Tool* ta = c.in.library.find(a.tool);
      const Tool* tb = c.in.library.find(b.tool);
      const int ca = toolClass(ta), cb = toolClass(tb);
      if (ca != cb) return ca < cb;
      const bool spot_a = isSpotDrill(ta), spot_b = isSpotDrill(tb);
      if (spot_a != spot_b) return spot_a;
      if (ta && tb && ca == 0 && ta->diameter != tb->diameter) return ta->diameter > tb->diameter;
      return first[a.tool] < first[b.tool];
    });
    std::optional<std::pair<std::string, Vec3>> roughing_end;  // the setup's last roughing operation's tool and end
    for (const RoughingOperation& r : c.in.roughing.operations)
      if (r.setup == k && !r.path.empty()) roughing_end = std::make_pair(r.tool, r.path.back().tip);
    shortenToolRuns(ops, roughing_end);
    lowerToolRunLinks(c, k, ops);
    std::string loaded;
    for (FinishingOperation& op : ops) {
      estimateTime(op, c.in.library, c.options);
      if (op.tool != loaded) ++plan.tool_changes_per_setup[k], loaded = op.tool;
      plan.operations.push_back(std::move(op));
    }
    plan.tool_changes += plan.tool_changes_per_setup[k];
  }
  for (int i = 0; i < static_cast<int>(plan.operations.size()); ++i) {
    for (CutterLocation& cl : plan.operations[i].path) cl.op = i;
    plan.seconds += plan.operations[i].seconds;
  }
  plan.seconds += plan.tool_changes * c.options.tool_change_s;
}

// Every face accounted for: its operations and tools, or why it stays unfinished.
void accountFaces(const Part& part, const std::vector<FaceAssignment>& assignment, const Tally& tally,
                  double smallest_radius, FinishingPlan& plan) {
  plan.faces.assign(part.faces.size(), {});
  for (int i = 0; i < static_cast<int>(plan.operations.size()); ++i)
    for (int f : plan.operations[i].faces) {
      FaceFinish& face = plan.faces[f];
      if (std::find(face.operations.begin(), face.operations.end(), i) == face.operations.end())
        face.operations.push_back(i);
      if (std::find(face.tools.begin(), face.tools.end(), plan.operations[i].tool) == face.tools.end())
        face.tools.push_back(plan.operations[i].tool);
    }
  for (int f = 0; f < static_cast<int>(part.faces.size()); ++f) {
    FaceFinish& face = plan.faces[f];
    face.face = f;
    face.area_mm2 = part.faces[f].area;
    const FaceAssignment& a = assignment[f];
    if (a.choices.empty()) {
      face.status = FaceStatus::Unmachinable;
      face.reason = a.reason;
      continue;
    }
    const int k = tally.choice[f] >= 0 ? tally.choice[f] : 0;
    const FinishingChoice& choice = a.choices[k];
    face.strategy = choice.kind;
    face.setup = choice.setup;
    face.direction = choice.direction;
    const double share = tally.share[f];
    face.planned_mm2 = share * face.area_mm2;
    std::string why = tally.shortfall[f];
    if (share >= kFinished && !face.operations.empty()) {
      face.status = FaceStatus::Finished;
      why.clear();
    } else if (share > 0 && !face.operations.empty()) {
      face.status = FaceStatus::Partial;
      if (why.empty()) {
        why = "corners or strips narrower than the smallest tool reaches";
        face.radius_needed_mm = smallest_radius;  // what is left needs a tool no larger than the smallest tried
      }
    } else {
      face.status = FaceStatus::Unmachinable;
      if (why.empty()) why = "no tool reaches it with its shank and holder clear";
    }
    if (!choice.note.empty() && face.status != FaceStatus::Finished) why += (why.empty() ? "" : "; ") + choice.note;
    face.reason = why;
  }
}

}  // namespace

FinishingPlan planFinishing(const FinishingInput& in, const FinishingOptions& options, const ProgressSink& progress) {
  const auto start = std::chrono::steady_clock::now();
  checkOptions(options);
  FinishingPlan plan;
  const Part& part = in.part;
  const Part solid = machiningSolid(part);
  const std::vector<const Tool*> flats = toolsOfType(in.library, ToolType::Flat);
  const std::vector<const Tool*> balls = toolsOfType(in.library, ToolType::Ball);
  double longest_flutes = 0;
  for (const Tool* t : flats) longest_flutes = std::max(longest_flutes, t->flute_length);
  const std::vector<FaceAssignment> assignment =
      assignFaces(part, in.visibility, in.setups, in.holes, in.hole_methods, longest_flutes, options);
  const std::vector<std::vector<int>> triangles = faceTriangles(part);
  const Mesh stock = roughingStock(part, RoughingOptions{});
  StockAfterRoughing after_roughing(solid, stock, in.roughing, in.library);
  StockBeyondCache stock_beyond;
  const Context c{in, options, solid, stock, flats, balls, triangles, after_roughing, stock_beyond};
  const std::size_t faces = part.faces.size();
  Tally tally{std::vector<double>(faces, 0), std::vector<int>(faces, -1), std::vector<std::string>(faces)};
  std::vector<std::vector<FinishingOperation>> per_setup(in.setups.setups.size());
  plan.holes = in.holes;
  plan.hole_methods = in.hole_methods;
  makeHoles(c, assignment, plan, tally, per_setup);

  // Rounds: each face's next choice while the ones before reached little of it ("checked by profiling, not assumed").
  std::vector<int> tried(faces, -1);
  long groups_done = 0;  // in the rounds before
  for (int round = 0; round < kRounds && !plan.cancelled; ++round) {
    std::vector<Group> groups;
    auto groupOf = [&](int setup, const Vec3& d) -> Group& {
      for (Group& g : groups)
        if (g.setup == setup && g.direction.dot(d) > std::cos(1e-6)) return g;
      groups.push_back({setup, d, {}, {}});
      return groups.back();
    };
    for (const FaceAssignment& a : assignment) {
      const int f = a.face;
      if (tally.share[f] > kRetryShare + kShareNoise) continue;
      int next = tried[f] + 1;
      while (next < static_cast<int>(a.choices.size()) && a.choices[next].hole >= 0) ++next;  // holes: made above
      if (next >= static_cast<int>(a.choices.size())) continue;
      tried[f] = next;
      const FinishingChoice& choice = a.choices[next];
      switch (choice.kind) {
        case FinishingKind::FaceMill:
        case FinishingKind::SideMill:
        case FinishingKind::Contour:
          groupOf(choice.setup, choice.direction).planar.push_back({f, choice.kind});
          break;
        case FinishingKind::Surface3Axis:
        case FinishingKind::Surface5Axis:
          groupOf(choice.setup, choice.direction).surface.push_back(f);
          break;
        default:
          break;
      }
    }
    if (groups.empty()) break;
    std::stable_sort(groups.begin(), groups.end(), [](const Group& a, const Group& b) { return a.setup < b.setup; });
    std::vector<GroupOutcome> outcomes(groups.size());
    std::atomic<int> latest{0};  // the group started last (of two starting at once, either)
    auto plan_group = [&](int i) {
      latest.store(std::max(latest.load(), i));
      const Group& group = groups[i];
      if (!group.planar.empty()) runPlanarGroup(c, group, tried, outcomes[i]);
      if (!group.surface.empty()) runSurfaceGroup(c, group, tried, outcomes[i]);
    };
    bool go_on = true;  // the sink's last answer (also after the round's last group)
    auto tick = [&](int done) {
      const Group& group = groups[latest.load()];
      std::ostringstream message;
      message << (round == 0 ? "" : "again, ") << "setup " << group.setup + 1 << " of " << in.setups.setups.size()
              << ": " << group.planar.size() << " plane and cylinder faces, " << group.surface.size() << " surfaces";
      const double fraction = (round + static_cast<double>(done) / groups.size()) / kRounds;
      go_on = reportProgress(progress, "finishing", fraction, message.str(), groups_done + done);
      return go_on;
    };
    const int count = static_cast<int>(groups.size());
    if (!parallelForTicking(count, options.threads, plan_group, kProgressSeconds, tick) || !go_on)
      plan.cancelled = true;
    groups_done += static_cast<long>(groups.size());
    for (std::size_t i = 0; i < groups.size(); ++i) {
      for (const GroupOutcome::Note& n : outcomes[i].notes) tally.note(n.face, n.choice, n.share, n.why);
      for (FinishingOperation& op : outcomes[i].ops) per_setup[groups[i].setup].push_back(std::move(op));
    }
  }
  orderOperations(c, per_setup, plan);
  accountFaces(part, assignment, tally, flats.empty() ? 0.0 : flats.back()->diameter / 2, plan);
  plan.plan_seconds = secondsSince(start);
  if (!plan.cancelled) reportProgress(progress, "finishing", 1.0, "done", groups_done);  // none once told to stop
  return plan;
}

}  // namespace art2part
