// STEP through OpenCASCADE: read a file, convert it to mm, tessellate it face by face and describe each face's
// analytic surface. Everything OCCT-specific stays in this file; the rest of the project sees plain data.
#include "art2part/geometry/step_import.h"

#include <BRepAdaptor_Surface.hxx>
#include <BRepBndLib.hxx>
#include <BRepMesh_IncrementalMesh.hxx>
#include <BRep_Tool.hxx>
#include <Bnd_Box.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <Interface_Static.hxx>
#include <Message.hxx>
#include <Message_Messenger.hxx>
#include <Message_PrinterOStream.hxx>
#include <Poly_Triangulation.hxx>
#include <STEPConstruct_UnitContext.hxx>
#include <STEPControl_Reader.hxx>
#include <StepData_StepModel.hxx>
#include <StepGeom_GeomRepContextAndGlobUnitAssCtxAndGlobUncertaintyAssCtx.hxx>
#include <StepGeom_GeometricRepresentationContextAndGlobalUnitAssignedContext.hxx>
#include <StepRepr_GlobalUnitAssignedContext.hxx>
#include <StepShape_AdvancedBrepShapeRepresentation.hxx>
#include <StepShape_FacetedBrepShapeRepresentation.hxx>
#include <StepShape_ManifoldSurfaceShapeRepresentation.hxx>
#include <StepShape_ShapeRepresentation.hxx>
#include <Standard_Failure.hxx>
#include <TopAbs.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopLoc_Location.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Shape.hxx>
#include <UnitsMethods.hxx>
#include <gp_Cone.hxx>
#include <gp_Cylinder.hxx>
#include <gp_Pln.hxx>
#include <gp_Sphere.hxx>
#include <gp_Torus.hxx>

#include <Eigen/Geometry>
#include <cmath>
#include <filesystem>
#include <mutex>
#include <string>
#include <utility>

