// Face-based finishing (issue 17): admissible directions, the wall stretches, planar finishing of floors and walls
// judged by the simulation, every face accounted for.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <optional>

#include "art2part/finishing/admissible.h"
#include "art2part/finishing/face_assignment.h"
#include "art2part/finishing/finishing.h"
#include "art2part/finishing/planar_finishing.h"
#include "art2part/simulation/verify.h"
#include "test_solids.h"

using namespace art2part;

namespace {

constexpr double kPi = 3.14159265358979323846;
const std::string kTools = std::string(ART2PART_SOURCE_DIR) + "/config/tools.yaml";

// The face of `part` whose type is `type` and whose normal (plane) or axis (cylinder) is along `d`, at height z along
// it (planes: the offset), -1 when none.
int faceWith(const Part& part, SurfaceType type, const Vec3& d, double offset = std::nan("")) {
  for (int f = 0; f < static_cast<int>(part.faces.size()); ++f) {
    const Face& face = part.faces[f];
    if (face.type != type) continue;
    const Vec3 n = type == SurfaceType::Plane ? face.normal : face.axis;
    if (std::abs(std::abs(n.dot(d)) - 1) > 1e-9 && type != SurfaceType::Plane) continue;
    if (type == SurfaceType::Plane && n.dot(d) < 1 - 1e-9) continue;
    if (!std::isnan(offset) && std::abs(face.offset - offset) > 1e-6) continue;
    return f;
  }
  return -1;
}

const AdmissibleSet& setOf(const std::vector<AdmissibleSet>& sets, FinishingKind kind) {
  for (const AdmissibleSet& s : sets)
    if (s.kind == kind) return s;
  throw std::runtime_error("no such set");
}

// Tessellated finely: the simulation judges against the mesh, and a round tool leaves R e / r in the corners of a
// polygon of chordal error e approximating an arc of radius r.
LoadOptions fine() {
  LoadOptions o;
  o.chordal_tolerance = 0.002;
  o.angular_tolerance = 0.05;
  return o;
}

// A 60 x 40 x 20 block with a 30 x 20 x 8 pocket, corners rounded to 4 mm.
Part pocketedBlock() {
  static const Part part =
      test::stepPart(test::pocketedBlock(Vec3(0, 0, 0), Vec3(60, 40, 20), 30, 20, 8, 4), "pocket", fine());
  return part;
}

// The stock roughing leaves on it: 0.3 mm on every face finished from above, the block's 2 mm beyond its sides.
constexpr double kSkin = 0.3;
const Part& pocketStock() {
  static const Part stock = test::stepPart(test::pocketedBlock(Vec3(-2, -2, 0), Vec3(62, 42, 20 + kSkin),
                                                               30 - 2 * kSkin, 20 - 2 * kSkin, 8, 4 - kSkin),
                                           "pocket_stock", fine());
  return stock;
}

// The operations' paths one after the other, and their tools.
struct Program {
  Toolpath path;
  std::vector<Tool> tools;
};
Program programOf(const std::vector<FinishingOperation>& operations, const ToolLibrary& library) {
  Program program;
  for (const FinishingOperation& op : operations) {
    program.path.insert(program.path.end(), op.path.begin(), op.path.end());
    if (std::none_of(program.tools.begin(), program.tools.end(), [&](const Tool& t) { return t.id == op.tool; }))
      program.tools.push_back(*library.find(op.tool));
  }
  return program;
}

// The simulation's judge: `path` swept through `stock` (what roughing left) at `resolution` mm gouges nothing of the
// part and no shank or holder meets the stock.
void expectNoGougeNorCollision(const Part& part, const Toolpath& path, const std::vector<Tool>& tools,
                               const Mesh& stock, double resolution) {
  VerifyOptions verify;
  verify.resolution = resolution;
  verify.stock_mesh = &stock;
  const VerificationReport report = verifyToolpath(part.mesh, part.triangle_face, path, tools, verify);
  EXPECT_EQ(report.gouges, 0) << report.worst_gouge_mm;
  EXPECT_EQ(report.collisions, 0) << report.worst_collision_mm;
}

// The library's flat end mills, largest first (shortest flutes first among equals), as finishing tries them.
std::vector<const Tool*> flatsLargestFirst(const ToolLibrary& library) {
  std::vector<const Tool*> flats;
  for (const Tool& t : library.tools)
    if (t.type == ToolType::Flat) flats.push_back(&t);
  std::stable_sort(flats.begin(), flats.end(), [](const Tool* a, const Tool* b) {
    return a->diameter != b->diameter ? a->diameter > b->diameter : a->flute_length < b->flute_length;
  });
  return flats;
}

// A planar group finishing the pocketed block from above, in a 2 mm stock box, no targets yet.
PlanarGroup fromAbove(const Part& part) {
  PlanarGroup group;
  group.frame = setupFrame(part, Vec3::UnitZ());
  group.stock = test::box(Vec3(-2, -2, -2), Vec3(62, 42, 22));
  return group;
}

}  // namespace

