// Roughing (issue 6): levels, shadows, and whole plans judged by the verification's simulation and by an independent
// measure of the stock the setups can reach (rays cast from the stock along the setup directions with Embree).
#include <gtest/gtest.h>

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <memory>

#include "art2part/roughing/in_process_stock.h"
#include "art2part/roughing/roughing.h"
#include "art2part/roughing/shadow.h"
#include "art2part/simulation/mesh_dexels.h"
#include "art2part/simulation/part_distance.h"
#include "art2part/simulation/verify.h"
#include "art2part/visibility/analysis.h"
#include "test_meshes.h"
#include "test_solids.h"

using namespace art2part;

namespace {

const std::string kParts = ART2PART_SHARED_PARTS;
const std::string kTools = std::string(ART2PART_SOURCE_DIR) + "/config/tools.yaml";

// A prism: the polygon `profile` (x, z; counter-clockwise, star-shaped around its first point) extruded along y from
// 0 to `depth`. Closed and outward.
Mesh extrudeXZ(const std::vector<Point2>& profile, double depth) {
  Mesh m;
  const int n = static_cast<int>(profile.size());
  for (double y : {0.0, depth})
    for (const Point2& p : profile) m.vertices.emplace_back(p.x(), y, p.y());
  // Profile CCW in (x, z) seen from -y (x right, z up) faces -y at y = 0.
  for (int i = 1; i + 1 < n; ++i) {
    m.triangles.push_back({0, i, i + 1});                // y = 0 cap, normal -y
    m.triangles.push_back({n, n + i + 1, n + i});        // y = depth cap, normal +y
  }
  for (int i = 0; i < n; ++i) {
    const int j = (i + 1) % n;
    m.triangles.push_back({i, n + i, n + j});
    m.triangles.push_back({i, n + j, j});
  }
  return m;
}

// An L: a 60 x 40 x 10 base with a 20 x 40 x 10 tower at x in [0, 20].
Part lPart() {
  const Mesh m = extrudeXZ({{0, 0}, {60, 0}, {60, 10}, {20, 10}, {20, 20}, {0, 20}}, 40);
  EXPECT_GT(signedVolume(m), 0);
  return partFromMesh(m, "L");
}

Setup topSetup(const Part& part) {
  Setup s;
  s.direction = 0;
  s.frame = setupFrame(part, Vec3::UnitZ());
  return s;
}

// Of the stock material that a thin tool (a cylinder of radius `skin`) along some setup direction reaches without
// meeting the part, and that lies farther than `skin` from the part: the fraction the simulation removed, and its
// volume. Sampled at the verification lattice's z-family ray positions (every `stride`-th ray) and cell centres along
// z. The thin tool has no length: it also reaches the middle of a tunnel 60 mm long or stock behind a whole part.
// The second figure counts only what one of `tools` also reaches standing upright along the direction, its tip at
// the point's level with the point at its centre or on its rim, every part of it (flutes and shank as a cylinder to
// the stickout, then the holder's steps) clear of the part by the `allowance`: what the shop's tools could take. Both
// are generous to the planner's critic: the body is probed by nine rays (a fin between them goes unseen), the holder
// by balls along its axis (a corner between them goes unseen), and stock left standing does not block.
struct Reach {
  double reachable_mm3 = 0, removed_mm3 = 0;
  double tool_reachable_mm3 = 0, tool_removed_mm3 = 0;
  double fraction() const { return reachable_mm3 > 0 ? removed_mm3 / reachable_mm3 : 1.0; }
  double toolFraction() const { return tool_reachable_mm3 > 0 ? tool_removed_mm3 / tool_reachable_mm3 : 1.0; }
};

class ReachProbe {
 public:
  explicit ReachProbe(const Mesh& mesh) : distance_(mesh) {
    device_ = rtcNewDevice(nullptr);
    scene_ = rtcNewScene(device_);
    RTCGeometry geometry = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                          3 * sizeof(float), mesh.vertices.size()));
    for (std::size_t i = 0; i < mesh.vertices.size(); ++i)
      for (int k = 0; k < 3; ++k) v[3 * i + k] = static_cast<float>(mesh.vertices[i][k]);
    auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                               3 * sizeof(unsigned), mesh.triangles.size()));
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
      for (int k = 0; k < 3; ++k) idx[3 * t + k] = static_cast<unsigned>(mesh.triangles[t][k]);
    rtcCommitGeometry(geometry);
    rtcAttachGeometry(scene_, geometry);
    rtcReleaseGeometry(geometry);
    rtcCommitScene(scene_);
    rtcInitIntersectContext(&context_);
  }
  ~ReachProbe() {
    rtcReleaseScene(scene_);
    rtcReleaseDevice(device_);
  }
  const PartDistance& distance() const { return distance_; }

  // A cylinder of `radius` from p along d for `length` meets no triangle (axis and eight rays on its rim).
  bool cylinderClear(const Vec3& p, const Vec3& d, double radius, double length) {
    const Vec3 e1 = (std::abs(d.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY()).cross(d).normalized();
    const Vec3 e2 = d.cross(e1);
    for (int k = -1; k < 8; ++k) {
      const double angle = k * 3.14159265358979323846 / 4;
      const Vec3 o = k < 0 ? p : Vec3(p + radius * (std::cos(angle) * e1 + std::sin(angle) * e2));
      RTCRay r{};
      r.org_x = static_cast<float>(o.x());
      r.org_y = static_cast<float>(o.y());
      r.org_z = static_cast<float>(o.z());
      r.dir_x = static_cast<float>(d.x());
      r.dir_y = static_cast<float>(d.y());
      r.dir_z = static_cast<float>(d.z());
      r.tnear = 0;
      r.tfar = static_cast<float>(length);
      r.mask = 0xFFFFFFFF;
      rtcOccluded1(scene_, &context_, &r);
      if (r.tfar < 0) return false;
    }
    return true;
  }

  // `tool` along d with its tip at p's level, p at its centre or on its rim (four sides), clear of the part by
  // `allowance`.
  bool toolReaches(const Tool& tool, const Vec3& p, const Vec3& d, double allowance) {
    const Vec3 e1 = (std::abs(d.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY()).cross(d).normalized();
    const Vec3 e2 = d.cross(e1);
    const double r = tool.diameter / 2;
    const double body = std::max(r, tool.shank_diameter / 2) + allowance;
    const Vec3 sides[5] = {Vec3::Zero(), e1, -e1, e2, -e2};
    for (const Vec3& side : sides) {
      const Vec3 tip = p + r * side;
      if (!cylinderClear(tip, d, body, tool.stickout)) continue;
      bool clear = true;
      const double length = toolLength(tool);
      for (double h = tool.stickout; h <= length && clear; h += 2.0) {
        const double radius = toolRadiusAt(tool, h);
        clear = distance_.distance(tip + h * d, nullptr, radius) > radius;
      }
      if (clear) return true;
    }
    return false;
  }

 private:
  PartDistance distance_;
  RTCDevice device_;
  RTCScene scene_;
  RTCIntersectContext context_;
};

Reach reachableRemoved(const Mesh& mesh, const std::vector<Vec3>& directions, const VerificationState& state,
                       double skin, int stride, const std::vector<const Tool*>& tools = {}, double allowance = 0) {
  ReachProbe probe(mesh);
  const DexelLattice& lattice = state.stock.lattice;
  const int nu = lattice.cells[DexelLattice::uAxis(2)], nv = lattice.cells[DexelLattice::vAxis(2)];
  const double cell = lattice.spacing.x() * lattice.spacing.y() * lattice.spacing.z() * stride * stride;
  Reach reach;
  for (int iv = stride / 2; iv < nv; iv += stride)
    for (int iu = stride / 2; iu < nu; iu += stride) {
      const int ray = lattice.rayIndex(2, iu, iv);
      const Vec3 origin = lattice.rayOrigin(2, iu, iv);
      for (int iz = 0; iz < lattice.cells[2]; ++iz) {
        const double z = lattice.coordinate(2, iz);
        if (state.part.contains(2, ray, z)) continue;
        const Vec3 p(origin.x(), origin.y(), z);
        if (probe.distance().distance(p, nullptr, skin + 1e-9) <= skin) continue;
        bool reachable = false, by_tool = false;
        for (const Vec3& d : directions) {
          if (!probe.cylinderClear(p, d, skin, 1e30)) continue;
          reachable = true;
          for (const Tool* tool : tools)
            if (probe.toolReaches(*tool, p, d, allowance)) {
              by_tool = true;
              break;
            }
          if (by_tool) break;
        }
        if (!reachable) continue;
        const bool removed = !spansContain(state.stock.ray(2, ray), z);
        reach.reachable_mm3 += cell;
        reach.removed_mm3 += removed ? cell : 0;
        if (by_tool) {
          reach.tool_reachable_mm3 += cell;
          reach.tool_removed_mm3 += removed ? cell : 0;
        }
        if (!removed && std::getenv("A2P_DEBUG")) std::printf("left %.2f %.2f %.2f %d\n", p.x(), p.y(), p.z(), by_tool);
      }
    }
  return reach;
}

Toolpath wholePath(const RoughingPlan& plan) {
  Toolpath path;
  for (const RoughingOperation& op : plan.operations) path.insert(path.end(), op.path.begin(), op.path.end());
  return path;
}

std::vector<Tool> toolsOf(const RoughingPlan& plan, const ToolLibrary& library) {
  std::vector<Tool> tools;
  for (const RoughingOperation& op : plan.operations) tools.push_back(*library.find(op.tool));
  return tools;
}

// featuretype and its level-2 setups, planned once for the tests that compare roughing options on it.
struct PlannedPart {
  Part part;
  SetupPlan setups;
};
const PlannedPart& featuretype() {
  static const PlannedPart planned = [] {
    PlannedPart p{loadPart(kParts + "/featuretype.STEP"), {}};
    VisibilityOptions visibility_options;
    visibility_options.level = 2;
    p.setups = planSetups(p.part, analyseVisibility(p.part, visibility_options));
    return p;
  }();
  return planned;
}

// The simulation's verdict on a roughing plan at 0.5 mm.
VerificationReport verifyRoughing(const Part& part, const RoughingPlan& roughing, const ToolLibrary& library) {
  VerifyOptions verify;
  verify.resolution = 0.5;
  return verifyToolpath(part.mesh, part.triangle_face, wholePath(roughing), toolsOf(roughing, library), verify);
}

// Issue 19 item 4's invariant, measured on the simulated stock: the column over every cut of a level is clear (the
// levels above took it), so an operation's level feeds cut no deeper than its step-down (RoughingOptions: the
// tool's, the option's, a rest pass's at most rest.stepdown; never over the flutes). Stock removed higher stood
// above the slab. Hairs shaved off walls higher up (a lower level's ring a few microns outside the one above it)
// are allowed: at most kAboveShare of what the operation removed (featuretype at level-2 setups, zig-zag, stay-down
// and adaptive: under 0.005 % above the step-down + a bin, though the highest hair is 7-40 mm up). `above`: each
// operation's share, for the figures.
constexpr double kAboveShare = 0.001;
void expectLevelCutsWithinTheStepDown(const RoughingPlan& roughing, const VerificationReport& report,
                                      const ToolLibrary& library, const RoughingOptions& options,
                                      std::vector<double>* above = nullptr) {
  for (std::size_t i = 0; i < roughing.operations.size(); ++i) {
    const RoughingOperation& op = roughing.operations[i];
    const Tool* tool = library.find(op.tool);
    ASSERT_TRUE(tool != nullptr) << op.tool;
    double stepdown = options.levels.stepdown > 0 ? options.levels.stepdown
                                                  : (tool->max_stepdown > 0 ? tool->max_stepdown : tool->diameter / 2);
    if (op.kind == "rest roughing") stepdown = std::min(stepdown, options.rest.stepdown);
    if (op.kind == "adaptive rest roughing") stepdown *= options.clearing.step_up_share;
    stepdown = std::min(stepdown, tool->flute_length);
    const auto check = report.by_op.find(static_cast<int>(i));
    ASSERT_TRUE(check != report.by_op.end()) << "operation " << i;
    const OperationSweep& swept = check->second.swept;
    const double share = levelCutAbove(swept, stepdown + report.tolerance_mm) / std::max(swept.removed_mm3, 1e-9);
    EXPECT_GT(levelCutAbove(swept, 0), 0) << "operation " << i << " cuts at its levels";
    EXPECT_LE(share, kAboveShare) << "operation " << i << " (" << op.kind << ", " << op.tool << ", setup "
                                  << op.setup << ") cut under stock standing above its slab; deepest at the move "
                                  << "ending at row " << swept.deepest_level_cut_row;
    if (above) above->push_back(share);
  }
}

}  // namespace

