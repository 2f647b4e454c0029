// art2part plan PART --out DIR [--mode 3axis|5axis] [--tilt DEG] [--level L] [--time-limit S] [--no-pp]
//                    [--tools FILE] [--tool ID] [--allowance MM] [--stepdown MM] [--no-rest] [--whole-stock] [--machine FILE]
//                    [--verify-resolution MM] [--roughing 3axis|5axis]
//                    plus the visibility options: the pipeline without ROS. Part -> visibility -> setups -> roughing
// -> verification -> post. --roughing 5axis (the default with --mode 5axis) adds 5-axis voxel roughing after each
// setup's 3-axis operations and posts for the trunnion (config/machines/trunnion_ac.yaml) unless --machine says. Writes DIR/plan.json, toolpaths.csv, tools.json, mesh.stl, program.ngc (with setup_<k>.ngc,
// tool tables, trajectory.csv), setups.png, remaining.png (the stock left, coloured by its thickness) and the
// visibility contract files (directions.csv, visibility.bits).
#include <algorithm>
#include <chrono>
#include <fstream>
#include <iostream>
#include <optional>

#include "arguments.h"
#include "art2part/post/joint_trajectory.h"
#include "art2part/post/machine_program.h"
#include "art2part/post/post_files.h"
#include "art2part/render/palette.h"
#include "art2part/render/picture.h"
#include "art2part/roughing/roughing.h"
#include "art2part/setup/setup_report.h"
#include "art2part/simulation/part_distance.h"
#include "art2part/simulation/stock_mesh.h"
#include "art2part/simulation/verify.h"
#include "art2part/visibility/analysis.h"
#include "commands.h"

#ifndef ART2PART_CONFIG_DIR
#define ART2PART_CONFIG_DIR "config"
#endif