TEST(Admissible, PlaneFaceMillsAlongItsNormalAndSideMillsInItsPlane) {
  const Part part = pocketedBlock();
  const int top = faceWith(part, SurfaceType::Plane, Vec3::UnitZ(), 20);
  ASSERT_GE(top, 0);
  const auto sets = admissibleSets(part, top, faceTriangles(part)[top]);
  const double tol = 0.1 * kPi / 180;
  EXPECT_TRUE(admits(setOf(sets, FinishingKind::FaceMill), Vec3::UnitZ(), tol));
  EXPECT_FALSE(admits(setOf(sets, FinishingKind::FaceMill), Vec3(0.01, 0, 1).normalized(), tol));
  EXPECT_FALSE(admits(setOf(sets, FinishingKind::FaceMill), -Vec3::UnitZ(), tol));
  EXPECT_TRUE(admits(setOf(sets, FinishingKind::SideMill), Vec3::UnitX(), tol));
  EXPECT_TRUE(admits(setOf(sets, FinishingKind::SideMill), Vec3(1, -1, 0).normalized(), tol));
  EXPECT_FALSE(admits(setOf(sets, FinishingKind::SideMill), Vec3::UnitZ(), tol));
  // 2-DOF: any direction in the face's front hemisphere (a plane has one normal).
  EXPECT_TRUE(admits(setOf(sets, FinishingKind::Surface3Axis), Vec3(1, 0, 1).normalized(), tol));
  EXPECT_TRUE(admits(setOf(sets, FinishingKind::Surface3Axis), Vec3::UnitX(), tol));
  EXPECT_FALSE(admits(setOf(sets, FinishingKind::Surface3Axis), Vec3(1, 0, -0.1).normalized(), tol));
}

TEST(Admissible, CylinderContoursAlongItsAxisEitherWayAndNeedsAToolWithinItsRadius) {
  const Part part = pocketedBlock();
  const int corner = faceWith(part, SurfaceType::Cylinder, Vec3::UnitZ());
  ASSERT_GE(corner, 0);
  const std::vector<int> tris = faceTriangles(part)[corner];
  const auto sets = admissibleSets(part, corner, tris);
  const double tol = 0.1 * kPi / 180;
  EXPECT_TRUE(admits(setOf(sets, FinishingKind::Contour), Vec3::UnitZ(), tol));
  EXPECT_TRUE(admits(setOf(sets, FinishingKind::Contour), -Vec3::UnitZ(), tol));
  EXPECT_FALSE(admits(setOf(sets, FinishingKind::Contour), Vec3::UnitX(), tol));
  EXPECT_TRUE(part.faces[corner].concave);
  EXPECT_NEAR(concaveRadius(part, corner, tris), 4.0, 1e-6);
  // The pocket's wall meets its floor at a concave sharp edge: a flat end mill along z lies in the wall's plane.
  bool concave_edge = false;
  for (const EdgeCondition& e : edgeConditions(part, faceWith(part, SurfaceType::Plane, Vec3::UnitZ(), 12),
                                               faceTriangles(part)[faceWith(part, SurfaceType::Plane, Vec3::UnitZ(), 12)]))
    if (e.klass == EdgeClass::Concave) {
      concave_edge = true;
      EXPECT_TRUE(flatMillMakesEdge(e, Vec3::UnitZ(), tol));
      EXPECT_FALSE(flatMillMakesEdge(e, Vec3(1, 1, 1).normalized(), tol));
    }
  EXPECT_TRUE(concave_edge);
}

