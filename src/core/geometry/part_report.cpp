#include "art2part/geometry/part_report.h"

#include <iomanip>
#include <sstream>

namespace art2part {

namespace {

nlohmann::json vec(const Vec3& v) { return {v.x(), v.y(), v.z()}; }

nlohmann::json faceCountsJson(const FaceCounts& c) {
  return {{"plane", c.plane}, {"cylinder", c.cylinder}, {"cone", c.cone}, {"sphere", c.sphere},
          {"torus", c.torus}, {"other", c.other},       {"total", c.total()}};
}

const char* faceSourceName(FaceSource s) { return s == FaceSource::BRep ? "brep" : "segmentation"; }

}  // namespace

nlohmann::json partReport(const Part& part) {
  const MeshCheck& c = part.check;
  nlohmann::json j;
  j["source"] = part.source;
  j["units"] = "mm";
  j["triangles"] = c.triangles;
  j["vertices"] = c.vertices;
  j["faces"] = faceCountsJson(countFaces(part.faces));
  j["faces_from"] = faceSourceName(part.face_source);
  j["bounding_box"] = {{"min", vec(c.box.min)}, {"max", vec(c.box.max)}, {"size", vec(c.box.size())}};
  j["closed"] = c.closed;
  j["manifold"] = c.manifold;
  j["boundary_edges"] = c.boundary_edges;
  j["nonmanifold_edges"] = c.nonmanifold_edges;
  j["components"] = c.components;
  j["volume_mm3"] = c.volume;
  j["area_mm2"] = c.area;
  j["repairs"] = {{"merged_vertices", part.repairs.merged_vertices},
                  {"dropped_degenerate", part.repairs.dropped_degenerate},
                  {"dropped_duplicate", part.repairs.dropped_duplicate},
                  {"flipped", part.repairs.flipped},
                  {"notes", part.repairs.notes}};
  j["warnings"] = partWarnings(part);
  return j;
}

std::string partReportText(const Part& part) {
  const MeshCheck& c = part.check;
  const FaceCounts f = countFaces(part.faces);
  std::ostringstream out;
  out << std::fixed << std::setprecision(3);
  out << "part:       " << part.source << "\n";
  out << "triangles:  " << c.triangles << " (" << c.vertices << " vertices)\n";
  out << "faces:      " << f.total() << " from " << faceSourceName(part.face_source) << ": " << f.plane << " plane, "
      << f.cylinder << " cylinder, " << f.cone << " cone, " << f.sphere << " sphere, " << f.torus << " torus, "
      << f.other << " other\n";
  const Vec3 s = c.box.size();
  out << "box:        " << s.x() << " x " << s.y() << " x " << s.z() << " mm, from (" << c.box.min.x() << ", "
      << c.box.min.y() << ", " << c.box.min.z() << ") to (" << c.box.max.x() << ", " << c.box.max.y() << ", "
      << c.box.max.z() << ")\n";
  out << "closed:     " << (c.closed ? "yes" : "no") << " (" << c.boundary_edges << " boundary edges)\n";
  out << "manifold:   " << (c.manifold ? "yes" : "no") << " (" << c.nonmanifold_edges << " non-manifold edges)\n";
  out << "components: " << c.components << "\n";
  out << "volume:     " << c.volume << " mm^3" << (c.closed ? "" : " (mesh open: not reliable)") << "\n";
  out << "repairs:    " << (part.repairs.notes.empty() ? "none" : "") << "\n";
  for (const std::string& note : part.repairs.notes) out << "  - " << note << "\n";
  for (const std::string& w : partWarnings(part)) out << "warning:    " << w << "\n";
  return out.str();
}

}  // namespace art2part
