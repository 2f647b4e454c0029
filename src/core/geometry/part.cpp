#include "art2part/geometry/part.h"

#include <algorithm>
#include <cctype>
#include <sstream>

#include "art2part/geometry/mesh_io.h"
#include "art2part/geometry/segmentation.h"
#include "art2part/geometry/step_import.h"

namespace art2part {

std::vector<std::vector<int>> faceTriangles(const Part& part) {
  std::vector<std::vector<int>> out(part.faces.size());
  const int n = std::min<int>(part.mesh.triangleCount(), static_cast<int>(part.triangle_face.size()));
  for (int t = 0; t < n; ++t) {
    const int f = part.triangle_face[t];
    if (f >= 0 && f < static_cast<int>(out.size())) out[f].push_back(t);
  }
  return out;
}

double lengthUnitToMm(LengthUnit unit) {
  switch (unit) {
    case LengthUnit::Inch: return 25.4;
    case LengthUnit::Metre: return 1000.0;
    case LengthUnit::Auto:
    case LengthUnit::Millimetre: return 1.0;
  }
  return 1.0;
}

LengthUnit parseLengthUnit(const std::string& text) {
  std::string t = text;
  std::transform(t.begin(), t.end(), t.begin(), [](unsigned char c) { return std::tolower(c); });
  if (t == "auto" || t.empty()) return LengthUnit::Auto;
  if (t == "mm") return LengthUnit::Millimetre;
  if (t == "in" || t == "inch") return LengthUnit::Inch;
  if (t == "m") return LengthUnit::Metre;
  throw InputError("unknown length unit '" + text + "' (use mm, in or m)");
}

void checkPartSize(const Box& box, const std::string& where) {
  const double extent = box.empty() ? 0.0 : box.size().maxCoeff();
  std::ostringstream out;
  out << where << ": ";
  if (!(extent > 0.0)) {
    out << "the part has zero size";
    throw InputError(out.str());
  }
  if (extent < 0.5) {
    out << "the part is only " << extent << " mm across; the file is probably in metres (give the unit: --units m, or units 'm' in a request)";
    throw InputError(out.str());
  }
  if (extent > 20000.0) {
    out << "the part is " << extent << " mm across; the file is probably in micrometres or another small unit";
    throw InputError(out.str());
  }
}

std::vector<std::string> partWarnings(const Part& part) {
  std::vector<std::string> warnings;
  const MeshCheck& c = part.check;
  if (c.boundary_edges > 0)
    warnings.push_back("the mesh is open: " + std::to_string(c.boundary_edges) +
                       " boundary edges (volume and stock are unreliable)");
  if (c.nonmanifold_edges > 0)
    warnings.push_back("the mesh is not manifold: " + std::to_string(c.nonmanifold_edges) + " edges");
  if (c.components > 1) warnings.push_back("the mesh has " + std::to_string(c.components) + " separate pieces");
  if (c.closed && c.volume <= 0.0) warnings.push_back("the closed mesh has no positive volume");
  return warnings;
}

namespace {

bool isStepFile(const std::string& path) {
  return hasExtension(path, "step") || hasExtension(path, "stp") || hasExtension(path, "p21");
}

double chordalToleranceFor(const Box& box, const LoadOptions& options) {
  if (options.chordal_tolerance > 0.0) return options.chordal_tolerance;
  return std::max(0.005, 5e-4 * box.diagonal());
}

// Repairs, checks the size, builds adjacency and the final check; keeps triangle_face in step with dropped triangles.
void finishPart(Part& part, const LoadOptions& options) {
  validateMesh(part.mesh, part.source);
  checkPartSize(boundingBox(part.mesh), part.source);
  if (options.repair) {
    std::vector<int> kept;
    part.repairs = repairMesh(part.mesh, &kept);
    if (!part.triangle_face.empty()) {
      std::vector<int> faces(kept.size());
      for (std::size_t i = 0; i < kept.size(); ++i) faces[i] = part.triangle_face[kept[i]];
      part.triangle_face.swap(faces);
    }
  }
  if (part.mesh.triangles.empty()) throw InputError(part.source + ": every triangle is degenerate");
  checkPartSize(boundingBox(part.mesh), part.source);
  part.adjacency = buildAdjacency(part.mesh);
  part.check = checkMesh(part.mesh);
}

void segmentPart(Part& part, const LoadOptions& options) {
  part.face_source = FaceSource::Segmentation;
  if (!options.segment_mesh) {
    part.triangle_face.assign(part.mesh.triangles.size(), 0);
    part.faces.assign(1, Face{});
  } else {
    Segmentation s = segmentFaces(part.mesh, part.adjacency);
    part.triangle_face = std::move(s.triangle_face);
    part.faces = std::move(s.faces);
  }
  updateFaceAreas(part.mesh, part.triangle_face, part.faces);
}

}  // namespace

Part partFromMesh(Mesh mesh, const std::string& source, const LoadOptions& options) {
  Part part;
  part.source = source;
  part.mesh = std::move(mesh);
  validateMesh(part.mesh, source);
  if (options.unit != LengthUnit::Auto) scaleMesh(part.mesh, lengthUnitToMm(options.unit));
  finishPart(part, options);
  segmentPart(part, options);
  return part;
}

Part loadPart(const std::string& path, const LoadOptions& options) {
  if (!isStepFile(path)) return partFromMesh(readMeshFile(path), path, options);
  const Box box = stepBoundingBox(path);
  checkPartSize(box, path);
  StepTessellation step = readStep(path, chordalToleranceFor(box, options), options.angular_tolerance);
  Part part;
  part.source = path;
  part.mesh = std::move(step.mesh);
  part.triangle_face = std::move(step.triangle_face);
  part.faces = std::move(step.faces);
  part.face_source = FaceSource::BRep;
  finishPart(part, options);
  updateFaceAreas(part.mesh, part.triangle_face, part.faces);
  return part;
}

}  // namespace art2part
