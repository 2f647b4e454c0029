// The finishing stage over every setup (finishing.h).
#include "art2part/finishing/finishing.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>

#include "art2part/finishing/admissible.h"
#include "art2part/finishing/face_assignment.h"
#include "art2part/finishing/planar_finishing.h"
#include "art2part/geometry/solid_closure.h"

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

namespace {

constexpr double kFinished = 0.99;  // a face whose reached share is at least this counts as finished

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

// Flat end mills by diameter, largest first; balls likewise.
std::vector<const Tool*> toolsOfType(const ToolLibrary& library, ToolType type) {
  std::vector<const Tool*> tools;
  for (const Tool& t : library.tools)
    if (t.type == type) tools.push_back(&t);
  std::stable_sort(tools.begin(), tools.end(), [](const Tool* a, const Tool* b) {
    if (a->diameter != b->diameter) return a->diameter > b->diameter;
    return a->flute_length < b->flute_length;
  });
  return tools;
}

// The frame of a direction within a setup: the setup's own when it is the setup's direction.
SetupFrame frameFor(const Part& part, const Setup& setup, const Vec3& d) {
  if (setup.frame.z.dot(d) > std::cos(1e-6)) return setup.frame;
  return setupFrame(part, d);
}

// A group of faces finished along one direction in one setup.
struct Group {
  int setup = 0;
  Vec3 direction = Vec3::UnitZ();
  std::vector<PlanarTarget> planar;
  std::vector<int> surface;  // faces
};

std::string number(double v, int precision = 3) {
  std::ostringstream s;
  s.precision(precision);
  s << v;
  return s.str();
}

void estimateTime(FinishingOperation& op, const ToolLibrary& library, const FinishingOptions& options) {
  op.feed_mm = toolpathLength(op.path, MoveKind::Feed);
  op.rapid_mm = toolpathLength(op.path, MoveKind::Rapid);
  const Tool* tool = library.find(op.tool);
  const double feed = tool ? std::max(1.0, tool->feed_mm_min) : 1000.0;
  op.seconds = 60.0 * (op.feed_mm / feed + op.rapid_mm / options.rapid_mm_min);
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

  plan.faces.resize(part.faces.size());
  for (int f = 0; f < static_cast<int>(part.faces.size()); ++f) {
    FaceFinish& face = plan.faces[f];
    face.face = f;
    face.area_mm2 = part.faces[f].area;
    face.strategy = assignment[f].kind;
    face.setup = assignment[f].setup;
    face.direction = assignment[f].direction;
    face.reason = assignment[f].setup < 0 ? assignment[f].reason : "";
  }

  // Groups per setup and direction.
  std::vector<Group> groups;
  auto groupOf = [&](int setup, const Vec3& d) -> Group& {
    for (Group& g : groups)
      if (g.setup == setup && g.direction.dot(d) > std::cos(1e-6)) return g;
    groups.push_back({setup, d, {}, {}});
    return groups.back();
  };
  for (const FaceAssignment& a : assignment) {
    if (a.setup < 0) continue;
    switch (a.kind) {
      case FinishingKind::FaceMill:
      case FinishingKind::SideMill:
      case FinishingKind::Contour: groupOf(a.setup, a.direction).planar.push_back({a.face, a.kind}); break;
      case FinishingKind::Surface3Axis:
      case FinishingKind::Surface5Axis: groupOf(a.setup, a.direction).surface.push_back(a.face); break;
      default: break;
    }
  }
  std::stable_sort(groups.begin(), groups.end(), [](const Group& a, const Group& b) { return a.setup < b.setup; });

  // Per face: the planner's reach.
  std::vector<double> reached(part.faces.size(), 0), size(part.faces.size(), 0);
  std::vector<std::string> shortfall(part.faces.size());
  std::vector<std::vector<FinishingOperation>> per_setup(in.setups.setups.size());
  auto addOperation = [&](int setup, FinishingOperation op) {
    estimateTime(op, in.library, options);
    per_setup[setup].push_back(std::move(op));
  };

  const double work = std::max<std::size_t>(1, groups.size() + in.holes.size() / 8 + 1);
  double done = 0;
  for (const Group& group : groups) {
    std::ostringstream message;
    message << "setup " << group.setup + 1 << " of " << in.setups.setups.size() << ": " << group.planar.size()
            << " plane and cylinder faces, " << group.surface.size() << " surfaces";
    if (!reportProgress(progress, "finishing", done / work, message.str())) {
      plan.cancelled = true;
      break;
    }
    const Setup& setup = in.setups.setups[group.setup];
    const SetupFrame frame = frameFor(part, setup, group.direction);
    if (!group.planar.empty()) {
      PlanarGroup pg;
      pg.setup = group.setup;
      pg.frame = frame;
      pg.targets = group.planar;
      pg.stock = stock;
      if (group.direction.dot(setup.frame.z) > std::cos(1e-6) &&  // the setup's own frame: roughing's slabs hold
          group.setup < static_cast<int>(in.roughing.stock_left.size()))
        pg.stock_left = in.roughing.stock_left[group.setup];
      PlanarResult result = finishPlanar(solid, pg, flats, options);
      for (const PlanarReach& r : result.reach) {
        size[r.face] = r.size;
        reached[r.face] = r.reached;
        if (r.depth > 0 && r.deepest_reached < r.depth - 0.5)
          shortfall[r.face] = number(r.depth) + " mm deep: the flutes reach " + number(r.deepest_reached) +
                              " mm down with the shank and holder clear";
      }
      for (FinishingOperation& op : result.operations) addOperation(group.setup, std::move(op));
    }
    if (!group.surface.empty()) {
      // The largest ball whose radius fits the faces' concave curvature.
      double least = std::numeric_limits<double>::infinity();
      for (int f : group.surface) least = std::min(least, concaveRadius(part, f, triangles[f]));
      const Tool* ball = nullptr;
      for (const Tool* t : balls)
        if (t->diameter / 2 <= least + 1e-9) { ball = t; break; }
      if (!ball && !balls.empty()) ball = balls.back();
      if (ball) {
        SurfaceFinishingOptions so = options.surface;
        so.skin = std::max(so.skin, options.allowance);
        so.holder_margin = options.tools.holder_margin;
        const bool five = options.mode == MachineMode::FiveAxis;
        SurfaceFinishingResult r = five ? finishSurfaces5Axis(solid, group.surface, setup.frame, group.direction, *ball,
                                                              group.setup, so)
                                        : finishSurfaces3Axis(solid, group.surface, frame, *ball, group.setup, so);
        double area = 0;
        for (int f : group.surface) area += part.faces[f].area;
        const double share = area > 0 ? std::clamp(r.planned_area_mm2 / area, 0.0, 1.0) : 0;
        for (int f : group.surface) {
          size[f] = part.faces[f].area;
          reached[f] = share * part.faces[f].area;
          if (r.skipped_area_mm2 > 0)
            shortfall[f] = "the shank or holder cannot clear " + number(r.skipped_area_mm2) + " mm2 of its group";
          if (ball->diameter / 2 > concaveRadius(part, f, triangles[f]) + 1e-9)
            shortfall[f] = "concave radius " + number(concaveRadius(part, f, triangles[f])) +
                           " mm below the smallest ball's " + number(ball->diameter / 2) + " mm";
        }
        if (!r.path.empty()) {
          FinishingOperation op;
          op.setup = group.setup;
          op.kind = five ? FinishingKind::Surface5Axis : FinishingKind::Surface3Axis;
          op.tool = ball->id;
          op.direction = group.direction;
          op.faces = group.surface;
          op.path = std::move(r.path);
          op.plan_seconds = r.seconds;
          addOperation(group.setup, std::move(op));
        }
      }
    }
    done += 1;
  }

  // Holes: a spot and a drill run per setup and drill (one signature's tool load), a helix per hole. A through hole
  // reached from its far end is made from there (reversedHole), its method chosen again for that end.
  std::vector<Hole>& holes = plan.holes;
  std::vector<HoleMachining>& methods = plan.hole_methods;
  holes = in.holes;
  methods = in.hole_methods;
  if (!plan.cancelled) {
    std::map<std::pair<int, std::string>, std::vector<int>> drilled;  // (setup, drill id) -> holes
    std::map<int, std::vector<int>> spotted;                          // setup -> holes
    std::vector<char> turned(holes.size(), 0);
    for (const FaceAssignment& a : assignment) {
      if (a.hole < 0 || a.setup < 0) continue;
      if (!turned[a.hole] && a.direction.dot(holes[a.hole].axis) < 0) {
        turned[a.hole] = 1;
        holes[a.hole] = reversedHole(part, in.holes[a.hole], options.holes);
        methods[a.hole] = chooseHoleMethod(holes[a.hole], in.library, options.holes);
      }
      const HoleMachining& m = methods[a.hole];
      if (m.method == HoleMethod::None) continue;
      auto& list = drilled[{a.setup, m.method == HoleMethod::Drill ? m.drill : "helix:" + m.drill}];  // NOLINT
      if (std::find(list.begin(), list.end(), a.hole) == list.end()) list.push_back(a.hole);
      if (m.method == HoleMethod::Drill && !m.spot.empty()) {
        auto& spots = spotted[a.setup];
        if (std::find(spots.begin(), spots.end(), a.hole) == spots.end()) spots.push_back(a.hole);
      }
    }
    // The rapids between holes at the setup's clearance plane: over the stock's top along the holes' axis.
    auto clearanceAbove = [&](const std::vector<int>& group) {
      const Vec3& d = holes[group.front()].axis;
      double top = -1e300, mouth = -1e300;
      for (const Vec3& v : stock.vertices) top = std::max(top, v.dot(d));
      for (int h : group) mouth = std::max(mouth, holes[h].mouth.dot(d));
      return std::max(options.holes.retract_height, top + options.clearance - mouth);
    };
    for (const auto& [setup, group] : spotted) {
      std::vector<Hole> list;
      for (int h : group) list.push_back(holes[h]);
      const Tool* spot = in.library.find(methods[group.front()].spot);
      if (!spot) continue;
      FinishingOperation op;
      op.setup = setup;
      op.kind = FinishingKind::Drill;
      op.tool = spot->id;
      op.direction = list.front().axis;
      op.path = drillingPath(list, *spot, true, setup, clearanceAbove(group), options.holes);
      for (int h : group) op.faces.insert(op.faces.end(), holes[h].faces.begin(), holes[h].faces.end());
      op.note = "spot drilling";
      if (!op.path.empty()) addOperation(setup, std::move(op));
    }
    for (const auto& [key, group] : drilled) {
      const auto& [setup, id] = key;
      const bool helix = id.rfind("helix:", 0) == 0;
      const Tool* tool = in.library.find(helix ? id.substr(6) : id);
      if (!tool) continue;
      FinishingOperation op;
      op.setup = setup;
      op.kind = helix ? FinishingKind::Helix : FinishingKind::Drill;
      op.tool = tool->id;
      op.direction = holes[group.front()].axis;
      for (int h : group) {
        op.faces.insert(op.faces.end(), holes[h].faces.begin(), holes[h].faces.end());
        if (helix) {
          const Toolpath p = helixPath(holes[h], *tool, setup, clearanceAbove(group), options.holes);
          op.path.insert(op.path.end(), p.begin(), p.end());
        }
      }
      if (!helix) {
        std::vector<Hole> list;
        for (int h : group) list.push_back(holes[h]);
        op.path = drillingPath(list, *tool, false, setup, clearanceAbove(group), options.holes);
      }
      if (op.path.empty()) continue;
      for (int h : group)
        for (int f : holes[h].faces) size[f] = reached[f] = part.faces[f].area;
      addOperation(setup, std::move(op));
    }
  }

  // Machining order per setup: each tool loaded once.
  plan.tool_changes_per_setup.assign(in.setups.setups.size(), 0);
  for (int k = 0; k < static_cast<int>(per_setup.size()); ++k) {
    std::vector<FinishingOperation>& ops = per_setup[k];
    std::map<std::string, int> first;  // tool -> first position
    for (int i = 0; i < static_cast<int>(ops.size()); ++i) first.try_emplace(ops[i].tool, i);
    std::stable_sort(ops.begin(), ops.end(), [&](const FinishingOperation& a, const FinishingOperation& b) {
      const Tool* ta = in.library.find(a.tool);
      const Tool* tb = in.library.find(b.tool);
      const int ca = toolClass(ta), cb = toolClass(tb);
      if (ca != cb) return ca < cb;
      const bool spot_a = ta && ta->type == ToolType::Drill && a.note == "spot drilling";
      const bool spot_b = tb && tb->type == ToolType::Drill && b.note == "spot drilling";
      if (spot_a != spot_b) return spot_a;
      if (ta && tb && ta->diameter != tb->diameter && ca == 0) return ta->diameter > tb->diameter;
      return first[a.tool] < first[b.tool];
    });
    std::string loaded;
    for (FinishingOperation& op : ops) {
      if (op.tool != loaded) ++plan.tool_changes_per_setup[k], loaded = op.tool;
      plan.operations.push_back(std::move(op));
    }
    plan.tool_changes += plan.tool_changes_per_setup[k];
  }
  for (int i = 0; i < static_cast<int>(plan.operations.size()); ++i) {
    for (CutterLocation& c : plan.operations[i].path) c.op = i;
    plan.seconds += plan.operations[i].seconds;
  }
  plan.seconds += plan.tool_changes * options.tool_change_s;

  // Every face accounted for.
  for (int i = 0; i < static_cast<int>(plan.operations.size()); ++i)
    for (int f : plan.operations[i].faces) {
      FaceFinish& face = plan.faces[f];
      if (std::find(face.operations.begin(), face.operations.end(), i) == face.operations.end())
        face.operations.push_back(i);
      if (std::find(face.tools.begin(), face.tools.end(), plan.operations[i].tool) == face.tools.end())
        face.tools.push_back(plan.operations[i].tool);
    }
  for (FaceFinish& face : plan.faces) {
    if (face.setup < 0) {
      face.status = FaceStatus::Unmachinable;
      continue;
    }
    face.planned_mm2 = size[face.face] > 0 ? reached[face.face] / size[face.face] * face.area_mm2 : 0;
    const double share = size[face.face] > 0 ? reached[face.face] / size[face.face] : 0;
    if (share >= kFinished && !face.operations.empty()) {
      face.status = FaceStatus::Finished;
    } else if (share > 0 && !face.operations.empty()) {
      face.status = FaceStatus::Partial;
      face.reason = !shortfall[face.face].empty() ? shortfall[face.face]
                                                   : "corners or strips narrower than the smallest tool reaches";
    } else {
      face.status = FaceStatus::Unmachinable;
      face.reason = !shortfall[face.face].empty() ? shortfall[face.face]
                                                   : "no tool reaches it with its shank and holder clear";
    }
    if (!assignment[face.face].note.empty() && face.status != FaceStatus::Finished)
      face.reason += face.reason.empty() ? assignment[face.face].note : "; " + assignment[face.face].note;
  }
  plan.plan_seconds = secondsSince(start);
  reportProgress(progress, "finishing", 1.0, plan.cancelled ? "cancelled" : "done");
  return plan;
}

}  // namespace art2part