TEST(Shadow, LPartShadowIsWhatLiesAbove) {
  const Part part = lPart();
  SetupFrame frame;  // the part frame itself
  SetupShadows shadows(toFrame(part.mesh.vertices, frame), part.mesh.triangles);
  EXPECT_TRUE(regionEmpty(shadows.at(25)));
  EXPECT_NEAR(regionArea(shadows.at(15)), 20 * 40, 1e-6);
  EXPECT_NEAR(regionArea(shadows.at(10)), 60 * 40, 1e-6);  // the step's floor is at the level: above it
  EXPECT_NEAR(regionArea(shadows.at(-1)), 60 * 40, 1e-6);
  // Asked out of order, from the nearest kept height above: the same shadows.
  SetupShadows upward(toFrame(part.mesh.vertices, frame), part.mesh.triangles);
  EXPECT_NEAR(regionArea(upward.at(-1)), 60 * 40, 1e-6);
  EXPECT_NEAR(regionArea(upward.at(15)), 20 * 40, 1e-6);
  EXPECT_NEAR(regionArea(upward.at(10)), 60 * 40, 1e-6);
  EXPECT_TRUE(regionEmpty(upward.at(25)));
}

TEST(Shadow, StockSlabOfATiltedBoxIsItsSection) {
  const Mesh box = boxMesh({Vec3(0, 0, 0), Vec3(10, 20, 30)});
  EXPECT_NEAR(signedVolume(box), 6000, 1e-9);
  SetupFrame frame;
  frame.z = Vec3(1, 0, 1).normalized();
  frame.x = Vec3(1, 0, -1).normalized();
  frame.y = frame.z.cross(frame.x);
  const std::vector<Vec3> v = toFrame(box.vertices, frame);
  // Thin slab through the middle: the section of the box by a plane at 45 degrees is 20 wide and 10 * sqrt(2) long.
  const double mid = Vec3(5, 10, 15).dot(frame.z);
  EXPECT_NEAR(regionArea(stockSlabRegion(v, box.triangles, mid - 1e-6, mid + 1e-6)), 20 * 10 * std::sqrt(2.0), 1e-3);
}