namespace art2part {
namespace {

Vec3 toVec(const gp_XYZ& p) { return Vec3(p.X(), p.Y(), p.Z()); }
Vec3 toVec(const gp_Pnt& p) { return toVec(p.XYZ()); }
Vec3 toVec(const gp_Dir& d) { return toVec(d.XYZ()); }

std::string quoted(const std::string& path) { return "'" + path + "'"; }

std::string describe(const Standard_Failure& failure) {
  std::string what = failure.DynamicType()->Name();
  const char* message = failure.GetMessageString();
  if (message != nullptr && *message != '\0') what += std::string(": ") + message;
  // One line, as InputError promises.
  for (char& c : what)
    if (c == '\n' || c == '\r') c = ' ';
  return what;
}

// The STEP reader reports statistics and warnings through OCCT's default messenger, which prints to stdout; our CLI
// owns stdout, so the printers go (once, for the whole process).
void silenceOcct() {
  static std::once_flag once;
  std::call_once(once, [] { Message::DefaultMessenger()->RemovePrinters(STANDARD_TYPE(Message_PrinterOStream)); });
}

const char* statusName(IFSelect_ReturnStatus status) {
  switch (status) {
    case IFSelect_RetVoid: return "nothing was read";
    case IFSelect_RetDone: return "done";
    case IFSelect_RetError: return "not a STEP file";
    case IFSelect_RetFail: return "not a valid STEP file";
    case IFSelect_RetStop: return "reading stopped";
  }
  return "unknown status";
}

// OCCT's answer to a missing file or a directory is an unhelpful status; say it plainly before asking OCCT.
void checkReadable(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code error;
  if (!fs::exists(path, error)) throw InputError("cannot read STEP file " + quoted(path) + ": no such file");
  if (!fs::is_regular_file(path, error)) throw InputError("cannot read STEP file " + quoted(path) + ": not a file");
  if (fs::file_size(path, error) == 0) throw InputError("cannot read STEP file " + quoted(path) + ": the file is empty");
}

// The length unit of a STEP representation context, in mm, or 0 when the context names none.
double contextUnitMm(const Handle(StepRepr_RepresentationContext) & context) {
  Handle(StepRepr_GlobalUnitAssignedContext) units;
  // Units live in complex (multiple-inheritance) entities; OCCT models each combination as its own class.
  if (auto c = Handle(StepGeom_GeomRepContextAndGlobUnitAssCtxAndGlobUncertaintyAssCtx)::DownCast(context))
    units = c->GlobalUnitAssignedContext();
  else if (auto c2 = Handle(StepGeom_GeometricRepresentationContextAndGlobalUnitAssignedContext)::DownCast(context))
    units = c2->GlobalUnitAssignedContext();
  if (units.IsNull()) return 0.0;
  STEPConstruct_UnitContext unit_context;
  if (unit_context.ComputeFactors(units) != 0 || !unit_context.LengthDone()) return 0.0;
  // LengthFactor is relative to OCCT's working ("cascade") unit, which GetCasCadeLengthUnit gives in mm.
  return unit_context.LengthFactor() * UnitsMethods::GetCasCadeLengthUnit();
}

// The file's own length unit in mm (25.4 for an inch file). OCCT converts on transfer; this is only to report it.
// B-rep representations come first, since PMI and wireframe representations may carry their own contexts.
double fileUnitMm(const Handle(StepData_StepModel) & model) {
  if (model.IsNull()) return 1.0;
  double any_unit = 0.0;
  for (Standard_Integer i = 1; i <= model->NbEntities(); ++i) {
    auto representation = Handle(StepShape_ShapeRepresentation)::DownCast(model->Value(i));
    if (representation.IsNull()) continue;
    const double unit = contextUnitMm(representation->ContextOfItems());
    if (unit <= 0.0) continue;
    if (representation->IsKind(STANDARD_TYPE(StepShape_AdvancedBrepShapeRepresentation)) ||
        representation->IsKind(STANDARD_TYPE(StepShape_FacetedBrepShapeRepresentation)) ||
        representation->IsKind(STANDARD_TYPE(StepShape_ManifoldSurfaceShapeRepresentation)))
      return unit;
    if (any_unit == 0.0) any_unit = unit;
  }
  return any_unit > 0.0 ? any_unit : 1.0;
}

// The faces that make up the part, each once (a face shared by two shells is visited once), in explorer order.
// When the file has solids, only their faces count: STEP files also carry free surface bodies (PMI supplemental
// geometry, construction planes; NIST CTC 2 has one inside the housing) that are not material to machine and would
// leave open, stray triangles in the mesh. A file of surfaces only keeps all its faces.
TopTools_IndexedMapOfShape partFaces(const TopoDS_Shape& shape) {
  TopTools_IndexedMapOfShape faces;
  for (TopExp_Explorer solid(shape, TopAbs_SOLID); solid.More(); solid.Next())
    TopExp::MapShapes(solid.Current(), TopAbs_FACE, faces);  // appends; does not clear the map
  if (faces.IsEmpty()) TopExp::MapShapes(shape, TopAbs_FACE, faces);
  return faces;
}

struct LoadedShape {
  TopoDS_Shape shape;  // in mm
  double unit_to_mm = 1.0;
};

// Reads and transfers the file's shape, in mm. Throws InputError; OCCT exceptions are the caller's to convert.
LoadedShape loadShape(const std::string& path) {
  checkReadable(path);
  silenceOcct();
  STEPControl_Reader reader;  // its constructor registers the STEP statics, so set them afterwards
  // mm is OCCT's default working unit, but it is a process-wide setting that other code could have changed.
  // The static governs the read; SetSystemLengthUnit below pins the transfer itself to mm.
  Interface_Static::SetCVal("xstep.cascade.unit", "MM");
  const IFSelect_ReturnStatus status = reader.ReadFile(path.c_str());
  if (status != IFSelect_RetDone)
    throw InputError("cannot read STEP file " + quoted(path) + ": " + statusName(status) + " (status " +
                     std::to_string(static_cast<int>(status)) + ")");
  reader.SetSystemLengthUnit(1.0);
  LoadedShape loaded;
  loaded.unit_to_mm = fileUnitMm(reader.StepModel());
  if (reader.TransferRoots() == 0) throw InputError("STEP file " + quoted(path) + " holds no shape OCCT can transfer");
  loaded.shape = reader.OneShape();
  if (loaded.shape.IsNull() || partFaces(loaded.shape).IsEmpty())
    throw InputError("STEP file " + quoted(path) + " holds no faces");
  return loaded;
}

// The caller asks for the box first (to pick a tolerance) and then for the tessellation: the shape read for the box
// is kept for that one next readStep of the same, unchanged file, so the file is parsed once (about 1 s for NIST
// CTC 2). readStep takes it out again, so a shape is never meshed twice with different tolerances.
class ShapeCache {
 public:
  void keep(const std::string& path, const LoadedShape& loaded) {
    std::lock_guard<std::mutex> lock(mutex_);
    key_ = key(path);
    loaded_ = key_.empty() ? LoadedShape() : loaded;
  }
  bool take(const std::string& path, LoadedShape& loaded) {
    std::lock_guard<std::mutex> lock(mutex_);
    const bool hit = !key_.empty() && key_ == key(path);
    if (hit) loaded = loaded_;
    key_.clear();
    loaded_ = LoadedShape();
    return hit;
  }

