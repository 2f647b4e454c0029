// The pipeline in one call (plan_part.h).
#include "art2part/plan/plan_part.h"

#include <algorithm>
#include <chrono>
#include <sstream>
#include <stdexcept>

#include <Eigen/Geometry>

#include "art2part/common/angles.h"
#include "art2part/plan/useless_operations.h"

namespace art2part {

namespace {

using Clock = std::chrono::steady_clock;

constexpr double kFinishedLeftMm = 0.05;  // a face the simulation leaves within this of its surface is finished
constexpr int kJudgedSamples = 3;         // ... when at least this many of its rays measure it
constexpr double kSameAxis = 1e-4;          // rad: operations whose axes differ by more are linked round the stock
constexpr double kTransitionStepDeg = 10;   // the linking arc's steps: chords sag by 0.4 % of its radius
constexpr double kTransitionMargin = 5;     // mm beyond the stock's sphere and clearance, at least (1 % of the size)

double secondsSince(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// The tools the path uses, in order of first use.
std::vector<Tool> toolsUsed(const Toolpath& path, const ToolLibrary& library) {
  std::vector<Tool> tools;
  for (const CutterLocation& c : path)
    if (std::none_of(tools.begin(), tools.end(), [&](const Tool& t) { return t.id == c.tool; })) {
      const Tool* t = library.find(c.tool);
      if (!t) throw InputError("plan: tool '" + c.tool + "' is not in the tool library");
      tools.push_back(*t);
    }
  return tools;
}

// The stock's top along a direction (its highest point) plus the clearance.
double topAlong(const Mesh& stock, const Vec3& d, double clearance) {
  double top = -1e300;
  for (const Vec3& v : stock.vertices) top = std::max(top, v.dot(d));
  return top + clearance;
}

// The directions from a to b along the sphere in steps of at most kTransitionStepDeg, both ends included: the shorter
// great circle, unless it leans further from the setup direction `up` than both ends do (a and b opposite, or the
// shorter way passing under the part), then by way of `up`: the tool never swings below the part towards the table.
std::vector<Vec3> transitionDirections(const Vec3& a, const Vec3& b, const Vec3& up) {
  auto arc = [](const Vec3& from, const Vec3& to) {
    const double angle = std::acos(std::clamp(from.dot(to), -1.0, 1.0));
    const int steps = std::max(1, static_cast<int>(std::ceil(angle / (kTransitionStepDeg * kPi / 180))));
    Vec3 turn = from.cross(to);  // a rotation taking `from` to `to` (any axis square to it when they are opposite)
    if (turn.norm() < 1e-9) turn = from.unitOrthogonal();
    turn.normalize();
    std::vector<Vec3> out;
    for (int i = 0; i <= steps; ++i) out.push_back(Eigen::AngleAxisd(angle * i / steps, turn) * from);
    return out;
  };
  const double lowest = std::min(a.dot(up), b.dot(up));
  std::vector<Vec3> direct = arc(a, b);
  for (const Vec3& d : direct)
    if (d.dot(up) < lowest - 1e-9) {
      std::vector<Vec3> via = arc(a, up);
      const std::vector<Vec3> rest = arc(up, b);
      via.insert(via.end(), rest.begin() + 1, rest.end());
      return via;
    }
  return direct;
}

// Rapids from `from` (axis a) to `to` (axis b) in one setup (direction `up`), when the two axes differ: up along a to
// the stock's top plane along it, out to the sphere round the stock (centre `centre`, radius `radius`: every point of
// the stock within it), along the sphere (transitionDirections) with the axis pointing out of it (the tool stays
// outside the sphere), in along b over `to`'s start, down to it. What the post makes of a rotary reposition (retract,
// turn, approach), written out so the simulation sweeps what the machine does.
Toolpath axisTransition(const CutterLocation& from, const CutterLocation& to, const Vec3& up, const Mesh& stock,
                        const Vec3& centre, double radius, double clearance) {
  Toolpath out;
  auto add = [&](const Vec3& tip, const Vec3& axis) {
    CutterLocation c = to;
    c.move = MoveKind::Rapid;
    c.tip = tip;
    c.axis = axis.normalized();
    out.push_back(c);
  };
  const Vec3 a = from.axis.normalized(), b = to.axis.normalized();
  const double up_a = std::max(0.0, topAlong(stock, a, clearance) - from.tip.dot(a));
  add(from.tip + up_a * a, a);
  for (const Vec3& d : transitionDirections(a, b, up.normalized())) add(centre + radius * d, d);
  const double down = std::max(0.0, topAlong(stock, b, clearance) - to.tip.dot(b));
  add(to.tip + down * b, b);
  return out;
}

// Setup by setup: its roughing, then its finishing; between operations of one setup whose axes differ, the
// transition above.
void combine(PlanResult& r, const Mesh& stock, double clearance) {
  const int setups = static_cast<int>(r.setups.setups.size());
  Box box = boundingBox(stock);
  const Vec3 centre = box.center();
  const double radius = 0.5 * box.diagonal() + clearance + std::max(kTransitionMargin, 0.01 * box.diagonal());
  for (int k = 0; k < setups; ++k) {
    auto append = [&](const Toolpath& path, const std::string& kind, const std::string& tool, bool finishing,
                      int source) {
      if (path.empty()) return;
      PlanOperation op;
      op.index = static_cast<int>(r.operations.size());
      op.setup = k;
      op.kind = kind;
      op.tool = tool;
      op.finishing = finishing;
      op.source = source;
      op.first_point = r.toolpath.size();
      Toolpath rows = path;
      if (!r.toolpath.empty() && r.toolpath.back().setup == k &&
          r.toolpath.back().axis.normalized().dot(path.front().axis.normalized()) < std::cos(kSameAxis)) {
        Toolpath link = axisTransition(r.toolpath.back(), path.front(), r.setups.setups[k].frame.z, stock, centre,
                                       radius, clearance);
        rows.insert(rows.begin(), link.begin(), link.end());
      }
      op.points = rows.size();
      for (CutterLocation c : rows) {
        c.op = op.index;
        r.toolpath.push_back(std::move(c));
      }
      r.operations.push_back(op);
    };
    for (int i = 0; i < static_cast<int>(r.roughing.operations.size()); ++i) {
      const RoughingOperation& op = r.roughing.operations[i];
      if (op.setup == k) append(op.path, op.kind, op.tool, false, i);
    }
    for (int i = 0; i < static_cast<int>(r.finishing.operations.size()); ++i) {
      const FinishingOperation& op = r.finishing.operations[i];
      if (op.setup == k) append(op.path, finishingKindName(op.kind), op.tool, true, i);
    }
  }
}

}  // namespace

void judgeFaces(const VerificationReport& report, FinishingPlan& finishing) {
  for (FaceFinish& face : finishing.faces) {
    if (face.face < 0 || face.face >= static_cast<int>(report.face_checks.size())) continue;
    const FaceVerification& check = report.face_checks[face.face];
    face.simulated_left_mm = check.left_max_mm;
    face.samples = check.samples;
    if (check.samples < kJudgedSamples) continue;
    std::ostringstream left;
    left.precision(3);
    left << check.left_max_mm;
    if (check.left_max_mm <= kFinishedLeftMm && face.status != FaceStatus::Finished) {
      face.reason = "finished by " + std::string(face.operations.empty() ? "its neighbours' operations" : "its operations") +
                    " though the planner believed otherwise (the simulation leaves " + left.str() + " mm; it thought: " +
                    face.reason + ")";
      face.status = FaceStatus::Finished;
    } else if (check.left_max_mm > kFinishedLeftMm && face.status == FaceStatus::Finished) {
      face.status = FaceStatus::Partial;
      face.reason = "the simulation finds " + left.str() + " mm left on it";
    }
  }
}

std::vector<double> faceAllowances(const Part& part, const FinishingPlan& finishing, const ToolLibrary& library) {
  std::vector<double> allowance = concaveSag(part.mesh, part.triangle_face, part.faces);
  for (std::size_t h = 0; h < finishing.holes.size() && h < finishing.hole_methods.size(); ++h) {
    const HoleMachining& m = finishing.hole_methods[h];
    const Tool* tool = m.method == HoleMethod::Drill ? library.find(m.drill) : nullptr;
    if (!tool) continue;
    const double over = std::max(0.0, (tool->diameter - finishing.holes[h].diameter) / 2);
    for (int f : finishing.holes[h].bore_faces)
      if (f >= 0 && f < static_cast<int>(allowance.size())) allowance[f] += over;
  }
  return allowance;
}

double planVerifyResolution(const Box& box) { return std::max({0.4, automaticResolution(box), box.diagonal() / 300}); }

Part pluggedPart(const Part& part, const std::vector<Hole>& holes, const std::vector<HoleMachining>& methods) {
  const Mesh plugs = holePlugs(holes, methods);
  if (plugs.triangles.empty()) return part;
  Part out = part;
  const int base = static_cast<int>(out.mesh.vertices.size());
  out.mesh.vertices.insert(out.mesh.vertices.end(), plugs.vertices.begin(), plugs.vertices.end());
  for (const Triangle& t : plugs.triangles) {
    out.mesh.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
    out.triangle_face.push_back(-1);
  }
  out.adjacency = buildAdjacency(out.mesh, part.adjacency.sharp_angle);
  return out;
}

FinishingOptions stageFinishingOptions(const PlanOptions& options) {
  FinishingOptions finishing = options.finishing;
  finishing.mode = options.setups.mode;
  finishing.allowance = options.roughing.allowance;
  return finishing;
}

SetupPlan planPartSetups(const Part& part, const VisibilityResult& visibility, const ToolLibrary& library,
                         const PlanOptions& options, const ProgressSink& progress) {
  SetupPlan setups = planSetups(part, visibility, options.setups, progress);
  if (!options.finish || setups.cancelled) return setups;
  double longest_flutes = 0;
  for (const Tool& t : library.tools)
    if (t.type == ToolType::Flat && t.max_engagement_deg == 0) longest_flutes = std::max(longest_flutes, t.flute_length);
  for (Setup& s : finishingSetups(part, visibility, setups, longest_flutes, stageFinishingOptions(options),
                                  options.finishing_setups))
    setups.setups.push_back(std::move(s));
  return setups;
}

RoughingStage planPartRoughing(const Part& part, const SetupPlan& setups, const ToolLibrary& library,
                               const PlanOptions& options, const ProgressSink& progress) {
  RoughingStage stage;
  const auto start = Clock::now();
  if (options.finish) {
    const FinishingOptions finishing = stageFinishingOptions(options);
    stage.holes = findHoles(part, finishing.holes);
    for (const Hole& h : stage.holes) stage.hole_methods.push_back(chooseHoleMethod(h, library, finishing.holes));
  }
  stage.seconds_holes = secondsSince(start);
  if (!reportProgress(progress, "roughing", 0, "roughing setup 1 of " + std::to_string(setups.setups.size()))) {
    stage.roughing.cancelled = true;
    return stage;
  }
  stage.roughing = planRoughing(pluggedPart(part, stage.holes, stage.hole_methods), setups, library, options.roughing,
                                progress);
  return stage;
}

FinishingPlan planPartFinishing(const Part& part, const VisibilityResult& visibility, const SetupPlan& setups,
                                const RoughingStage& roughing, const ToolLibrary& library, const PlanOptions& options,
                                const ProgressSink& progress) {
  const FinishingInput input{part, visibility, setups, roughing.roughing, roughing.holes, roughing.hole_methods,
                             library};
  return planFinishing(input, stageFinishingOptions(options), progress);
}

void combinePlan(PlanResult& plan, const Part& part, const ToolLibrary& library, const PlanOptions& options) {
  plan.operations.clear();
  plan.toolpath.clear();
  combine(plan, roughingStock(part, options.roughing), options.roughing.clearing.clearance);
  plan.tools = toolsUsed(plan.toolpath, library);
}

VerifyOptions planVerifyOptions(const Part& part, const PlanResult& plan, const ToolLibrary& library,
                                const PlanOptions& options) {
  VerifyOptions verify = options.verification;
  if (verify.resolution <= 0) verify.resolution = planVerifyResolution(boundingBox(part.mesh));
  if (verify.face_allowance.empty()) verify.face_allowance = faceAllowances(part, plan.finishing, library);
  return verify;
}

PlanResult planPart(const Part& part, const ToolLibrary& library, const PlanOptions& options,
                    const ProgressSink& progress) {
  PlanResult r;
  auto stage = [&](const std::string& name, double fraction, const std::string& message) {
    if (!reportProgress(progress, name, fraction, message)) r.cancelled = true;
    return !r.cancelled;
  };
  auto timed = [&](const std::string& name, Clock::time_point start) { r.timings.emplace_back(name, secondsSince(start)); };
  const auto all = Clock::now();

  auto start = Clock::now();
  if (!stage("visibility", 0, "directions and visibility cones")) return r;
  r.visibility = analyseVisibility(part, options.visibility, progress);
  r.cancelled = r.visibility.cancelled;
  timed("visibility", start);
  if (r.cancelled) return r;

  start = Clock::now();
  if (!stage("setups", 0, "minimum cover of the visibility cones")) return r;
  r.setups = planPartSetups(part, r.visibility, library, options, progress);
  r.cancelled = r.setups.cancelled;
  if (r.cancelled) return r;
  timed("setups", start);

  start = Clock::now();
  if (options.finish && !stage("holes", 0, "holes and the drills that make them")) return r;
  RoughingStage roughing = planPartRoughing(part, r.setups, library, options, progress);
  r.holes = roughing.holes;
  r.hole_methods = roughing.hole_methods;
  r.roughing = roughing.roughing;
  r.cancelled = r.roughing.cancelled;
  r.timings.emplace_back("holes", roughing.seconds_holes);
  r.timings.emplace_back("roughing", secondsSince(start) - roughing.seconds_holes);
  if (r.cancelled) return r;

  if (options.finish) {
    start = Clock::now();
    r.finishing = planPartFinishing(part, r.visibility, r.setups, roughing, library, options, progress);
    r.cancelled = r.finishing.cancelled;
    timed("finishing", start);
  }

  combinePlan(r, part, library, options);
  if (options.verify && !r.toolpath.empty() && !r.cancelled) {
    start = Clock::now();
    stage("verification", 0, "simulating " + std::to_string(r.toolpath.size()) + " moves");
    VerifyOptions first = planVerifyOptions(part, r, library, options);
    if (options.drop_useless) first.checkpoints = options.resume_checkpoints;
    r.verification =
        verifyToolpath(part.mesh, part.triangle_face, r.toolpath, r.tools, first, &r.simulation, progress);
    r.cancelled = r.verification.cancelled;
    r.verified = !r.cancelled;
    timed("verification", start);
    if (r.verified && options.drop_useless) {
      start = Clock::now();
      const auto verify = [&](const PlanResult& p, VerificationState& state, const TrialSweep& trial) {
        stage("verification", 0, "simulating again without the roughing that removes almost nothing");
        VerifyOptions again = planVerifyOptions(part, p, library, options);
        again.checkpoints = trial.checkpoints;
        again.keep_sweeping = trial.keep_sweeping;
        return verifyToolpath(part.mesh, part.triangle_face, p.toolpath, p.tools, again, &state, progress,
                              trial.resume_from);
      };
      dropUselessRoughing(r, part, library, options, verify);
      if (r.useless.found > 0) timed("verification without useless roughing", start);
    }
    r.simulation.checkpoints.clear();
    judgeFaces(r.verification, r.finishing);
  }
  r.timings.emplace_back("total", secondsSince(all));
  return r;
}

}  // namespace art2part