TEST(RoughingLevels, CriticalHeightsAndStepDown) {
  const Part part = lPart();
  const art2part::Setup setup = topSetup(part);
  const std::vector<Vec3> v = toFrame(part.mesh.vertices, setup.frame);
  RoughingOptions options;
  options.allowance = 0.3;
  // In the frame the part's top is at 0: the step's floor at -10, the bottom at -20; stock 2 mm around.
  const std::vector<RoughingLevel> levels = roughingLevels(part, v, 2, -22, 3, options);
  ASSERT_FALSE(levels.empty());
  bool floor = false;
  double previous = 2;
  for (const RoughingLevel& l : levels) {
    EXPECT_LT(l.z, previous);
    EXPECT_LE(previous - l.z, 3 + 1e-9);
    previous = l.z;
    if (l.critical && std::abs(l.z - (-10 + 0.3)) < 1e-9) floor = true;
  }
  EXPECT_TRUE(floor) << "a level exactly at the step's floor plus the allowance";
  EXPECT_NEAR(levels.back().z, -22, 1e-12);
}

TEST(Roughing, LPartFromTheTopIsCleanAndLeavesTheAllowance) {
  const Part part = lPart();
  const ToolLibrary library = loadToolLibrary(kTools);
  SetupPlan setups;
  setups.setups.push_back(topSetup(part));
  RoughingOptions options;
  const RoughingPlan plan = planRoughing(part, setups, library, options);
  ASSERT_FALSE(plan.operations.empty());
  const Tool* tool = library.find(plan.operations[0].tool);
  ASSERT_NE(tool, nullptr);
  EXPECT_GE(tool->diameter, 12) << "open shapes take a large tool";
  VerifyOptions verify;
  verify.resolution = 0.5;
  VerificationState state;
  const VerificationReport report =
      verifyToolpath(part.mesh, part.triangle_face, wholePath(plan), toolsOf(plan, library), verify, &state);
  EXPECT_EQ(report.gouges, 0);
  EXPECT_EQ(report.collisions, 0);
  const Reach reach = reachableRemoved(part.mesh, {Vec3::UnitZ()}, state, options.allowance + 0.5, 1);
  std::printf("L part: %s, %zu points; reachable %.0f mm3, removed %.4f; leftover max %.3f mm\n", tool->id.c_str(),
              plan.operations[0].path.size(), reach.reachable_mm3, reach.fraction(), report.leftover_max_mm);
  EXPECT_GE(reach.fraction(), 0.999);
  // Above the floor at z = 10 (x > 20) only the allowance is left: sample the stock's z rays there.
  const DexelLattice& lattice = state.stock.lattice;
  double worst = 0;
  for (int iv = 0; iv < lattice.cells[DexelLattice::vAxis(2)]; ++iv)
    for (int iu = 0; iu < lattice.cells[DexelLattice::uAxis(2)]; ++iu) {
      const Vec3 o = lattice.rayOrigin(2, iu, iv);
      if (o.x() < 20 + 2 || o.x() > 58 || o.y() < 2 || o.y() > 38) continue;
      for (const Span& s : state.stock.ray(2, lattice.rayIndex(2, iu, iv)))
        if (s.hi > 10 - 1e-9) worst = std::max(worst, s.hi - 10);
    }
  EXPECT_NEAR(worst, options.allowance, 0.02) << "the critical level leaves the allowance on the floor";
}

