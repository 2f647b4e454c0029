#include "part_conversions.h"

#include "art2part/plan/stage_records.h"

#include "marker_helpers.h"  // toVectorMsg

namespace art2part {

geometry_msgs::Point toPointMsg(const Vec3& mm) {
  geometry_msgs::Point p;
  p.x = mm.x() * kMetresPerMm;
  p.y = mm.y() * kMetresPerMm;
  p.z = mm.z() * kMetresPerMm;
  return p;
}

namespace {

FaceSurface toFaceMsg(const Face& f) {
  FaceSurface m;
  m.type = static_cast<uint8_t>(f.type);  // the enum order matches the message constants
  m.normal = toVectorMsg(f.normal);
  m.offset = f.offset * kMetresPerMm;
  m.axis = toVectorMsg(f.axis);
  m.point = toPointMsg(f.point);
  m.radius = f.radius * kMetresPerMm;
  m.minor_radius = f.minor_radius * kMetresPerMm;
  m.half_angle = f.half_angle;
  m.concave = f.concave;
  m.area = f.area * kMetresPerMm * kMetresPerMm;
  m.triangle_count = static_cast<uint32_t>(f.triangle_count);
  return m;
}

Face fromFaceMsg(const FaceSurface& m) {
  Face f;
  if (m.type > FaceSurface::OTHER) throw InputError("face message with unknown type " + std::to_string(m.type));
  f.type = static_cast<SurfaceType>(m.type);
  f.normal = Vec3(m.normal.x, m.normal.y, m.normal.z);
  f.offset = m.offset / kMetresPerMm;
  f.axis = Vec3(m.axis.x, m.axis.y, m.axis.z);
  f.point = Vec3(m.point.x, m.point.y, m.point.z) / kMetresPerMm;
  f.radius = m.radius / kMetresPerMm;
  f.minor_radius = m.minor_radius / kMetresPerMm;
  f.half_angle = m.half_angle;
  f.concave = m.concave;
  return f;
}

}  // namespace

PartSummary toSummaryMsg(const Part& part) {
  PartSummary s;
  const MeshCheck& c = part.check;
  s.triangles = static_cast<uint32_t>(c.triangles);
  s.vertices = static_cast<uint32_t>(c.vertices);
  s.faces_from_brep = part.face_source == FaceSource::BRep;
  const FaceCounts counts = countFaces(part.faces);
  s.planes = counts.plane;
  s.cylinders = counts.cylinder;
  s.cones = counts.cone;
  s.spheres = counts.sphere;
  s.tori = counts.torus;
  s.others = counts.other;
  s.box_min = toPointMsg(c.box.min);
  s.box_max = toPointMsg(c.box.max);
  s.closed = c.closed;
  s.manifold = c.manifold;
  s.boundary_edges = c.boundary_edges;
  s.nonmanifold_edges = c.nonmanifold_edges;
  s.components = c.components;
  s.volume = c.volume * 1e-9;
  s.repairs = part.repairs.notes;
  s.warnings = partWarnings(part);
  return s;
}

LoadedPart toMsg(const Part& part, const std::string& id) {
  LoadedPart m;
  m.id = id;
  m.source = part.source;
  m.mesh.vertices.reserve(part.mesh.vertices.size());
  for (const Vec3& v : part.mesh.vertices) m.mesh.vertices.push_back(toPointMsg(v));
  m.mesh.triangles.resize(part.mesh.triangles.size());
  for (std::size_t t = 0; t < part.mesh.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) m.mesh.triangles[t].vertex_indices[k] = part.mesh.triangles[t][k];
  m.triangle_face.assign(part.triangle_face.begin(), part.triangle_face.end());
  for (const Face& f : part.faces) m.faces.push_back(toFaceMsg(f));
  m.summary = toSummaryMsg(part);
  m.record = partRecord(part);
  return m;
}

Part fromMsg(const LoadedPart& msg) {
  if (!msg.record.empty()) return partFromRecord(msg.record);  // exact: what the file gave (mm)
  Mesh mesh;
  for (const auto& p : msg.mesh.vertices) mesh.vertices.emplace_back(p.x / kMetresPerMm, p.y / kMetresPerMm, p.z / kMetresPerMm);
  for (const auto& t : msg.mesh.triangles)
    mesh.triangles.push_back({static_cast<int>(t.vertex_indices[0]), static_cast<int>(t.vertex_indices[1]),
                              static_cast<int>(t.vertex_indices[2])});
  const std::string where = "part message '" + msg.id + "'";
  if (msg.triangle_face.size() != mesh.triangles.size())
    throw InputError(where + ": " + std::to_string(msg.triangle_face.size()) + " face ids for " +
                     std::to_string(mesh.triangles.size()) + " triangles");
  validateMesh(mesh, where);
  Part part;
  part.source = msg.source;
  part.mesh = std::move(mesh);
  part.triangle_face.assign(msg.triangle_face.begin(), msg.triangle_face.end());
  for (const auto& f : msg.faces) part.faces.push_back(fromFaceMsg(f));
  for (int f : part.triangle_face)
    if (f >= static_cast<int>(part.faces.size())) throw InputError(where + ": face id " + std::to_string(f) + " out of range");
  part.face_source = msg.summary.faces_from_brep ? FaceSource::BRep : FaceSource::Segmentation;
  part.repairs.notes = msg.summary.repairs;
  updateFaceAreas(part.mesh, part.triangle_face, part.faces);
  part.adjacency = buildAdjacency(part.mesh);
  part.check = checkMesh(part.mesh);
  return part;
}

}  // namespace art2part
