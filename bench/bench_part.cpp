// Part model benchmarks (issue 2): loading every shared part, and how well mesh segmentation recovers B-rep faces:
// the STEP tessellation exported as an STL would be (float32 vertices), segmented, compared face by face.
#include <chrono>
#include <cstdio>
#include <string>

#include "art2part/geometry/part.h"
#include "art2part/geometry/segmentation.h"
#include "bench_main.h"

using namespace art2part;

namespace {

const char* const kUsage = "bench_part   (no arguments: every shared part)\n";
const std::string kParts = ART2PART_SHARED_PARTS;

double since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void printFaces(const Part& part) {
  const FaceCounts c = countFaces(part.faces);
  std::printf("%5d faces (%d plane, %d cyl, %d cone, %d sphere, %d torus, %d other)", c.total(), c.plane, c.cylinder,
              c.cone, c.sphere, c.torus, c.other);
}

int benchMain(const std::vector<std::string>& args) {
  positionalAtMost(Arguments(args, {}, {}), 0);  // no arguments: any is a usage mistake
  std::printf("loading: triangles, faces, seconds (load + repair + faces + adjacency)\n");
  for (const char* name : {"nist_ctc_01_asme1_rd.stp", "nist_ctc_02_asme1_rc.stp", "ANC101.stp", "featuretype.STEP",
                           "ktoolcav.stl", "mount_rush.stl", "Ailette001Solid-nohole-decimated-smoothed.stl",
                           "nist_ctc_02_asme1_rc_fine_tess.stl"}) {
    const auto start = std::chrono::steady_clock::now();
    const Part part = loadPart(kParts + "/" + name);
    const double s = since(start);
    std::printf("  %-46s %7d tri  ", name, part.mesh.triangleCount());
    printFaces(part);
    std::printf("  %s  %.2f s\n", part.check.closed ? "closed" : "open  ", s);
  }

  std::printf("segmentation vs B-rep faces (STEP tessellation, float32 vertices as in an STL export)\n");
  for (const char* name : {"nist_ctc_01_asme1_rd.stp", "ANC101.stp", "featuretype.STEP", "nist_ctc_02_asme1_rc.stp"}) {
    const Part brep = loadPart(kParts + "/" + name);
    Mesh exported = brep.mesh;
    for (Vec3& v : exported.vertices) v = v.cast<float>().cast<double>();
    const auto start = std::chrono::steady_clock::now();
    const Part mesh_part = partFromMesh(exported, name);
    const double s = since(start);
    const SegmentationScore score =
        scoreSegmentation(mesh_part.triangle_face, mesh_part.faces, brep.triangle_face, brep.faces);
    std::printf("  %-28s %6d tri  matched %6.2f%%  type agreement %6.2f%%  %4d segments / %4d faces  %.2f s\n", name,
                brep.mesh.triangleCount(), 100 * score.matched_fraction, 100 * score.type_agreement, score.segments,
                score.reference_faces, s);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) { return runBench(argc, argv, kUsage, benchMain); }