TEST(Roughing, BadToolsAreRefused) {
  const Part part = lPart();
  const ToolLibrary library = loadToolLibrary(kTools);
  SetupPlan setups;
  setups.setups.push_back(topSetup(part));
  RoughingOptions options;
  options.clearing.tool = "no-such-tool";
  EXPECT_THROW(planRoughing(part, setups, library, options), InputError);
  options.clearing.tool = "ball6";
  EXPECT_THROW(planRoughing(part, setups, library, options), InputError);
}

// Whole plans on shared parts: visibility at level 2, setups, roughing, the simulation's verdict.
class RoughingOnParts : public ::testing::TestWithParam<const char*> {};

TEST_P(RoughingOnParts, NoGougeNoCollisionAndTheReachableStockIsRemoved) {
  const Part part = loadPart(kParts + "/" + GetParam());
  VisibilityOptions visibility_options;
  visibility_options.level = 2;
  const VisibilityResult visibility = analyseVisibility(part, visibility_options);
  const SetupPlan setups = planSetups(part, visibility);
  const ToolLibrary library = loadToolLibrary(kTools);
  RoughingOptions options;
  const RoughingPlan plan = planRoughing(part, setups, library, options);
  ASSERT_FALSE(plan.operations.empty());
  VerificationState state;
  VerifyOptions verify;
  // The simulation's lattice: no finer than 0.5 mm nor than 1/300 of the part's diagonal (CTC-01 is 800 mm long).
  const Box box = boundingBox(part.mesh);
  verify.resolution = std::max({0.5, automaticResolution(box), box.diagonal() / 300});
  const VerificationReport report =
      verifyToolpath(part.mesh, part.triangle_face, wholePath(plan), toolsOf(plan, library), verify, &state);
  std::vector<Vec3> directions;
  for (const art2part::Setup& s : setups.setups) directions.push_back(s.frame.z);
  const Reach reach = reachableRemoved(part.mesh, directions, state, options.allowance + 2 * report.resolution_mm, 2,
                                      roughingTools(library), options.allowance);
  std::printf("%s: %zu setups, %zu operations, %.1f s planning; %d gouges, %d collisions; reachable %.0f mm3, "
              "removed %.4f; reachable with the library's tools %.0f mm3, removed %.4f; leftover %.0f mm3 "
              "(max %.2f mm)\n",
              GetParam(), setups.setups.size(), plan.operations.size(), plan.seconds, report.gouges,
              report.collisions, reach.reachable_mm3, reach.fraction(), reach.tool_reachable_mm3,
              reach.toolFraction(), report.leftover_volume_mm3, report.leftover_max_mm);
  EXPECT_EQ(report.gouges, 0);
  EXPECT_EQ(report.collisions, 0);
  // Issue 6 asks for 97 % of the stock the setups can reach. What the shop's tools reach: featuretype 99.2 %, ANC101
  // 99.9 %. What a thin tool of no length reaches: ANC101 98.5 %, featuretype 95.9 % (the middle of a tunnel 7.9 mm
  // wide running 63.5 mm through the part along setup 0, deeper than any library tool's stickout with its holder, and
  // the 2 mm of stock under the part that only a side cut 63 mm deep would take); that floor guards against regression.
  EXPECT_GE(reach.toolFraction(), 0.97);
  EXPECT_GE(reach.fraction(), 0.95);
}

INSTANTIATE_TEST_SUITE_P(SharedParts, RoughingOnParts,
                         // CTC-01 is planned and verified by test_setup_plan (the README's example); the others
                         // take minutes each (bench_roughing).
                         ::testing::Values("featuretype.STEP", "ANC101.stp"));