TEST(Admissible, PermissibleIsWhatIsAdmissibleAndSeen) {
  const Part part = pocketedBlock();
  VisibilityOptions vo;
  vo.level = 2;
  const VisibilityResult vis = analyseVisibility(part, vo);
  const int floor = faceWith(part, SurfaceType::Plane, Vec3::UnitZ(), 12);
  ASSERT_GE(floor, 0);
  const std::vector<int> tris = faceTriangles(part)[floor];
  const Cone seen = commonCone(vis.map, tris);
  const auto sets = admissibleSets(part, floor, tris);
  const Cone mill = permissibleCone(setOf(sets, FinishingKind::FaceMill), vis.directions, seen, 0.1 * kPi / 180);
  ASSERT_EQ(coneSize(mill), 1);  // +z, a special direction of the part, sees the pocket's floor whole
  for (int d = 0; d < vis.directions.size(); ++d) {
    if (coneHas(mill, d)) {
      EXPECT_GT(vis.directions.directions[d].z(), 1 - 1e-9);
    }
  }
  // Surface finishing of the floor: every direction that sees it whole and is not behind it (side visibility also
  // counts directions a hair past its plane).
  const Cone surface = permissibleCone(setOf(sets, FinishingKind::Surface3Axis), vis.directions, seen, 0.1 * kPi / 180);
  int front = 0;
  for (int d = 0; d < vis.directions.size(); ++d) front += coneHas(seen, d) && vis.directions.directions[d].z() > -0.01;
  EXPECT_EQ(coneSize(surface), front);
  EXPECT_GE(front, 1);
}

TEST(ContourStretches, FollowTheWallsToFinishInClimbDirection) {
  // The tool centre may go anywhere in a 10 x 10 square; the wall to finish lies 1 mm left of its left side.
  const Region square = regionFromPolygons({{Point2(0, 0), Point2(10, 0), Point2(10, 10), Point2(0, 10)}});
  std::vector<Point2> wall;
  for (double y = 3; y <= 7; y += 0.25) wall.emplace_back(-1, y);
  const auto stretches = contourStretches(square, wall, 1.1, 2.0, 0.5);
  ASSERT_EQ(stretches.size(), 1u);
  const ContourStretch& s = stretches[0];
  EXPECT_FALSE(s.closed);
  double lo = 1e9, hi = -1e9;
  for (const Point2& p : s.points) {
    EXPECT_NEAR(p.x(), 0, 1e-3);
    lo = std::min(lo, p.y()), hi = std::max(hi, p.y());
  }
  // The points within reach (y 2.6 .. 7.4 at most) and half a mm of lead beyond them.
  EXPECT_LT(lo, 3 - 0.4);
  EXPECT_GT(hi, 7 + 0.4);
  EXPECT_GT(lo, 1.5);
  EXPECT_LT(hi, 8.5);
  // Climb milling with the spindle turning clockwise: the material (the wall) on the right of the feed (the tool on
  // the left of the contour, as G41 keeps it), so down -y here.
  EXPECT_LT(s.points.back().y(), s.points.front().y());
  // All round: the whole ring, closed.
  std::vector<Point2> around;
  for (double t = 0; t <= 10; t += 0.25) {
    around.emplace_back(-1, t), around.emplace_back(11, t), around.emplace_back(t, -1), around.emplace_back(t, 11);
  }
  const auto ring = contourStretches(square, around, 1.1, 2.0, 0.5);
  ASSERT_EQ(ring.size(), 1u);
  EXPECT_TRUE(ring[0].closed);
}