namespace art2part {
namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

nlohmann::json vectorJson(const Vec3& v) { return nlohmann::json::array({v.x(), v.y(), v.z()}); }

nlohmann::json partJson(const Part& part) {
  const Box box = boundingBox(part.mesh);
  return {{"source", part.source},
          {"triangles", part.mesh.triangleCount()},
          {"faces", part.faces.size()},
          {"bounding_box", {{"min", vectorJson(box.min)}, {"max", vectorJson(box.max)}}}};
}

nlohmann::json directionsJson(const DirectionSet& directions) {
  nlohmann::json out = nlohmann::json::array();
  for (const Vec3& d : directions.directions) out.push_back(vectorJson(d));
  return out;
}

nlohmann::json operationJson(int index, const RoughingOperation& op) {
  int critical = 0;
  for (const RoughingLevel& l : op.levels) critical += l.critical ? 1 : 0;
  return {{"index", index},         {"setup", op.setup},         {"kind", op.kind},
          {"tool", op.tool},        {"points", op.path.size()},  {"length_mm", op.feed_mm},
          {"rapid_mm", op.rapid_mm}, {"time_s", op.seconds},      {"levels", op.levels.size()},
          {"critical_levels", critical}, {"ramps", op.ramps},    {"plunges", op.plunges},
          {"retracts", op.retracts}, {"plan_seconds", op.plan_seconds},
          {"direct_shadow_levels", op.direct_levels}};
}

nlohmann::json verificationJson(const VerificationReport& report) {
  return {{"gouges", report.gouges},
          {"collisions", report.collisions},
          {"passed", report.passed()},
          {"worst_gouge_mm", report.worst_gouge_mm},
          {"worst_collision_mm", report.worst_collision_mm},
          {"stock_volume_mm3", report.stock_volume_mm3},
          {"part_volume_mm3", report.part_volume_mm3},
          {"removed_volume_mm3", report.removed_volume_mm3},
          {"remaining_volume_mm3", report.remaining_volume_mm3},
          {"leftover_volume_mm3", report.leftover_volume_mm3},
          {"leftover_max_mm", report.leftover_max_mm},
          {"resolution_mm", report.resolution_mm},
          {"open_mesh_closed_edges", report.closed_open_mesh_edges},
          {"seconds", report.seconds_total}};
}

// The whole plan: part, directions, setups, operations, verification and timings.
nlohmann::json planJson(const Part& part, const VisibilityResult& visibility, const SetupPlan& plan,
                        const RoughingPlan& roughing, const VerificationReport* report, const nlohmann::json& timings) {
  nlohmann::json j = setupPlanJson(plan, visibility.directions);
  j["setup_seconds"] = j["seconds"];
  j.erase("seconds");
  j["part"] = partJson(part);
  j["directions"] = directionsJson(visibility.directions);
  j["operations"] = nlohmann::json::array();
  for (int i = 0; i < static_cast<int>(roughing.operations.size()); ++i)
    j["operations"].push_back(operationJson(i, roughing.operations[i]));
  j["roughing_region_failures"] = roughing.region_failures;
  j["roughing_direct_shadow_levels"] = roughing.direct_levels;
  j["verification"] = report ? verificationJson(*report) : nlohmann::json(nullptr);
  j["timings"] = timings;
  return j;
}

void writeJson(const nlohmann::json& j, const std::string& path) {
  std::ofstream out(path);
  if (!out) throw InputError("cannot write '" + path + "'");
  out << j.dump() << "\n";
  if (!out) throw InputError("cannot write '" + path + "'");
}

// Setup colours, far from the red of what no setup reaches; after ten they repeat darker.
std::array<unsigned char, 3> setupColour(int k) {
  static const Rgb palette[] = {{0.25f, 0.45f, 0.85f}, {0.30f, 0.70f, 0.35f}, {0.95f, 0.78f, 0.20f},
                                {0.60f, 0.40f, 0.80f}, {0.20f, 0.75f, 0.80f}, {0.95f, 0.55f, 0.15f},
                                {0.55f, 0.35f, 0.20f}, {0.90f, 0.50f, 0.75f}, {0.55f, 0.60f, 0.30f},
                                {0.50f, 0.50f, 0.50f}};
  const int n = sizeof palette / sizeof palette[0];
  const float shade = 1.0f / static_cast<float>(1 + k / n);
  const Rgb& c = palette[k % n];
  return {static_cast<unsigned char>(255 * c[0] * shade), static_cast<unsigned char>(255 * c[1] * shade),
          static_cast<unsigned char>(255 * c[2] * shade)};
}

// The part coloured by the setup that machines each triangle, unmachinable triangles red.
void writeSetupPicture(const Part& part, const SetupPlan& plan, const std::string& path) {
  PictureOptions picture;
  picture.triangle_colours.assign(part.mesh.triangleCount(), {220, 220, 220});
  for (int k = 0; k < static_cast<int>(plan.setups.size()); ++k)
    for (int t : plan.setups[k].triangles) picture.triangle_colours[t] = setupColour(k);
  for (int t : plan.unmachinable_triangles) picture.triangle_colours[t] = {230, 25, 25};
  const Image image = renderPicture(part.mesh, picture);
  try {
    writePng(image, path);
  } catch (const std::runtime_error& e) {
    throw InputError(e.what());  // a path the user gave us
  }
}

RoughingOptions roughingOptionsFrom(const Arguments& a) {
  RoughingOptions options;
  options.allowance = a.number("allowance", options.allowance);
  options.stepdown = a.number("stepdown", options.stepdown);
  options.tool = a.value("tool", "");
  options.rest_pass = !a.flag("no-rest");
  options.in_process_stock = !a.flag("whole-stock");
  if (!(options.allowance >= 0) || !(options.stepdown >= 0))
    throw UsageError("--allowance and --stepdown must not be negative");
  // 5-axis voxel roughing after the 3-axis operations: asked for, or implied by 5-axis setups.
  const std::string roughing = a.value("roughing", a.value("mode", "3axis") == "5axis" ? "5axis" : "3axis");
  if (roughing != "3axis" && roughing != "5axis") throw UsageError("--roughing is 3axis or 5axis");
  options.five_axis = roughing == "5axis";
  return options;
}

// The tools the operations use, in order of first use.
std::vector<Tool> toolsUsed(const RoughingPlan& roughing, const ToolLibrary& library) {
  std::vector<Tool> tools;
  for (const RoughingOperation& op : roughing.operations)
    if (std::none_of(tools.begin(), tools.end(), [&](const Tool& t) { return t.id == op.tool; }))
      tools.push_back(*library.find(op.tool));
  return tools;
}

Toolpath wholePath(const RoughingPlan& roughing) {
  Toolpath path;
  for (const RoughingOperation& op : roughing.operations) path.insert(path.end(), op.path.begin(), op.path.end());
  return path;
}

// Every setup clamps the part anew, facing up: the setup frame along the table's axes, the middle of the stock's
// bottom (in that frame) on the table's origin.
PostOptions clampedPostOptions(const Part& part, const SetupPlan& plan, const RoughingOptions& roughing) {
  PostOptions options;
  const Mesh stock = roughingStock(part, roughing);
  for (int k = 0; k < static_cast<int>(plan.setups.size()); ++k) {
    const SetupFrame& f = plan.setups[k].frame;
    Box box;  // the stock in the setup frame
    for (const Vec3& p : stock.vertices) {
      const Vec3 d = p - f.origin;
      box.extend(Vec3(d.dot(f.x), d.dot(f.y), d.dot(f.z)));
    }
    const Vec3 bottom(box.center().x(), box.center().y(), box.min.z());
    const Vec3 anchor = f.origin + bottom.x() * f.x + bottom.y() * f.y + bottom.z() * f.z;
    options.fixtures[k] = fixtureFacingUp(f.x, f.y, f.z, anchor, Vec3::Zero());
  }
  return options;
}

void writeRemainingPicture(const Part& part, const VerificationState& state, const VerificationReport& report,
                           const std::string& path) {
  const PartDistance distance(part.mesh);
  const StockMesh stock = remainingStockMesh(state.stock, state.part, distance);
  writeDeviationPicture(stock, std::max(report.leftover_max_mm, 10.0 * report.tolerance_mm), report.tolerance_mm, path);
}

}  // namespace