// A roughing plan's cutting where `counted` says (the feed of those operations) and the simulation's verdict on it;
// the level cuts checked within the step-down on the way.
struct CountedFeed {
  double feed_mm = 0;
  VerificationReport report;
};
CountedFeed plannedFeed(const Part& part, const SetupPlan& setups, const RoughingOptions& options,
                        const std::function<bool(const RoughingOperation&)>& counted) {
  const ToolLibrary library = loadToolLibrary(kTools);
  const RoughingPlan roughing = planRoughing(part, setups, library, options);
  CountedFeed out;
  for (const RoughingOperation& op : roughing.operations)
    if (counted(op)) out.feed_mm += op.feed_mm;
  out.report = verifyRoughing(part, roughing, library);
  expectLevelCutsWithinTheStepDown(roughing, out.report, library, options);
  return out;
}

// A rule leaving pieces out (`ruled`) against every piece kept: clean by the simulation, under `feed_share` of the
// counted feed, the simulation's removal within `removal_share` of it.
void expectLessCutForTheSameRemoval(const CountedFeed& every_piece, const CountedFeed& ruled, double feed_share,
                                    double removal_share, const char* otherwise) {
  EXPECT_EQ(ruled.report.gouges, 0);
  EXPECT_EQ(ruled.report.collisions, 0);
  EXPECT_LT(ruled.feed_mm, feed_share * every_piece.feed_mm) << otherwise;
  EXPECT_NEAR(ruled.report.removed_volume_mm3, every_piece.report.removed_volume_mm3,
              removal_share * every_piece.report.removed_volume_mm3);
}

// Rest roughing only where material is (issue 19): rest passes leave out the pieces of their centre regions that would
// cut air round stock the tool cannot reach. On featuretype they remove what they removed with every piece kept (the
// simulation's volume within 0.05 %), cut less, and neither gouge nor collide. Every setup starts from the block here
// (no in-process stock): with it, the second setup's rest passes no longer meet the first's film round the part
// (ALaterSetupTracesNoFilmAnEarlierOneLeftOnSlantedFaces), which was most of what this rule kept them from (11,536 ->
// 10,448 mm of feed before that; 9,372 -> 9,181 after), and the rule's own effect is seen on stock it cannot reach.
TEST(Roughing, RestPassesCutOnlyWhereTheirStockIs) {
  const auto& [part, setups] = featuretype();
  auto plan = [&](double least_target_mm2) {
    RoughingOptions options;
    options.rest.least_target_mm2 = least_target_mm2;
    options.stock.in_process = false;
    return plannedFeed(part, setups, options, [](const RoughingOperation& op) { return op.kind == "rest roughing"; });
  };
  const CountedFeed every_piece = plan(0), reaching = plan(RoughingOptions().rest.least_target_mm2);
  std::printf("rest passes: %.0f mm of feed with every piece, %.0f mm where their stock is; removed %.0f / %.0f mm3\n",
              every_piece.feed_mm, reaching.feed_mm, every_piece.report.removed_volume_mm3,
              reaching.report.removed_volume_mm3);
  expectLessCutForTheSameRemoval(every_piece, reaching, 0.95, 5e-4, "the air round unreachable stock is cut");
}

// A later setup's main pass over the in-process stock leaves out the pieces of its centre regions whose sweep misses
// the stock the model proves (slivers a cutter's radius and a millimetre beyond it, each a hop for nothing): on
// featuretype the later setups' main passes cut less (3,066 -> 2,177 mm of feed) and the roughing removes what it
// removed with every piece kept (the simulation's volume within 0.1 %), neither gouging nor colliding.
TEST(Roughing, ALaterSetupsMainPassCutsOnlyWhereProvenStockIs) {
  const Part& part = featuretype().part;
  // The plan's setups (visibility at its default level): the third one's main pass meets the slivers.
  const SetupPlan setups = planSetups(part, analyseVisibility(part, VisibilityOptions()));
  auto plan = [&](double least_proven_mm2) {
    RoughingOptions options;
    options.stock.least_proven_mm2 = least_proven_mm2;
    return plannedFeed(part, setups, options,
                       [](const RoughingOperation& op) { return op.setup > 0 && op.kind == "roughing"; });
  };
  const CountedFeed every_piece = plan(0), reaching = plan(RoughingOptions().stock.least_proven_mm2);
  std::printf("later setups' main passes: %.0f mm of feed with every piece, %.0f mm where proven stock is; removed "
              "%.0f / %.0f mm3\n",
              every_piece.feed_mm, reaching.feed_mm, every_piece.report.removed_volume_mm3,
              reaching.report.removed_volume_mm3);
  expectLessCutForTheSameRemoval(every_piece, reaching, 0.8, 1e-3, "slivers missing the stock are cut");
}