TEST(PlanarFinishing, FinishesAPocketedBlockFromAboveToItsNominalFaces) {
  const Part part = pocketedBlock();
  const ToolLibrary library = loadToolLibrary(kTools);
  const std::vector<const Tool*> flats = flatsLargestFirst(library);
  PlanarGroup group = fromAbove(part);
  std::vector<int> targets;
  for (int f = 0; f < static_cast<int>(part.faces.size()); ++f) {
    const Face& face = part.faces[f];
    if (face.type == SurfaceType::Plane && face.normal.z() > 1 - 1e-9) {
      group.targets.push_back({f, FinishingKind::FaceMill});
    } else if (face.type == SurfaceType::Plane && std::abs(face.normal.z()) < 1e-9 && face.area < 30 * 8 + 1) {
      group.targets.push_back({f, FinishingKind::SideMill});  // the pocket's walls, not the block's sides
    } else if (face.type == SurfaceType::Cylinder) {
      group.targets.push_back({f, FinishingKind::Contour});
    } else {
      continue;
    }
    targets.push_back(f);
  }
  ASSERT_EQ(group.targets.size(), 10u) << "top, floor, 4 walls, 4 corners";
  FinishingOptions options;
  const PlanarResult result = finishPlanar(part, group, flats, options);
  ASSERT_FALSE(result.operations.empty());
  for (const PlanarReach& r : result.reach) EXPECT_GE(r.reached, 0.99 * r.size) << "face " << r.face;
  // The corners (4 mm) need a tool of at most 4 mm radius: a rest tool finishes them after the main one.
  const ToolLibrary& lib = library;
  EXPECT_GT(lib.find(result.operations.front().tool)->diameter, 8);
  bool rest = false;
  for (const FinishingOperation& op : result.operations)
    rest = rest || (op.kind == FinishingKind::Rest && lib.find(op.tool)->diameter <= 8);
  EXPECT_TRUE(rest);

  // The judge: the finishing passes swept through the stock roughing leaves (the part with 0.3 mm on every face
  // finished from above) find no gouge and no collision, and leave those faces within 0.01 mm (+ the lattice's
  // rounding) of nominal.
  const Program program = programOf(result.operations, library);
  VerifyOptions verify;
  verify.resolution = 0.1;
  verify.stock_mesh = &pocketStock().mesh;
  verify.max_listed = 1000;
  const VerificationReport report = verifyToolpath(part.mesh, part.triangle_face, program.path, program.tools, verify);
  EXPECT_EQ(report.gouges, 0) << report.worst_gouge_mm;
  EXPECT_EQ(report.collisions, 0) << report.worst_collision_mm;
  // What is left over the faces finished: every piece of leftover inside the part's outline (the stock beyond its
  // sides is no target here) is thinner than the tolerance.
  for (const LeftoverRegion& r : report.regions) {
    if (r.box.min.x() > -1e-6 && r.box.max.x() < 60 + 1e-6 && r.box.min.y() > -1e-6 && r.box.max.y() < 40 + 1e-6) {
      EXPECT_LE(r.max_thickness_mm, 0.01) << "leftover at " << r.thickest_point.transpose();
    }
  }
}

