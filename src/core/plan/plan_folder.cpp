// The plan folder: one writer, one reader (plan_folder.h).
#include "art2part/plan/plan_folder.h"

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>

#include "art2part/geometry/mesh.h"  // InputError
#include "art2part/geometry/mesh_io.h"
#include "art2part/plan/plan_json.h"
#include "art2part/plan/plan_pictures.h"
#include "art2part/plan/setup_sheet.h"
#include "art2part/post/joint_trajectory.h"
#include "art2part/post/post_files.h"
#include "art2part/tooling/toolpath.h"
#include "art2part/visibility/analysis.h"

namespace art2part {

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

void makeFolder(const std::string& dir) {
  std::error_code error;
  fs::create_directories(dir, error);
  if (error || !fs::is_directory(dir)) throw InputError("cannot create the plan folder '" + dir + "'");
}

void writeJsonFile(const nlohmann::json& j, const std::string& path) {
  std::ofstream out(path);
  if (!out) throw InputError("cannot write '" + path + "'");
  out << j.dump() << "\n";
  if (!out) throw InputError("cannot write '" + path + "'");
}

std::string partName(const Part& part) {
  const std::string name = fs::path(part.source).stem().string();
  return name.empty() ? "part" : name;
}

}  // namespace

std::map<int, Clamping> setupClampings(const Machine& machine, const Part& part, const SetupPlan& plan,
                                       const RoughingOptions& roughing) {
  const Box stock = boundingBox(roughingStock(part, roughing));
  std::map<int, Clamping> clampings;
  for (int k = 0; k < static_cast<int>(plan.setups.size()); ++k)
    clampings[k] = clampFacingUp(machine, plan.setups[k].frame, stock);
  return clampings;
}

void writeToolpathFiles(const std::string& dir, const Toolpath& path, const std::vector<Tool>& tools) {
  makeFolder(dir);
  writeToolpathsCsv(path, (fs::path(dir) / "toolpaths.csv").string());
  writeToolsJson(tools, (fs::path(dir) / "tools.json").string());
}

WrittenPlan writePlanFolder(const std::string& dir, const Part& part, const PlanResult& plan,
                            const PlanFolderOptions& options,
                            const std::vector<std::pair<std::string, double>>& extra_timings) {
  WrittenPlan written;
  auto start = Clock::now();
  makeFolder(dir);
  const fs::path folder(dir);
  if (options.visibility_files && !plan.visibility.directions.directions.empty())
    writeVisibilityFiles(part, plan.visibility, dir);  // mesh.stl with them
  else
    writeBinaryStl(part.mesh, (folder / "mesh.stl").string(), "art2part plan mesh, mm");
  writeToolpathFiles(dir, plan.toolpath, plan.tools);
  if (options.pictures) {
    writeSetupPicture(part, plan.setups, (folder / "setups.png").string());
    writeSetupPictures(dir, part, plan.setups);
    if (plan.verified && options.remaining_picture) writeRemainingPicture(part, plan, (folder / "remaining.png").string());
  }
  written.write_seconds = secondsSince(start);

  if (options.program.write && !plan.toolpath.empty()) {
    start = Clock::now();
    try {  // a machine too small for the part is a finding of the plan, not a failure of it
      const Machine& machine = options.program.machine;
      written.placement = placeSetups(machine, plan.toolpath, plan.tools, options.program.clampings, options.program.post);
      if (!written.placement.allReachable()) throw InputError(written.placement.unreachableText());
      PostOptions post = options.program.post;
      post.fixtures = written.placement.fixtures();
      const MachineProgram program = buildMachineProgram(machine, plan.toolpath, plan.tools, partName(part), post);
      const JointTrajectory trajectory =
          parameterizeTrajectory(options.program.machine, programWaypoints(program), TrajectoryOptions{});
      writePostFiles(program, trajectory, options.program.trajectory_rate_hz, dir);
      written.program_written = true;
    } catch (const InputError& e) {
      written.program_error = e.what();
    }
    written.post_seconds = secondsSince(start);
  } else if (options.program.write) {
    written.program_error = "the plan has no toolpath";
  } else {
    written.program_error = "no program asked for";
  }

  nlohmann::json j = planJson(part, plan, options.program.machine);
  for (const auto& [stage, seconds] : extra_timings) j["timings"][stage] = seconds;
  j["timings"]["write"] = written.write_seconds;
  j["timings"]["post"] = written.post_seconds;
  j["program"] = {{"machine", options.program.machine.name},
                  {"written", written.program_written},
                  {"error", written.program_written ? "" : written.program_error}};
  recordFixtures(j, written.placement);
  writeJsonFile(j, (folder / "plan.json").string());
  writeSetupSheet(dir);
  written.plan = std::move(j);
  return written;
}

PlanFolder readPlanFolder(const std::string& dir) {
  PlanFolder f;
  f.dir = dir;
  const fs::path folder(dir);
  if (!fs::is_directory(folder)) throw InputError("'" + dir + "' is not a plan folder (no such directory)");
  for (const char* file : {"toolpaths.csv", "tools.json"})
    if (!fs::is_regular_file(folder / file))
      throw InputError("'" + dir + "' is not a plan folder: it has no " + file);
  f.toolpath = readToolpathsCsv((folder / "toolpaths.csv").string());
  f.tools = readToolsJson((folder / "tools.json").string());
  if (fs::is_regular_file(folder / "mesh.stl")) f.mesh_path = (folder / "mesh.stl").string();
  f.plan = readPlanJson(dir);
  return f;
}

nlohmann::json readPlanJson(const std::string& dir) {
  const fs::path path = fs::path(dir) / "plan.json";
  if (!fs::is_regular_file(path)) return nullptr;
  std::ifstream in(path);
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw InputError("'" + path.string() + "' is not JSON: " + e.what());
  }
}

nlohmann::json planSummary(const nlohmann::json& plan) {
  nlohmann::json s = nlohmann::json::object();
  auto copy = [&](const char* key) {
    if (plan.contains(key)) s[key] = plan[key];
  };
  s["setups"] = plan.contains("setups") ? plan["setups"].size() : 0;
  s["operations"] = plan.contains("operations") ? plan["operations"].size() : 0;
  if (plan.contains("finishing")) s["faces_by_status"] = plan["finishing"].value("faces_by_status", nlohmann::json::object());
  copy("machining_time");
  copy("verification");
  copy("program");
  copy("timings");
  copy("cancelled");
  if (s.contains("verification") && s["verification"].is_object()) {
    nlohmann::json& v = s["verification"];
    for (const char* bulky : {"open_mesh_closed_edges", "resolution_mm"}) v.erase(bulky);
  }
  return s;
}

}  // namespace art2part
