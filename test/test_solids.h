// Test parts with B-rep faces, made with OpenCASCADE by the tests themselves: boxes, cylinders and cones fused and cut,
// written to a STEP file and loaded as a user's part would be (faces typed with their planes, axes and radii).
#pragma once

#include <BRepAlgoAPI_Cut.hxx>
#include <BRepAlgoAPI_Fuse.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCone.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <STEPControl_Writer.hxx>
#include <ShapeUpgrade_UnifySameDomain.hxx>
#include <TopoDS_Shape.hxx>
#include <gp_Ax2.hxx>
#include <gp_Dir.hxx>
#include <gp_Pnt.hxx>

#include <stdexcept>
#include <string>
#include <vector>

#include "art2part/geometry/part.h"
#include "test_meshes.h"

namespace art2part::test {

inline TopoDS_Shape solidBox(const Vec3& lo, const Vec3& hi) {
  return BRepPrimAPI_MakeBox(gp_Pnt(lo.x(), lo.y(), lo.z()), gp_Pnt(hi.x(), hi.y(), hi.z())).Shape();
}

// A cylinder of `radius` from `base` along `axis` for `height`.
inline TopoDS_Shape solidCylinder(const Vec3& base, const Vec3& axis, double radius, double height) {
  return BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(base.x(), base.y(), base.z()), gp_Dir(axis.x(), axis.y(), axis.z())),
                                  radius, height)
      .Shape();
}

// A cone frustum from `base` (radius r1) along `axis` to radius r2 at `height`.
inline TopoDS_Shape solidCone(const Vec3& base, const Vec3& axis, double r1, double r2, double height) {
  return BRepPrimAPI_MakeCone(gp_Ax2(gp_Pnt(base.x(), base.y(), base.z()), gp_Dir(axis.x(), axis.y(), axis.z())), r1,
                              r2, height)
      .Shape();
}

// Boolean operations, faces of one surface merged again (as a CAD system writes them).
inline TopoDS_Shape unified(const TopoDS_Shape& shape) {
  ShapeUpgrade_UnifySameDomain unify(shape, true, true, true);
  unify.Build();
  return unify.Shape();
}
inline TopoDS_Shape cut(const TopoDS_Shape& a, const TopoDS_Shape& b) { return unified(BRepAlgoAPI_Cut(a, b).Shape()); }
inline TopoDS_Shape fuse(const TopoDS_Shape& a, const TopoDS_Shape& b) { return unified(BRepAlgoAPI_Fuse(a, b).Shape()); }

// The shape written to a STEP file (mm) in a fresh temporary folder, loaded as a part.
inline Part stepPart(const TopoDS_Shape& shape, const std::string& name, const LoadOptions& options = {}) {
  const std::string path = tempDir() + "/" + name + ".step";
  STEPControl_Writer writer;
  if (writer.Transfer(shape, STEPControl_AsIs) != IFSelect_RetDone || writer.Write(path.c_str()) != IFSelect_RetDone)
    throw std::runtime_error("cannot write " + path);
  return loadPart(path, options);
}

// The part's faces of one surface type.
inline std::vector<int> facesOfType(const Part& part, SurfaceType type) {
  std::vector<int> out;
  for (int f = 0; f < static_cast<int>(part.faces.size()); ++f)
    if (part.faces[f].type == type) out.push_back(f);
  return out;
}

// A box of solid with a rectangular pocket whose vertical corners are rounded: the pocket `size` (x, y) and `depth`,
// centred on the block's top, corner radius `corner`.
inline TopoDS_Shape pocketedBlock(const Vec3& lo, const Vec3& hi, double size_x, double size_y, double depth,
                                  double corner) {
  const Vec3 c = 0.5 * (lo + hi);
  const double z0 = hi.z() - depth, z1 = hi.z() + 1;
  const double x0 = c.x() - size_x / 2, x1 = c.x() + size_x / 2, y0 = c.y() - size_y / 2, y1 = c.y() + size_y / 2;
  TopoDS_Shape pocket = fuse(solidBox(Vec3(x0 + corner, y0, z0), Vec3(x1 - corner, y1, z1)),
                             solidBox(Vec3(x0, y0 + corner, z0), Vec3(x1, y1 - corner, z1)));
  for (const Vec3& p : {Vec3(x0 + corner, y0 + corner, z0), Vec3(x1 - corner, y0 + corner, z0),
                        Vec3(x0 + corner, y1 - corner, z0), Vec3(x1 - corner, y1 - corner, z0)})
    pocket = fuse(pocket, solidCylinder(p, Vec3::UnitZ(), corner, z1 - z0));
  return cut(solidBox(lo, hi), pocket);
}

}  // namespace art2part::test