namespace {

// The stock roughing leaves on the pocketed block (pocketStock) as slabs 1 mm deep from its top, in the group's frame,
// beyond the allowance as finishing takes it: the block, less the pocket (its corners' arcs by inscribed chords: a
// hole a hair smaller than the stock's) where the slab lies above the pocket's floor.
std::vector<SlabState> pocketStockBeyondSkin(const Part& part, const PlanarGroup& group) {
  const double floor = 20 + kSkin - 8, corner = 4 - kSkin;
  // Drawn in the part's coordinates, taken into the group's frame.
  const SetupFrame& frame = group.frame;
  const auto in_frame = [&](const Ring& ring) {
    Ring out;
    for (const Point2& p : ring) {
      const Vec3 d = Vec3(p.x(), p.y(), 0) - frame.origin;
      out.emplace_back(d.dot(frame.x), d.dot(frame.y));
    }
    return out;
  };
  const Point2 lo(15 + kSkin, 10 + kSkin), hi(45 - kSkin, 30 - kSkin);
  Ring pocket;
  const Point2 centres[4] = {Point2(hi.x() - corner, lo.y() + corner), Point2(hi.x() - corner, hi.y() - corner),
                             Point2(lo.x() + corner, hi.y() - corner), Point2(lo.x() + corner, lo.y() + corner)};
  for (int c = 0; c < 4; ++c)
    for (int k = 0; k <= 16; ++k) {
      const double a = kPi / 2 * (c - 1) + kPi / 2 * k / 16;
      pocket.push_back(centres[c] + corner * Point2(std::cos(a), std::sin(a)));
    }
  const Region block = regionFromPolygons({in_frame({Point2(-2, -2), Point2(62, -2), Point2(62, 42), Point2(-2, 42)})});
  const Region hole = regionFromPolygons({in_frame(pocket)});
  std::vector<SlabState> stock_left;
  for (double top = 20 + kSkin; top > 1e-9; top -= 1) {
    const double z = std::max(0.0, top - 1);
    stock_left.push_back(
        {z - frame.origin.z(), top - frame.origin.z(), z >= floor - 1e-9 ? subtract(block, hole) : block});
  }
  return stockBeyondSkin(stock_left, FinishingOptions{}.allowance, toFrame(part.mesh.vertices, group.frame),
                         part.mesh.triangles);
}

// The group's targets finished on the pocketed block without the stock roughing left and with it: with it, some
// rapids across run below `below` and the rapids climb less by a fifth at least (both plans cross the same ways: the
// links only differ in how high they go), and the simulation finds every link
// clear of that stock.
void expectLinksStayDown(const Part& part, PlanarGroup group, double below) {
  ASSERT_NEAR(group.frame.z.z(), 1, 1e-12);
  const ToolLibrary library = loadToolLibrary(kTools);
  const std::vector<const Tool*> flats = flatsLargestFirst(library);
  const Toolpath blind = programOf(finishPlanar(part, group, flats, FinishingOptions{}).operations, library).path;
  group.stock_beyond = pocketStockBeyondSkin(part, group);
  const PlanarResult result = finishPlanar(part, group, flats, FinishingOptions{});
  const auto [path, tools] = programOf(result.operations, library);
  ASSERT_FALSE(path.empty()) << result.operations.size() << " operations";
  int low_links = 0;  // rapids across below `below`
  for (std::size_t i = 1; i < path.size(); ++i)
    low_links += path[i].move == MoveKind::Rapid && path[i].tip.z() < below &&
                 (path[i].tip - path[i - 1].tip).head<2>().norm() > 1e-3;
  const double rapid = toolpathLength(path, MoveKind::Rapid), blind_rapid = toolpathLength(blind, MoveKind::Rapid);
  const auto climb = [](const Toolpath& moves) {  // mm of rapids up and down
    double mm = 0;
    for (std::size_t i = 1; i < moves.size(); ++i)
      if (moves[i].move == MoveKind::Rapid) mm += std::abs(moves[i].tip.z() - moves[i - 1].tip.z());
    return mm;
  };
  std::printf("rapids: %.0f mm (%.0f up and down) with the stock left (%d across below %.1f mm), %.0f mm (%.0f) "
              "without; cutting %.0f mm\n", rapid, climb(path), low_links, below, blind_rapid, climb(blind),
              toolpathLength(path, MoveKind::Feed));
  EXPECT_GT(low_links, 0);
  EXPECT_LT(rapid, blind_rapid);
  EXPECT_LT(climb(path), 0.8 * climb(blind));
  expectNoGougeNorCollision(part, path, tools, pocketStock().mesh, 0.1);
}

}  // namespace

// Links between wall stretches stay down where the stock left proves the way clear, instead of climbing to the
// clearance plane every time.
TEST(PlanarFinishing, WallLinksStayDownWhereTheStockLeftProvesTheWayClear) {
  const Part part = pocketedBlock();
  PlanarGroup group = fromAbove(part);
  for (int f = 0; f < static_cast<int>(part.faces.size()); ++f) {
    const Face& face = part.faces[f];
    if (face.type == SurfaceType::Plane && std::abs(face.normal.z()) < 1e-9 && face.area < 30 * 8 + 1)
      group.targets.push_back({f, FinishingKind::SideMill});
    else if (face.type == SurfaceType::Cylinder)
      group.targets.push_back({f, FinishingKind::Contour});
  }
  ASSERT_EQ(group.targets.size(), 8u) << "4 walls, 4 corners";
  expectLinksStayDown(part, group, 20 + kSkin);  // beside the walls, under the stock's top
}

