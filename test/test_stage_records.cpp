// Stage records (stage_records.h): a plan made stage by stage, each stage's result handed on as a record (as the cell's
// stage nodes and supervisor do), writes the same plan folder as planPart in one process: the same toolpaths.csv byte
// for byte and the same plan.json but for timings. Bytes that are not the record asked for are refused by name.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <string>
#include <utility>

#include "art2part/plan/plan_folder.h"
#include "art2part/plan/stage_records.h"
#include "test_meshes.h"
#include "test_solids.h"

namespace art2part {
namespace {

namespace fs = std::filesystem;

const std::string kConfig = std::string(ART2PART_SOURCE_DIR) + "/config";

// plan.json without what depends on the clock: timings and every "...seconds..." figure.
nlohmann::json withoutClock(nlohmann::json j) {
  if (j.is_object()) {
    nlohmann::json out = nlohmann::json::object();
    for (auto it = j.begin(); it != j.end(); ++it)
      if (it.key() != "timings" && it.key().find("seconds") == std::string::npos &&
          it.key().find("per_second") == std::string::npos)
        out[it.key()] = withoutClock(it.value());
    return out;
  }
  if (j.is_array())
    for (auto& v : j) v = withoutClock(v);
  return j;
}

// A block with a pocket and an 8 mm through hole (a library drill makes it): every record has something to carry.
Part drilledPocket() {
  const TopoDS_Shape block = test::pocketedBlock(Vec3(0, 0, 0), Vec3(60, 40, 20), 24, 16, 8, 4);
  return test::stepPart(test::cut(block, test::solidCylinder(Vec3(50, 20, -1), Vec3(0, 0, 1), 4.0, 22)), "drilled");
}

TEST(StageRecords, AStageByStagePlanThroughRecordsWritesWhatPlanPartWrites) {
  const Part original = drilledPocket();
  const ToolLibrary library = loadToolLibrary(kConfig + "/tools.yaml");
  PlanOptions options;
  options.visibility.level = 2;
  const PlanResult whole = planPart(original, library, options);
  ASSERT_FALSE(whole.holes.empty());
  ASSERT_FALSE(whole.finishing.operations.empty());
  ASSERT_TRUE(whole.verified);

  // The cell's hand-offs: the part from part_server, each stage's result as the next one receives it.
  const Part part = partFromRecord(partRecord(original));
  PlanResult staged;
  staged.visibility = analyseVisibility(part, options.visibility);
  staged.setups = setupsFromRecord(setupsRecord(planPartSetups(part, staged.visibility, library, options)));
  const RoughingStage roughing =
      roughingFromRecord(roughingRecord(planPartRoughing(part, staged.setups, library, options)));
  staged.holes = roughing.holes;
  staged.hole_methods = roughing.hole_methods;
  staged.roughing = roughing.roughing;
  staged.finishing = finishingFromRecord(finishingRecord(
      planPartFinishing(part, staged.visibility, staged.setups, roughing, library, options)));
  combinePlan(staged, part, library, options);
  const ToolpathAndTools sent = toolpathFromRecord(toolpathRecord(staged.toolpath, staged.tools));
  const VerifyOptions verify = verifyOptionsFromRecord(verifyOptionsRecord(planVerifyOptions(part, staged, library, options)));
  staged.verification = verificationFromRecord(verificationRecord(
      verifyToolpath(part.mesh, part.triangle_face, sent.path, sent.tools, verify, &staged.simulation)));
  staged.verified = true;
  judgeFaces(staged.verification, staged.finishing);

  PlanFolderOptions folder;
  folder.pictures = false;
  folder.program.write = false;
  const std::string a = test::tempDir() + "/whole", b = test::tempDir() + "/staged";
  const WrittenPlan wa = writePlanFolder(a, original, whole, folder);
  const WrittenPlan wb = writePlanFolder(b, part, staged, folder);
  EXPECT_EQ(test::slurp(fs::path(a) / "toolpaths.csv"), test::slurp(fs::path(b) / "toolpaths.csv"));
  EXPECT_EQ(test::slurp(fs::path(a) / "tools.json"), test::slurp(fs::path(b) / "tools.json"));
  EXPECT_EQ(test::slurp(fs::path(a) / "mesh.stl"), test::slurp(fs::path(b) / "mesh.stl"));
  EXPECT_EQ(withoutClock(wa.plan).dump(1), withoutClock(wb.plan).dump(1));
  // What the records carry beyond plan.json: the stock roughing leaves (finishing keeps clear of it).
  ASSERT_EQ(staged.roughing.stock_left.size(), whole.roughing.stock_left.size());
  for (std::size_t k = 0; k < whole.roughing.stock_left.size(); ++k) {
    ASSERT_EQ(staged.roughing.stock_left[k].size(), whole.roughing.stock_left[k].size());
    for (std::size_t s = 0; s < whole.roughing.stock_left[k].size(); ++s)
      EXPECT_EQ(staged.roughing.stock_left[k][s].remaining, whole.roughing.stock_left[k][s].remaining);
  }
  auto unclocked = [](VerificationReport r) {
    r.seconds_sweep = r.seconds_total = r.moves_per_second = 0;
    r.resumed_at_row = 0;  // how the sweep went (a trial without useless roughing resumes), not what it found
    return verificationRecord(r);
  };
  EXPECT_EQ(unclocked(staged.verification), unclocked(whole.verification))
      << "the report of the same path, apart or in one process";
}

// Finishing plans its groups of faces (one setup's direction each) side by side: the operations, their order and every
// face's verdict are the same for any number of threads, as the record carries them (the planning clock aside).
TEST(StageRecords, FinishingIsTheSameForAnyNumberOfThreads) {
  // The drilled pocket with a pocket in its bottom and a notch in a side: faces finished along several directions.
  const TopoDS_Shape top = test::cut(test::pocketedBlock(Vec3(0, 0, 0), Vec3(60, 40, 20), 24, 16, 8, 4),
                                     test::solidCylinder(Vec3(50, 20, -1), Vec3(0, 0, 1), 4.0, 22));
  const TopoDS_Shape bottom = test::cut(top, test::solidBox(Vec3(5, 5, -1), Vec3(25, 20, 4)));
  const Part part = test::stepPart(test::cut(bottom, test::solidBox(Vec3(30, 34, 8), Vec3(45, 41, 14))), "notched");
  const ToolLibrary library = loadToolLibrary(kConfig + "/tools.yaml");
  for (MachineMode mode : {MachineMode::ThreeAxis, MachineMode::FiveAxis}) {
    SCOPED_TRACE(machineModeName(mode));
    PlanOptions options;
    options.visibility.level = 2;
    options.setups.mode = mode;
    const VisibilityResult visibility = analyseVisibility(part, options.visibility);
    const SetupPlan setups = planPartSetups(part, visibility, library, options);
    const RoughingStage roughing = planPartRoughing(part, setups, library, options);
    auto finishing = [&](int threads) {
      PlanOptions o = options;
      o.finishing.threads = threads;
      FinishingPlan plan = planPartFinishing(part, visibility, setups, roughing, library, o);
      plan.plan_seconds = 0;
      for (FinishingOperation& op : plan.operations) op.plan_seconds = 0;
      return plan;
    };
    const FinishingPlan one = finishing(1);
    std::set<std::pair<int, std::string>> groups;  // (setup, direction) of the operations: several to interleave
    for (const FinishingOperation& op : one.operations)
      groups.insert({op.setup, std::to_string(op.direction.x()) + " " + std::to_string(op.direction.y()) + " " +
                                   std::to_string(op.direction.z())});
    ASSERT_GE(groups.size(), 3u);
    const RecordBytes expected = finishingRecord(one);
    for (int threads : {2, 3}) EXPECT_TRUE(finishingRecord(finishing(threads)) == expected) << threads << " threads";
  }
}

TEST(StageRecords, BytesThatAreNotTheRecordAskedForAreRefusedByName) {
  SetupPlan plan;
  plan.setups.resize(2);
  const RecordBytes setups = setupsRecord(plan);
  EXPECT_EQ(setupsFromRecord(setups).setups.size(), 2u);
  auto message = [](auto read) {
    try {
      read();
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message([&] { roughingFromRecord(setups); }).find("a roughing record was expected, not a setups record"),
            std::string::npos);
  EXPECT_NE(message([] { finishingFromRecord({}); }).find("none given"), std::string::npos);
  EXPECT_NE(message([] { partFromRecord({0xc1, 0x00, 0x17}); }).find("not MessagePack"), std::string::npos);
  RecordBytes truncated(setups.begin(), setups.begin() + static_cast<long>(setups.size() / 2));
  EXPECT_NE(message([&] { setupsFromRecord(truncated); }), "no error");
}

}  // namespace
}  // namespace art2part