 private:
  // Path, size and modification time: a file rewritten between the two calls is read again. Empty when unknown.
  static std::string key(const std::string& path) {
    std::error_code error;
    const auto size = std::filesystem::file_size(path, error);
    if (error) return {};
    const auto time = std::filesystem::last_write_time(path, error);
    if (error) return {};
    return path + '\n' + std::to_string(size) + '\n' + std::to_string(time.time_since_epoch().count());
  }
  std::mutex mutex_;
  std::string key_;
  LoadedShape loaded_;
};

ShapeCache& shapeCache() {
  static ShapeCache cache;
  return cache;
}

// Analytic surface of a face. Concavity is left for concavity(), which needs the face's triangles.
Face describeSurface(const TopoDS_Face& face) {
  const BRepAdaptor_Surface surface(face);  // carries the face's location, so the frames are in part coordinates
  const bool reversed = face.Orientation() == TopAbs_REVERSED;
  Face out;
  switch (surface.GetType()) {
    case GeomAbs_Plane: {
      const gp_Ax3 frame = surface.Plane().Position();
      // The parametric normal is XDir x YDir; it is the axis only for a right-handed frame. The face's material
      // side then flips it once more when the face is reversed.
      Vec3 normal = toVec(frame.XDirection()).cross(toVec(frame.YDirection())).normalized();
      if (reversed) normal = -normal;
      out.type = SurfaceType::Plane;
      out.normal = normal;
      out.offset = normal.dot(toVec(frame.Location()));
      break;
    }
    case GeomAbs_Cylinder: {
      const gp_Cylinder cylinder = surface.Cylinder();
      out.type = SurfaceType::Cylinder;
      out.axis = toVec(cylinder.Axis().Direction());
      out.point = toVec(cylinder.Location());
      out.radius = cylinder.Radius();
      break;
    }
    case GeomAbs_Cone: {
      const gp_Cone cone = surface.Cone();
      out.type = SurfaceType::Cone;
      out.point = toVec(cone.Apex());
      out.half_angle = std::abs(cone.SemiAngle());
      // The axis must point from the apex towards the face, whichever way OCCT's frame points: test a point of the
      // face (the middle of its parameter range).
      const gp_Pnt middle = surface.Value(0.5 * (surface.FirstUParameter() + surface.LastUParameter()),
                                          0.5 * (surface.FirstVParameter() + surface.LastVParameter()));
      Vec3 axis = toVec(cone.Axis().Direction());
      if (axis.dot(toVec(middle) - out.point) < 0.0) axis = -axis;
      out.axis = axis;
      break;
    }
    case GeomAbs_Sphere: {
      const gp_Sphere sphere = surface.Sphere();
      out.type = SurfaceType::Sphere;
      out.point = toVec(sphere.Location());
      out.radius = sphere.Radius();
      break;
    }
    case GeomAbs_Torus: {
      const gp_Torus torus = surface.Torus();
      out.type = SurfaceType::Torus;
      out.axis = toVec(torus.Axis().Direction());
      out.point = toVec(torus.Location());
      out.radius = torus.MajorRadius();
      out.minor_radius = torus.MinorRadius();
      break;
    }
    default:
      out.type = SurfaceType::Other;
      break;
  }
  return out;
}

// Appends the face's triangles (in part coordinates, counter-clockwise from outside) and returns how many.
// A face the mesher could not triangulate contributes none. BRepMesh keeps two nodes where a periodic face's seam
// meets a pole or an edge end, and may span them with a triangle; once the caller merges vertices such a triangle
// would collapse to a line and make a non-manifold edge (148 of them on NIST CTC 2), so it is dropped here.
int appendTriangles(const TopoDS_Face& face, int face_index, StepTessellation& out) {
  TopLoc_Location location;
  const Handle(Poly_Triangulation) & triangulation = BRep_Tool::Triangulation(face, location);
  if (triangulation.IsNull() || triangulation->NbTriangles() == 0) return 0;
  const gp_Trsf transform = location.Transformation();
  const int first_vertex = static_cast<int>(out.mesh.vertices.size());
  for (Standard_Integer i = 1; i <= triangulation->NbNodes(); ++i)
    out.mesh.vertices.push_back(toVec(triangulation->Node(i).Transformed(transform)));
  // BRepMesh winds triangles by the surface's parametric normal; a reversed face has its material on the other side.
  const bool reversed = face.Orientation() == TopAbs_REVERSED;
  int count = 0;
  for (Standard_Integer i = 1; i <= triangulation->NbTriangles(); ++i) {
    Standard_Integer a = 0, b = 0, c = 0;
    triangulation->Triangle(i).Get(a, b, c);
    if (reversed) std::swap(b, c);
    const Triangle triangle{first_vertex + a - 1, first_vertex + b - 1, first_vertex + c - 1};
    const auto& v = out.mesh.vertices;
    if (v[triangle[0]] == v[triangle[1]] || v[triangle[1]] == v[triangle[2]] || v[triangle[2]] == v[triangle[0]])
      continue;
    out.mesh.triangles.push_back(triangle);
    out.triangle_face.push_back(face_index);
    ++count;
  }
  return count;
}

// Where a surface "is" as seen from a point on it: the nearest point of its axis, centre or tube circle. The outward
// normal points away from it on a convex face (a boss) and towards it on a concave one (a hole).
Vec3 surfaceCore(const Face& face, const Vec3& p) {
  switch (face.type) {
    case SurfaceType::Cylinder:
    case SurfaceType::Cone:
      return face.point + face.axis * face.axis.dot(p - face.point);
    case SurfaceType::Torus: {
      const Vec3 d = p - face.point;
      const Vec3 radial = d - face.axis * face.axis.dot(d);
      if (radial.norm() == 0.0) return face.point;
      return face.point + face.radius * radial.normalized();
    }
    default:
      return face.point;  // sphere: the centre
  }
}

// Sets concave and area from the face's triangles [first, first + count). The raw cross product weighs each
// triangle by its area, so slivers along seams cannot outvote the bulk of the face.
void measureFace(const Mesh& mesh, int first, int count, Face& face) {
  const bool curved = face.type == SurfaceType::Cylinder || face.type == SurfaceType::Cone ||
                      face.type == SurfaceType::Sphere || face.type == SurfaceType::Torus;
  double area = 0.0, outwardness = 0.0;
  for (int t = first; t < first + count; ++t) {
    const Vec3& a = mesh.corner(t, 0);
    const Vec3& b = mesh.corner(t, 1);
    const Vec3& c = mesh.corner(t, 2);
    const Vec3 doubled_normal = (b - a).cross(c - a);
    area += 0.5 * doubled_normal.norm();
    if (curved) {
      const Vec3 centroid = (a + b + c) / 3.0;
      outwardness += doubled_normal.dot(centroid - surfaceCore(face, centroid));
    }
  }
  face.area = area;
  face.triangle_count = count;
  face.concave = curved && outwardness < 0.0;
}

void readAndTessellate(const std::string& path, double chordal_tolerance, double angular_tolerance,
                       StepTessellation& out) {
  LoadedShape loaded;
  if (!shapeCache().take(path, loaded)) loaded = loadShape(path);
  out.unit_to_mm = loaded.unit_to_mm;
  const TopoDS_Shape& shape = loaded.shape;
  // Absolute deflection in mm; serial, so results do not depend on scheduling (the files are small).
  BRepMesh_IncrementalMesh mesher(shape, chordal_tolerance, Standard_False, angular_tolerance, Standard_False);
  (void)mesher;  // meshing happens in the constructor and is stored in the shape's faces

  const TopTools_IndexedMapOfShape faces = partFaces(shape);
  out.faces.reserve(faces.Extent());
  for (Standard_Integer i = 1; i <= faces.Extent(); ++i) {
    const TopoDS_Face& face = TopoDS::Face(faces(i));
    const int index = static_cast<int>(out.faces.size());
    Face described;
    try {
      described = describeSurface(face);
    } catch (const Standard_Failure&) {
      described = Face();  // an odd surface is still a face: keep it as free-form
    }
    const int first = out.mesh.triangleCount();
    const int count = appendTriangles(face, index, out);
    measureFace(out.mesh, first, count, described);
    out.faces.push_back(described);
  }
  if (out.mesh.triangles.empty()) throw InputError("STEP file " + quoted(path) + ": no face could be tessellated");
}

}  // namespace

StepTessellation readStep(const std::string& path, double chordal_tolerance, double angular_tolerance) {
  if (!(chordal_tolerance > 0.0) || !(angular_tolerance > 0.0))
    throw InputError("cannot tessellate STEP file " + quoted(path) + ": tolerances must be positive");
  StepTessellation out;
  try {
    readAndTessellate(path, chordal_tolerance, angular_tolerance, out);
  } catch (const Standard_Failure& failure) {
    throw InputError("cannot read STEP file " + quoted(path) + ": OpenCASCADE failed (" + describe(failure) + ")");
  }
  return out;
}

Box stepBoundingBox(const std::string& path) {
  Bnd_Box occt_box;
  try {
    const LoadedShape loaded = loadShape(path);
    const TopoDS_Shape& shape = loaded.shape;
    // The box of the faces readStep will tessellate: not of free edges and points (NIST CTC 1 carries PMI wireframe
    // far outside the part). AddOptimal is the geometric box; Add would pad it by tolerances and coarse curve bounds.
    const TopTools_IndexedMapOfShape faces = partFaces(shape);
    for (Standard_Integer i = 1; i <= faces.Extent(); ++i)
      BRepBndLib::AddOptimal(faces(i), occt_box, /*useTriangulation=*/Standard_False, /*useShapeTolerance=*/Standard_False);
    shapeCache().keep(path, loaded);
  } catch (const Standard_Failure& failure) {
    throw InputError("cannot read STEP file " + quoted(path) + ": OpenCASCADE failed (" + describe(failure) + ")");
  }
  if (occt_box.IsVoid()) throw InputError("STEP file " + quoted(path) + " holds no geometry");
  double x0 = 0, y0 = 0, z0 = 0, x1 = 0, y1 = 0, z1 = 0;
  occt_box.Get(x0, y0, z0, x1, y1, z1);
  Box box;
  box.extend(Vec3(x0, y0, z0));
  box.extend(Vec3(x1, y1, z1));
  return box;
}

}  // namespace art2part