// Likewise the hops between floor passes: the block's top round the pocket (passes the pocket cuts short) and the
// pocket's floor, over the stock's top (a descent's rapid ends 1 mm over the allowance) but under the clearance plane.
TEST(PlanarFinishing, FloorLinksStayDownWhereTheStockLeftProvesTheWayClear) {
  const Part part = pocketedBlock();
  PlanarGroup group = fromAbove(part);
  for (int f = 0; f < static_cast<int>(part.faces.size()); ++f)
    if (part.faces[f].type == SurfaceType::Plane && part.faces[f].normal.z() > 1 - 1e-9)
      group.targets.push_back({f, FinishingKind::FaceMill});
  ASSERT_EQ(group.targets.size(), 2u) << "the top, the pocket's floor";
  expectLinksStayDown(part, group, 20 + kSkin + FinishingOptions{}.clearance - 1);
}

// Two stepped pockets 60 mm apart, each an upper pocket 10 mm deep with a lower one 10 mm deeper in its floor: their
// walls and floors stand at two levels; `grow` adds a skin (the stock roughing leaves).
namespace {

TopoDS_Shape steppedPockets(double g) {
  TopoDS_Shape shape = test::solidBox(Vec3(-g, -g, 0), Vec3(120 + g, 40 + g, 30 + g));
  for (double cx : {30.0, 90.0}) {
    shape = test::cut(shape, test::solidBox(Vec3(cx - 15 + g, 5 + g, 20 + g), Vec3(cx + 15 - g, 35 - g, 32)));
    shape = test::cut(shape, test::solidBox(Vec3(cx - 13 + g, 8 + g, 10 + g), Vec3(cx + 13 - g, 32 - g, 21)));
  }
  return shape;
}

// Finishes the stepped pockets' faces that `kind` gives a kind (none: not a target) from above; the tool crosses from
// one pocket to the other at most once per operation (a tool change starts again), and the simulation, against the
// stock with its 0.3 mm skin, finds no gouge and no collision.
void expectPocketByPocket(const std::function<std::optional<FinishingKind>(const Face&)>& kind, std::size_t targets) {
  const Part part = test::stepPart(steppedPockets(0), "stepped_pockets", fine());
  const Part stock = test::stepPart(steppedPockets(kSkin), "stepped_pockets_stock", fine());
  const ToolLibrary library = loadToolLibrary(kTools);
  PlanarGroup group;
  group.frame = setupFrame(part, Vec3::UnitZ());
  group.stock = test::box(Vec3(-2, -2, -2), Vec3(122, 42, 32));
  for (int f = 0; f < static_cast<int>(part.faces.size()); ++f)
    if (const std::optional<FinishingKind> k = kind(part.faces[f])) group.targets.push_back({f, *k});
  ASSERT_EQ(group.targets.size(), targets);
  const PlanarResult result = finishPlanar(part, group, flatsLargestFirst(library), FinishingOptions{});
  const auto [path, tools] = programOf(result.operations, library);
  ASSERT_FALSE(path.empty());
  int crossings = 0;
  for (std::size_t i = 1; i < path.size(); ++i)
    crossings += path[i].tool == path[i - 1].tool && (path[i].tip.x() > 60) != (path[i - 1].tip.x() > 60);
  std::printf("%zu operations, %d crossings between the pockets\n", result.operations.size(), crossings);
  EXPECT_LE(crossings, static_cast<int>(result.operations.size()));
  expectNoGougeNorCollision(part, path, tools, stock.mesh, 0.2);
}

}  // namespace

// Level after level, the tool crossed from one pocket to the other at each level; now it finishes one pocket's walls
// top down before crossing.
TEST(PlanarFinishing, WallsAreFinishedPocketByPocketTopDown) {
  expectPocketByPocket(
      [](const Face& face) -> std::optional<FinishingKind> {
        if (face.type == SurfaceType::Plane && std::abs(face.normal.z()) < 1e-9 && face.area < 30 * 10 + 1)
          return FinishingKind::SideMill;
        return std::nullopt;
      },
      16);  // 4 walls in each of the 4 pockets
}

