// The progress and cancel contract (common/progress.h) for the setup and verification stages: reports of their own
// stage with a share in [0, 1] that never goes back, at least once a second and at each step; asked to stop, the
// call returns within a second, flagged cancelled, without throwing.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <random>
#include <stdexcept>
#include <thread>

#include "art2part/common/parallel.h"
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

// ---- parallelForTicking (common/parallel.h): finishing's groups -----------------------------------------------------

void sleepMs(int ms) { std::this_thread::sleep_for(std::chrono::milliseconds(ms)); }

TEST(ParallelForTicking, RunsEveryItemOnceAndTicksWhileTheyRun) {
  constexpr int kItems = 30;
  std::vector<std::atomic<int>> runs(kItems);
  std::vector<int> ticks;
  std::vector<double> at;
  const auto start = Clock::now();
  const bool all = parallelForTicking(
      kItems, 3,
      [&](int k) {
        sleepMs(k % 3 == 0 ? 40 : 5);  // of different cost
        ++runs[k];
      },
      0.02,
      [&](int done) {
        ticks.push_back(done);
        at.push_back(since(start));
        return true;
      });
  EXPECT_TRUE(all);
  for (int k = 0; k < kItems; ++k) EXPECT_EQ(runs[k].load(), 1) << "item " << k;
  ASSERT_GE(ticks.size(), 3u) << "ticks while the items ran (about 0.2 s of them)";
  for (std::size_t i = 1; i < ticks.size(); ++i) EXPECT_GE(ticks[i], ticks[i - 1]);
  EXPECT_EQ(ticks.back(), kItems) << "the last tick counts every item";
  for (std::size_t i = 1; i < at.size(); ++i) EXPECT_LT(at[i] - at[i - 1], 0.5);
}

TEST(ParallelForTicking, StartsNoItemOnceTickSaysStop) {
  constexpr int kItems = 200, kThreads = 2;
  std::atomic<int> started{0};
  int ticks_after = 0, started_at_stop = -1;
  const bool all = parallelForTicking(
      kItems, kThreads,
      [&](int) {
        ++started;
        sleepMs(50);
      },
      0.01,
      [&](int done) {
        if (started_at_stop >= 0) ++ticks_after;
        if (started_at_stop < 0 && done >= 4) started_at_stop = started.load();
        return started_at_stop < 0;
      });
  EXPECT_FALSE(all);
  ASSERT_GE(started_at_stop, 4);
  EXPECT_EQ(ticks_after, 0) << "no tick after it said stop";
  // A thread past its check for the stop when it came may still take one more item; no other starts.
  EXPECT_LE(started.load(), started_at_stop + kThreads);
}

TEST(ParallelForTicking, AnItemsExceptionComesOutOnceEveryWorkerStopped) {
  std::atomic<int> running{0}, started{0};
  auto body = [&](int k) {
    ++started;
    ++running;
    sleepMs(5);
    --running;
    if (k == 3) throw std::runtime_error("item 3 failed");
  };
  try {
    parallelForTicking(100, 2, body, 0.01, [](int) { return true; });
    ADD_FAILURE() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "item 3 failed");
  }
  EXPECT_EQ(running.load(), 0);
  EXPECT_LT(started.load(), 100) << "the items after the failure were not started";
  EXPECT_THROW(parallelForTicking(
                   4, 2, [](int) { sleepMs(50); }, 0.01, [](int) -> bool { throw std::logic_error("tick"); }),
               std::logic_error);
}

// runTicking, which parallelForTicking and the verification's sweep are built on: every work once with its own index,
// on threads of their own; the stop that tick raises reaches every work, and tick is not called again.
TEST(RunTicking, EveryWorkRunsOnceAndAStopFromTickReachesAll) {
  constexpr int kThreads = 3;
  std::vector<std::atomic<int>> ran(kThreads);
  std::atomic<int> watching{0};
  int ticks = 0, ticks_after = 0;
  bool said_stop = false;
  const bool stopped = runTicking(
      kThreads,
      [&](int t, const std::atomic<bool>& stop) {
        ++ran[t];
        ++watching;
        while (!stop.load()) sleepMs(1);  // only the stop ends it
      },
      0.01,
      [&] {
        if (said_stop) ++ticks_after;
        ++ticks;
        said_stop = ticks >= 3 && watching.load() == kThreads;
        return !said_stop;
      });
  EXPECT_TRUE(stopped);
  for (int t = 0; t < kThreads; ++t) EXPECT_EQ(ran[t].load(), 1) << "work " << t;
  EXPECT_EQ(ticks_after, 0);
  EXPECT_FALSE(runTicking(2, [](int, const std::atomic<bool>&) { sleepMs(20); }, 0.005, [] { return true; }));
}

// ---- finishing ------------------------------------------------------------------------------------------------------

// Finishing's groups run side by side while the calling thread reports; stopped, it starts no further group, reports
// nothing more and returns what it finished, flagged cancelled.
TEST(FinishingProgress, ReportsWhileItsGroupsRunAndStopsBetweenThem) {
  const TopoDS_Shape top = test::cut(test::pocketedBlock(Vec3(0, 0, 0), Vec3(60, 40, 20), 24, 16, 8, 4),
                                     test::solidCylinder(Vec3(50, 20, -1), Vec3(0, 0, 1), 4.0, 22));
  const Part part = test::stepPart(test::cut(top, test::solidBox(Vec3(5, 5, -1), Vec3(25, 20, 4))), "two pockets");
  const ToolLibrary library = loadToolLibrary(std::string(ART2PART_SOURCE_DIR) + "/config/tools.yaml");
  PlanOptions options;
  options.visibility.level = 2;
  const VisibilityResult visibility = analyseVisibility(part, options.visibility);
  const SetupPlan setups = planPartSetups(part, visibility, library, options);
  const RoughingStage roughing = planPartRoughing(part, setups, library, options);

  Recorder recorder;
  const FinishingPlan whole = planPartFinishing(part, visibility, setups, roughing, library, options, recorder.sink());
  expectTheContract(recorder, "finishing", since(recorder.start));
  EXPECT_FALSE(whole.cancelled);
  ASSERT_FALSE(whole.operations.empty());
  for (std::size_t i = 1; i < recorder.reports.size(); ++i)
    EXPECT_GE(recorder.reports[i].done, recorder.reports[i - 1].done);

  int reports_after = 0;
  bool asked = false;
  const FinishingPlan stopped =
      planPartFinishing(part, visibility, setups, roughing, library, options, [&](const ProgressReport&) {
        reports_after += asked;
        asked = true;
        return false;
      });
  EXPECT_TRUE(asked);
  EXPECT_EQ(reports_after, 0);
  EXPECT_TRUE(stopped.cancelled);
  EXPECT_LT(stopped.operations.size(), whole.operations.size()) << "no group started after the stop";
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
