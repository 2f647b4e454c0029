// The progress and cancel contract (common/progress.h) for the setup and verification stages: reports of their own
// stage with a share in [0, 1] that never goes back, at least once a second and at each step; asked to stop, the
// call returns within a second, flagged cancelled, without throwing.
#include <gtest/gtest.h>

#include <chrono>
#include <random>

#include "art2part/geometry/part.h"
#include "art2part/plan/plan_part.h"
#include "art2part/setup/minimum_cover.h"
#include "art2part/setup/setup_plan.h"
#include "art2part/simulation/verify.h"
#include "art2part/visibility/analysis.h"
#include "test_meshes.h"
#include "test_solids.h"

using namespace art2part;

namespace {

using Clock = std::chrono::steady_clock;

double since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// Every report of a call, and when it came.
struct Recorder {
  Clock::time_point start = Clock::now();
  std::vector<ProgressReport> reports;
  std::vector<double> at;  // seconds since start

  ProgressSink sink() {
    return [this](const ProgressReport& p) {
      reports.push_back(p);
      at.push_back(since(start));
      return true;
    };
  }
};

// The reports of one stage: its name, fractions in [0, 1] never decreasing, no more than a second between two of
// them, nor from the call to the first or from the last to the return (`returned`, seconds since the start).
void expectTheContract(const Recorder& r, const std::string& stage, double returned) {
  ASSERT_FALSE(r.reports.empty());
  for (std::size_t i = 0; i < r.reports.size(); ++i) {
    SCOPED_TRACE("report " + std::to_string(i) + ": " + r.reports[i].message);
    EXPECT_EQ(r.reports[i].stage, stage);
    EXPECT_GE(r.reports[i].fraction, 0.0);
    EXPECT_LE(r.reports[i].fraction, 1.0);
    if (i > 0) {
      EXPECT_GE(r.reports[i].fraction, r.reports[i - 1].fraction);
    }
    EXPECT_LE(r.at[i] - (i > 0 ? r.at[i - 1] : 0.0), 1.0) << "a second without a report";
  }
  EXPECT_LE(returned - r.at.back(), 1.0) << "a second between the last report and the return";
  EXPECT_DOUBLE_EQ(r.reports.back().fraction, 1.0);
}

// ---- setups ----------------------------------------------------------------------------------------------------------

struct SmallPart {
  Part part = partFromMesh(test::box(Vec3(0, 0, 0), Vec3(30, 20, 10)), "box");
  VisibilityResult visibility;
  SmallPart() {
    VisibilityOptions options;
    options.level = 2;
    visibility = analyseVisibility(part, options);
  }
};

TEST(SetupProgress, ReportsEachStepWithAShareThatNeverGoesBack) {
  const SmallPart small;
  Recorder recorder;
  const SetupPlan plan = planSetups(small.part, small.visibility, {}, recorder.sink());
  const double returned = since(recorder.start);
  EXPECT_FALSE(plan.cancelled);
  EXPECT_FALSE(plan.setups.empty());
  expectTheContract(recorder, "setups", returned);
  EXPECT_GE(recorder.reports.size(), 4u) << "reach, cover problem, search, assignment, done";
  // The same plan as without a sink.
  const SetupPlan quiet = planSetups(small.part, small.visibility);
  ASSERT_EQ(quiet.setups.size(), plan.setups.size());
  for (std::size_t k = 0; k < plan.setups.size(); ++k) EXPECT_EQ(quiet.setups[k].direction, plan.setups[k].direction);
}

TEST(SetupProgress, StopsAfterTheFirstReportWithoutThrowing) {
  const SmallPart small;
  int reports = 0;
  SetupPlan plan;
  const auto start = Clock::now();
  EXPECT_NO_THROW(plan = planSetups(small.part, small.visibility, {}, [&](const ProgressReport&) {
    ++reports;
    return false;
  }));
  EXPECT_LT(since(start), 1.0);
  EXPECT_TRUE(plan.cancelled);
  EXPECT_TRUE(plan.setups.empty());
  EXPECT_EQ(reports, 1) << "no report after the stop";
}

// A cover problem the exact search does not finish in seconds: random, 120 candidates, 2000 elements.
CoverProblem hardCover() {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> uniform(0, 1);
  CoverProblem p;
  p.candidates = 120;
  p.coverers = BitMatrix(2000, p.candidates);
  for (int e = 0; e < 2000; ++e)
    for (int c = 0; c < p.candidates; ++c)
      if (uniform(rng) < 0.06) p.coverers.set(e, c);
  p.earners = BitMatrix(0, p.candidates);
  return p;
}

// The search under planSetups: asked to stop, it ends within a second and hands back a cover all the same.
TEST(SetupProgress, TheCoverSearchStopsWithinASecondOfTheAsking) {
  const CoverProblem p = hardCover();
  CoverOptions options;
  options.time_limit_s = 30;
  options.use_bonus = false;
  const auto start = Clock::now();
  double asked_at = -1;
  options.keep_going = [&] {
    if (asked_at < 0 && since(start) > 0.5) asked_at = since(start);
    return asked_at < 0;
  };
  const CoverResult result = minimumCover(p, options);
  const double returned = since(start);
  ASSERT_GT(asked_at, 0) << "the search ended before it was asked to stop: the instance is too easy for this test";
  EXPECT_LT(returned - asked_at, 1.0);
  EXPECT_TRUE(result.stopped);
  EXPECT_FALSE(result.proven_minimal);
  EXPECT_TRUE(coversAll(p, result.chosen));
}

// ---- verification ----------------------------------------------------------------------------------------------------

CutterLocation at(MoveKind move, double x, double y, double z) {
  CutterLocation c;
  c.tool = "flat6";
  c.move = move;
  c.tip = Vec3(x, y, z);
  c.axis = Vec3::UnitZ();
  return c;
}


// Zig-zag facing of the 2 mm of stock over a 40 x 20 x 10 block in 0.25 mm layers at a 0.12 mm lattice: seconds of
// sweeping.
Toolpath facing() {
  Toolpath path = {at(MoveKind::Rapid, -5, -3, 20)};
  for (double z = 11.75; z >= 10.0; z -= 0.25) {
    for (double y = -3; y <= 23; y += 2) {
      path.push_back(at(MoveKind::Feed, -5, y, z));
      path.push_back(at(MoveKind::Feed, 45, y, z));
      path.push_back(at(MoveKind::Feed, 45, y + 1, z));
      path.push_back(at(MoveKind::Feed, -5, y + 1, z));
    }
  }
  path.push_back(at(MoveKind::Feed, path.back().tip.x(), path.back().tip.y(), 20));
  return path;
}

VerifyOptions fineLattice() {
  VerifyOptions o;
  o.resolution = 0.12;
  o.stock_margin = 2;
  return o;
}

const Mesh kBlock = test::box(Vec3(0, 0, 0), Vec3(40, 20, 10));

TEST(VerificationProgress, ReportsAtLeastEverySecondWithTheShareOfTheMoves) {
  Recorder recorder;
  VerificationReport report;
  EXPECT_NO_THROW(report = verifyToolpath(kBlock, {}, facing(), {test::flat6()}, fineLattice(), nullptr, recorder.sink()));
  const double returned = since(recorder.start);
  EXPECT_FALSE(report.cancelled);
  EXPECT_TRUE(report.passed());
  expectTheContract(recorder, "verification", returned);
  int during_sweep = 0;
  for (const ProgressReport& p : recorder.reports) during_sweep += p.fraction > 0 && p.fraction < 0.9;
  if (returned > 1.0) {
    EXPECT_GE(during_sweep, 1) << "a sweep of " << returned << " s with no report of the moves done";
  }
  // The same figures as without a sink.
  const VerificationReport quiet = verifyToolpath(kBlock, {}, facing(), {test::flat6()}, fineLattice());
  EXPECT_DOUBLE_EQ(quiet.removed_volume_mm3, report.removed_volume_mm3);
  EXPECT_DOUBLE_EQ(quiet.leftover_volume_mm3, report.leftover_volume_mm3);
}

TEST(VerificationProgress, StopsAfterTheFirstReportWithoutThrowing) {
  int reports = 0;
  VerificationReport report;
  const auto start = Clock::now();
  EXPECT_NO_THROW(report = verifyToolpath(kBlock, {}, facing(), {test::flat6()}, fineLattice(), nullptr,
                                          [&](const ProgressReport&) { return ++reports < 1; }));
  EXPECT_LT(since(start), 1.0);
  EXPECT_TRUE(report.cancelled);
  EXPECT_FALSE(report.passed());
  EXPECT_EQ(reports, 1) << "no report after the stop";
}

TEST(VerificationProgress, StopsWithinASecondInTheMiddleOfTheSweep) {
  double asked_at = -1;
  const auto start = Clock::now();
  VerificationReport report;
  EXPECT_NO_THROW(report = verifyToolpath(kBlock, {}, facing(), {test::flat6()}, fineLattice(), nullptr,
                                          [&](const ProgressReport& p) {
                                            if (asked_at < 0 && p.fraction > 0 && p.fraction < 0.9)
                                              asked_at = since(start);
                                            return asked_at < 0;
                                          }));
  const double returned = since(start);
  ASSERT_GT(asked_at, 0) << "no report during the sweep (" << returned << " s)";
  EXPECT_LT(returned - asked_at, 1.0);
  EXPECT_TRUE(report.cancelled);
  EXPECT_FALSE(report.passed());
  EXPECT_LT(report.removed_volume_mm3, verifyToolpath(kBlock, {}, facing(), {test::flat6()}, fineLattice()).removed_volume_mm3)
      << "stopped part way, it removed less than the whole path";
}

// ---- through planPart -------------------------------------------------------------------------------------------------

// planPart hands its sink to both stages: stopped in one, it returns within a second, cancelled, with the stages
// before kept.
TEST(PlanProgress, StopsInTheSetupsAndInTheVerification) {
  const Part part = test::stepPart(test::pocketedBlock(Vec3(0, 0, 0), Vec3(60, 40, 20), 30, 20, 8, 4), "pocket");
  const ToolLibrary library = loadToolLibrary(std::string(ART2PART_SOURCE_DIR) + "/config/tools.yaml");
  PlanOptions options;
  options.visibility.level = 2;
  for (const std::string stage : {"setups", "verification"}) {
    SCOPED_TRACE(stage);
    double asked_at = -1;
    int reports_after = 0;
    const auto start = Clock::now();
    PlanResult plan;
    EXPECT_NO_THROW(plan = planPart(part, library, options, [&](const ProgressReport& p) {
      if (asked_at >= 0) ++reports_after;
      if (asked_at < 0 && p.stage == stage && p.fraction > 0) asked_at = since(start);
      return asked_at < 0;
    }));
    ASSERT_GE(asked_at, 0) << "no report of the stage past its start";
    EXPECT_LT(since(start) - asked_at, 1.0);
    EXPECT_TRUE(plan.cancelled);
    EXPECT_FALSE(plan.verified);
    EXPECT_EQ(reports_after, 0);
    if (stage == "setups") {
      EXPECT_TRUE(plan.setups.setups.empty());
      EXPECT_TRUE(plan.roughing.operations.empty());
    } else {
      EXPECT_FALSE(plan.setups.setups.empty()) << "the stages before are kept";
      EXPECT_FALSE(plan.roughing.operations.empty());
      EXPECT_TRUE(plan.verification.cancelled);
    }
  }
}

}  // namespace