// Likewise the floors (each pocket's two): the face mill went level after level; now piece by piece, nearest first,
// each after the floors above it (level after level: 4 crossings for 3 operations).
TEST(PlanarFinishing, FloorsAreFacedPocketByPocketTopDown) {
  expectPocketByPocket(
      [](const Face& face) -> std::optional<FinishingKind> {
        if (face.type == SurfaceType::Plane && face.normal.z() > 1 - 1e-9 && face.offset < 25)
          return FinishingKind::FaceMill;
        return std::nullopt;
      },
      4);  // the upper and the lower floor of each pocket
}

// A 100 x 60 x 80 block with a 40 x 40 pocket 70 deep, its top and the pocket's floor to face-mill: flat20's holder
// stops it 60 mm down, so only flat20L reaches the floor. flat20 (1,150 mm/min) faces the top first and flat20L
// (690 mm/min) follows for the floor alone: its feed time is under 85 % of flat20L doing both (71 % by the areas),
// every floor is reached, and the simulation finds no gouge and no collision.
TEST(PlanarFinishing, AShortToolFacesWhatItReachesBeforeALongOneTakesTheDepth) {
  const Part part = test::stepPart(test::pocketedBlock(Vec3(0, 0, 0), Vec3(100, 60, 80), 40, 40, 70, 12),
                                   "deep_pocket", fine());
  const Part stock = test::stepPart(test::pocketedBlock(Vec3(-2, -2, 0), Vec3(102, 62, 80 + kSkin), 40 - 2 * kSkin,
                                                        40 - 2 * kSkin, 70, 12 - kSkin),
                                    "deep_pocket_stock", fine());
  const ToolLibrary library = loadToolLibrary(kTools);
  std::vector<const Tool*> flats;  // as finishing takes them: not the high-efficiency roughing cutters
  for (const Tool* t : flatsLargestFirst(library))
    if (t->max_engagement_deg == 0) flats.push_back(t);
  PlanarGroup group;
  group.frame = setupFrame(part, Vec3::UnitZ());
  group.stock = test::box(Vec3(-2, -2, -2), Vec3(102, 62, 82));
  for (int f = 0; f < static_cast<int>(part.faces.size()); ++f)
    if (part.faces[f].type == SurfaceType::Plane && part.faces[f].normal.z() > 1 - 1e-9)
      group.targets.push_back({f, FinishingKind::FaceMill});
  ASSERT_EQ(group.targets.size(), 2u) << "the top and the pocket's floor";

  const auto feedSeconds = [&](const PlanarResult& result) {
    double s = 0;
    for (const FinishingOperation& op : result.operations)
      s += toolpathLength(op.path, MoveKind::Feed) / library.find(op.tool)->feed_mm_min * 60;
    return s;
  };
  const PlanarResult result = finishPlanar(part, group, flats, FinishingOptions{});
  ASSERT_GE(result.operations.size(), 2u);
  EXPECT_EQ(result.operations.front().tool, "flat20");
  EXPECT_TRUE(std::any_of(result.operations.begin(), result.operations.end(),
                          [](const FinishingOperation& op) { return op.tool == "flat20L"; }));
  for (const PlanarReach& r : result.reach) EXPECT_GE(r.reached, 0.99 * r.size) << "face " << r.face;

  std::vector<const Tool*> long_only;  // flat20 out of the library: flat20L does both
  for (const Tool* t : flats)
    if (t->id != "flat20") long_only.push_back(t);
  const PlanarResult long_result = finishPlanar(part, group, long_only, FinishingOptions{});
  ASSERT_FALSE(long_result.operations.empty());
  EXPECT_EQ(long_result.operations.front().tool, "flat20L");
  std::printf("feed time: %.0f s short tool first, %.0f s with flat20L alone\n", feedSeconds(result),
              feedSeconds(long_result));
  EXPECT_LT(feedSeconds(result), 0.85 * feedSeconds(long_result));

  const auto [path, tools] = programOf(result.operations, library);
  expectNoGougeNorCollision(part, path, tools, stock.mesh, 0.25);
}