int runPlan(const std::vector<std::string>& args) {
  std::set<std::string> options = setupValueOptions();
  for (const char* o : {"out", "tools", "tool", "allowance", "stepdown", "machine", "verify-resolution", "roughing"}) options.insert(o);
  std::set<std::string> flags = setupFlags();
  flags.insert("no-rest");
  flags.insert("whole-stock");
  const Arguments a(args, flags, options);
  const std::string path = a.requirePositional(1, "one part file: art2part plan PART --out DIR");
  if (!a.has("out")) throw UsageError("plan needs --out DIR");
  const std::string out = a.value("out");
  const SetupOptions setup_options = setupOptionsFrom(a);
  const VisibilityOptions visibility_options = visibilityOptionsFrom(a);
  const RoughingOptions roughing_options = roughingOptionsFrom(a);
  const ToolLibrary library = loadToolLibrary(a.value("tools", std::string(ART2PART_CONFIG_DIR) + "/tools.yaml"));
  const std::string default_machine = roughing_options.five_axis ? "trunnion_ac.yaml" : "vmc_3axis.yaml";
  const Machine machine = loadMachine(a.value("machine", std::string(ART2PART_CONFIG_DIR) + "/machines/" + default_machine));
  nlohmann::json timings;
  const auto all = Clock::now();

  auto start = Clock::now();
  const Part part = loadPart(path, loadOptionsFrom(a));
  timings["load"] = secondsSince(start);
  start = Clock::now();
  const VisibilityResult visibility = analyseVisibility(part, visibility_options);
  timings["visibility"] = secondsSince(start);
  start = Clock::now();
  const SetupPlan plan = planSetups(part, visibility, setup_options);
  timings["setups"] = secondsSince(start);

  start = Clock::now();
  const RoughingPlan roughing = planRoughing(part, plan, library, roughing_options);
  timings["roughing"] = secondsSince(start);

  start = Clock::now();
  writeVisibilityFiles(part, visibility, out);
  writeSetupPicture(part, plan, out + "/setups.png");
  const Toolpath toolpath = wholePath(roughing);
  const std::vector<Tool> tools = toolsUsed(roughing, library);
  writeToolpathsCsv(toolpath, out + "/toolpaths.csv");
  writeToolsJson(tools, out + "/tools.json");
  timings["write"] = secondsSince(start);

  std::optional<VerificationReport> report;
  std::string post_error;
  if (!toolpath.empty()) {
    start = Clock::now();
    VerifyOptions verify;
    verify.stock_margin = roughing_options.stock_margin;
    // The simulation's lattice: at least 0.4 mm and 1/300 of the part's diagonal (the sweep's cost grows with the
    // cube of the lattice's fineness; --verify-resolution for a finer check).
    const Box box = boundingBox(part.mesh);
    verify.resolution =
        a.number("verify-resolution", std::max({0.4, automaticResolution(box), box.diagonal() / 300}));
    VerificationState state;
    report = verifyToolpath(part.mesh, part.triangle_face, toolpath, tools, verify, &state);
    writeRemainingPicture(part, state, *report, out + "/remaining.png");
    timings["verification"] = secondsSince(start);

    start = Clock::now();
    try {  // a machine too small for the part is a finding of the plan, not a failure of it
      const MachineProgram program =
          buildMachineProgram(machine, toolpath, tools, part.source, clampedPostOptions(part, plan, roughing_options));
      const JointTrajectory trajectory = parameterizeTrajectory(machine, programWaypoints(program), TrajectoryOptions{});
      writePostFiles(program, trajectory, 50, out);
    } catch (const InputError& e) {
      post_error = e.what();
      std::cerr << "art2part: no program for " << machine.name << ": " << post_error << "\n";
    }
    timings["post"] = secondsSince(start);
  }
  timings["total"] = secondsSince(all);
  nlohmann::json j = planJson(part, visibility, plan, roughing, report ? &*report : nullptr, timings);
  j["program"] = {{"machine", machine.name}, {"written", !toolpath.empty() && post_error.empty()}, {"error", post_error}};
  writeJson(j, out + "/plan.json");
  std::cout << "timings:     ";
  for (const auto& [stage, seconds] : timings.items()) std::cout << " " << stage << " " << seconds.get<double>() << " s";
  std::cout << "\n";

  std::cout << "part:         " << path << " (" << part.mesh.triangleCount() << " triangles, "
            << visibility.directions.size() << " directions)\n"
            << setupPlanText(part, plan, visibility.directions);
  if (roughing.closed_open_mesh_edges > 0)
    std::cout << "solid:        the mesh is open (" << roughing.closed_open_mesh_edges
              << " boundary edges): roughed and simulated as the solid between it and a floor on its open side\n";
  if (roughing.region_failures > 0 || roughing.direct_levels > 0)
    std::cout << "warning:      " << roughing.region_failures << " polygon operations failed, " << roughing.direct_levels
              << " levels took the shadow directly (the grown forbidden region missed part of it)\n";
  for (int i = 0; i < static_cast<int>(roughing.operations.size()); ++i) {
    const RoughingOperation& op = roughing.operations[i];
    std::cout << "operation " << i << ":  " << op.kind << ", setup " << op.setup << ", tool " << op.tool << ", "
              << op.levels.size() << " levels, " << op.path.size() << " points, " << static_cast<long>(op.feed_mm)
              << " mm cutting, ~" << static_cast<long>(op.seconds) << " s\n";
  }
  if (report)
    std::cout << "verification: " << (report->passed() ? "" : "FAILED: ") << report->gouges << " gouges, " << report->collisions << " collisions, "
              << static_cast<long>(report->removed_volume_mm3) << " of "
              << static_cast<long>(report->stock_volume_mm3 - report->part_volume_mm3)
              << " mm3 of stock removed, " << static_cast<long>(report->leftover_volume_mm3)
              << " mm3 left beyond the tolerance\n";
  std::cout << "wrote:        " << out << "/{plan.json,toolpaths.csv,tools.json,mesh.stl,program.ngc,setups.png,"
            << "remaining.png,directions.csv,visibility.bits}\n";
  // A plan the simulation rejects is still written (plan.json says passed: false, and why); the exit status is for
  // errors in the input. `art2part verify DIR` exits 1 on any gouge or collision.
  return 0;
}

}  // namespace art2part
