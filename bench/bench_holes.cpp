// Hole benchmarks (issue 17, item 4): on every shared STEP part (and the fine CTC-02 mesh, segmented), the holes
// findHoles finds, how each gets made with the shop's library (drill / helix / none, with the reasons), the groups of
// equal signature, and the seconds findHoles takes (work size: triangles x holes, the clearance bands' cost).
//   bench_holes [--simulate] [PART ...]   (default: the shared STEP parts; a name without a slash is looked up in the
//                                          shared folder). --simulate: sweep every hole's paths (spot, drill, helix)
//                                          through the plugs with verifyToolpath and print gouges, collisions, leftover
//                                          (--resolution MM: the lattice's spacing; default automatic).
#include <chrono>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "art2part/finishing/holes.h"
#include "art2part/geometry/part.h"
#include "art2part/simulation/verify.h"
#include "bench_main.h"

using namespace art2part;

namespace {

const char* const kUsage =
    "bench_holes [--simulate] [--resolution MM] [PART ...]\n"
    "  PART: default the shared STEP parts; a name without a slash is looked up in the shared folder\n"
    "  --simulate: sweep every hole's paths (spot, drill, helix) through the plugs with verifyToolpath and print\n"
    "  gouges, collisions, leftover (--resolution MM: the lattice's spacing; default automatic)\n";
const std::string kParts = ART2PART_SHARED_PARTS;

double since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Every drilled and helix-milled hole's path (spot, drill; helix), one run per tool and axis as a setup would make them,
// swept through stock that is the holes' plugs: what the simulation says of them on the whole part.
void simulateHoles(const Part& part, const std::vector<Hole>& holes, const std::vector<HoleMachining>& methods,
                   const ToolLibrary& library, double resolution) {
  Toolpath path;
  std::vector<Tool> tools;
  const auto add = [&](Toolpath run, const std::string& id) {
    const int op = path.empty() ? 0 : path.back().op + 1;
    for (CutterLocation& point : run) point.op = op;
    path.insert(path.end(), run.begin(), run.end());
    bool known = false;
    for (const Tool& tool : tools) known = known || tool.id == id;
    if (!known) tools.push_back(*library.find(id));
  };
  // Rapids between holes at 5 mm over the part's top along their axis (what a setup's clearance plane does).
  const auto clearance = [&](const std::vector<Hole>& group) {
    double top = -1e300, mouth = -1e300;
    for (const Vec3& v : part.mesh.vertices) top = std::max(top, v.dot(group.front().axis));
    for (const Hole& hole : group) mouth = std::max(mouth, hole.mouth.dot(hole.axis));
    return top - mouth + 5;
  };
  std::vector<bool> done(holes.size(), false);
  for (size_t h = 0; h < holes.size(); ++h) {
    if (done[h] || methods[h].method == HoleMethod::None) continue;
    std::vector<Hole> group;  // same method, tools and axis: one tool load per tool
    for (size_t k = h; k < holes.size(); ++k)
      if (!done[k] && methods[k].method == methods[h].method && methods[k].drill == methods[h].drill &&
          methods[k].spot == methods[h].spot && holes[k].axis.dot(holes[h].axis) > 1 - 1e-9) {
        group.push_back(holes[k]);
        done[k] = true;
      }
    if (methods[h].method == HoleMethod::Helix) {
      for (const Hole& hole : group)
        add(helixPath(hole, *library.find(methods[h].drill), 0, clearance({hole})), methods[h].drill);
      continue;
    }
    if (!methods[h].spot.empty())
      add(drillingPath(group, *library.find(methods[h].spot), true, 0, clearance(group)), methods[h].spot);
    add(drillingPath(group, *library.find(methods[h].drill), false, 0, clearance(group)), methods[h].drill);
  }
  if (path.empty()) return;
  const Mesh plugs = holePlugs(holes, methods);
  VerifyOptions options;
  options.stock_mesh = &plugs;
  options.resolution = resolution;
  const VerificationReport report = verifyToolpath(part.mesh, part.triangle_face, path, tools, options);
  std::printf("  simulated: %zu points, %d moves, %lld poses, lattice %.3f mm, %.2f s (%.0f moves/s): %d gouges (worst "
              "%.4f mm), %d collisions (worst %.3f mm); plugs %.0f mm^3, removed %.0f, left %.2f mm^3 (thickest %.3f "
              "mm)\n",
              path.size(), report.moves, static_cast<long long>(report.poses), report.resolution_mm,
              report.seconds_total, report.moves_per_second, report.gouges, report.worst_gouge_mm, report.collisions,
              report.worst_collision_mm, signedVolume(plugs), report.removed_volume_mm3, report.leftover_volume_mm3,
              report.leftover_max_mm);
  for (size_t g = 0; g < report.gouge_list.size() && g < 3; ++g)
    std::printf("    gouge %.4f mm by %s at [%.2f %.2f %.2f]\n", report.gouge_list[g].depth_mm,
                report.gouge_list[g].tool.c_str(), report.gouge_list[g].position.x(), report.gouge_list[g].position.y(),
                report.gouge_list[g].position.z());
}

void benchPart(const std::string& path, const ToolLibrary& library, bool simulate, double resolution) {
  auto start = std::chrono::steady_clock::now();
  const Part part = loadPart(path);
  const double load_s = since(start);
  start = std::chrono::steady_clock::now();
  const std::vector<Hole> holes = findHoles(part);
  const double find_s = since(start);
  start = std::chrono::steady_clock::now();
  std::vector<HoleMachining> methods;
  for (const Hole& hole : holes) methods.push_back(chooseHoleMethod(hole, library));
  const double choose_s = since(start);
  const Mesh plugs = holePlugs(holes, methods);

  std::map<HoleMethod, int> by_method;
  for (const HoleMachining& m : methods) ++by_method[m.method];
  const double work = static_cast<double>(part.mesh.triangleCount()) * std::max<size_t>(1, holes.size());
  std::printf("\n%s: %d triangles, %zu faces (%s), loaded in %.2f s\n", path.c_str(), part.mesh.triangleCount(),
              part.faces.size(), part.face_source == FaceSource::BRep ? "B-rep" : "segmented", load_s);
  std::printf("  findHoles %.3f s: %zu holes, %.2f M triangle-hole pairs/s; chooseHoleMethod %.3f s (%.0f holes/s)\n",
              find_s, holes.size(), work / find_s / 1e6, choose_s, holes.size() / std::max(choose_s, 1e-9));
  std::printf("  by method: drill %d, helix %d, none %d; plugs %d triangles, %.0f mm^3\n", by_method[HoleMethod::Drill],
              by_method[HoleMethod::Helix], by_method[HoleMethod::None], plugs.triangleCount(), signedVolume(plugs));

  // One line per signature and method: how many, with what, or why not.
  struct Group {
    int count = 0;
    std::string what;
  };
  std::map<std::string, Group> groups;
  for (size_t h = 0; h < holes.size(); ++h) {
    const HoleMachining& m = methods[h];
    std::string what = holeMethodName(m.method);
    if (m.method != HoleMethod::None) what += " " + m.drill + (m.spot.empty() ? "" : " after " + m.spot) +
                                              (m.peck ? " pecked" : "");
    if (!m.reason.empty()) what += " (" + m.reason + ")";
    Group& group = groups[holes[h].signature + " | " + what];
    ++group.count;
    group.what = what;
  }
  for (const auto& [key, group] : groups)
    std::printf("  %3d x %s\n", group.count, key.c_str());
  if (simulate) simulateHoles(part, holes, methods, library, resolution);
}

int benchMain(const std::vector<std::string>& args) {
  const Arguments a(args, {"simulate"}, {"resolution"});
  const bool simulate = a.flag("simulate");
  const double resolution = a.number("resolution", 0);  // the lattice: 0 automatic
  if (resolution < 0) throw UsageError("--resolution must not be negative");
  std::vector<std::string> parts;
  for (const std::string& name : a.positional())
    parts.push_back(name.find('/') == std::string::npos ? kParts + "/" + name : name);
  if (parts.empty())
    for (const char* name : {"nist_ctc_01_asme1_rd.stp", "nist_ctc_02_asme1_rc.stp", "ANC101.stp", "featuretype.STEP"})
      parts.push_back(kParts + "/" + name);
  for (const std::string& path : parts) requireFile(path);
  const ToolLibrary library = loadToolLibrary(std::string(ART2PART_SOURCE_DIR) + "/config/tools.yaml");
  std::printf("holes on %zu parts, library %zu tools\n", parts.size(), library.tools.size());
  for (const std::string& path : parts) benchPart(path, library, simulate, resolution);
  return 0;
}

}  // namespace

int main(int argc, char** argv) { return runBench(argc, argv, kUsage, benchMain); }