// A square pyramid, its base 2 x `half` wide at z = 0 round (cx, cy), its apex `height` over the centre, turned by
// `turn_deg` about z: its faces' normals lie in no coordinate plane. `heightAt` gives its top at (x, y).
struct TurnedPyramid {
  double cx = 30, cy = 30, half = 15, height = 15, turn_deg = 30;
  double heightAt(double x, double y) const {
    const double c = std::cos(turn_deg * M_PI / 180), s = std::sin(turn_deg * M_PI / 180);
    const double u = c * (x - cx) + s * (y - cy), v = -s * (x - cx) + c * (y - cy);
    return std::max(0.0, height * (1 - std::max(std::abs(u), std::abs(v)) / half));
  }
  Mesh mesh() const {
    Mesh m;
    const double c = std::cos(turn_deg * M_PI / 180), s = std::sin(turn_deg * M_PI / 180);
    for (const auto& [u, v] : {std::pair{-1, -1}, {1, -1}, {1, 1}, {-1, 1}})
      m.vertices.emplace_back(cx + half * (c * u - s * v), cy + half * (s * u + c * v), 0.0);
    m.vertices.emplace_back(cx, cy, height);
    m.triangles = {{0, 2, 1}, {0, 3, 2}, {0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {3, 0, 4}};
    return m;
  }
};

// An earlier setup's finishing-like cut with a flat mill: its tip over every point of a 1 mm grid over the block at
// the pyramid's highest point under its disc plus the allowance, row after row.
Toolpath dropCutterRows(const TurnedPyramid& pyramid, const Tool& tool, double allowance, double lo, double hi) {
  const double r = tool.diameter / 2;
  Toolpath path;
  bool forth = true;
  for (double y = lo; y <= hi + 1e-9; y += 1, forth = !forth)
    for (double i = 0; i <= hi - lo + 1e-9; i += 1) {
      const double x = forth ? lo + i : hi - i;
      double top = 0;
      for (double dx = -r; dx <= r + 1e-9; dx += 0.25)
        for (double dy = -r; dy <= r + 1e-9; dy += 0.25)
          if (dx * dx + dy * dy <= r * r) top = std::max(top, pyramid.heightAt(x + dx, y + dy));
      CutterLocation c;
      c.tool = tool.id;
      c.tip = Vec3(x, y, top + allowance);
      path.push_back(c);
    }
  return path;
}

// What earlier setups left round the part (issue 19): on faces at a slant to every axis the in-process model keeps
// the allowance and a film thicker than its proof of stock sees through, which a later setup's passes traced at every
// level for next to nothing (Ailette's setups 2 and 3: 101 and 129 cm3 planned, 4 and 5 removed). The stock the
// model proves within its doubt of both the skin and a face cut before is no target; raw stock is (the block's own
// faces bear no film).
TEST(Roughing, ALaterSetupTracesNoFilmAnEarlierOneLeftOnSlantedFaces) {
  const TurnedPyramid pyramid;
  const Part part = partFromMesh(pyramid.mesh(), "turned pyramid");
  ASSERT_GT(signedVolume(part.mesh), 0);
  const Mesh block = test::box(Vec3(0, 0, 0), Vec3(60, 60, 20));
  const ToolLibrary library = loadToolLibrary(kTools);
  const Tool& flat10 = *library.find("flat10");
  RoughingOptions options;
  options.stock.mesh = std::make_shared<Mesh>(block);
  const art2part::Setup top = topSetup(part);
  auto later = [&](bool cut_before) {
    InProcessStock in_process(part, block, 20000, 1.5);
    if (cut_before) in_process.remove(dropCutterRows(pyramid, flat10, options.allowance, -6, 66), {flat10});
    RoughingStart start;
    start.earlier = &in_process;
    return roughSetup(part, top, 1, flat10, options, start).operation;
  };
  const RoughingOperation over_film = later(true), over_raw = later(false);
  std::printf("later setup's main pass: %.0f mm3 planned in %.0f mm of feed over the film, %.0f mm3 in %.0f mm over "
              "the raw block\n",
              over_film.planned_removal_mm3, over_film.feed_mm, over_raw.planned_removal_mm3, over_raw.feed_mm);
  // The earlier cut left the allowance and cusps under 0.05 mm between its rows: nothing for a roughing pass.
  EXPECT_LT(over_film.planned_removal_mm3, 10);
  EXPECT_LT(over_film.feed_mm, 0.05 * over_raw.feed_mm);
  // Over the raw block everything beyond the skin is a target: the block less the pyramid less a film the
  // allowance thick, less what a 10 mm mill leaves in the corners of the stairs (under 3 %).
  const double pyramid_volume = 4 * pyramid.half * pyramid.half * pyramid.height / 3;
  EXPECT_GT(over_raw.planned_removal_mm3, 0.9 * (60 * 60 * 20 - pyramid_volume));
}

// A reach pass (issue 19): a pocket deeper than the main tool reaches before its holder meets the block's top. The
// main tool's long-fluted twin, at its own step-down, takes what the main pass could not, where before the rest
// passes (whose holders are no slimmer) left it to finishing. By the simulation: no gouge, no collision, each level
// cutting within its step-down, and the pocket's bottom removed.
TEST(Roughing, AReachPassTakesWhatTheMainToolsHolderKeptItFrom) {
  const Part part = test::stepPart(test::pocketedBlock(Vec3(0, 0, 0), Vec3(100, 100, 100), 36, 36, 90, 12), "deep_pocket");
  const ToolLibrary library = loadToolLibrary(kTools);
  SetupPlan setups;
  setups.setups.push_back(topSetup(part));
  struct Outcome {
    RoughingPlan roughing;
    VerificationReport report;
  };
  auto plan = [&](bool reach) {
    RoughingOptions options;
    options.rest.reach = reach;
    Outcome out{planRoughing(part, setups, library, options), {}};
    out.report = verifyRoughing(part, out.roughing, library);
    expectLevelCutsWithinTheStepDown(out.roughing, out.report, library, options);
    return out;
  };
  const Outcome with = plan(true), without = plan(false);
  ASSERT_FALSE(with.roughing.operations.empty());
  const RoughingOperation& main = with.roughing.operations.front();
  const Tool* main_tool = library.find(main.tool);
  ASSERT_NE(main_tool, nullptr);
  const RoughingOperation* reach = nullptr;
  for (const RoughingOperation& op : with.roughing.operations)
    if (op.kind == "reach roughing") reach = &op;
  ASSERT_NE(reach, nullptr) << "no reach pass after " << main.tool;
  const Tool* reach_tool = library.find(reach->tool);
  ASSERT_NE(reach_tool, nullptr);
  EXPECT_DOUBLE_EQ(reach_tool->diameter, main_tool->diameter);
  EXPECT_GT(reach_tool->flute_length, main_tool->flute_length);
  for (const RoughingOperation& op : without.roughing.operations) EXPECT_NE(op.kind, "reach roughing");
  std::printf("deep pocket: %s then %s; removed %.0f mm3 with the reach pass, %.0f without\n", main.tool.c_str(),
              reach->tool.c_str(), with.report.removed_volume_mm3, without.report.removed_volume_mm3);
  for (const Outcome* o : {&with, &without}) {
    EXPECT_EQ(o->report.gouges, 0);
    EXPECT_EQ(o->report.collisions, 0);
  }
  // The main tool's holder stops it about its stickout down: the pocket's bottom 25 mm and more stayed.
  EXPECT_GT(with.report.removed_volume_mm3 - without.report.removed_volume_mm3, 0.8 * 35.4 * 35.4 * 25);

  // No pass cuts at its tool's full library rate all the time (entries, links, the pocket's corners): asked for
  // that, the reach pass is left out with its line, and the rest passes start from what the main pass left.
  RoughingOptions strict;
  strict.rest.least_reach_rate_share = 1.0;
  const RoughingPlan slow = planRoughing(part, setups, library, strict);
  for (const RoughingOperation& op : slow.operations) EXPECT_NE(op.kind, "reach roughing");
  const auto dropped = std::find_if(slow.dropped.begin(), slow.dropped.end(),
                                    [](const DroppedOperation& d) { return d.kind == "reach roughing"; });
  ASSERT_NE(dropped, slow.dropped.end());
  EXPECT_NE(dropped->reason.find("library rate"), std::string::npos) << dropped->reason;
  EXPECT_GT(dropped->plan_seconds, 0);  // the planning it cost, for nothing
  std::printf("left out at a full-rate demand: %s (planned in %.2f s)\n", dropped->reason.c_str(),
              dropped->plan_seconds);
}

// Stay-down links (issue 19): the same plan with links kept low (inside cleared material, over stock the slabs prove
// clear) and with every link over the clearance plane. By the simulation: neither gouges nor collides, both remove
// the same stock; the low links cut the rapid length to under 0.6x and the retracts to under 0.3x (featuretype at
// level-2 setups: 45.5 -> 20.5 m of rapids, 416 -> 79 retracts).
TEST(Roughing, StayDownLinksKeepTheToolLowWithoutCollisions) {
  const auto& [part, setups] = featuretype();
  const ToolLibrary library = loadToolLibrary(kTools);
  struct Outcome {
    double rapid_mm = 0;
    int retracts = 0, operations = 0;
    std::vector<double> planned_mm3, above_share;
    VerificationReport report;
  };
  auto plan = [&](bool stay_down) {
    RoughingOptions options;
    options.clearing.stay_down = stay_down;
    const RoughingPlan roughing = planRoughing(part, setups, library, options);
    Outcome out;
    for (const RoughingOperation& op : roughing.operations) out.planned_mm3.push_back(op.planned_removal_mm3);
    for (const RoughingOperation& op : roughing.operations) out.rapid_mm += op.rapid_mm, out.retracts += op.retracts;
    out.operations = static_cast<int>(roughing.operations.size());
    out.report = verifyRoughing(part, roughing, library);
    expectLevelCutsWithinTheStepDown(roughing, out.report, library, options, &out.above_share);
    return out;
  };
  const Outcome high = plan(false), low = plan(true);
  std::printf("links over the clearance plane: %.0f mm of rapids, %d retracts; stay-down: %.0f mm, %d retracts "
              "(%d operations); removed %.0f / %.0f mm3\n",
              high.rapid_mm, high.retracts, low.rapid_mm, low.retracts, low.operations,
              high.report.removed_volume_mm3, low.report.removed_volume_mm3);
  EXPECT_EQ(low.report.gouges, 0);
  EXPECT_EQ(low.report.collisions, 0);
  EXPECT_LT(low.rapid_mm, 0.6 * high.rapid_mm);
  EXPECT_LT(low.retracts, 0.3 * high.retracts);
  EXPECT_NEAR(low.report.removed_volume_mm3, high.report.removed_volume_mm3, 5e-4 * high.report.removed_volume_mm3);
  // What each operation is planned to remove bounds what it removes in the simulation (why dropping a rest pass
  // planned to remove almost nothing is sound), to within the dexel lattice's error on thin bands (3 % + 10 mm3).
  for (std::size_t i = 0; i < low.planned_mm3.size(); ++i) {
    const auto check = low.report.by_op.find(static_cast<int>(i));
    const double simulated = check == low.report.by_op.end() ? 0 : check->second.swept.removed_mm3;
    EXPECT_LE(simulated, 1.03 * low.planned_mm3[i] + 10) << "operation " << i;
    std::printf("operation %zu: %.2f %% of its cut above its slab\n", i, 100 * low.above_share.at(i));
  }
}

// Constant-engagement clearing (issue 19 item 3) for the main passes against zig-zag, on the same setups: by the
// simulation it neither gouges nor collides; the main passes take the library's high-efficiency cutters at their own
// step-down and, in the first setup, which takes the block's bulk, run in less estimated time, step-up pass included
// (featuretype at level-2 setups: 238 s against 400 s). In the second setup, over what the first left, zig-zag is
// quicker since its main pass no longer traces the first setup's film (221 s against 171 + 230 s: the step-up pass's
// fronts keep the engagement step where the stock is thin); all main passes 622 / 640 s (752 / 669 s before).
// Not asserted, printed: the stock left after the rest
// passes (36,017 mm3 zig-zag, 34,929 mm3 adaptive; 36,917 mm3 before the step-up pass: the main pass's slabs are up
// to 40 mm thick and leave stairs the 2 mm rest levels did not all take).
TEST(Roughing, AdaptiveMainPassesCutUnderTheirEngagementWithoutCollisions) {
  const auto& [part, setups] = featuretype();
  const ToolLibrary library = loadToolLibrary(kTools);
  struct Outcome {
    double main_s = 0, first_setup_main_s = 0, all_s = 0;
    VerificationReport report;
  };
  auto plan = [&](RoughingOptions::Clearing::Strategy strategy) {
    RoughingOptions options;
    options.clearing.strategy = strategy;
    const RoughingPlan roughing = planRoughing(part, setups, library, options);
    Outcome out;
    for (const RoughingOperation& op : roughing.operations) {
      out.all_s += op.seconds;
      if (op.kind == "rest roughing" || op.kind == "reach roughing") continue;  // zig-zag after either main pass
      out.main_s += op.seconds;
      if (op.setup == 0) out.first_setup_main_s += op.seconds;
      const Tool* tool = library.find(op.tool);
      EXPECT_TRUE(tool != nullptr);
      const bool adaptive = strategy == RoughingOptions::Clearing::Strategy::Engagement;
      EXPECT_TRUE(adaptive ? op.kind == "adaptive roughing" || op.kind == "adaptive rest roughing"
                           : op.kind == "roughing") << op.kind;
      if (tool) {
        EXPECT_EQ(tool->max_engagement_deg > 0, adaptive) << op.tool;
      }
    }
    out.report = verifyRoughing(part, roughing, library);
    expectLevelCutsWithinTheStepDown(roughing, out.report, library, options);
    return out;
  };
  const Outcome zigzag = plan(RoughingOptions::Clearing::Strategy::ZigZag);
  const Outcome adaptive = plan(RoughingOptions::Clearing::Strategy::Engagement);
  std::printf("main passes: zig-zag %.0f s, adaptive %.0f s (first setup %.0f / %.0f s; all operations %.0f / %.0f s); "
              "removed %.0f / %.0f mm3, left %.0f / %.0f mm3\n",
              zigzag.main_s, adaptive.main_s, zigzag.first_setup_main_s, adaptive.first_setup_main_s, zigzag.all_s,
              adaptive.all_s, zigzag.report.removed_volume_mm3,
              adaptive.report.removed_volume_mm3,
              zigzag.report.leftover_volume_mm3, adaptive.report.leftover_volume_mm3);
  EXPECT_EQ(adaptive.report.gouges, 0);
  EXPECT_EQ(adaptive.report.collisions, 0);
  EXPECT_LT(adaptive.first_setup_main_s, 0.9 * zigzag.first_setup_main_s);
}

// The progress contract (common/progress.h): a report after every level, the share never decreasing and the levels
// counted up; asked to stop, planRoughing stops at the next level and keeps only the setups finished before.
TEST(Roughing, ReportsEveryLevelAndStopsAtTheNextOneWhenAsked) {
  const Part part = lPart();
  const ToolLibrary library = loadToolLibrary(kTools);
  SetupPlan setups;
  setups.setups.push_back(topSetup(part));
  setups.setups.push_back(topSetup(part));  // the same direction again: a second setup with (almost) nothing to do
  std::vector<ProgressReport> reports;
  const RoughingPlan whole = planRoughing(part, setups, library, {}, [&](const ProgressReport& p) {
    reports.push_back(p);
    return true;
  });
  ASSERT_FALSE(whole.cancelled);
  std::size_t levels = 0;
  for (const RoughingOperation& op : whole.operations) levels += op.levels.size();
  EXPECT_GE(reports.size(), levels) << "a report per level at least";
  for (std::size_t i = 1; i < reports.size(); ++i) {
    EXPECT_EQ(reports[i].stage, "roughing");
    EXPECT_GE(reports[i].fraction, reports[i - 1].fraction - 1e-12) << i;
    EXPECT_GE(reports[i].done, reports[i - 1].done) << i;
  }
  EXPECT_DOUBLE_EQ(reports.back().fraction, 1.0);

  // Stop in the middle of the first setup's main operation: nothing of that setup is kept.
  int calls = 0, after_no = 0;
  bool said_no = false;
  const RoughingPlan stopped = planRoughing(part, setups, library, {}, [&](const ProgressReport&) {
    if (said_no) ++after_no;
    said_no = said_no || ++calls == 4;
    return !said_no;
  });
  EXPECT_TRUE(stopped.cancelled);
  EXPECT_TRUE(stopped.operations.empty());
  EXPECT_EQ(after_no, 0) << "reports after the stop was asked";
}
