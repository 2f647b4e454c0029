// Hole benchmarks (issue 17, item 4): on every shared STEP part (and the fine CTC-02 mesh, segmented), the holes
// findHoles finds, how each gets made with the shop's library (drill / helix / none, with the reasons), the groups of
// equal signature, and the seconds findHoles takes (work size: triangles x holes, the clearance bands' cost).
//   bench_holes [PART ...]     (default: the shared parts; a name without a slash is looked up in the shared folder)
#include <chrono>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "art2part/finishing/holes.h"
#include "art2part/geometry/part.h"

using namespace art2part;

namespace {

const std::string kParts = ART2PART_SHARED_PARTS;

double since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void benchPart(const std::string& path, const ToolLibrary& library) {
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
}

}  // namespace

int main(int argc, char** argv) {
  const ToolLibrary library = loadToolLibrary(std::string(ART2PART_SOURCE_DIR) + "/config/tools.yaml");
  std::vector<std::string> parts;
  for (int a = 1; a < argc; ++a) {
    const std::string name = argv[a];
    parts.push_back(name.find('/') == std::string::npos ? kParts + "/" + name : name);
  }
  if (parts.empty())
    for (const char* name : {"nist_ctc_01_asme1_rd.stp", "nist_ctc_02_asme1_rc.stp", "ANC101.stp", "featuretype.STEP"})
      parts.push_back(kParts + "/" + name);
  std::printf("holes on %zu parts, library %zu tools\n", parts.size(), library.tools.size());
  for (const std::string& path : parts) benchPart(path, library);
  return 0;
}
